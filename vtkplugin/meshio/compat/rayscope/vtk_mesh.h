// Transitional: the former name and place of the VTK-side mesh loader, kept
// only for code not yet switched to "rayscope_vtk/mesh_files.h"
// (tests/test_scene_io.cpp and bench/). Remove this folder with the last of
// them.
#pragma once

#include "rayscope_vtk/mesh_files.h"

namespace rayscope {

/// read_mesh_file(path): rayscope_vtk::read_mesh_file (the file as stored);
/// as a scene's MeshLoader, load_scene(file, read_mesh_file):
/// rayscope_vtk::load_mesh.
struct ReadMeshFile {
  TriangleMesh operator()(const std::filesystem::path& path) const {
    return rayscope_vtk::read_mesh_file(path);
  }
  TriangleMesh operator()(const MeshOptions& options) const {
    return rayscope_vtk::load_mesh(options);
  }
};
inline constexpr ReadMeshFile read_mesh_file{};

}  // namespace rayscope
