// Mesh files for the rayscope command: read with VTK's readers and converted
// by the VTK module's conversion (mesh_conversion.h), so a file gives the
// triangles, normals and colors vtkRayScopeMeshConverter gives. load_mesh is
// the MeshLoader of scene files (rayscope/scene_io.h).
#pragma once

#include <array>
#include <filesystem>
#include <string_view>

#include <vtkSmartPointer.h>

#include "rayscope/scene.h"
#include "rayscope/scene_io.h"

class vtkDataSet;

namespace rayscope_vtkio {

/// The file extensions read_dataset_file() reads (lower case, with the dot).
inline constexpr std::array<std::string_view, 6> kDatasetFileExtensions = {".vtp", ".vtu", ".vtk",
                                                                           ".stl", ".ply", ".obj"};

/// Whether `path` has one of kDatasetFileExtensions, in any letter case.
bool has_dataset_file_extension(const std::filesystem::path& path);

/// Reads .vtp, .vtu, .vtk (legacy), .stl, .ply or .obj with VTK's readers,
/// after RayScope's checks of the file (mesh_checks.h), and checks the cells
/// of what VTK read (check_cell_point_ids()), so the dataset returned names
/// only points it has. Throws std::runtime_error "FILE: problem" for a
/// missing, unreadable, damaged or unsupported file. vtkRayScopeMeshReader is
/// this function as a VTK reader.
vtkSmartPointer<vtkDataSet> read_dataset_file(const std::filesystem::path& path);

/**
 * The mesh of a scene file's mesh object (a rayscope::MeshLoader): the file's
 * outer surface as triangles (polygons and strips triangulated, volumetric
 * cells reduced to their boundary faces), converted as vtkRayScopeMeshConverter
 * converts it with its default settings.
 *
 * - Normals (options.smooth): the file's point normals, else computed by
 *   vtkPolyDataNormals (edges sharper than SurfaceOptions::feature_angle
 *   split). Without smooth: none, flat shading.
 * - Colors: with options.color_by, the named point or cell array mapped
 *   through the color map over the range (the array's range by default; the
 *   magnitude of arrays with several components) by a vtkMapper with that
 *   lookup table; otherwise RGB(A) unsigned-char point scalars as they are.
 *
 * Throws rayscope::MeshOptionError ("color_by.array: problem") when color_by
 * names an array the file lacks, std::runtime_error "FILE: problem" for a file
 * it cannot read or that has no surface triangles.
 */
rayscope::TriangleMesh load_mesh(const rayscope::MeshOptions& options);
/// The same for `data` already read from options.file by read_dataset_file()
/// (e.g. to choose options.to_scene from its bounds first).
rayscope::TriangleMesh load_mesh_from(const rayscope::MeshOptions& options, vtkDataSet* data);

/// The file's triangles as stored: the same conversion without computing
/// normals (the file's own are kept) and with its RGB(A) unsigned-char point
/// colors. Throws as load_mesh().
rayscope::TriangleMesh read_mesh_file(const std::filesystem::path& path);

}  // namespace rayscope_vtkio
