// vtkRayScopeViewer's background render: the core's frame loop on a worker
// thread, tile by tile, feeding the image viewport (the finished tiles while
// it runs, then the image in its ImageMode), and the interactor's repeating
// timer that shows its progress while the window stays responsive.
#include "vtkRayScopeViewerInternals.h"

using namespace rayscope_vtkmodule::viewer;

// The frame loop's statistics policy (cost AOVs for the heat map) that also
// writes each finished tile into the next image, on the thread that rendered
// it, and hands the tile over to be shown.
struct vtkRayScopeViewer::Internals::Policy : rayscope::StatsPolicy {
  Internals* in;
  explicit Policy(Internals* internals) : in(internals) {}
  void tile_done(int x0, int y0, int x1, int y1, const rayscope::Framebuffer& fb) {
    rayscope_vtkio::framebuffer_rect_to_image(fb, x0, y0, x1, y1, in->Next);
    std::lock_guard<std::mutex> lock(in->TilesMutex);
    in->FinishedTiles.push_back({x0, y0, x1, y1});
  }
};

// A repeating timer on the interactor: while a render runs, its finished
// tiles and its progress are shown every kProgressTimerMs.
void vtkRayScopeViewer::Internals::StartProgressTimer() {
  vtkNew<vtkCallbackCommand> on_timer;
  on_timer->SetClientData(this);
  on_timer->SetCallback([](vtkObject*, unsigned long, void* client, void*) {
    Internals* in = static_cast<Internals*>(client);
    if (!in->Worker.joinable()) return;
    in->Poll();
    in->Redraw();
  });
  this->Interactor->AddObserver(vtkCommand::TimerEvent, on_timer);
  this->Interactor->CreateRepeatingTimer(kProgressTimerMs);
}

// Starts a render of the scene with Settings on the worker thread, into Next.
// A new size clears the shown image to gray and fits the image viewport to it.
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
  rayscope_vtkio::prepare_image(this->Next, w, h, true);
  this->FinishedTiles.clear();
  this->TilesShown = 0;
  this->TilesTotal = rayscope::TileGrid(rs).count();
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

// A render is done: its image becomes the last one and is shown, and the
// picked pixel's overlay is made again for it (or the pick is dropped when
// the image no longer has that pixel).
void vtkRayScopeViewer::Internals::FinishRender() {
  if (!this->RenderError.empty()) {
    this->Say("render failed: " + this->RenderError);
    return;
  }
  this->Self->LastRenderSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - this->RenderStart).count();
  // The next image becomes the last one; its arrays were filled tile by tile.
  // The last one's arrays are kept for the next render to fill.
  rayscope_vtkio::counters_to_image(this->Counters, this->Next);
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
    << " ms; image: " << rayscope_vtkmodule::display_mode_name(this->Self->ImageMode);
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

// Shows the last image in the ImageMode, with the color scale of the cost
// and depth modes.
void vtkRayScopeViewer::Internals::ShowImage() {
  auto* shown = vtkUnsignedCharArray::SafeDownCast(this->Display->GetPointData()->GetScalars());
  // (A render of another size has begun: its tiles are shown as they come.)
  if (!this->HasImage || !shown || shown->GetNumberOfTuples() != this->Image->GetNumberOfPoints())
    return;
  std::vector<unsigned char> rgb;
  if (this->Self->ImageMode != rayscope_vtkmodule::kDisplayColor)
    rgb = rayscope_vtkmodule::display_pixels(this->Image, this->Self->ImageMode);
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
  const bool scale = rayscope_vtkmodule::display_scale(this->Image, this->Self->ImageMode,
                                                       this->ScaleTable, title);
  this->ScaleBar->SetVisibility(scale);
  if (scale) this->ScaleBar->SetTitle(title.c_str());
  this->Changed |= kImageView;
}

bool vtkRayScopeViewer::IsRendering() {
  return this->Internal->Worker.joinable();
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
