// Small OBJ files written by the tests that read meshes (the core's scene
// reader, test_scene_io; VTK's readers, tests/vtk/test_vtk_mesh_files), the
// same text in both so that they read the same file.
#pragma once

namespace rstest {

/// A quad (two triangles once triangulated) and a triangle.
inline constexpr const char* kQuadObj = R"(# quad and triangle
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
f 1 2 3 4
f 1 2 5
)";

}  // namespace rstest
