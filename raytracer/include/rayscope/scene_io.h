// The JSON scene format (documented in docs/scene-format.md).
#pragma once

#include <array>
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "rayscope/integrator.h"
#include "rayscope/scene.h"

namespace rayscope {

/// Any problem with a scene file. what() is one line: "FILE: problem".
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The color maps a mesh's "color_by" can name. The core only names them; the
/// mesh loader builds them (the VTK-side loader with VTK's lookup tables).
enum class ColorMap { CoolWarm, Rainbow, Grayscale };

/// The scene-file names of the color maps, indexed by ColorMap.
inline constexpr std::array<const char*, 3> kColorMapNames = {"cool-warm", "rainbow", "grayscale"};

/// A mesh colored by one of its scalar arrays mapped through a color map
/// (docs/scene-format.md, "color_by").
struct MeshColorBy {
  enum class Association { Point, Cell };
  std::string array;  ///< Name of the point or cell array (non-empty).
  Association association = Association::Point;
  /// Scalar values mapped to the two ends of the map (lo < hi); without it
  /// the array's range.
  std::optional<std::array<double, 2>> range;
  ColorMap map = ColorMap::CoolWarm;
};

/// What a scene file asks of one mesh object, for the MeshLoader.
struct MeshOptions {
  std::filesystem::path file;  ///< Resolved against the scene file's folder.
  /// true: shaded smooth with point normals (the file's, else computed);
  /// false: no normals, flat shading.
  bool smooth = true;
  std::optional<MeshColorBy> color_by;  ///< Vertex colors from scalars; none without.
  /// From the file's coordinates to the scene's local ones (Scene::origin):
  /// the object's "transform", then the move by -origin. The loader applies it
  /// to the points in double precision, before they are rounded to float, and
  /// its inverse transpose to the normals.
  glm::dmat4 to_scene{1.0};
  /// Radius of the tubes drawn around the file's line cells and of the
  /// spheres at its vertex cells, in the scene's units; 0: automatic (the
  /// loader's rule, a fraction of the file's size).
  double line_radius = 0.0, point_radius = 0.0;
  /// A point array (one component) giving the radius at each point of lines
  /// and vertices; empty: none.
  std::string radius_array;
};

/// Thrown by a MeshLoader when the file is read but an option does not fit it
/// (e.g. color_by names an array the file lacks). what() is the problem; the
/// parser reports it under the object's "color_by".
class MeshOptionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// What a MeshLoader read from one mesh object's file: the scene objects it
/// gives (one member per kind of object a file can hold).
struct LoadedMeshFile {
  /// One mesh per dataset of the file, in the file's order: one for a file of
  /// one dataset, one per leaf for a composite file (blocks, partitions,
  /// element blocks). Each mesh's name is its place in the file: empty for a
  /// file of one dataset, e.g. "block 3 (wall)" for a leaf; the scene parser
  /// puts the object's name before it.
  std::vector<TriangleMesh> meshes;
  /// The line cells of the datasets as tubes and their vertex cells as
  /// spheres, a set per dataset that has them, named like the meshes with
  /// " lines" or " vertices" after ("lines" for a file of one dataset).
  std::vector<TubeSet> tubes;
  std::vector<PointSet> points;
  /// What was left out, one line each ("FILE: block 3 (wall): no surface
  /// triangles, lines or vertices, left out"); front ends print each as a
  /// warning.
  std::vector<std::string> warnings;
};

/// Adds the objects of `file` to `scene`, each named `name`, or `name` and
/// its own name after a space, and given `material`; returns the warnings.
std::vector<std::string> add_mesh_file_objects(Scene& scene, LoadedMeshFile&& file,
                                               const std::string& name, uint32_t material);

/// Reads the meshes a scene object describes (positions, triangles, optional
/// normals and colors). The core has no mesh readers of its own;
/// rayscope_vtkio::load_meshes (vtkplugin/vtkio) is the one the rayscope
/// command uses. Throws MeshOptionError for an option that does not fit the
/// file, another std::exception ("FILE: problem") for a file it cannot read.
using MeshLoader = std::function<LoadedMeshFile(const MeshOptions&)>;

struct LoadedScene {
  Scene scene;
  RenderSettings settings;  ///< From the file's "render" block, defaults otherwise.
  /// The mesh loader's warnings, each "SCENE: objects[I].file: WARNING".
  std::vector<std::string> warnings;
};

/// Parses a scene file. Relative mesh paths are resolved against the scene's
/// folder. Unknown keys, wrong types, non-finite numbers and out-of-range values
/// are errors. Throws SceneError. The scene is not committed.
LoadedScene load_scene(const std::filesystem::path& path, const MeshLoader& mesh_loader);

/// Same, from text; `name` is used in error messages and `base_dir` for meshes.
LoadedScene parse_scene(const std::string& text, const std::string& name,
                        const std::filesystem::path& base_dir, const MeshLoader& mesh_loader);

}  // namespace rayscope
