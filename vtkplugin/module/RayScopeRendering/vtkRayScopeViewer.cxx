#include "vtkRayScopeViewer.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <sstream>
#include <thread>
#include <vector>

#include "vtkActor.h"
#include "vtkActor2D.h"
#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellPicker.h"
#include "vtkCommand.h"
#include "vtkDataSetMapper.h"
#include "vtkFieldData.h"
#include "vtkGeometryFilter.h"
#include "vtkHedgeHog.h"
#include "vtkImageActor.h"
#include "vtkImageData.h"
#include "vtkImageMapper3D.h"
#include "vtkIntArray.h"
#include "vtkInteractorStyleTrackballCamera.h"
#include "vtkLabeledDataMapper.h"
#include "vtkLegendBoxActor.h"
#include "vtkLookupTable.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPNGWriter.h"
#include "vtkPassArrays.h"
#include "vtkPlaneSource.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkScalarBarActor.h"
#include "vtkSmartPointer.h"
#include "vtkSphereSource.h"
#include "vtkStringArray.h"
#include "vtkTextActor.h"
#include "vtkTextProperty.h"
#include "vtkThreshold.h"
#include "vtkUnsignedCharArray.h"
#include "vtkWindowToImageFilter.h"
#include "vtkXMLPolyDataWriter.h"

#include "RayScopeDisplay.h"
#include "rayscope/frame.h"
#include "rayscope/image.h"
#include "rayscope/raytree_format.h"
#include "rayscope/replay.h"
#include "vtkRayScopeBVHSource.h"
#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopeRayTreeSource.h"

namespace {

// Layout of the window (fractions of its size): the header line on top, the
// image and the 3D view side by side, the text panel below.
constexpr double kHeaderBottom = 0.95;
constexpr double kPanelTop = 0.30;
constexpr int kProgressTimerMs = 40;  // how often finished tiles are shown
constexpr int kPanelLines = 18;       // lines of the inspect text shown at once
constexpr int kPanelLinesBefore = 4;  // of them, before the selected ray's line
constexpr int kGridRadius = 4;        // pixel grid shown: the picked pixel +- this
constexpr int kClickSlop = 3;         // a press and release this close is a click, not a drag
constexpr double kImagePlaneFraction = 0.25;   // image plane at this fraction of eye..look_at
constexpr double kNormalFraction = 0.04;       // normals drawn this fraction of the scene size
constexpr double kLightFraction = 0.015;       // light markers' radius, same
constexpr unsigned char kUnrenderedGray = 40;  // pixels not rendered yet
constexpr double kSceneZoom =
    1.6;  // the 3D view, closer than VTK's ResetCamera (a bounding sphere)

// Colors of the overlay, one per ray kind (rayscope::RayKind order), then
// skipped rays; and the played walk's states (vtkRayScopeBVHSource order).
constexpr double kKindColors[4][3] = {
    {1.0, 0.85, 0.1}, {0.55, 0.75, 1.0}, {0.2, 1.0, 0.45}, {1.0, 0.35, 0.9}};
constexpr const char* kKindNames[4] = {"primary", "shadow", "reflection", "refraction"};
constexpr double kSkippedColor[3] = {0.5, 0.5, 0.5};
constexpr double kNormalColor[3] = {1.0, 0.55, 0.1};
constexpr double kPickColor[3] = {1.0, 0.1, 0.1};
constexpr double kSelectedColor[3] = {1.0, 1.0, 1.0};
constexpr double kOccluderColor[3] = {0.95, 0.2, 0.15};
constexpr int kEndOccluder = 3;  // vtkRayScopeRayTreeSource's EndKind of a blocked shadow ray
constexpr double kWalkColors[6][3] = {{0, 0, 0},       {0.9, 0.9, 0.3}, {0.9, 0.2, 0.2},
                                      {0.2, 0.9, 0.2}, {0.3, 0.5, 1.0}, {1.0, 1.0, 1.0}};
constexpr const char* kWalkNames[6] = {"",        "box hit, not entered yet",   "box missed",
                                       "entered", "culled (early termination)", "hit leaf"};

const char* kHelp =
    "click: pick | Up/Down: depth | Right/Left: ray | t/T: BVH walk | b: BVH, l/L: level | "
    "k: kind | d: labels | m: image | +/-: spp, ]/[: depth, p: projection, r: 3D camera | "
    "s: screenshot, x: .vtp | q: quit";

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

// A short horizontal line: the symbol of a legend entry.
vtkSmartPointer<vtkPolyData> legend_symbol() {
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> pts;
  pts->InsertNextPoint(0, 0, 0);
  pts->InsertNextPoint(1, 0, 0);
  vtkNew<vtkCellArray> lines;
  vtkIdType ids[2] = {0, 1};
  lines->InsertNextCell(2, ids);
  pd->SetPoints(pts);
  pd->SetLines(lines);
  return pd;
}

void srgb(const rayscope::Color& linear, double out[3]) {
  for (int k = 0; k < 3; ++k) out[k] = rayscope::linear_to_srgb(std::clamp(linear[k], 0.0f, 1.0f));
}

}  // namespace

class vtkRayScopeViewerStyle;

struct vtkRayScopeViewer::Internals {
  vtkRayScopeViewer* Self;
  vtkSmartPointer<vtkRayScopeImageAlgorithm> Algorithm;
  vtkNew<vtkRenderWindow> Window;
  vtkNew<vtkRenderWindowInteractor> Interactor;
  vtkNew<vtkRenderer> ImageRen, SceneRen, PanelRen, HeaderRen;
  bool Initialized = false;
  std::string LastError, Message, InspectText, PanelText;

  // The image: the last finished render with every array, and what is shown.
  vtkNew<vtkImageData> Image, Display;
  vtkNew<vtkImageActor> ImageActor;
  vtkNew<vtkLookupTable> ScaleTable;
  vtkNew<vtkScalarBarActor> ScaleBar;
  vtkNew<vtkPolyData> Marker;
  vtkNew<vtkActor> MarkerActor;
  bool HasImage = false;

  // The render running on the worker thread.
  std::thread Worker;
  std::atomic<bool> Running{false};
  rayscope::RenderSettings Settings;
  rayscope::Framebuffer Frame;
  rayscope::RayCounters Counters;
  std::string RenderError;
  std::vector<unsigned char> Staging;  // sRGB bytes, core row order, per finished tile
  std::mutex TilesMutex;
  std::vector<std::array<int, 4>> FinishedTiles;  // x0, y0, x1, y1 not yet shown
  size_t TilesShown = 0, TilesTotal = 0;
  std::chrono::steady_clock::time_point RenderStart;
  unsigned long TimerObserver = 0;

  // The picked pixel's tree.
  rayscope::PixelRecord Record;
  bool HasRecord = false;
  int RecordDepth = 0;  // deepest ray of the record
  vtkNew<vtkRayScopeRayTreeSource> Tree;
  vtkNew<vtkPassArrays> NoStrings;
  vtkSmartPointer<vtkThreshold> ByDepth, ByRay, ByKind, Traced, Skipped;
  vtkNew<vtkGeometryFilter> Shown;
  vtkNew<vtkActor> TracedActor, SkippedActor, NormalActor, SelectedActor;
  vtkSmartPointer<vtkThreshold> Selected;
  vtkNew<vtkPolyData> Labels;  // a point per shown ray, at its middle, with its label
  vtkNew<vtkActor2D> LabelActor;
  vtkNew<vtkPolyData> Occluders;  // where shown shadow rays are blocked
  vtkNew<vtkActor> OccluderActor;
  vtkNew<vtkHedgeHog> Normals;
  vtkNew<vtkRayScopeBVHSource> BVH;
  vtkNew<vtkPolyData> NoBoxes;
  vtkNew<vtkPolyDataMapper> BVHMapper;
  vtkNew<vtkActor> BVHActor;
  vtkSmartPointer<vtkLookupTable> LevelTable, WalkTable;

  // The scene in 3D.
  std::vector<vtkSmartPointer<vtkActor>> GeometryActors;
  vtkNew<vtkPolyData> CameraGeometry, PickedCell;
  vtkNew<vtkActor> CameraActor, PickedCellActor;
  vtkNew<vtkCellPicker> Picker;
  vtkNew<vtkLegendBoxActor> Legend;
  vtkNew<vtkTextActor> HelpActor, MessageActor, PanelActor;
  vtkSmartPointer<vtkRayScopeViewerStyle> Style;
  int ScreenshotCount = 0, ExportCount = 0;

  explicit Internals(vtkRayScopeViewer* self) : Self(self) {}
  struct Policy;

  ~Internals() {
    if (this->Worker.joinable()) this->Worker.join();
  }

  rayscope::Scene* scene() { return this->Algorithm->GetCoreScene(); }
  void Build();
  void BuildSceneGeometry();
  void UpdateCameraGeometry();
  void StartRender();
  void Poll();
  void ShowTiles();
  void FinishRender();
  void ShowImage();
  void UpdateOverlay();
  void UpdateBVH();
  void UpdateLabels();
  void UpdateOccluders();
  void UpdatePanel();
  void UpdateLegend();
  void Say(const std::string& message) {
    this->Message = message;
    this->MessageActor->SetInput(message.c_str());
  }
  void Redraw() {
    if (this->Initialized) this->Window->Render();
  }
};

// The window's interaction: clicks pick, keys go to the viewer, dragging in
// the 3D view orbits (vtkInteractorStyleTrackballCamera).
class vtkRayScopeViewerStyle : public vtkInteractorStyleTrackballCamera {
 public:
  static vtkRayScopeViewerStyle* New();
  vtkTypeMacro(vtkRayScopeViewerStyle, vtkInteractorStyleTrackballCamera);
  vtkRayScopeViewer* Viewer = nullptr;

  void OnLeftButtonDown() override {
    const int* p = this->Interactor->GetEventPosition();
    this->Press[0] = p[0];
    this->Press[1] = p[1];
    if (this->Viewer->GetImageRenderer()->IsInViewport(p[0], p[1])) {
      this->Viewer->PickAtDisplay(p[0], p[1]);
      return;
    }
    this->Superclass::OnLeftButtonDown();
  }
  void OnLeftButtonUp() override {
    this->Superclass::OnLeftButtonUp();
    const int* p = this->Interactor->GetEventPosition();
    if (std::abs(p[0] - this->Press[0]) <= kClickSlop &&
        std::abs(p[1] - this->Press[1]) <= kClickSlop &&
        this->Viewer->GetSceneRenderer()->IsInViewport(p[0], p[1]))
      this->Viewer->PickAtDisplay(p[0], p[1]);
  }
  void OnKeyPress() override {
    const char* key = this->Interactor->GetKeySym();
    if (key && this->Viewer->HandleKey(key)) return;
    this->Superclass::OnKeyPress();
  }
  // VTK's own character keys (wireframe, reset, stereo, fly, pick) would fight
  // the viewer's; only quitting is kept.
  void OnChar() override {
    const char c = this->Interactor->GetKeyCode();
    if (c == 'q' || c == 'e') this->Superclass::OnChar();
  }

 private:
  int Press[2] = {-1000, -1000};
};
vtkStandardNewMacro(vtkRayScopeViewerStyle);

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
vtkRayScopeBVHSource* vtkRayScopeViewer::GetBVHSource() {
  return this->Internal->BVH;
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

// --- Building the window ------------------------------------------------------

void vtkRayScopeViewer::Internals::Build() {
  vtkRayScopeViewer* self = this->Self;
  this->Window->SetSize(self->WindowSize);
  this->Window->SetWindowName("rayscope view");
  this->Window->SetMultiSamples(0);
  this->HeaderRen->SetViewport(0.0, kHeaderBottom, 1.0, 1.0);
  this->ImageRen->SetViewport(0.0, kPanelTop, 0.5, kHeaderBottom);
  this->SceneRen->SetViewport(0.5, kPanelTop, 1.0, kHeaderBottom);
  this->PanelRen->SetViewport(0.0, 0.0, 1.0, kPanelTop);
  this->ImageRen->SetBackground(0.08, 0.08, 0.08);
  this->SceneRen->SetBackground(0.15, 0.16, 0.2);
  this->PanelRen->SetBackground(0.05, 0.05, 0.05);
  this->HeaderRen->SetBackground(0.0, 0.0, 0.0);
  for (vtkRenderer* r :
       {this->HeaderRen.Get(), this->ImageRen.Get(), this->SceneRen.Get(), this->PanelRen.Get()})
    this->Window->AddRenderer(r);
  this->Interactor->SetRenderWindow(this->Window);
  this->Style = vtkSmartPointer<vtkRayScopeViewerStyle>::New();
  this->Style->Viewer = self;
  this->Style->SetDefaultRenderer(this->SceneRen);
  this->Interactor->SetInteractorStyle(this->Style);

  // Image viewport.
  this->ImageActor->GetMapper()->SetInputData(this->Display);
  this->ImageActor->InterpolateOff();
  this->ImageRen->AddActor(this->ImageActor);
  vtkNew<vtkPolyDataMapper> marker_mapper;
  marker_mapper->SetInputData(this->Marker);
  this->MarkerActor->SetMapper(marker_mapper);
  this->MarkerActor->GetProperty()->SetColor(kPickColor[0], kPickColor[1], kPickColor[2]);
  this->MarkerActor->GetProperty()->SetLineWidth(2.0);
  this->MarkerActor->VisibilityOff();
  this->ImageRen->AddActor(this->MarkerActor);
  this->ImageRen->GetActiveCamera()->ParallelProjectionOn();
  this->ScaleBar->SetLookupTable(this->ScaleTable);
  this->ScaleBar->SetOrientationToHorizontal();
  this->ScaleBar->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  this->ScaleBar->GetPositionCoordinate()->SetValue(0.1, 0.01);
  this->ScaleBar->SetWidth(0.8);
  this->ScaleBar->SetHeight(0.12);
  this->ScaleBar->SetNumberOfLabels(5);
  this->ScaleBar->VisibilityOff();
  this->ImageRen->AddActor2D(this->ScaleBar);

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
  traced_mapper->SetLookupTable(make_table(4, kKindColors));
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
  this->OccluderActor->GetProperty()->LightingOff();
  this->OccluderActor->PickableOff();
  this->OccluderActor->VisibilityOff();
  this->SceneRen->AddActor(this->OccluderActor);
  // Labels on demand: "#id dDEPTH wWEIGHT" at the middle of each shown ray
  // (the mapper's "field data" mode reads the named point-data array).
  vtkNew<vtkLabeledDataMapper> label_mapper;
  label_mapper->SetInputData(this->Labels);
  label_mapper->SetLabelModeToLabelFieldData();
  label_mapper->SetFieldDataName("Label");
  label_mapper->GetLabelTextProperty()->SetFontSize(12);
  label_mapper->GetLabelTextProperty()->SetColor(1.0, 1.0, 1.0);
  label_mapper->GetLabelTextProperty()->ShadowOn();
  this->LabelActor->SetMapper(label_mapper);
  this->LabelActor->VisibilityOff();
  this->SceneRen->AddActor2D(this->LabelActor);

  // BVH boxes: by level, or a played walk by state.
  this->BVH->SetSceneSource(this->Algorithm);
  this->LevelTable = vtkSmartPointer<vtkLookupTable>::New();
  this->LevelTable->SetHueRange(0.66, 0.0);
  this->LevelTable->Build();
  this->WalkTable = make_table(6, kWalkColors);
  this->BVHMapper->SetInputData(this->NoBoxes);
  this->BVHMapper->SetScalarModeToUseCellFieldData();
  this->BVHActor->SetMapper(this->BVHMapper);
  this->BVHActor->GetProperty()->SetLineWidth(1.5);
  this->BVHActor->GetProperty()->LightingOff();
  this->BVHActor->PickableOff();
  this->SceneRen->AddActor(this->BVHActor);

  // The camera, its image plane, the pixel grid and the picked pixel.
  vtkNew<vtkPolyDataMapper> camera_mapper;
  camera_mapper->SetInputData(this->CameraGeometry);
  this->CameraActor->SetMapper(camera_mapper);
  this->CameraActor->GetProperty()->SetColor(0.85, 0.85, 0.85);
  this->CameraActor->GetProperty()->LightingOff();
  this->CameraActor->PickableOff();
  this->SceneRen->AddActor(this->CameraActor);
  vtkNew<vtkPolyDataMapper> cell_mapper;
  cell_mapper->SetInputData(this->PickedCell);
  this->PickedCellActor->SetMapper(cell_mapper);
  this->PickedCellActor->GetProperty()->SetColor(kPickColor[0], kPickColor[1], kPickColor[2]);
  this->PickedCellActor->PickableOff();
  this->SceneRen->AddActor(this->PickedCellActor);

  // Text: help and message lines on top, the inspect text below.
  this->HelpActor->SetInput(kHelp);
  this->HelpActor->GetTextProperty()->SetFontSize(13);
  this->HelpActor->GetTextProperty()->SetColor(0.8, 0.8, 0.8);
  this->HelpActor->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  this->HelpActor->GetPositionCoordinate()->SetValue(0.005, 0.52);
  this->HeaderRen->AddActor2D(this->HelpActor);
  this->MessageActor->GetTextProperty()->SetFontSize(13);
  this->MessageActor->GetTextProperty()->SetColor(1.0, 0.85, 0.3);
  this->MessageActor->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  this->MessageActor->GetPositionCoordinate()->SetValue(0.005, 0.06);
  this->HeaderRen->AddActor2D(this->MessageActor);
  this->PanelActor->GetTextProperty()->SetFontFamilyToCourier();
  this->PanelActor->GetTextProperty()->SetFontSize(12);
  this->PanelActor->GetTextProperty()->SetVerticalJustificationToTop();
  this->PanelActor->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  this->PanelActor->GetPositionCoordinate()->SetValue(0.005, 0.98);
  this->PanelActor->SetInput("click a pixel of the image (left) or a surface (right)");
  this->PanelRen->AddActor2D(this->PanelActor);
  this->Legend->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  this->Legend->GetPositionCoordinate()->SetValue(0.0, 0.0);
  this->Legend->GetPosition2Coordinate()->SetValue(0.2, 0.3);
  this->Legend->UseBackgroundOn();
  this->Legend->SetBackgroundColor(0.0, 0.0, 0.0);
  this->SceneRen->AddActor2D(this->Legend);
  this->UpdateLegend();

  this->Picker->PickFromListOn();
  this->Picker->SetTolerance(0.0005);
  this->BuildSceneGeometry();
  this->Initialized = true;
}

// The core scene's objects, drawn by VTK: meshes, spheres, planes (sized to
// the rest of the scene) and point lights, in their material colors, half
// transparent so that rays inside them stay visible.
void vtkRayScopeViewer::Internals::BuildSceneGeometry() {
  for (vtkActor* a : this->GeometryActors) this->SceneRen->RemoveActor(a);
  this->GeometryActors.clear();
  this->Picker->InitializePickList();
  const rayscope::Scene& s = *this->scene();
  rayscope::Bounds3 b = s.bvh().bounds();
  b.extend(s.camera.look_at);
  const double size = std::max(1e-3, double(glm::length(b.extent())));
  auto add = [&](vtkPolyData* pd, vtkAlgorithmOutput* port, uint32_t material, bool pickable) {
    vtkNew<vtkPolyDataMapper> mapper;
    if (pd)
      mapper->SetInputData(pd);
    else
      mapper->SetInputConnection(port);
    mapper->ScalarVisibilityOff();
    auto actor = vtkSmartPointer<vtkActor>::New();
    actor->SetMapper(mapper);
    double c[3] = {1.0, 0.9, 0.4};
    if (material < s.materials.size()) srgb(s.materials[material].color, c);
    actor->GetProperty()->SetColor(c);
    actor->GetProperty()->SetOpacity(pickable ? 0.45 : 1.0);
    this->SceneRen->AddActor(actor);
    if (pickable) this->Picker->AddPickList(actor);
    this->GeometryActors.push_back(actor);
  };
  for (const rayscope::TriangleMesh& m : s.meshes) {
    vtkNew<vtkPolyData> pd;
    vtkNew<vtkPoints> pts;
    pts->SetDataTypeToDouble();
    for (const rayscope::Vec3& p : m.positions) {
      const rayscope::DVec3 w = s.to_world(p);
      pts->InsertNextPoint(w.x, w.y, w.z);
    }
    vtkNew<vtkCellArray> tris;
    for (const glm::uvec3& t : m.triangles) {
      const vtkIdType ids[3] = {vtkIdType(t.x), vtkIdType(t.y), vtkIdType(t.z)};
      tris->InsertNextCell(3, ids);
    }
    pd->SetPoints(pts);
    pd->SetPolys(tris);
    add(pd, nullptr, m.material, true);
  }
  for (const rayscope::Sphere& sp : s.spheres) {
    vtkNew<vtkSphereSource> src;
    const rayscope::DVec3 c = s.to_world(sp.center);
    src->SetCenter(c.x, c.y, c.z);
    src->SetRadius(sp.radius);
    src->SetThetaResolution(48);
    src->SetPhiResolution(32);
    src->Update();
    add(src->GetOutput(), nullptr, sp.material, true);
  }
  for (const rayscope::Plane& pl : s.planes) {
    // A square of the scene's size around the point of the plane nearest to
    // the scene's center.
    const rayscope::Vec3 n = glm::normalize(pl.normal);
    const rayscope::Vec3 c = b.center() - glm::dot(b.center() - pl.point, n) * n;
    const rayscope::Vec3 t0 = glm::normalize(
        glm::cross(n, std::abs(n.x) < 0.9f ? rayscope::Vec3(1, 0, 0) : rayscope::Vec3(0, 1, 0)));
    const rayscope::Vec3 t1 = glm::cross(n, t0);
    const float h = float(size);
    vtkNew<vtkPlaneSource> src;
    const rayscope::DVec3 o = s.to_world(c - h * t0 - h * t1), p1 = s.to_world(c + h * t0 - h * t1),
                          p2 = s.to_world(c - h * t0 + h * t1);
    src->SetOrigin(o.x, o.y, o.z);
    src->SetPoint1(p1.x, p1.y, p1.z);
    src->SetPoint2(p2.x, p2.y, p2.z);
    src->SetResolution(16, 16);
    src->Update();
    add(src->GetOutput(), nullptr, pl.material, true);
  }
  for (const rayscope::Light& l : s.lights) {
    vtkNew<vtkSphereSource> src;
    src->SetRadius(kLightFraction * size);
    if (l.type == rayscope::Light::Type::Point) {
      const rayscope::DVec3 c = s.to_world(l.position);
      src->SetCenter(c.x, c.y, c.z);
      src->Update();
      add(src->GetOutput(), nullptr, ~0u, false);
      continue;
    }
    // A directional light: a sphere outside the scene where its light comes
    // from, and a line along the way it travels.
    const rayscope::Vec3 d = glm::normalize(l.direction);
    const rayscope::DVec3 from = s.to_world(b.center() - float(size) * d),
                          to = s.to_world(b.center() - float(0.6 * size) * d);
    src->SetCenter(from.x, from.y, from.z);
    src->Update();
    add(src->GetOutput(), nullptr, ~0u, false);
    vtkNew<vtkPolyData> ray;
    vtkNew<vtkPoints> pts;
    pts->InsertNextPoint(from.x, from.y, from.z);
    pts->InsertNextPoint(to.x, to.y, to.z);
    vtkNew<vtkCellArray> line;
    const vtkIdType ids[2] = {0, 1};
    line->InsertNextCell(2, ids);
    ray->SetPoints(pts);
    ray->SetLines(line);
    add(ray, nullptr, ~0u, false);
  }
  this->Normals->SetScaleFactor(kNormalFraction * size);
}

// The camera as the lecture draws it: frustum edges from the eye to the image
// plane (put at a fraction of the way to look_at so that it is in view), the
// plane's outline, the pixel grid around the picked pixel and that pixel.
void vtkRayScopeViewer::Internals::UpdateCameraGeometry() {
  const rayscope::Scene& s = *this->scene();
  const rayscope::Camera& cam = s.camera;
  const rayscope::RenderSettings& rs = this->Settings;
  const float plane = float(kImagePlaneFraction) * glm::length(cam.look_at - cam.eye);
  auto on_plane = [&](float px, float py) {
    const rayscope::Ray r = cam.generate_ray(px, py);
    const float t =
        (plane - glm::dot(r.origin - cam.eye, cam.forward())) / glm::dot(r.dir, cam.forward());
    return r.origin + t * r.dir;
  };
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  vtkNew<vtkCellArray> lines;
  auto point = [&](const rayscope::Vec3& p) {
    const rayscope::DVec3 w = s.to_world(p);
    return pts->InsertNextPoint(w.x, w.y, w.z);
  };
  auto line = [&](const rayscope::Vec3& a, const rayscope::Vec3& b) {
    const vtkIdType ids[2] = {point(a), point(b)};
    lines->InsertNextCell(2, ids);
  };
  const float w = float(rs.width), h = float(rs.height);
  const std::array<std::array<float, 2>, 4> corners = {
      {{0.0f, 0.0f}, {w, 0.0f}, {w, h}, {0.0f, h}}};
  for (size_t k = 0; k < 4; ++k) {
    const auto [px, py] = corners[k];
    line(cam.generate_ray(px, py).origin, on_plane(px, py));
    line(on_plane(px, py), on_plane(corners[(k + 1) % 4][0], corners[(k + 1) % 4][1]));
  }
  vtkNew<vtkCellArray> quad;
  if (this->Self->PickedPixel[0] >= 0) {
    const int x = this->Self->PickedPixel[0], y = rs.height - 1 - this->Self->PickedPixel[1];
    const int x0 = std::max(0, x - kGridRadius), x1 = std::min(rs.width, x + kGridRadius + 1);
    const int y0 = std::max(0, y - kGridRadius), y1 = std::min(rs.height, y + kGridRadius + 1);
    for (int gx = x0; gx <= x1; ++gx)
      line(on_plane(float(gx), float(y0)), on_plane(float(gx), float(y1)));
    for (int gy = y0; gy <= y1; ++gy)
      line(on_plane(float(x0), float(gy)), on_plane(float(x1), float(gy)));
    const vtkIdType ids[4] = {
        point(on_plane(float(x), float(y))), point(on_plane(float(x + 1), float(y))),
        point(on_plane(float(x + 1), float(y + 1))), point(on_plane(float(x), float(y + 1)))};
    quad->InsertNextCell(4, ids);
  }
  this->CameraGeometry->Initialize();
  this->CameraGeometry->SetPoints(pts);
  this->CameraGeometry->SetLines(lines);
  this->PickedCell->Initialize();
  this->PickedCell->SetPoints(pts);
  this->PickedCell->SetPolys(quad);
}

void vtkRayScopeViewer::Internals::UpdateLegend() {
  // Rebuilt only when its entries change: each entry is text to rasterize.
  const bool walk = this->Self->TraversalSteps >= 0;
  const int n = 7 + (walk ? 5 : 0);
  if (this->Legend->GetNumberOfEntries() == n) return;
  this->Legend->SetNumberOfEntries(n);
  vtkSmartPointer<vtkPolyData> symbol = legend_symbol();
  int e = 0;
  for (int k = 0; k < 4; ++k) {
    double c[3] = {kKindColors[k][0], kKindColors[k][1], kKindColors[k][2]};
    this->Legend->SetEntry(e++, symbol, (std::string(kKindNames[k]) + " ray").c_str(), c);
  }
  double gray[3] = {kSkippedColor[0], kSkippedColor[1], kSkippedColor[2]};
  this->Legend->SetEntry(e++, symbol, "skipped (not traced)", gray);
  double orange[3] = {kNormalColor[0], kNormalColor[1], kNormalColor[2]};
  this->Legend->SetEntry(e++, symbol, "shading normal", orange);
  double dark[3] = {kOccluderColor[0], kOccluderColor[1], kOccluderColor[2]};
  this->Legend->SetEntry(e++, symbol, "shadow ray blocked here", dark);
  if (walk)
    for (int k = 1; k < 6; ++k) {
      double c[3] = {kWalkColors[k][0], kWalkColors[k][1], kWalkColors[k][2]};
      this->Legend->SetEntry(e++, symbol, (std::string("BVH: ") + kWalkNames[k]).c_str(), c);
    }
}

// --- Rendering ------------------------------------------------------------------

// The frame loop's statistics policy (cost AOVs for the heat map) that also
// hands each finished tile to the viewer.
struct vtkRayScopeViewer::Internals::Policy : rayscope::StatsPolicy {
  Internals* in;
  explicit Policy(Internals* internals) : in(internals) {}
  void tile_done(int x0, int y0, int x1, int y1, const rayscope::Framebuffer& fb) {
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const size_t i = fb.index(x, y);
        for (int k = 0; k < 3; ++k)
          in->Staging[3 * i + size_t(k)] = (unsigned char)std::lround(
              255.0f * rayscope::linear_to_srgb(std::clamp(fb.color[i][k], 0.0f, 1.0f)));
      }
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
  }
  this->Staging.assign(size_t(w) * size_t(h) * 3, 0);
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
      this->Frame = rayscope::render_frame(*scene, rs, policy, &this->Counters);
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

void vtkRayScopeViewer::Internals::ShowTiles() {
  std::vector<std::array<int, 4>> tiles;
  {
    std::lock_guard<std::mutex> lock(this->TilesMutex);
    tiles.swap(this->FinishedTiles);
  }
  const int w = this->Settings.width, h = this->Settings.height;
  auto* shown = vtkUnsignedCharArray::SafeDownCast(this->Display->GetPointData()->GetScalars());
  for (const auto& t : tiles)
    for (int y = t[1]; y < t[3]; ++y)
      for (int x = t[0]; x < t[2]; ++x)
        for (int k = 0; k < 3; ++k)
          shown->SetTypedComponent(
              vtkIdType(h - 1 - y) * w + x, k,
              this->Staging[3 * (size_t(y) * size_t(w) + size_t(x)) + size_t(k)]);
  this->TilesShown += tiles.size();
  if (!tiles.empty()) {
    this->Display->Modified();
    std::ostringstream m;
    m << "rendering " << w << "x" << h << ", " << this->Settings.samples << "x"
      << this->Settings.samples << " samples, depth " << this->Settings.max_depth << ": "
      << (100 * this->TilesShown) / std::max<size_t>(1, this->TilesTotal) << "% ("
      << this->TilesShown << "/" << this->TilesTotal << " tiles)";
    this->Say(m.str());
  }
}

void vtkRayScopeViewer::Internals::FinishRender() {
  if (!this->RenderError.empty()) {
    this->Say("render failed: " + this->RenderError);
    return;
  }
  this->Self->LastRenderSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - this->RenderStart).count();
  vtkRayScopeImageAlgorithm::FramebufferToImage(this->Frame, this->Counters, this->Image);
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
  if (!this->HasImage) return;
  std::vector<unsigned char> rgb = rayscope_vtk::display_pixels(this->Image, this->Self->ImageMode);
  if (rgb.empty()) rgb = rayscope_vtk::display_pixels(this->Image, rayscope_vtk::kDisplayColor);
  auto* shown = vtkUnsignedCharArray::SafeDownCast(this->Display->GetPointData()->GetScalars());
  std::copy(rgb.begin(), rgb.end(), shown->GetPointer(0));
  this->Display->Modified();
  // The color scale of the cost and depth modes.
  std::string title;
  const bool scale =
      rayscope_vtk::display_scale(this->Image, this->Self->ImageMode, this->ScaleTable, title);
  this->ScaleBar->SetVisibility(scale);
  if (scale) this->ScaleBar->SetTitle(title.c_str());
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
  this->WaitForRender();
  in.LastError.clear();
  if (!in.Algorithm->UpdateScene()) {
    in.Say("cannot render: " + in.LastError);
    in.Redraw();
    return 0;
  }
  in.Settings = in.Algorithm->GetRenderSettings();
  in.StartRender();
  in.Redraw();
  return 1;
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
  vtkRayScopeBVHSource* bvh = this->BVH;
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
  this->PanelActor->SetInput(shown.c_str());
}

// --- Keys ------------------------------------------------------------------------

void vtkRayScopeViewer::SetImageMode(int mode) {
  mode = std::clamp(mode, int(COLOR), int(OBJECT_IDS));
  static_assert(int(COLOR) == rayscope_vtk::kDisplayColor &&
                int(OBJECT_IDS) == rayscope_vtk::kDisplayObjectId);
  if (mode == this->ImageMode) return;
  this->ImageMode = mode;
  this->Internal->ShowImage();
  this->Modified();
}

int vtkRayScopeViewer::HandleKey(const char* keysym) {
  Internals& in = *this->Internal;
  if (!keysym || !in.Initialized) return 0;
  const std::string key = keysym;
  const bool picked = in.HasRecord && this->PickedPixel[0] >= 0;
  const int nrays = picked ? int(in.Record.rays.size()) : 0;
  auto say = [&](const std::string& m) {
    in.Say(m);
    in.Redraw();
    return 1;
  };
  auto need_pick = [&] { return say(key + ": pick a pixel first (click the image)"); };
  auto refresh = [&](const std::string& m) {
    in.UpdateOverlay();
    in.UpdateLegend();
    return say(m);
  };
  auto rerender = [&](const std::string& m) {
    if (this->Rerender()) in.Say(m);
    in.Redraw();
    return 1;
  };
  using RS = rayscope::RenderSettings;
  vtkRayScopeImageAlgorithm* alg = in.Algorithm;

  if (key == "Up" || key == "Down") {
    if (!picked) return need_pick();
    const bool up = key == "Up";
    if (up && this->ShownDepth >= in.RecordDepth)
      return say("Up: the whole tree is shown (its deepest ray has depth " +
                 std::to_string(in.RecordDepth) + ")");
    if (!up && this->ShownDepth <= 0) return say("Down: only the primary rays are shown");
    this->ShownDepth += up ? 1 : -1;
    return refresh("showing rays up to depth " + std::to_string(this->ShownDepth));
  }
  if (key == "Right" || key == "Left") {
    if (!picked) return need_pick();
    if (key == "Right" && this->SelectedRay >= nrays - 1)
      return say("Right: ray #" + std::to_string(nrays - 1) + " is the last ray traced");
    if (key == "Left" && this->SelectedRay < 0)
      return say("Left: no ray is selected (every ray is shown); Right selects the first");
    this->SelectedRay += key == "Right" ? 1 : -1;
    this->TraversalSteps = -1;
    return refresh(this->SelectedRay < 0
                       ? std::string("every ray shown")
                       : "ray #" + std::to_string(this->SelectedRay) + " selected (" +
                             rayscope::to_string(in.Record.rays[size_t(this->SelectedRay)].kind) +
                             "); rays after it are hidden");
  }
  if (key == "t" || key == "T") {
    if (!picked) return need_pick();
    if (this->SelectedRay < 0) this->SelectedRay = 0;
    const rayscope::RayRecord& r = in.Record.rays[size_t(this->SelectedRay)];
    const int entries = int(r.traversal.nodes().size());
    const std::string ray = "ray #" + std::to_string(r.id);
    if (r.skipped) return say("t: " + ray + " was not traced, so it has no walk");
    if (key == "t") {
      if (this->TraversalSteps >= entries)
        return say("t: the walk of " + ray + " is complete (" + std::to_string(entries) +
                   " nodes entered)");
      this->TraversalSteps = std::max(0, this->TraversalSteps) + 1;
    } else {
      if (this->TraversalSteps < 0) return say("T: no walk is playing (t plays one)");
      --this->TraversalSteps;  // from 0: the walk is no longer played
    }
    return refresh(this->TraversalSteps < 0
                       ? std::string("walk hidden")
                       : "walk of " + ray + ": " + std::to_string(this->TraversalSteps) + " of " +
                             std::to_string(entries) + " nodes entered");
  }
  if (key == "b") {
    this->ShowBVH = !this->ShowBVH;
    if (!picked) {  // without a pick the BVH is still worth seeing
      in.UpdateBVH();
      return say(this->ShowBVH ? "BVH shown" : "BVH hidden");
    }
    return refresh(this->ShowBVH ? "BVH shown" : "BVH hidden");
  }
  if (key == "l" || key == "L") {
    const rayscope::Scene& s = *in.scene();
    const int depth = int(s.bvh().quality().depth);
    if (key == "l" && this->BVHLevel >= depth - 1)
      return say("l: level " + std::to_string(this->BVHLevel) + " is the deepest of the BVH");
    if (key == "L" && this->BVHLevel < 0) return say("L: every level is shown");
    this->BVHLevel += key == "l" ? 1 : -1;
    this->ShowBVH = true;
    const std::string m =
        this->BVHLevel < 0 ? "BVH: every level" : "BVH: level " + std::to_string(this->BVHLevel);
    if (picked) return refresh(m);
    in.UpdateBVH();
    return say(m);
  }
  if (key == "k") {
    this->ShownKind = this->ShownKind >= 3 ? -1 : this->ShownKind + 1;
    const std::string m = this->ShownKind < 0
                              ? std::string("every ray kind shown")
                              : std::string("only ") + kKindNames[this->ShownKind] + " rays shown";
    return picked ? refresh(m) : say(m);
  }
  if (key == "m") {
    const int mode = (this->ImageMode + 1) % rayscope_vtk::kDisplayModes;
    if (in.HasImage && rayscope_vtk::display_pixels(in.Image, mode).empty())
      return say(std::string("m: the image has no data for ") +
                 rayscope_vtk::display_mode_name(mode));
    this->SetImageMode(mode);
    return say(std::string("image: ") + rayscope_vtk::display_mode_name(mode));
  }
  if (key == "plus" || key == "KP_Add" || key == "minus" || key == "KP_Subtract") {
    const bool up = key == "plus" || key == "KP_Add";
    const int spp = alg->GetSamples();
    if (up && spp >= RS::kMaxSamples)
      return say("+: samples per pixel at their maximum, " + std::to_string(spp) + "x" +
                 std::to_string(spp));
    if (!up && spp <= 1) return say("-: samples per pixel at their minimum, 1x1");
    alg->SetSamples(spp + (up ? 1 : -1));
    return rerender("re-rendering with " + std::to_string(alg->GetSamples()) + "x" +
                    std::to_string(alg->GetSamples()) + " samples per pixel");
  }
  if (key == "bracketright" || key == "bracketleft") {
    const bool up = key == "bracketright";
    const int d = alg->GetMaxDepth();
    if (up && d >= RS::kMaxDepth) return say("]: maximum depth at its limit, " + std::to_string(d));
    if (!up && d <= 0) return say("[: maximum depth already 0 (primary rays only)");
    alg->SetMaxDepth(d + (up ? 1 : -1));
    this->ShownDepth = VTK_INT_MAX;
    return rerender("re-rendering with maximum depth " + std::to_string(alg->GetMaxDepth()));
  }
  if (key == "d") {
    this->ShowLabels = !this->ShowLabels;
    const std::string m = this->ShowLabels ? "ray labels: #id, depth, weight" : "ray labels hidden";
    if (!picked) return say(m);
    return refresh(m);
  }
  if (key == "p") {
    // Central <-> parallel projection, for contrast; the parallel view shows
    // what the central one shows at the focal point.
    const bool parallel = !alg->GetParallelProjection();
    if (parallel) {
      double eye[3], at[3];
      alg->GetPosition(eye);
      alg->GetFocalPoint(at);
      const double d = std::sqrt(vtkMath::Distance2BetweenPoints(eye, at));
      alg->SetParallelScale(d * std::tan(0.5 * vtkMath::RadiansFromDegrees(alg->GetViewAngle())));
    }
    alg->SetParallelProjection(parallel);
    return rerender(parallel ? "re-rendering with a parallel projection"
                             : "re-rendering with the central projection");
  }
  if (key == "r") {
    alg->CopyCamera(in.SceneRen->GetActiveCamera());
    return rerender("re-rendering from the 3D view's camera");
  }
  if (key == "s") {
    const std::string file =
        std::string(this->OutputPrefix) + "_" + std::to_string(++in.ScreenshotCount) + ".png";
    return say(this->SaveScreenshot(file.c_str()) ? "screenshot: " + file
                                                  : "screenshot failed: " + in.Message);
  }
  if (key == "x") {
    const std::string prefix =
        std::string(this->OutputPrefix) + "_" + std::to_string(++in.ExportCount);
    if (!picked) return need_pick();
    return say(this->ExportVTP(prefix.c_str())
                   ? "exported " + prefix + "_raytree.vtp and " + prefix + "_bvh.vtp"
                   : "export failed: " + in.Message);
  }
  return 0;
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
  vtkNew<vtkRayScopeBVHSource> all;
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
  os << indent << "ImageMode: " << rayscope_vtk::display_mode_name(this->ImageMode) << "\n";
  os << indent << "OutputPrefix: " << (this->OutputPrefix ? this->OutputPrefix : "") << "\n";
}
