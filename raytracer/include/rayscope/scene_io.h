// The JSON scene format (documented in docs/scene-format.md).
#pragma once

#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>

#include "rayscope/integrator.h"
#include "rayscope/scene.h"

namespace rayscope {

/// Any problem with a scene file. what() is one line: "FILE: problem".
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Reads a mesh file into a TriangleMesh (positions, triangles, optional normals
/// and colors). The core has no mesh readers of its own; the VTK converter in
/// vtkplugin/ provides one. Throws std::exception on failure.
using MeshLoader = std::function<TriangleMesh(const std::filesystem::path&)>;

struct LoadedScene {
  Scene scene;
  RenderSettings settings;  ///< From the file's "render" block, defaults otherwise.
};

/// Parses a scene file. Relative mesh paths are resolved against the scene's
/// folder. Unknown keys, wrong types, non-finite numbers and out-of-range values
/// are errors. Throws SceneError. The scene is not committed.
LoadedScene load_scene(const std::filesystem::path& path, const MeshLoader& mesh_loader);

/// Same, from text; `name` is used in error messages and `base_dir` for meshes.
LoadedScene parse_scene(const std::string& text, const std::string& name,
                        const std::filesystem::path& base_dir, const MeshLoader& mesh_loader);

}  // namespace rayscope
