// The line and vertex cells of a dataset, which VTK's mappers draw as lines
// and points, to what the ray tracer intersects: tubes (rayscope::TubeSet, a
// capsule per segment) and spheres (rayscope::PointSet), colored by the same
// mapper code as the surface (mesh_conversion.h). VTK's and ParaView's OSPRay
// ray tracing draws them the same way.
#pragma once

#include <string>

#include <glm/glm.hpp>

class vtkDataSet;
class vtkMapper;

namespace rayscope {
struct PointSet;
struct TubeSet;
}  // namespace rayscope

namespace rayscope_vtkio {

/// The automatic radius of tubes and spheres: this fraction of the diagonal of
/// what is rendered, times the line width or point size, as VTK's OSPRay pass
/// sizes them (a line width of 1 is a tube 1/500 of the diagonal across).
inline constexpr double kAutomaticRadiusFraction = 1e-3;

/// The automatic radius (at a line width or point size of 1) of what has
/// bounds of this diagonal: kAutomaticRadiusFraction of it, or 1 when the
/// diagonal is 0 (everything at one point: a sphere there that a camera can
/// frame, rather than nothing).
inline double automatic_radius(double diagonal) {
  return diagonal > 0.0 ? kAutomaticRadiusFraction * diagonal : 1.0;
}

/// How thick tubes and spheres are, in world units.
struct CurveRadii {
  double line = 1.0;   ///< Radius of the tube around line and polyline cells.
  double point = 1.0;  ///< Radius of the sphere at each vertex cell's points.
  /// A point array (one component) whose value at a point is the radius
  /// there, for tubes and spheres alike; empty: none. Values that are not
  /// finite and > 0 leave their segment or point out (the scene reports it).
  std::string array;
};

/// The line and polyline cells of `input` as `tubes` (a segment between each
/// pair of consecutive points of a cell; each cell with its own copy of its
/// points) and its vertex and polyvertex cells as `points` (one sphere per
/// point of a cell), replacing what they held. For datasets other than
/// polydata, these cells are those vtkDataSetSurfaceFilter passes through
/// (0-D and 1-D cells; a 1-D image's lines). Colors: as `coloring` (may be
/// null) maps the scalars (map_colors()), per point, or per cell (every point
/// of the cell its color), decoded to linear RGB; none without scalars.
/// `to_scene` moves the points to the scene's coordinates in double
/// precision, as mesh_from_converted(); radii are not scaled by it. Returns
/// whether the dataset has any such cell. Throws std::invalid_argument
/// (check_cell_point_ids()'s message) when a cell names a point the data
/// lacks, or when `radii.array` names no one-component point array.
bool convert_lines_and_points(vtkDataSet* input, vtkMapper* coloring, const CurveRadii& radii,
                              rayscope::TubeSet& tubes, rayscope::PointSet& points,
                              const glm::dmat4& to_scene = glm::dmat4(1.0));

}  // namespace rayscope_vtkio
