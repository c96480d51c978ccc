// vtkRayScopeViewer's API: the scene source, the window's parts, setup and
// the event loop, picking, the image mode, screenshots and .vtp export. The
// parts of the viewer live in files of their own (vtkRayScopeViewerInternals.h).
#include "RayScopeDisplayCheck.h"
#include "vtkRayScopeViewerInternals.h"

using namespace rayscope_vtkmodule::viewer;

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
      ShowTreeDiagram(false),
      ShowPacket(false),
      LastRenderSeconds(0.0),
      OutputPrefix(nullptr),
      WindowSize{1400, 820},
      FontScale(1.0),
      Chapter(-1),
      Internal(new Internals(this)) {
  this->SetOutputPrefix("rayscope_view");
  this->Internal->Algorithm = vtkSmartPointer<vtkRayScopeImageAlgorithm>::New();
  Internals& in = *this->Internal;
  in.OnError->SetClientData(&in);
  in.OnError->SetCallback([](vtkObject*, unsigned long, void* client, void* call) {
    // VTK's error text is "ERROR: In FILE, line N\nCLASS (ADDRESS): MESSAGE\n\n":
    // the message is what a user needs.
    std::string text = call ? static_cast<const char*>(call) : "";
    if (const size_t at = text.find("): "); at != std::string::npos) text.erase(0, at + 3);
    while (!text.empty() && text.back() == '\n') text.pop_back();
    static_cast<Internals*>(client)->LastError = text;
  });
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
  return Internals::HelpLine().c_str();
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

vtkPolyData* vtkRayScopeViewer::GetPixelMarker() {
  return this->Internal->Marker;
}

vtkPolyData* vtkRayScopeViewer::GetPacketBoxes() {
  return this->Internal->PacketBoxes;
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

vtkPolyData* vtkRayScopeViewer::GetTreeDiagram() {
  return this->Internal->Diagram;
}

vtkPolyData* vtkRayScopeViewer::GetWalkSteps() {
  return this->Internal->WalkSteps;
}

vtkPolyData* vtkRayScopeViewer::GetWalkCurrentNode() {
  return this->Internal->WalkCurrent;
}

std::string vtkRayScopeViewer::SettingsError() const {
  const int w = this->WindowSize[0], h = this->WindowSize[1];
  if (w < MinWindowWidth || h < MinWindowHeight)
    return "window size " + std::to_string(w) + "x" + std::to_string(h) +
           " is smaller than the viewer's smallest, " + std::to_string(MinWindowWidth) + "x" +
           std::to_string(MinWindowHeight);
  if (!(this->FontScale >= MinFontScale && this->FontScale <= MaxFontScale)) {
    std::ostringstream s;
    s << "font scale " << this->FontScale << " is outside " << MinFontScale << " to "
      << MaxFontScale;
    return s.str();
  }
  return {};
}

int vtkRayScopeViewer::Initialize() {
  Internals& in = *this->Internal;
  if (in.Initialized) return 1;
  in.LastError.clear();
  if (const std::string e = this->SettingsError(); !e.empty()) {
    in.Message = e;
    vtkErrorMacro(<< e);
    return 0;
  }
  in.WatchErrors(in.Algorithm);
  in.WatchErrors(in.Tree);
  in.WatchErrors(in.BVH);
  if (!in.Algorithm->UpdateScene()) {
    in.Message = "cannot render the scene: " + in.LastError;
    vtkErrorMacro(<< in.Message);
    return 0;
  }
  in.Settings = in.Algorithm->GetRenderSettings();
  in.Build();
  if (const std::string missing = rayscope_vtkmodule::connect_display(in.Window);
      !missing.empty()) {
    in.Message = missing;
    vtkErrorMacro(<< in.Message);
    return 0;
  }
  in.Interactor->Initialize();
  in.StartProgressTimer();
  in.StartRender();
  // The 3D view shows the scene's objects and the camera.
  in.UpdateCameraGeometry();
  in.FrameScene();
  in.Changed = kAllViews;
  in.Redraw();
  return 1;
}

void vtkRayScopeViewer::Start() {
  if (!this->Initialize()) return;
  this->Internal->Interactor->Start();
}

// --- A lecture's chapters -------------------------------------------------------------

void vtkRayScopeViewer::AddChapter(vtkRayScopeImageAlgorithm* source, const char* title,
                                   const char* caption, int pickI, int pickJ, const char* keys) {
  if (!source) {
    vtkErrorMacro(<< "AddChapter: no scene source");
    return;
  }
  Internals::ChapterEntry c{source, title ? title : "", caption ? caption : "", {pickI, pickJ}, {}};
  std::istringstream list(keys ? keys : "");
  for (std::string key; std::getline(list, key, ',');)
    if (!key.empty()) c.Keys.push_back(key);
  this->Internal->Chapters.push_back(std::move(c));
  this->Modified();
}

int vtkRayScopeViewer::GetNumberOfChapters() {
  return int(this->Internal->Chapters.size());
}

const char* vtkRayScopeViewer::GetCaption() {
  return this->Internal->Caption.c_str();
}

int vtkRayScopeViewer::SetChapter(int n) {
  Internals& in = *this->Internal;
  if (n < 0 || n >= int(in.Chapters.size())) return 0;
  if (in.Worker.joinable()) this->WaitForRender();
  const Internals::ChapterEntry& c = in.Chapters[size_t(n)];
  std::ostringstream caption;
  caption << n + 1 << "/" << in.Chapters.size() << " " << c.Title << (c.Caption.empty() ? "" : ": ")
          << c.Caption;
  in.Caption = caption.str();
  // The view as a new viewer shows it, on the chapter's scene.
  this->Chapter = n;
  this->PickedPixel[0] = this->PickedPixel[1] = -1;
  this->ShownDepth = 0;
  this->SelectedRay = -1;
  this->ShownKind = -1;
  this->TraversalSteps = -1;
  this->ShowBVH = false;
  this->BVHLevel = -1;
  this->ShowLabels = false;
  this->ShowTreeDiagram = false;
  this->ShowPacket = false;
  this->ImageMode = COLOR;
  in.Algorithm = c.Source;
  in.Tree->SetSceneSource(in.Algorithm);
  in.BVH->SetSceneSource(in.Algorithm);
  if (!in.Initialized) {
    if (!this->Initialize()) return 0;
  } else {
    in.WatchErrors(in.Algorithm);
    in.ClearOverlay();
    if (!in.Restart("chapter " + std::to_string(n + 1) + ": " + c.Title)) return 0;
    in.BuildSceneGeometry();
    in.UpdateCameraGeometry();
    in.FrameScene();
    in.UpdateLegend();
  }
  in.ShowCaption();
  this->WaitForRender();
  if (c.Pick[0] >= 0 && !this->PickPixel(c.Pick[0], c.Pick[1])) {
    in.Say("chapter " + std::to_string(n + 1) + ": pixel (" + std::to_string(c.Pick[0]) + ", " +
           std::to_string(c.Pick[1]) + ") is outside its image");
    in.Redraw();
    return 0;
  }
  for (const std::string& key : c.Keys) {
    this->WaitForRender();
    if (!this->HandleKey(key.c_str())) {
      in.Say("chapter " + std::to_string(n + 1) + ": '" + key + "' is not a key of the viewer");
      in.Redraw();
      return 0;
    }
  }
  this->WaitForRender();
  in.Changed = kAllViews;
  in.Redraw();
  return 1;
}

// --- Picking ------------------------------------------------------------------------

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

int vtkRayScopeViewer::SetSceneView(const double eye[3], const double at[3]) {
  Internals& in = *this->Internal;
  if (!in.Initialized) return 0;
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(eye[k]) || !std::isfinite(at[k])) return 0;
  if (eye[0] == at[0] && eye[1] == at[1] && eye[2] == at[2]) return 0;
  vtkCamera* cam = in.SceneRen->GetActiveCamera();
  const rayscope::Vec3 up = in.scene()->camera.up;
  cam->SetPosition(eye);
  cam->SetFocalPoint(at);
  cam->SetViewUp(up.x, up.y, up.z);
  cam->OrthogonalizeViewUp();
  in.SceneRen->ResetCameraClippingRange();
  in.Changed |= kSceneView;
  in.Redraw();
  return 1;
}

// --- Image mode, screenshots, export -------------------------------------------

void vtkRayScopeViewer::SetImageMode(int mode) {
  mode = std::clamp(mode, int(COLOR), int(OBJECT_IDS));
  static_assert(int(COLOR) == rayscope_vtkmodule::kDisplayColor &&
                int(OBJECT_IDS) == rayscope_vtkmodule::kDisplayObjectId);
  if (mode == this->ImageMode) return;
  this->ImageMode = mode;
  this->Internal->ShowImage();
  this->Modified();
}

int vtkRayScopeViewer::SaveScreenshot(const char* filename) {
  Internals& in = *this->Internal;
  if (!in.Initialized || !filename) return 0;
  in.Window->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(in.Window);
  grab->ReadFrontBufferOff();
  vtkNew<vtkPNGWriter> writer;
  writer->SetInputConnection(grab->GetOutputPort());
  writer->SetFileName(filename);
  writer->Write();
  if (writer->GetErrorCode() != 0) {
    in.Message = std::string("cannot write ") + filename;
    vtkErrorMacro(<< in.Message);
    return 0;
  }
  return 1;
}

int vtkRayScopeViewer::ExportVTP(const char* prefix) {
  Internals& in = *this->Internal;
  if (!in.HasRecord || !prefix) {
    in.Message = "nothing to export: pick a pixel first";
    return 0;
  }
  vtkNew<vtkRayScopeAccelSource> all;
  all->SetSceneSource(in.Algorithm);
  vtkPolyData* boxes = this->GetShownBVH();
  if (!boxes || boxes->GetNumberOfCells() == 0) {
    all->Update();
    boxes = all->GetOutput();
  }
  for (auto [suffix, data] :
       {std::pair{"_raytree.vtp", this->GetShownRays()}, std::pair{"_bvh.vtp", boxes}}) {
    vtkNew<vtkXMLPolyDataWriter> writer;
    const std::string file = std::string(prefix) + suffix;
    writer->SetInputData(data);
    writer->SetFileName(file.c_str());
    // ASCII: VTK 9.1's reader fails on string arrays (KindName) written in
    // its binary modes. The files are small: one pixel's rays, one BVH.
    writer->SetDataModeToAscii();
    if (!writer->Write()) {
      in.Message = "cannot write " + file;
      vtkErrorMacro(<< in.Message);
      return 0;
    }
  }
  return 1;
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
  os << indent << "ShowTreeDiagram: " << this->ShowTreeDiagram << "\n";
  os << indent << "ShowPacket: " << this->ShowPacket << "\n";
  os << indent << "ImageMode: " << rayscope_vtkmodule::display_mode_name(this->ImageMode) << "\n";
  os << indent << "Chapter: " << this->Chapter << " of " << this->Internal->Chapters.size() << "\n";
  os << indent << "OutputPrefix: " << (this->OutputPrefix ? this->OutputPrefix : "") << "\n";
}
