#include "vtkRayScopeViewerInternals.h"

using namespace rayscope_vtk::viewer;

vtkStandardNewMacro(vtkRayScopeViewer);

vtkRayScopeViewer::vtkRayScopeViewer()
    : PickedPixel{-1, -1},
      ShownDepth(0),
      SelectedRay(-1),
      ShownKind(-1),
      TraversalSteps(-1),
      ShowBVH(false),
      BVHLevel(-1),
      ImageMode(COLOR),
      ShowLabels(false),
      LastRenderSeconds(0.0),
      OutputPrefix(nullptr),
      WindowSize{1400, 820},
      Internal(new Internals(this)) {
  this->SetOutputPrefix("rayscope_view");
  this->Internal->Algorithm = vtkSmartPointer<vtkRayScopeImageAlgorithm>::New();
}

vtkRayScopeViewer::~vtkRayScopeViewer() {
  delete this->Internal;
  this->SetOutputPrefix(nullptr);
}

void vtkRayScopeViewer::SetSceneSource(vtkRayScopeImageAlgorithm* source) {
  if (!source || source == this->Internal->Algorithm) return;
  if (this->Internal->Worker.joinable()) this->WaitForRender();
  this->Internal->Algorithm = source;
  this->Modified();
}

vtkRayScopeImageAlgorithm* vtkRayScopeViewer::GetSceneSource() {
  return this->Internal->Algorithm;
}
vtkRenderWindow* vtkRayScopeViewer::GetRenderWindow() {
  return this->Internal->Window;
}
vtkRenderWindowInteractor* vtkRayScopeViewer::GetInteractor() {
  return this->Internal->Interactor;
}
vtkRenderer* vtkRayScopeViewer::GetImageRenderer() {
  return this->Internal->ImageRen;
}
vtkRenderer* vtkRayScopeViewer::GetSceneRenderer() {
  return this->Internal->SceneRen;
}
vtkRenderer* vtkRayScopeViewer::GetTextRenderer() {
  return this->Internal->PanelRen;
}
vtkRayScopeRayTreeSource* vtkRayScopeViewer::GetRayTreeSource() {
  return this->Internal->Tree;
}
vtkRayScopeAccelSource* vtkRayScopeViewer::GetAccelSource() {
  return this->Internal->BVH;
}
vtkRayScopeAccelSource* vtkRayScopeViewer::GetBVHSource() {
  vtkWarningMacro(<< "GetBVHSource() is deprecated and will be removed in the next release: use "
                     "GetAccelSource()");
  return this->GetAccelSource();
}
const char* vtkRayScopeViewer::GetInspectText() {
  return this->Internal->InspectText.c_str();
}
const char* vtkRayScopeViewer::GetPanelText() {
  return this->Internal->PanelText.c_str();
}
const char* vtkRayScopeViewer::GetMessage() {
  return this->Internal->Message.c_str();
}
const char* vtkRayScopeViewer::GetHelpText() {
  return kHelp;
}
bool vtkRayScopeViewer::IsRendering() {
  return this->Internal->Worker.joinable();
}

vtkImageData* vtkRayScopeViewer::GetShownImage() {
  return this->Internal->Display;
}

vtkImageData* vtkRayScopeViewer::GetLastImage() {
  return this->Internal->Image;
}

vtkPolyData* vtkRayScopeViewer::GetShownRays() {
  return this->Internal->Shown->GetOutput();
}

vtkPolyData* vtkRayScopeViewer::GetOccluderMarkers() {
  return this->Internal->Occluders;
}

vtkPolyData* vtkRayScopeViewer::GetRayLabels() {
  return this->Internal->Labels;
}

vtkPolyData* vtkRayScopeViewer::GetShownBVH() {
  return vtkPolyData::SafeDownCast(this->Internal->BVHMapper->GetInput());
}

// --- Rendering ------------------------------------------------------------------

// The frame loop's statistics policy (cost AOVs for the heat map) that also
// writes each finished tile into the next image, on the thread that rendered
// it, and hands the tile over to be shown.
struct vtkRayScopeViewer::Internals::Policy : rayscope::StatsPolicy {
  Internals* in;
  explicit Policy(Internals* internals) : in(internals) {}
  void tile_done(int x0, int y0, int x1, int y1, const rayscope::Framebuffer& fb) {
    rayscope_vtk::framebuffer_rect_to_image(fb, x0, y0, x1, y1, in->Next);
    std::lock_guard<std::mutex> lock(in->TilesMutex);
    in->FinishedTiles.push_back({x0, y0, x1, y1});
  }
};

void vtkRayScopeViewer::Internals::StartRender() {
  const rayscope::RenderSettings& rs = this->Settings;
  const int w = rs.width, h = rs.height;
  int* dims = this->Display->GetDimensions();
  if (dims[0] != w || dims[1] != h || !this->Display->GetPointData()->GetScalars()) {
    this->Display->SetDimensions(w, h, 1);
    this->Display->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
    auto* s = vtkUnsignedCharArray::SafeDownCast(this->Display->GetPointData()->GetScalars());
    std::fill(s->GetPointer(0), s->GetPointer(0) + size_t(w) * size_t(h) * 3, kUnrenderedGray);
    vtkCamera* cam = this->ImageRen->GetActiveCamera();
    cam->SetFocalPoint(0.5 * (w - 1), 0.5 * (h - 1), 0.0);
    cam->SetPosition(0.5 * (w - 1), 0.5 * (h - 1), double(std::max(w, h)));
    cam->SetViewUp(0, 1, 0);
    double vp[4];
    this->ImageRen->GetViewport(vp);
    const int* ws = this->Window->GetSize();
    const double aspect = ((vp[2] - vp[0]) * ws[0]) / std::max(1.0, (vp[3] - vp[1]) * ws[1]);
    cam->SetParallelScale(0.5 * std::max(double(h), double(w) / aspect) * 1.02);
    this->ImageRen->ResetCameraClippingRange();
    this->Changed |= kImageView;
  }
  // The statistics policy gives every pixel its cost: the image has them all.
  rayscope_vtk::prepare_image(this->Next, w, h, true);
  this->FinishedTiles.clear();
  this->TilesShown = 0;
  this->TilesTotal =
      size_t((w + rs.tile_size - 1) / rs.tile_size) * size_t((h + rs.tile_size - 1) / rs.tile_size);
  this->RenderError.clear();
  this->RenderStart = std::chrono::steady_clock::now();
  this->Running = true;
  const rayscope::Scene* scene = this->scene();
  this->Worker = std::thread([this, scene, rs] {
    Policy policy(this);
    try {
      this->Counters = rayscope::RayCounters{};
      rayscope::render_frame_into(this->Frame, *scene, rs, policy, &this->Counters);
    } catch (const std::exception& e) {
      this->RenderError = e.what();
    }
    this->Running = false;
  });
}

// Shows the tiles finished since the last call; finishes a render whose
// worker is done.
void vtkRayScopeViewer::Internals::Poll() {
  if (!this->Worker.joinable()) return;
  this->ShowTiles();
  if (!this->Running) {
    this->Worker.join();
    this->FinishRender();
  }
}

// Copies the colors of the tiles finished since the last call from the next
// image into the one shown (both in VTK's row order).
void vtkRayScopeViewer::Internals::ShowTiles() {
  std::vector<std::array<int, 4>> tiles;
  {
    std::lock_guard<std::mutex> lock(this->TilesMutex);
    tiles.swap(this->FinishedTiles);
  }
  if (tiles.empty()) return;
  const int w = this->Settings.width, h = this->Settings.height;
  auto* shown = vtkUnsignedCharArray::SafeDownCast(this->Display->GetPointData()->GetScalars());
  auto* color =
      vtkUnsignedCharArray::SafeDownCast(this->Next->GetPointData()->GetAbstractArray("Color"));
  for (const auto& t : tiles)
    for (int y = t[1]; y < t[3]; ++y) {
      const size_t at = 3 * (size_t(h - 1 - y) * size_t(w) + size_t(t[0]));
      std::copy_n(color->GetPointer(0) + at, 3 * size_t(t[2] - t[0]), shown->GetPointer(0) + at);
    }
  this->TilesShown += tiles.size();
  this->Display->Modified();
  this->Changed |= kImageView;
  std::ostringstream m;
  m << "rendering " << w << "x" << h << ", " << this->Settings.samples << "x"
    << this->Settings.samples << " samples, depth " << this->Settings.max_depth << ": "
    << (100 * this->TilesShown) / std::max<size_t>(1, this->TilesTotal) << "% (" << this->TilesShown
    << "/" << this->TilesTotal << " tiles)";
  this->Say(m.str());
}

void vtkRayScopeViewer::Internals::FinishRender() {
  if (!this->RenderError.empty()) {
    this->Say("render failed: " + this->RenderError);
    return;
  }
  this->Self->LastRenderSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - this->RenderStart).count();
  // The next image becomes the last one; its arrays were filled tile by tile.
  // The last one's arrays are kept for the next render to fill.
  rayscope_vtk::counters_to_image(this->Counters, this->Next);
  vtkNew<vtkImageData> previous;
  previous->ShallowCopy(this->Image);
  this->Image->ShallowCopy(this->Next);
  this->Next->ShallowCopy(previous);
  this->HasImage = true;
  this->ShowImage();
  std::ostringstream m;
  m << "rendered " << this->Settings.width << "x" << this->Settings.height << ", "
    << this->Settings.samples << "x" << this->Settings.samples << " samples, depth "
    << this->Settings.max_depth << " in " << std::lround(1000.0 * this->Self->LastRenderSeconds)
    << " ms; image: " << rayscope_vtk::display_mode_name(this->Self->ImageMode);
  this->Say(m.str());
  this->UpdateCameraGeometry();
  if (this->Self->PickedPixel[0] >= 0) {
    const int i = this->Self->PickedPixel[0], j = this->Self->PickedPixel[1];
    if (i < this->Settings.width && j < this->Settings.height)
      this->UpdateOverlay();
    else
      this->Self->PickedPixel[0] = this->Self->PickedPixel[1] = -1;
  }
}

void vtkRayScopeViewer::Internals::ShowImage() {
  auto* shown = vtkUnsignedCharArray::SafeDownCast(this->Display->GetPointData()->GetScalars());
  // (A render of another size has begun: its tiles are shown as they come.)
  if (!this->HasImage || !shown || shown->GetNumberOfTuples() != this->Image->GetNumberOfPoints())
    return;
  std::vector<unsigned char> rgb;
  if (this->Self->ImageMode != rayscope_vtk::kDisplayColor)
    rgb = rayscope_vtk::display_pixels(this->Image, this->Self->ImageMode);
  if (rgb.empty()) {  // the colors, as they are
    vtkDataArray* color = this->Image->GetPointData()->GetScalars();
    std::copy_n(static_cast<unsigned char*>(color->GetVoidPointer(0)), shown->GetNumberOfValues(),
                shown->GetPointer(0));
  } else {
    std::copy(rgb.begin(), rgb.end(), shown->GetPointer(0));
  }
  this->Display->Modified();
  // The color scale of the cost and depth modes.
  std::string title;
  const bool scale =
      rayscope_vtk::display_scale(this->Image, this->Self->ImageMode, this->ScaleTable, title);
  this->ScaleBar->SetVisibility(scale);
  if (scale) this->ScaleBar->SetTitle(title.c_str());
  this->Changed |= kImageView;
}

int vtkRayScopeViewer::Initialize() {
  Internals& in = *this->Internal;
  if (in.Initialized) return 1;
  in.LastError.clear();
  vtkNew<vtkCallbackCommand> on_error;
  on_error->SetClientData(&in);
  on_error->SetCallback([](vtkObject*, unsigned long, void* client, void* call) {
    // VTK's error text is "ERROR: In FILE, line N\nCLASS (ADDRESS): MESSAGE\n\n":
    // the message is what a user needs.
    std::string text = call ? static_cast<const char*>(call) : "";
    if (const size_t at = text.find("): "); at != std::string::npos) text.erase(0, at + 3);
    while (!text.empty() && text.back() == '\n') text.pop_back();
    static_cast<Internals*>(client)->LastError = text;
  });
  in.Algorithm->AddObserver(vtkCommand::ErrorEvent, on_error);
  in.Tree->AddObserver(vtkCommand::ErrorEvent, on_error);
  in.BVH->AddObserver(vtkCommand::ErrorEvent, on_error);
  if (!in.Algorithm->UpdateScene()) {
    in.Message = "cannot render the scene: " + in.LastError;
    vtkErrorMacro(<< in.Message);
    return 0;
  }
  in.Settings = in.Algorithm->GetRenderSettings();
  in.Build();
  in.Interactor->Initialize();
  vtkNew<vtkCallbackCommand> on_timer;
  on_timer->SetClientData(&in);
  on_timer->SetCallback([](vtkObject*, unsigned long, void* client, void*) {
    Internals* in = static_cast<Internals*>(client);
    if (!in->Worker.joinable()) return;
    in->Poll();
    in->Redraw();
  });
  in.Interactor->AddObserver(vtkCommand::TimerEvent, on_timer);
  in.Interactor->CreateRepeatingTimer(kProgressTimerMs);
  in.StartRender();
  // The 3D view shows the scene's objects and the camera.
  in.UpdateCameraGeometry();
  rayscope::Bounds3 b = in.scene()->bvh().bounds();
  b.extend(in.scene()->camera.eye);
  b.extend(in.scene()->camera.look_at);
  const rayscope::DVec3 lo = in.scene()->to_world(b.lo), hi = in.scene()->to_world(b.hi);
  double bounds[6] = {lo.x, hi.x, lo.y, hi.y, lo.z, hi.z};
  in.SceneRen->ResetCamera(bounds);
  in.SceneRen->GetActiveCamera()->Zoom(kSceneZoom);
  in.Changed = kAllViews;
  in.Redraw();
  return 1;
}

void vtkRayScopeViewer::Start() {
  if (!this->Initialize()) return;
  this->Internal->Interactor->Start();
}

int vtkRayScopeViewer::WaitForRender() {
  Internals& in = *this->Internal;
  if (in.Worker.joinable()) {
    in.Worker.join();
    in.ShowTiles();
    in.FinishRender();
    in.Redraw();
  }
  return in.HasImage ? 1 : 0;
}

int vtkRayScopeViewer::Rerender() {
  Internals& in = *this->Internal;
  if (!in.Initialized) return this->Initialize();
  const rayscope::RenderSettings& rs = in.Algorithm->GetRenderSettings();
  std::ostringstream m;
  m << "re-rendering " << rs.width << "x" << rs.height << ", " << rs.samples << "x" << rs.samples
    << " samples, depth " << rs.max_depth;
  return in.Restart(m.str()) ? 1 : 0;
}

// Waits for a running render, then starts one of the scene source's scene
// with its settings, `message` in the message line (what the key asked for).
// The message is drawn with the render's first tiles (the progress timer's
// next tick, within kProgressTimerMs), not now: drawing the window here
// would take the CPU from the render it announces. False, with the error
// drawn, when the scene fails.
bool vtkRayScopeViewer::Internals::Restart(const std::string& message) {
  this->Self->WaitForRender();
  this->LastError.clear();
  if (!this->Algorithm->UpdateScene()) {
    this->Say("cannot render: " + this->LastError);
    this->Redraw();
    return false;
  }
  this->Settings = this->Algorithm->GetRenderSettings();
  this->StartRender();
  this->Say(message);
  return true;
}

// --- Picking and the overlay -----------------------------------------------------

int vtkRayScopeViewer::PickPixel(int i, int j) {
  Internals& in = *this->Internal;
  if (!in.Initialized && !this->Initialize()) return 0;
  this->WaitForRender();
  if (i < 0 || j < 0 || i >= in.Settings.width || j >= in.Settings.height) return 0;
  this->PickedPixel[0] = i;
  this->PickedPixel[1] = j;
  this->SelectedRay = -1;
  this->TraversalSteps = -1;
  this->ShownDepth = VTK_INT_MAX;
  in.UpdateOverlay();
  in.UpdateCameraGeometry();
  in.UpdateLegend();
  std::ostringstream m;
  m << "pixel (" << i << ", " << j << ") [rayscope --pixel " << i << ","
    << in.Settings.height - 1 - j << "]: " << in.Record.rays.size() << " rays";
  in.Say(m.str());
  in.Redraw();
  return 1;
}

int vtkRayScopeViewer::PickAtDisplay(int x, int y) {
  Internals& in = *this->Internal;
  if (!in.Initialized) return 0;
  if (in.ImageRen->IsInViewport(x, y)) {
    in.ImageRen->SetDisplayPoint(x, y, 0.0);
    in.ImageRen->DisplayToWorld();
    double w[4];
    in.ImageRen->GetWorldPoint(w);
    if (w[3] != 0.0)
      for (int k = 0; k < 3; ++k) w[k] /= w[3];
    const int i = int(std::floor(w[0] + 0.5)), j = int(std::floor(w[1] + 0.5));
    return this->PickPixel(i, j);  // outside the image: nothing happens
  }
  if (!in.SceneRen->IsInViewport(x, y)) return 0;
  if (!in.Picker->Pick(x, y, 0.0, in.SceneRen)) return 0;
  this->WaitForRender();
  const rayscope::Scene& s = *in.scene();
  double p[3];
  in.Picker->GetPickPosition(p);
  const rayscope::Vec3 local(rayscope::DVec3(p[0], p[1], p[2]) - s.origin);
  float px, py;
  if (!s.camera.project(local, px, py)) return 0;
  return this->PickPixel(int(std::floor(px)), in.Settings.height - 1 - int(std::floor(py)));
}

void vtkRayScopeViewer::Internals::UpdateOverlay() {
  vtkRayScopeViewer* self = this->Self;
  const int i = self->PickedPixel[0], j = self->PickedPixel[1];
  const rayscope::Scene& s = *this->scene();
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
  self->ShownDepth = std::min(self->ShownDepth, this->RecordDepth);
  if (self->SelectedRay >= int(this->Record.rays.size())) self->SelectedRay = -1;
  this->InspectText = rayscope::format_text(this->Record, s);

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

  // Image marker: the picked pixel's square and a cross hair.
  vtkNew<vtkPoints> pts;
  const double x = i, y = j, r = 0.5, arm = 6.0;
  for (auto [px, py] : {std::pair{x - r, y - r},
                        {x + r, y - r},
                        {x + r, y + r},
                        {x - r, y + r},
                        {x - arm, y},
                        {x - r, y},
                        {x + r, y},
                        {x + arm, y},
                        {x, y - arm},
                        {x, y - r},
                        {x, y + r},
                        {x, y + arm}})
    pts->InsertNextPoint(px, py, 0.5);
  vtkNew<vtkCellArray> lines;
  const vtkIdType square[5] = {0, 1, 2, 3, 0};
  lines->InsertNextCell(5, square);
  for (vtkIdType k = 4; k < 12; k += 2) {
    const vtkIdType seg[2] = {k, k + 1};
    lines->InsertNextCell(2, seg);
  }
  this->Marker->Initialize();
  this->Marker->SetPoints(pts);
  this->Marker->SetLines(lines);
  this->MarkerActor->VisibilityOn();

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
  } else if (self->ShowBVH) {
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
    this->BVHMapper->SetInputData(this->NoBoxes);
  }
  this->Changed |= kSceneView;
}

// The panel: the inspect text from a few lines before the selected ray,
// that ray's line marked ">>".
void vtkRayScopeViewer::Internals::UpdatePanel() {
  std::vector<std::string> lines;
  std::istringstream text(this->InspectText);
  for (std::string l; std::getline(text, l);) lines.push_back(l);
  int selected = -1;
  if (this->Self->SelectedRay >= 0) {
    const std::string tag = "#" + std::to_string(this->Self->SelectedRay) + " ";
    for (size_t k = 0; k < lines.size(); ++k) {
      const size_t at = lines[k].find_first_not_of(' ');
      if (at != std::string::npos && lines[k].compare(at, tag.size(), tag) == 0) {
        selected = int(k);
        lines[k].replace(0, std::min<size_t>(2, at), ">>");
        break;
      }
    }
  }
  const int first =
      std::max(0, std::min(selected - kPanelLinesBefore, int(lines.size()) - kPanelLines));
  std::string shown;
  for (int k = std::max(0, first); k < int(lines.size()) && k < first + kPanelLines; ++k)
    shown += lines[size_t(k)] + "\n";
  this->PanelText = shown;
  this->ShowPanelLines(std::vector<std::string>(
      lines.begin() + std::max(0, first),
      lines.begin() + std::min<int>(int(lines.size()), first + kPanelLines)));
}

// Puts `lines` (at most kPanelLines) on the panel, top down. A line already
// shown keeps its actor and is only moved; the others take the actors left.
void vtkRayScopeViewer::Internals::ShowPanelLines(const std::vector<std::string>& lines) {
  const size_t n = this->PanelLines.size();
  std::vector<int> actor(lines.size(), -1);
  std::vector<bool> taken(n, false);
  for (size_t k = 0; k < lines.size() && k < n; ++k)
    for (size_t a = 0; a < n; ++a)
      if (!taken[a] && this->PanelLineText[a] == lines[k]) {
        actor[k] = int(a);
        taken[a] = true;
        break;
      }
  size_t free_actor = 0;
  for (size_t k = 0; k < lines.size() && k < n; ++k) {
    if (actor[k] >= 0) continue;
    while (taken[free_actor]) ++free_actor;
    actor[k] = int(free_actor);
    taken[free_actor] = true;
    this->PanelLineText[free_actor] = lines[k];
    this->PanelLines[free_actor]->SetInput(lines[k].c_str());
  }
  for (size_t a = 0; a < n; ++a)
    this->PanelLines[a]->SetVisibility(taken[a] && !this->PanelLineText[a].empty());
  for (size_t k = 0; k < lines.size() && k < n; ++k) {
    vtkCoordinate* at = this->PanelLines[size_t(actor[k])]->GetPositionCoordinate();
    const double y = -double(k) * double(this->PanelLineHeight);
    if (at->GetValue()[1] != y) at->SetValue(0.0, y);
  }
  this->Changed |= kPanelView;
}

void vtkRayScopeViewer::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "PickedPixel: " << this->PickedPixel[0] << " " << this->PickedPixel[1] << "\n";
  os << indent << "ShownDepth: " << this->ShownDepth << "\n";
  os << indent << "SelectedRay: " << this->SelectedRay << "\n";
  os << indent << "ShownKind: " << this->ShownKind << "\n";
  os << indent << "TraversalSteps: " << this->TraversalSteps << "\n";
  os << indent << "ShowBVH: " << this->ShowBVH << "\n";
  os << indent << "BVHLevel: " << this->BVHLevel << "\n";
  os << indent << "ShowLabels: " << this->ShowLabels << "\n";
  os << indent << "ImageMode: " << rayscope_vtk::display_mode_name(this->ImageMode) << "\n";
  os << indent << "OutputPrefix: " << (this->OutputPrefix ? this->OutputPrefix : "") << "\n";
}
