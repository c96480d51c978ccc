#include "rayscope_vtkio/line_conversion.h"

#include <stdexcept>
#include <string>

#include <vtkCellArray.h>
#include <vtkCellType.h>
#include <vtkCellTypes.h>
#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkDataSetSurfaceFilter.h>
#include <vtkMapper.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>

#include "rayscope/image.h"
#include "rayscope/scene.h"
#include "rayscope_vtkio/mesh_checks.h"
#include "rayscope_vtkio/mesh_conversion.h"

namespace rayscope_vtkio {
namespace {

// Whether `input` has a vertex, polyvertex, line or polyline cell.
bool has_lines_or_points(vtkDataSet* input) {
  if (auto* pd = vtkPolyData::SafeDownCast(input))
    return pd->GetNumberOfVerts() > 0 || pd->GetNumberOfLines() > 0;
  if (input->GetNumberOfCells() == 0) return false;
  vtkNew<vtkCellTypes> types;
  input->GetCellTypes(types);
  for (vtkIdType i = 0; i < types->GetNumberOfTypes(); ++i) switch (types->GetCellType(i)) {
      case VTK_VERTEX:
      case VTK_POLY_VERTEX:
      case VTK_LINE:
      case VTK_POLY_LINE:
        return true;
      default:
        break;
    }
  return false;
}

}  // namespace

bool convert_lines_and_points(vtkDataSet* input, vtkMapper* coloring, const CurveRadii& radii,
                              rayscope::TubeSet& tubes, rayscope::PointSet& points,
                              const glm::dmat4& to_scene) {
  tubes.positions.clear();
  tubes.segments.clear();
  tubes.radii.clear();
  tubes.colors.clear();
  points.positions.clear();
  points.radii.clear();
  points.colors.clear();
  tubes.radius = float(radii.line);
  points.radius = float(radii.point);
  if (!input || !has_lines_or_points(input)) return false;
  if (std::string e = check_cell_point_ids(input); !e.empty()) throw std::invalid_argument(e);

  vtkSmartPointer<vtkPolyData> data = vtkPolyData::SafeDownCast(input);
  if (!data) {
    vtkNew<vtkDataSetSurfaceFilter> sf;
    sf->SetInputData(input);
    sf->Update();
    data = sf->GetOutput();
  }
  vtkDataArray* radius_array = nullptr;
  if (!radii.array.empty()) {
    radius_array = data->GetPointData()->GetArray(radii.array.c_str());
    if (!radius_array || radius_array->GetNumberOfComponents() != 1)
      throw std::invalid_argument("the radius array '" + radii.array +
                                  "' is not a point array of one component");
  }

  // Colors per point or per cell (polydata numbers its verts first, then its
  // lines); field data colors (one tuple for everything) as a cell color.
  int cell_flag = 0;
  vtkSmartPointer<vtkUnsignedCharArray> mapped = map_colors(coloring, data, cell_flag);
  if (mapped && mapped->GetNumberOfComponents() != 4) mapped = nullptr;
  const vtkIdType field_tuple = cell_flag == 2 && coloring ? coloring->GetFieldDataTupleId() : -1;
  const auto& table = rayscope::srgb_byte_table();
  auto color = [&](vtkIdType tuple) {
    return rayscope::Color(table[mapped->GetTypedComponent(tuple, 0)],
                           table[mapped->GetTypedComponent(tuple, 1)],
                           table[mapped->GetTypedComponent(tuple, 2)]);
  };
  // The color tuple of point `p` of cell `cell`, or -1 for none.
  auto tuple_of = [&](vtkIdType p, vtkIdType cell) -> vtkIdType {
    if (!mapped) return -1;
    const vtkIdType t = cell_flag == 0     ? p
                        : cell_flag == 1   ? cell
                        : field_tuple >= 0 ? field_tuple
                                           : cell;
    return t >= 0 && t < mapped->GetNumberOfTuples() ? t : -1;
  };
  const bool identity = to_scene == glm::dmat4(1.0);
  auto position = [&](vtkIdType p) {
    double x[3];
    data->GetPoint(p, x);
    const glm::dvec3 q = identity ? glm::dvec3(x[0], x[1], x[2])
                                  : glm::dvec3(to_scene * glm::dvec4(x[0], x[1], x[2], 1.0));
    return rayscope::Vec3(q);
  };
  bool colored = mapped != nullptr;

  const vtkIdType nverts = data->GetNumberOfVerts();
  const vtkIdType* ids = nullptr;
  vtkIdType n = 0;
  vtkCellArray* verts = data->GetVerts();
  for (vtkIdType c = 0; c < nverts; ++c) {
    verts->GetCellAtId(c, n, ids);
    for (vtkIdType k = 0; k < n; ++k) {
      points.positions.push_back(position(ids[k]));
      if (radius_array) points.radii.push_back(float(radius_array->GetComponent(ids[k], 0)));
      const vtkIdType t = tuple_of(ids[k], c);
      colored &= t >= 0;
      if (colored) points.colors.push_back(color(t));
    }
  }
  vtkCellArray* lines = data->GetLines();
  for (vtkIdType c = 0; c < data->GetNumberOfLines(); ++c) {
    lines->GetCellAtId(c, n, ids);
    const auto first = uint32_t(tubes.positions.size());
    for (vtkIdType k = 0; k < n; ++k) {
      tubes.positions.push_back(position(ids[k]));
      if (radius_array) tubes.radii.push_back(float(radius_array->GetComponent(ids[k], 0)));
      const vtkIdType t = tuple_of(ids[k], nverts + c);
      colored &= t >= 0;
      if (colored) tubes.colors.push_back(color(t));
      if (k > 0) tubes.segments.emplace_back(first + uint32_t(k - 1), first + uint32_t(k));
    }
  }
  // Colors for every point or none (a mapping that missed some gives none).
  if (!colored) {
    points.colors.clear();
    tubes.colors.clear();
  }
  return !points.positions.empty() || !tubes.segments.empty();
}

}  // namespace rayscope_vtkio
