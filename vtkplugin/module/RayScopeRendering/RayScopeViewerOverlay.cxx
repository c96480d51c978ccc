// vtkRayScopeViewer's 3D overlay: the picked pixel's ray tree (a line per
// ray in its kind's color, skipped rays gray, hit points, shading normals,
// the selected ray white, labels, where shadow rays are blocked), filtered by
// depth, ray and kind; and the structure the rays walk (vtkRayScopeAccelSource),
// by level or as the selected ray's walk played node by node.
#include <map>

#include "RayScopeArrays.h"
#include "vtkBoundingBox.h"
#include "vtkLabelPlacementMapper.h"
#include "vtkPointSetToLabelHierarchy.h"

#include "vtkRayScopeViewerInternals.h"

using namespace rayscope_vtkmodule::viewer;

namespace {

vtkSmartPointer<vtkThreshold> make_threshold(vtkAlgorithmOutput* input, const char* array) {
  auto t = vtkSmartPointer<vtkThreshold>::New();
  t->SetInputConnection(input);
  t->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, array);
  t->SetThresholdFunction(vtkThreshold::THRESHOLD_BETWEEN);
  t->SetLowerThreshold(-VTK_DOUBLE_MAX);
  t->SetUpperThreshold(VTK_DOUBLE_MAX);
  return t;
}

vtkSmartPointer<vtkLookupTable> make_table(int n, const double (*colors)[3]) {
  auto lut = vtkSmartPointer<vtkLookupTable>::New();
  lut->SetNumberOfTableValues(n);
  lut->SetTableRange(0, n - 1);
  for (int i = 0; i < n; ++i) lut->SetTableValue(i, colors[i][0], colors[i][1], colors[i][2], 1.0);
  lut->Build();
  return lut;
}

}  // namespace

// The overlay's pipelines and actors, in the 3D view.
void vtkRayScopeViewer::Internals::BuildOverlay() {
  // Ray tree: filtered by depth, ray and kind; traced rays in their kind's
  // color with hit points and normals, skipped rays gray.
  this->Tree->SetSceneSource(this->Algorithm);
  // KindName (strings) is left out: VTK 9.1's threshold and geometry filters
  // drop its values, and Kind says the same.
  this->NoStrings->SetInputConnection(this->Tree->GetOutputPort());
  this->NoStrings->RemoveArraysOn();
  this->NoStrings->AddCellDataArray("KindName");
  this->ByDepth = make_threshold(this->NoStrings->GetOutputPort(), "Depth");
  this->ByRay = make_threshold(this->ByDepth->GetOutputPort(), "RayId");
  this->ByKind = make_threshold(this->ByRay->GetOutputPort(), "Kind");
  this->Shown->SetInputConnection(this->ByKind->GetOutputPort());
  this->Traced = make_threshold(this->Shown->GetOutputPort(), "Skipped");
  this->Traced->SetLowerThreshold(0);
  this->Traced->SetUpperThreshold(0);
  this->Skipped = make_threshold(this->Shown->GetOutputPort(), "Skipped");
  this->Skipped->SetLowerThreshold(1);
  vtkNew<vtkDataSetMapper> traced_mapper;
  traced_mapper->SetInputConnection(this->Traced->GetOutputPort());
  double kinds[rayscope::kRayKindCount][3];
  for (int k = 0; k < rayscope::kRayKindCount; ++k)
    vtkRayScopeRayTreeSource::GetKindColor(k, kinds[k]);
  traced_mapper->SetLookupTable(make_table(rayscope::kRayKindCount, kinds));
  traced_mapper->SetScalarModeToUseCellFieldData();
  traced_mapper->SelectColorArray("Kind");
  traced_mapper->SetScalarRange(0, 3);
  this->TracedActor->SetMapper(traced_mapper);
  this->TracedActor->GetProperty()->SetLineWidth(2.5);
  this->TracedActor->GetProperty()->SetPointSize(9.0);
  this->TracedActor->GetProperty()->RenderPointsAsSpheresOn();
  // Unlit: the tree's point normals are those of hit points, 0 at other ends.
  this->TracedActor->GetProperty()->LightingOff();
  vtkNew<vtkDataSetMapper> skipped_mapper;
  skipped_mapper->SetInputConnection(this->Skipped->GetOutputPort());
  skipped_mapper->ScalarVisibilityOff();
  this->SkippedActor->SetMapper(skipped_mapper);
  this->SkippedActor->GetProperty()->SetColor(kSkippedColor[0], kSkippedColor[1], kSkippedColor[2]);
  this->SkippedActor->GetProperty()->SetLineWidth(1.5);
  this->SkippedActor->GetProperty()->LightingOff();
  this->Normals->SetInputConnection(this->Traced->GetOutputPort());
  this->Normals->SetVectorModeToUseNormal();
  vtkNew<vtkPolyDataMapper> normal_mapper;
  normal_mapper->SetInputConnection(this->Normals->GetOutputPort());
  normal_mapper->ScalarVisibilityOff();
  this->NormalActor->SetMapper(normal_mapper);
  this->NormalActor->GetProperty()->SetColor(kNormalColor[0], kNormalColor[1], kNormalColor[2]);
  this->NormalActor->GetProperty()->SetLineWidth(2.0);
  this->NormalActor->GetProperty()->LightingOff();
  // The selected ray, drawn over the others.
  this->Selected = make_threshold(this->Shown->GetOutputPort(), "RayId");
  vtkNew<vtkDataSetMapper> selected_mapper;
  selected_mapper->SetInputConnection(this->Selected->GetOutputPort());
  selected_mapper->ScalarVisibilityOff();
  this->SelectedActor->SetMapper(selected_mapper);
  this->SelectedActor->GetProperty()->SetColor(kSelectedColor[0], kSelectedColor[1],
                                               kSelectedColor[2]);
  this->SelectedActor->GetProperty()->SetLineWidth(6.0);
  this->SelectedActor->GetProperty()->SetPointSize(12.0);
  this->SelectedActor->GetProperty()->RenderPointsAsSpheresOn();
  this->SelectedActor->GetProperty()->LightingOff();
  for (vtkActor* a : {this->TracedActor.Get(), this->SkippedActor.Get(), this->NormalActor.Get(),
                      this->SelectedActor.Get()}) {
    a->VisibilityOff();
    a->PickableOff();
    this->SceneRen->AddActor(a);
  }
  // Occluders of shadow rays.
  vtkNew<vtkPolyDataMapper> occluder_mapper;
  occluder_mapper->SetInputData(this->Occluders);
  occluder_mapper->ScalarVisibilityOff();
  this->OccluderActor->SetMapper(occluder_mapper);
  this->OccluderActor->GetProperty()->SetColor(kOccluderColor[0], kOccluderColor[1],
                                               kOccluderColor[2]);
  this->OccluderActor->GetProperty()->SetPointSize(13.0);
  this->OccluderActor->GetProperty()->RenderPointsAsSpheresOn();
  // A marker of the overlay: unlit, not picked, hidden until there is
  // something to mark.
  auto add_marker = [&](vtkActor* a) {
    a->GetProperty()->LightingOff();
    a->PickableOff();
    a->VisibilityOff();
    this->SceneRen->AddActor(a);
  };
  add_marker(this->OccluderActor);
  // Text at points of the 3D view: each vertex of `points` labelled with
  // its point-data string `array` (the mapper's "field data" mode), hidden
  // until asked for.
  // Text at points of the 3D view: each vertex of `points` labelled with
  // its point-data string `array`, hidden until asked for. VTK's label
  // placement draws only the labels that do not overlap one already placed
  // (a label hierarchy, front to back), so that labels never pile up; the
  // others appear as the view zooms in (f).
  auto add_labels = [&](vtkPolyData* points, const char* array, int size, const double color[3],
                        vtkActor2D* actor) {
    vtkNew<vtkPointSetToLabelHierarchy> hierarchy;
    hierarchy->SetInputData(points);
    hierarchy->SetLabelArrayName(array);
    vtkTextProperty* text = hierarchy->GetTextProperty();
    text->SetFontSize(this->FontSize(size));
    text->SetColor(color[0], color[1], color[2]);
    text->ShadowOn();
    vtkNew<vtkLabelPlacementMapper> mapper;
    mapper->SetInputConnection(hierarchy->GetOutputPort());
    actor->SetMapper(mapper);
    actor->VisibilityOff();
    this->SceneRen->AddActor2D(actor);
    return text;
  };
  // Labels on demand: "#id dDEPTH wWEIGHT" at the middle of each shown ray.
  add_labels(this->Labels, "Label", 12, kSelectedColor, this->LabelActor);

  // BVH boxes: by level, or a played walk by state.
  this->BVH->SetSceneSource(this->Algorithm);
  // A grid's empty cells would fill its box with lines; the cells that hold
  // something show where the objects are.
  this->BVH->HideEmptyLeavesOn();
  // Levels from blue (the root) to red (the deepest), light enough to read
  // on the legend's black (pure blue is not).
  this->LevelTable = vtkSmartPointer<vtkLookupTable>::New();
  this->LevelTable->SetHueRange(0.62, 0.0);
  this->LevelTable->SetSaturationRange(0.7, 0.7);
  this->LevelTable->Build();
  this->WalkTable = make_table(6, kWalkColors);
  this->BVHMapper->SetInputData(this->NoBoxes);
  this->BVHMapper->SetScalarModeToUseCellFieldData();
  this->BVHActor->SetMapper(this->BVHMapper);
  this->BVHActor->GetProperty()->SetLineWidth(kWalkBoxWidth);
  this->BVHActor->GetProperty()->LightingOff();
  this->BVHActor->PickableOff();
  this->SceneRen->AddActor(this->BVHActor);
  // The played walk's order: the current node thick, in its state's color.
  vtkNew<vtkPolyDataMapper> current_mapper;
  current_mapper->SetInputData(this->WalkCurrent);
  current_mapper->SetScalarModeToUseCellFieldData();
  current_mapper->SetLookupTable(this->WalkTable);
  current_mapper->SelectColorArray("TraversalState");
  current_mapper->SetScalarRange(0, 5);
  this->WalkCurrentActor->SetMapper(current_mapper);
  this->WalkCurrentActor->GetProperty()->SetLineWidth(kWalkCurrentWidth);
  add_marker(this->WalkCurrentActor);
  add_labels(this->WalkSteps, "Step", 16, kWalkColors[3], this->WalkStepActor)->BoldOn();
  // The packet's nodes: red where one ray was active, through yellow to
  // cyan where the whole packet walked together.
  this->PacketTable = vtkSmartPointer<vtkLookupTable>::New();
  this->PacketTable->SetNumberOfTableValues(rayscope::kPacketRays);
  this->PacketTable->SetHueRange(0.0, 0.5);
  this->PacketTable->SetSaturationRange(0.8, 0.8);
  this->PacketTable->Build();
  vtkNew<vtkPolyDataMapper> packet_mapper;
  packet_mapper->SetInputData(this->PacketBoxes);
  packet_mapper->SetScalarModeToUseCellFieldData();
  packet_mapper->SetLookupTable(this->PacketTable);
  packet_mapper->SelectColorArray("ActiveRays");
  packet_mapper->SetScalarRange(1, rayscope::kPacketRays);
  this->PacketBoxActor->SetMapper(packet_mapper);
  this->PacketBoxActor->GetProperty()->SetLineWidth(kWalkBoxWidth);
  add_marker(this->PacketBoxActor);
}

// A line cell per box edge, with the rays active in the box's node as cell
// data "ActiveRays" and its step as "Step" (1 for the root).
void vtkRayScopeViewer::Internals::UpdatePacketBoxes() {
  this->PacketBoxes->Initialize();
  const bool shown = this->Self->ShowPacket && this->HasRecord && !this->Packet.boxes.empty();
  this->PacketBoxActor->SetVisibility(shown);
  this->Changed |= kSceneView;
  if (!shown) return;
  const rayscope::Scene& s = *this->scene();
  const size_t n = this->Packet.boxes.size();
  const vtkSmartPointer<vtkPoints> pts = rayscope_vtkmodule::make_world_points(s, vtkIdType(8 * n));
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkIntArray> active, step;
  active->SetName("ActiveRays");
  step->SetName("Step");
  for (size_t i = 0; i < n; ++i) {
    const rayscope::Bounds3& b = this->Packet.boxes[i];
    const vtkIdType p0 = vtkIdType(8 * i);
    for (int c = 0; c < 8; ++c)
      rayscope_vtkmodule::set_world_point(
          pts, p0 + c, s,
          rayscope::Vec3((c & 1) ? b.hi.x : b.lo.x, (c & 2) ? b.hi.y : b.lo.y,
                         (c & 4) ? b.hi.z : b.lo.z));
    for (const auto& e : rayscope_vtkmodule::kBoxEdges) {
      const vtkIdType ends[2] = {p0 + e[0], p0 + e[1]};
      lines->InsertNextCell(2, ends);
      active->InsertNextValue(__builtin_popcount(this->Packet.steps[i].lanes));
      step->InsertNextValue(int(i) + 1);
    }
  }
  this->PacketBoxes->SetPoints(pts);
  this->PacketBoxes->SetLines(lines);
  this->PacketBoxes->GetCellData()->AddArray(active);
  this->PacketBoxes->GetCellData()->AddArray(step);
}

void vtkRayScopeViewer::Internals::UpdateWalkOrder(bool played) {
  this->WalkCurrentActor->SetVisibility(played);
  this->WalkStepActor->SetVisibility(played);
  if (!played) {
    this->WalkSteps->Initialize();
    this->WalkCurrent->Initialize();
    return;
  }
  // A box is 12 line cells (faces: 6 quads) sharing its EntryOrder: the step
  // number goes on its top left corner (largest y, smallest x: above the
  // scene's floor, where nested boxes' corners stand apart); the cells of the
  // node entered last (EntryOrder steps - 1) are copied into WalkCurrent.
  vtkPolyData* boxes = this->BVH->GetOutput();
  vtkDataArray* order = boxes->GetCellData()->GetArray("EntryOrder");
  vtkDataArray* state = boxes->GetCellData()->GetArray("TraversalState");
  const int current = this->Self->TraversalSteps - 1;
  vtkNew<vtkPoints> current_points;
  vtkNew<vtkCellArray> current_lines;
  vtkNew<vtkIntArray> current_state;
  current_state->SetName("TraversalState");
  std::map<int, vtkBoundingBox> entered;
  for (vtkIdType c = 0; order && state && c < boxes->GetNumberOfCells(); ++c) {
    const int k = int(order->GetTuple1(c));
    if (k < 0) continue;
    vtkCell* cell = boxes->GetCell(c);
    vtkBoundingBox& box = entered[k];
    for (vtkIdType p = 0; p < cell->GetNumberOfPoints(); ++p)
      box.AddPoint(boxes->GetPoint(cell->GetPointId(p)));
    if (k != current) continue;
    current_lines->InsertNextCell(cell->GetNumberOfPoints());
    for (vtkIdType p = 0; p < cell->GetNumberOfPoints(); ++p)
      current_lines->InsertCellPoint(
          current_points->InsertNextPoint(boxes->GetPoint(cell->GetPointId(p))));
    current_state->InsertNextValue(int(state->GetTuple1(c)));
  }
  vtkNew<vtkPoints> step_points;
  vtkNew<vtkCellArray> step_verts;
  vtkNew<vtkStringArray> steps;
  steps->SetName("Step");
  // Nested boxes that share that corner share one label: "2, 3".
  std::map<std::array<double, 3>, std::string> corners;
  for (const auto& [k, box] : entered) {
    std::string& text = corners[{box.GetMinPoint()[0], box.GetMaxPoint()[1], box.GetMaxPoint()[2]}];
    text += (text.empty() ? "" : ", ") + std::to_string(k + 1);
  }
  for (const auto& [corner, text] : corners) {
    const vtkIdType v = step_points->InsertNextPoint(corner.data());
    step_verts->InsertNextCell(1, &v);
    steps->InsertNextValue(text);
  }
  this->WalkSteps->Initialize();
  this->WalkSteps->SetPoints(step_points);
  this->WalkSteps->SetVerts(step_verts);
  this->WalkSteps->GetPointData()->AddArray(steps);
  this->WalkCurrent->Initialize();
  this->WalkCurrent->SetPoints(current_points);
  this->WalkCurrent->SetLines(current_lines);
  this->WalkCurrent->GetCellData()->AddArray(current_state);
}

// Records the picked pixel (its tree and the inspect text) and shows what
// the viewer's settings select of it: the rays, their labels and occluders,
// the marker in the image, the structure, the panel.
void vtkRayScopeViewer::Internals::UpdateOverlay() {
  vtkRayScopeViewer* self = this->Self;
  const int i = self->PickedPixel[0], j = self->PickedPixel[1];
  const rayscope::Scene& s = *this->scene();
  // A tree shown whole stays whole when it is recorded again deeper (a
  // re-render after ]): the new depths are shown too.
  const bool whole = !this->HasRecord || self->ShownDepth >= this->RecordDepth;
  try {
    this->Record = rayscope::record_pixel(s, this->Settings, i, this->Settings.height - 1 - j);
  } catch (const std::exception& e) {
    this->Say(std::string("recording the pixel failed: ") + e.what());
    return;
  }
  this->HasRecord = true;
  this->RecordDepth = 0;
  for (const rayscope::RayRecord& r : this->Record.rays)
    this->RecordDepth = std::max(this->RecordDepth, r.depth);
  self->ShownDepth = whole ? this->RecordDepth : std::min(self->ShownDepth, this->RecordDepth);
  if (self->SelectedRay >= int(this->Record.rays.size())) self->SelectedRay = -1;
  this->InspectText = rayscope::format_text(this->Record, s);
  if (self->ShowPacket) {
    this->Packet = rayscope::record_packet(s, this->Settings, i, this->Settings.height - 1 - j);
    this->PacketText = rayscope::format_packet_text(this->Packet, s);
  }
  this->UpdatePacketBoxes();

  this->Tree->SetPixel(i, j);
  this->ByDepth->SetUpperThreshold(self->ShownDepth);
  this->ByRay->SetUpperThreshold(self->SelectedRay < 0 ? VTK_DOUBLE_MAX : self->SelectedRay);
  this->ByKind->SetLowerThreshold(self->ShownKind < 0 ? -VTK_DOUBLE_MAX : self->ShownKind);
  this->ByKind->SetUpperThreshold(self->ShownKind < 0 ? VTK_DOUBLE_MAX : self->ShownKind);
  this->Shown->Update();
  for (vtkActor* a : {this->TracedActor.Get(), this->SkippedActor.Get(), this->NormalActor.Get()})
    a->VisibilityOn();
  this->Selected->SetLowerThreshold(self->SelectedRay);
  this->Selected->SetUpperThreshold(self->SelectedRay);
  this->SelectedActor->SetVisibility(self->SelectedRay >= 0);
  this->UpdateLabels();
  this->UpdateOccluders();
  this->UpdateMarker();
  this->UpdateBVH();
  this->UpdatePanel();
  this->Changed |= kSceneView | kPanelView | kImageView;  // the tree, its text, the marker
}

// A marker where each shown shadow ray is blocked: the end of its line, on
// the nearest occluder (the ray-tree source's EndKind 3).
void vtkRayScopeViewer::Internals::UpdateOccluders() {
  vtkPolyData* shown = this->Shown->GetOutput();
  vtkDataArray* end = shown->GetCellData()->GetArray("EndKind");
  vtkNew<vtkPoints> pts;
  vtkNew<vtkCellArray> verts;
  for (vtkIdType c = 0; end && c < shown->GetNumberOfCells(); ++c) {
    if (shown->GetCellType(c) != VTK_LINE || int(end->GetTuple1(c)) != kEndOccluder) continue;
    const vtkIdType k = pts->InsertNextPoint(shown->GetPoint(shown->GetCell(c)->GetPointId(1)));
    verts->InsertNextCell(1, &k);
  }
  this->Occluders->Initialize();
  this->Occluders->SetPoints(pts);
  this->Occluders->SetVerts(verts);
  this->OccluderActor->VisibilityOn();
}

// A label per shown ray (line cell): its id, depth and weight, at its middle.
void vtkRayScopeViewer::Internals::UpdateLabels() {
  this->LabelActor->SetVisibility(this->Self->ShowLabels);
  vtkPolyData* shown = this->Shown->GetOutput();
  vtkDataArray* id = shown->GetCellData()->GetArray("RayId");
  vtkDataArray* depth = shown->GetCellData()->GetArray("Depth");
  vtkDataArray* weight = shown->GetCellData()->GetArray("Weight");
  vtkNew<vtkPoints> pts;
  vtkNew<vtkStringArray> text;
  text->SetName("Label");
  vtkNew<vtkCellArray> verts;
  for (vtkIdType c = 0; id && depth && weight && c < shown->GetNumberOfCells(); ++c) {
    if (shown->GetCellType(c) != VTK_LINE) continue;
    double a[3], b[3];
    shown->GetPoint(shown->GetCell(c)->GetPointId(0), a);
    shown->GetPoint(shown->GetCell(c)->GetPointId(1), b);
    const vtkIdType k =
        pts->InsertNextPoint(0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2]));
    verts->InsertNextCell(1, &k);
    const double* w = weight->GetTuple3(c);
    char label[64];
    std::snprintf(label, sizeof label, "#%d d%d w%.3g", int(id->GetTuple1(c)),
                  int(depth->GetTuple1(c)), std::max({w[0], w[1], w[2]}));
    text->InsertNextValue(label);
  }
  this->Labels->Initialize();
  this->Labels->SetPoints(pts);
  this->Labels->SetVerts(verts);
  this->Labels->GetPointData()->AddArray(text);
}

// The BVH shown: the selected ray's walk, or the boxes of a level (all
// levels), or nothing.
void vtkRayScopeViewer::Internals::UpdateBVH() {
  vtkRayScopeViewer* self = this->Self;
  const int i = self->PickedPixel[0], j = self->PickedPixel[1];
  vtkRayScopeAccelSource* bvh = this->BVH;
  if (self->PickedPixel[0] >= 0 && self->TraversalSteps >= 0 && self->SelectedRay >= 0) {
    bvh->SetVisitModeToPixel();
    bvh->SetPixel(i, j);
    bvh->SetVisitRay(self->SelectedRay);
    bvh->SetTraversalSteps(self->TraversalSteps);
    bvh->SetLevelRange(0, VTK_INT_MAX);
    bvh->Update();
    this->BVHMapper->SetInputConnection(bvh->GetOutputPort());
    this->BVHMapper->SetLookupTable(this->WalkTable);
    this->BVHMapper->SelectColorArray("TraversalState");
    this->BVHMapper->SetScalarRange(0, 5);
    this->BVHMapper->ScalarVisibilityOn();
    this->UpdateWalkOrder(true);
  } else if (self->ShowBVH) {
    this->UpdateWalkOrder(false);
    // A BSP tree as its split planes: the boxes around its cells overlap
    // one another in a tangle.
    bvh->SetOnlySplitPlanes(this->StructureLabel() == "bsp");
    bvh->SetVisitModeToNone();
    bvh->SetTraversalSteps(-1);
    if (self->BVHLevel < 0)
      bvh->SetLevelRange(0, VTK_INT_MAX);
    else
      bvh->SetLevelRange(self->BVHLevel, self->BVHLevel);
    bvh->Update();
    this->BVHMapper->SetInputConnection(bvh->GetOutputPort());
    this->BVHMapper->SetLookupTable(this->LevelTable);
    this->BVHMapper->SelectColorArray("Level");
    vtkDataArray* depth = bvh->GetOutput()->GetFieldData()->GetArray("TreeDepth");
    this->BVHMapper->SetScalarRange(0, depth ? std::max(1.0, depth->GetTuple1(0) - 1) : 1.0);
    this->BVHMapper->ScalarVisibilityOn();
  } else {
    this->UpdateWalkOrder(false);
    this->BVHMapper->SetInputData(this->NoBoxes);
  }
  this->Changed |= kSceneView;
}

void vtkRayScopeViewer::Internals::ClearOverlay() {
  this->HasRecord = false;
  this->InspectText.clear();
  const std::initializer_list<vtkProp*> shown = {
      this->TracedActor.Get(),   this->SkippedActor.Get(),     this->NormalActor.Get(),
      this->SelectedActor.Get(), this->LabelActor.Get(),       this->OccluderActor.Get(),
      this->MarkerActor.Get(),   this->WalkCurrentActor.Get(), this->WalkStepActor.Get(),
      this->PacketBoxActor.Get()};
  for (vtkProp* a : shown) a->VisibilityOff();
  this->BVHMapper->SetInputData(this->NoBoxes);
  this->UpdateTreeDiagram();
  this->ShowPanelLines({kPickPrompt});
  this->Changed |= kAllViews;
}
