// The core scene of a vtkRayScopeImageAlgorithm (private header): built from
// its inputs, converters, materials, lights and camera, and updated in place
// so that only what changed is redone.
#pragma once

#include <string>
#include <vector>

#include "vtkTimeStamp.h"

#include "rayscope/scene.h"
#include "vtkRayScopeSceneSettings.h"

class vtkDataSet;
class vtkRayScopeImageAlgorithm;

namespace rayscope_vtkmodule {

/// Where a scene object comes from: an input, and for a composite input the
/// leaf (rayscope_vtkio::dataset_leaves()).
struct ObjectSource {
  int input = 0;
  /// The leaf's flat index in a composite input; -1 for a dataset input.
  int flat_index = -1;
  std::string name;  ///< The object's name ("input 0", "input 1 block 3 'wall'").
};

/// A light besides the headlight, in VTK terms (sRGB color).
using SceneLight = vtkRayScopeSceneSettings::Light;

/// The core storage choice of a Storage value (STORAGE_*), and back.
rayscope::PrimStorage storage_of(int storage);
int storage_value_of(rayscope::PrimStorage storage);
/// The algorithm's GridResolution as the grid builder takes it (negative
/// values, which Validate refuses, as 0).
glm::uvec3 grid_resolution_of(const int resolution[3]);
/// What `alg` asks to build: its Accel, Storage, LooseFactor, KdSplit and
/// GridResolution, in the core's terms (its parameters validated: an unknown
/// Accel gives the BVH).
rayscope::AccelConfig accel_config_of(vtkRayScopeImageAlgorithm* alg);

class SceneBuilder {
 public:
  /// Builds the scene of `alg` from its updated inputs, or updates the
  /// previous one: meshes are converted again only when an input or its
  /// converter changed, and the BVH is rebuilt only when the meshes or what
  /// commit() summarises changed (number of lights, whether any material
  /// reflects or refracts); then the camera is prepared for the image size.
  /// The parameters of `alg` must have been validated. Reports problems with
  /// vtkErrorMacro (and worked-around input with vtkWarningMacro) on `alg`;
  /// returns 1 on success, 0 after an error (the scene is then unusable).
  int Update(vtkRayScopeImageAlgorithm* alg, const std::vector<SceneLight>& lights);

  /// From now on Update() uses `scene` (committed) as it is, instead of the
  /// inputs, materials and lights: only the camera is taken from the
  /// algorithm, and the BVH is rebuilt when the algorithm's Accel differs from
  /// the scene's.
  void SetFixedScene(const rayscope::Scene& scene);

  /// Where each object of the scene comes from, in the scene's order: one
  /// mesh per dataset, then the tube sets and the point sets of the datasets
  /// that have lines and vertices (empty for a fixed scene).
  const std::vector<ObjectSource>& GetObjects() const { return this->Objects; }

  /// The scene of the last successful Update(), else null.
  rayscope::Scene* GetScene() { return this->HasScene ? &this->Scene : nullptr; }
  /// How often Update() converted the inputs to triangles, and committed the
  /// scene (building its BVH), since construction.
  size_t GetConversions() const { return this->Conversions; }
  size_t GetCommits() const { return this->Commits; }

 private:
  // Converted datasets with nothing to draw (no triangle, line or vertex;
  // tube_of and point_of: the dataset of each tube set and point set): an
  // error when no dataset has anything (returns 0), else a warning per empty
  // dataset (returns 1).
  static int CheckDrawable(vtkRayScopeImageAlgorithm* alg, const std::vector<vtkDataSet*>& data,
                           const std::vector<ObjectSource>& sources,
                           const std::vector<rayscope::TriangleMesh>& meshes,
                           const std::vector<size_t>& tube_of, const std::vector<size_t>& point_of);

  int UpdateFixed(vtkRayScopeImageAlgorithm* alg);
  // Scene.commit(accel), its error reported on `alg`; 1 on success.
  int Commit(vtkRayScopeImageAlgorithm* alg, const rayscope::AccelConfig& accel);
  // The camera of `alg` into the scene (scene-local); with AutoCamera, fitted
  // to `data`.
  void PlaceCamera(vtkRayScopeImageAlgorithm* alg, const std::vector<vtkDataSet*>& data = {});
  // The scene's camera prepared for the image size (an invalid camera is an
  // error on `alg`); 1 on success.
  int PrepareCamera(vtkRayScopeImageAlgorithm* alg);

  rayscope::Scene Scene;
  bool HasScene = false;
  bool Fixed = false;                       // SetFixedScene() was called
  vtkTimeStamp GeometryTime;                // when the meshes were last converted
  std::vector<vtkDataSet*> GeometryInputs;  // the datasets converted, one per object
  std::vector<ObjectSource> Objects;
  // The dataset (index into GeometryInputs) of each tube set and point set.
  std::vector<size_t> TubeOf, PointOf;
  // The settings the tubes and spheres were made with (a change converts
  // the geometry again).
  struct CurveSettings {
    double line_radius = 0.0, point_radius = 0.0;
    std::string radius_array;
    bool operator==(const CurveSettings&) const = default;
  };
  CurveSettings Curves;
  size_t Conversions = 0, Commits = 0;
};

}  // namespace rayscope_vtkmodule
