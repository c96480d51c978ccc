// Reading mesh files with VTK's readers and converting VTK data to core meshes.
#pragma once

#include <filesystem>

#include "rayscope/scene.h"

class vtkDataSet;

namespace rayscope {

/// Reads .vtp, .vtu, .vtk (legacy), .stl, .ply or .obj with VTK's readers and
/// returns its outer surface as triangles (polygons and strips triangulated,
/// volumetric cells reduced to their boundary faces). Point normals and RGB(A)
/// unsigned-char point colors are kept when the file has them. Throws
/// std::runtime_error with "FILE: problem" for a missing, unreadable, empty or
/// unsupported file.
TriangleMesh read_mesh_file(const std::filesystem::path& path);

/// Converts any dataset to a triangle mesh (outer surface, triangulated).
TriangleMesh mesh_from_vtk(vtkDataSet* data, const std::string& name = "vtk");

}  // namespace rayscope
