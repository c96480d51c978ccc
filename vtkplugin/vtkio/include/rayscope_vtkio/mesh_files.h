// Mesh files for the rayscope command: read with VTK's readers and converted
// by the VTK module's conversion (mesh_conversion.h), so a file gives the
// triangles, normals and colors vtkRayScopeMeshConverter gives. load_meshes is
// the MeshLoader of scene files (rayscope/scene_io.h).
#pragma once

#include <array>
#include <filesystem>
#include <string_view>

#include <vtkSmartPointer.h>

#include "rayscope/scene.h"
#include "rayscope/scene_io.h"

class vtkDataObject;
class vtkDataSet;

namespace rayscope_vtkio {

/// A mesh file format, by its extension.
struct MeshFileFormat {
  std::string_view extension;  ///< Lower case, with the dot.
  /// A composite file: several datasets (blocks, partitions, element blocks),
  /// each its own scene object. Otherwise one dataset; a parallel file's
  /// pieces (.pvtp .pvtu .pvti) are joined into one by VTK's reader.
  bool composite;
};

/// Every mesh file format the rayscope command reads, in the order its help
/// and messages list them.
inline constexpr std::array<MeshFileFormat, 15> kMeshFileFormats = {{
    {".obj", false},
    {".stl", false},
    {".ply", false},
    {".vtp", false},
    {".vtu", false},
    {".vti", false},
    {".vtk", false},
    {".pvtp", false},
    {".pvtu", false},
    {".pvti", false},
    {".vtm", true},
    {".vtpc", true},
    {".ex2", true},
    {".exo", true},
    {".e", true},
}};

/// Whether `path` has the extension of a format of one dataset in
/// kMeshFileFormats (what read_dataset_file() reads), in any letter case.
bool has_dataset_file_extension(const std::filesystem::path& path);

/// The extensions of kMeshFileFormats, all of them or those of one dataset
/// only, as text: ".obj .stl ... .e".
std::string mesh_file_extensions(bool composite_too = true);

/// Reads a file of one dataset (the formats of kMeshFileFormats that are not
/// composite) with VTK's reader of its format, after RayScope's checks of the
/// file (mesh_checks.h; for a parallel file, of every piece it names too,
/// each also read on its own first: VTK's parallel reader joins a piece its
/// serial reader failed on), and
/// checks the cells of what VTK read (check_cell_point_ids()), so the dataset
/// returned names only points it has. Throws std::runtime_error "FILE:
/// problem" for a missing, unreadable, damaged or unsupported file (a
/// composite one too). vtkRayScopeMeshReader is this function as a VTK reader.
vtkSmartPointer<vtkDataSet> read_dataset_file(const std::filesystem::path& path);

/// Reads a file of any format of kMeshFileFormats: a dataset as
/// read_dataset_file() reads it, or a composite file (.vtm, .vtpc: after the
/// checks of the file and of every block file it names; Exodus II: after
/// check_exodus_file(), every element block at the first time step) as a
/// composite dataset whose every leaf dataset (dataset_leaves()) has passed
/// check_cell_point_ids(). Throws as read_dataset_file(), naming the block of
/// a leaf that fails.
vtkSmartPointer<vtkDataObject> read_mesh_data_file(const std::filesystem::path& path);

/**
 * The meshes of a scene file's mesh object (a rayscope::MeshLoader): for each
 * dataset of the file (one, or each leaf of a composite file, as
 * dataset_leaves() lists them), its outer surface as triangles (polygons and
 * strips triangulated, volumetric cells and images reduced to their boundary
 * faces), converted as vtkRayScopeMeshConverter converts it with its default
 * settings, in its own mesh. A leaf's mesh is named "block N" (its flat
 * index) or "block N (NAME)" (its name in the file); a dataset alone's has no
 * name.
 *
 * - Normals (options.smooth): the file's point normals, else computed by
 *   vtkPolyDataNormals (edges sharper than SurfaceOptions::feature_angle
 *   split). Without smooth: none, flat shading.
 * - Colors: with options.color_by, the named point or cell array mapped
 *   through the color map over the range (by default the array's range over
 *   every dataset that has it; the magnitude of arrays with several
 *   components) by a vtkMapper with that lookup table, one for every leaf;
 *   otherwise RGB(A) unsigned-char point scalars as they are.
 *
 * - Lines and vertices: each dataset's line and polyline cells as tubes and
 *   its vertex and polyvertex cells as spheres (convert_lines_and_points(),
 *   colored as its surface), sets named "lines" and "vertices" ("block N
 *   lines" for a leaf). Radii: options.line_radius and point_radius, else
 *   kAutomaticRadiusFraction of the diagonal of the file's bounds in the
 *   scene; options.radius_array, when given, per point.
 *
 * A leaf without surface triangles, lines or vertices, a leaf lacking the
 * color_by array (drawn in the material's color) and a block that is not a
 * dataset are left out with a warning naming the block. Throws
 * rayscope::MeshOptionError ("color_by.array: problem", "radius_array:
 * problem") when color_by names an array no dataset of the file has or a
 * dataset with lines or vertices lacks the radius array, std::runtime_error
 * "FILE: problem" for a file it cannot read, with non-finite points on its
 * triangles, lines or vertices, or with nothing to draw at all.
 */
rayscope::LoadedMeshFile load_meshes(const rayscope::MeshOptions& options);
/// The same for `data` already read from options.file by
/// read_mesh_data_file() (e.g. to choose options.to_scene from its bounds
/// first).
rayscope::LoadedMeshFile load_meshes_from(const rayscope::MeshOptions& options,
                                          vtkDataObject* data);

/// The mesh of a file of one dataset, as load_meshes() makes it, named after
/// the file. Throws as load_meshes(), for a composite file, and for a file
/// of lines or vertices only.
rayscope::TriangleMesh load_mesh(const rayscope::MeshOptions& options);

/// The file's triangles as stored: the same conversion without computing
/// normals (the file's own are kept) and with its RGB(A) unsigned-char point
/// colors. Throws as load_mesh().
rayscope::TriangleMesh read_mesh_file(const std::filesystem::path& path);

}  // namespace rayscope_vtkio
