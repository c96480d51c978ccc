// Datasets to the triangles the ray tracer intersects. The one conversion of
// RayScope's VTK side: the VTK module's vtkRayScopeMeshConverter and the
// rayscope command's mesh files (mesh_files.h) both call it, so a file gives
// the same triangles, normals and colors in both.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "vtkSmartPointer.h"

class vtkDataSet;
class vtkMapper;
class vtkPolyData;
class vtkUnsignedCharArray;

namespace rayscope {
struct TriangleMesh;
}

namespace rayscope_vtkio {

/// How the surface is made (vtkRayScopeMeshConverter documents each setting).
struct SurfaceOptions {
  /// Compute point normals (vtkPolyDataNormals) when the data has none.
  bool compute_normals = true;
  /// Split sharp edges whose dihedral angle exceeds feature_angle degrees.
  bool splitting = true;
  double feature_angle = 30.0;
  /// Tessellation level of non-linear cells (vtkDataSetSurfaceFilter).
  int nonlinear_subdivision_level = 1;
};

/// Where the colors of a conversion came from.
enum class ColorSource { None = 0, Point = 1, Cell = 2, Field = 3 };

/// The triangulated surface of `input` in `output` (replaced): points of the
/// input's precision (double stays double; anything else becomes float),
/// triangles only (its vertices and lines are line_conversion.h's), point data "Normals" (the
/// data's own or computed; absent without either), "Colors" (RGBA unsigned
/// char, sRGB as `coloring` maps the scalars, per point) and "LinearColors"
/// (float RGB). `coloring` (may be null: no colors) is not modified: a copy
/// of it, with a copy of its lookup table, maps the scalars with
/// vtkMapper::MapScalars(). Cell colors duplicate a point shared by cells of
/// different colors, once per color. Returns where the colors came from.
/// Throws std::invalid_argument (check_cell_point_ids()'s message, no file
/// name) when a cell names a point the data lacks, before any VTK filter runs.
ColorSource convert_dataset(vtkDataSet* input, const SurfaceOptions& options, vtkMapper* coloring,
                            vtkPolyData* output);

/// The colors `coloring` (may be null: none) gives `data`, as its
/// vtkMapper::MapScalars(data, 1.0, cell_flag) maps them, by a private copy
/// of the mapper and its lookup table (neither is modified): RGBA bytes per
/// point (cell_flag 0), per cell (1) or field tuple (2), or null.
vtkSmartPointer<vtkUnsignedCharArray> map_colors(vtkMapper* coloring, vtkPolyData* data,
                                                 int& cell_flag);

/// The union of the bounds of `data` (null entries and datasets without points
/// ignored), finite: a dataset with a NaN or infinite point, whose
/// vtkDataSet::GetBounds() are then not finite, counts with the finite range
/// of each coordinate of its points (vtkDataArray::GetFiniteRange), so that
/// the triangles the tracer keeps are framed. False when no point is finite.
bool finite_bounds(const std::vector<vtkDataSet*>& data, double bounds[6]);

/// The local origin (rayscope::Scene::origin) the rayscope command and the
/// VTK module trace `data` around (null entries and datasets without points
/// ignored): rayscope::choose_local_origin() of the center of their bounds,
/// in double precision, and of their diagonal (of their finite_bounds()). The
/// world's origin when there are no finite bounds.
glm::dvec3 local_origin(const std::vector<vtkDataSet*>& data);

/// A core mesh from polydata made by convert_dataset(): positions,
/// triangles, normals and linear colors. `to_scene` (e.g. the move to the
/// scene's local origin, rayscope::Scene::origin) is applied to the points in
/// double precision before they are rounded to float, and its inverse
/// transpose to the normals.
void mesh_from_converted(vtkPolyData* converted, rayscope::TriangleMesh& mesh,
                         const glm::dmat4& to_scene = glm::dmat4(1.0));

}  // namespace rayscope_vtkio
