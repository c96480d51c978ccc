// The core scene of a vtkRayScopeImageAlgorithm (private header): built from
// its inputs, converters, materials, lights and camera, and updated in place
// so that only what changed is redone.
#pragma once

#include <vector>

#include "vtkTimeStamp.h"

#include "rayscope/scene.h"
#include "vtkRayScopeSceneSettings.h"

class vtkDataSet;
class vtkRayScopeImageAlgorithm;

namespace rayscope_vtkmodule {

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

  /// The scene of the last successful Update(), else null.
  rayscope::Scene* GetScene() { return this->HasScene ? &this->Scene : nullptr; }
  /// How often Update() converted the inputs to triangles, and committed the
  /// scene (building its BVH), since construction.
  size_t GetConversions() const { return this->Conversions; }
  size_t GetCommits() const { return this->Commits; }

 private:
  // Converted inputs without any triangle: an error when no input has one
  // (returns 0), else a warning per empty input (returns 1).
  static int CheckTriangles(vtkRayScopeImageAlgorithm* alg, const std::vector<vtkDataSet*>& inputs,
                            const std::vector<rayscope::TriangleMesh>& meshes);

  int UpdateFixed(vtkRayScopeImageAlgorithm* alg);
  // Scene.commit(accel), its error reported on `alg`; 1 on success.
  int Commit(vtkRayScopeImageAlgorithm* alg, const rayscope::AccelConfig& accel);
  // The camera of `alg` into the scene, prepared for the image size; with
  // AutoCamera, fitted to `inputs`.
  int PrepareCamera(vtkRayScopeImageAlgorithm* alg, const std::vector<vtkDataSet*>& inputs = {});

  rayscope::Scene Scene;
  bool HasScene = false;
  bool Fixed = false;         // SetFixedScene() was called
  vtkTimeStamp GeometryTime;  // when the meshes were last converted
  std::vector<vtkDataSet*> GeometryInputs;
  size_t Conversions = 0, Commits = 0;
};

}  // namespace rayscope_vtkmodule
