// vtkRayScopeViewer's tree diagram (key g): the picked pixel's ray tree drawn
// as a tree in the panel below the image, one dot per ray, each below its
// parent, joined to it by a line in the child's kind color; the rays the
// 3D view hides (deeper than the shown depth, after the selected ray, of
// another kind) dimmed, the selected ray white, every ray named "#id" while
// the tree is small enough to read.
#include "vtkActor2D.h"
#include "vtkLabeledDataMapper.h"
#include "vtkPolyDataMapper2D.h"
#include "vtkProperty2D.h"
#include "vtkRayScopeViewerInternals.h"

using namespace rayscope_vtkmodule::viewer;

namespace {

// Tidy layout of a forest of rays (one tree per sample): leaves one column
// apart in trace order, a parent centered over its first and last child;
// x in columns, from 0.
std::vector<double> tree_columns(const std::vector<rayscope::RayRecord>& rays, int& columns) {
  const size_t n = rays.size();
  std::vector<std::vector<int>> children(n);
  std::vector<int> roots;
  for (size_t i = 0; i < n; ++i) {
    const int p = rays[i].parent;
    if (p >= 0 && size_t(p) < n)
      children[size_t(p)].push_back(int(i));
    else
      roots.push_back(int(i));
  }
  std::vector<double> x(n, 0.0);
  columns = 0;
  // Post order, with an explicit stack: each ray's column after its
  // children's.
  std::vector<std::pair<int, size_t>> stack;
  for (int root : roots) {
    stack.push_back({root, 0});
    while (!stack.empty()) {
      auto& [ray, next] = stack.back();
      const std::vector<int>& c = children[size_t(ray)];
      if (next < c.size()) {
        const int child = c[next++];
        stack.push_back({child, 0});
        continue;
      }
      x[size_t(ray)] =
          c.empty() ? double(columns++) : 0.5 * (x[size_t(c.front())] + x[size_t(c.back())]);
      stack.pop_back();
    }
  }
  return x;
}

}  // namespace

void vtkRayScopeViewer::Internals::BuildTreeDiagram() {
  vtkNew<vtkPolyDataMapper2D> mapper;
  mapper->SetInputData(this->Diagram);
  mapper->SetScalarModeToUseCellData();
  mapper->SetColorModeToDirectScalars();
  this->DiagramActor->SetMapper(mapper);
  this->DiagramActor->GetProperty()->SetPointSize(float(this->FontSize(9)));
  this->DiagramActor->GetProperty()->SetLineWidth(2.0f);
  this->DiagramActor->VisibilityOff();
  this->PanelRen->AddActor2D(this->DiagramActor);
  vtkNew<vtkLabeledDataMapper> labels;
  labels->SetInputData(this->DiagramLabels);
  labels->SetLabelModeToLabelFieldData();
  labels->SetFieldDataName("Label");
  labels->CoordinateSystemDisplay();
  labels->GetLabelTextProperty()->SetFontSize(this->FontSize(11));
  labels->GetLabelTextProperty()->SetColor(0.85, 0.85, 0.85);
  labels->GetLabelTextProperty()->SetJustificationToCentered();
  labels->GetLabelTextProperty()->SetVerticalJustificationToBottom();
  this->DiagramLabelActor->SetMapper(labels);
  this->DiagramLabelActor->VisibilityOff();
  this->PanelRen->AddActor2D(this->DiagramLabelActor);
}

void vtkRayScopeViewer::Internals::UpdateTreeDiagram() {
  const bool shown = this->Self->ShowTreeDiagram && this->HasRecord;
  this->DiagramActor->SetVisibility(shown);
  this->DiagramLabelActor->SetVisibility(shown);
  this->Diagram->Initialize();
  this->DiagramLabels->Initialize();
  this->Changed |= kPanelView;
  if (!shown) return;
  const std::vector<rayscope::RayRecord>& rays = this->Record.rays;
  int columns = 0;
  const std::vector<double> column = tree_columns(rays, columns);
  // The panel's pixels below its first line (the diagram's title), with a
  // margin for the dots and the labels above them.
  const int* size = this->PanelRen->GetSize();
  const int* origin = this->PanelRen->GetOrigin();
  const double margin = this->FontSize(12);
  const double left = margin, right = size[0] - margin;
  const double top = size[1] - 2.5 * this->PanelLineHeight - margin, bottom = margin;
  vtkNew<vtkPoints> pts;
  vtkNew<vtkCellArray> verts, lines;
  vtkNew<vtkUnsignedCharArray> colors;
  colors->SetName("Colors");
  colors->SetNumberOfComponents(3);
  vtkNew<vtkIntArray> ray_ids;
  ray_ids->SetName("RayId");
  vtkNew<vtkPoints> label_pts;
  vtkNew<vtkCellArray> label_verts;
  vtkNew<vtkStringArray> label_text;
  label_text->SetName("Label");
  const bool named = rays.size() <= size_t(kDiagramMostLabels);
  const vtkRayScopeViewer* self = this->Self;
  // The color of a ray's dot and of the line to it.
  auto color = [&](const rayscope::RayRecord& r, unsigned char rgb[3]) {
    double c[3];
    if (r.id == self->SelectedRay) {
      std::copy_n(kSelectedColor, 3, c);
    } else if (r.skipped) {
      std::copy_n(kSkippedColor, 3, c);
    } else {
      vtkRayScopeRayTreeSource::GetKindColor(int(r.kind), c);
    }
    const bool hidden = r.depth > self->ShownDepth ||
                        (self->SelectedRay >= 0 && r.id > self->SelectedRay) ||
                        (self->ShownKind >= 0 && int(r.kind) != self->ShownKind);
    for (int k = 0; k < 3; ++k)
      rgb[k] = static_cast<unsigned char>(std::lround(255.0 * c[k] * (hidden ? kDiagramDim : 1.0)));
  };
  for (size_t i = 0; i < rays.size(); ++i) {
    const double x = left + (column[i] + 0.5) / std::max(1, columns) * (right - left);
    const double y = this->RecordDepth > 0
                         ? top - double(rays[i].depth) / this->RecordDepth * (top - bottom)
                         : 0.5 * (top + bottom);
    pts->InsertNextPoint(x, y, 0.0);
    if (named) {
      const vtkIdType v =
          label_pts->InsertNextPoint(origin[0] + x, origin[1] + y + 0.6 * margin, 0.0);
      label_verts->InsertNextCell(1, &v);
      std::string name = "#";  // (appended: GCC 12 warns falsely on "#" + ..., -Wrestrict)
      name += std::to_string(rays[i].id);
      label_text->InsertNextValue(name);
    }
  }
  // A dot per ray, then a line from each ray's parent to it: the cell data
  // follows VTK's order of cells, vertices before lines.
  auto add_cell_data = [&](const rayscope::RayRecord& r) {
    unsigned char rgb[3];
    color(r, rgb);
    colors->InsertNextTypedTuple(rgb);
    ray_ids->InsertNextValue(r.id);
  };
  for (size_t i = 0; i < rays.size(); ++i) {
    const vtkIdType v = vtkIdType(i);
    verts->InsertNextCell(1, &v);
    add_cell_data(rays[i]);
  }
  for (size_t i = 0; i < rays.size(); ++i) {
    const int p = rays[i].parent;
    if (p < 0 || size_t(p) >= rays.size()) continue;
    const vtkIdType ends[2] = {vtkIdType(p), vtkIdType(i)};
    lines->InsertNextCell(2, ends);
    add_cell_data(rays[i]);
  }
  this->Diagram->SetPoints(pts);
  this->Diagram->SetVerts(verts);
  this->Diagram->SetLines(lines);
  this->Diagram->GetCellData()->SetScalars(colors);
  this->Diagram->GetCellData()->AddArray(ray_ids);
  this->DiagramLabels->SetPoints(label_pts);
  this->DiagramLabels->SetVerts(label_verts);
  this->DiagramLabels->GetPointData()->AddArray(label_text);
}
