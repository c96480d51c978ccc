// The private state of vtkRayScopeViewer, shared by its source files, one
// per part of the viewer:
//   vtkRayScopeViewer.cxx               the API: setup, picking, screenshots, .vtp export
//   RayScopeViewerWindow.cxx            the window, its viewports, the image viewport and
//                                       the scene drawn in 3D (objects, lights, camera)
//   RayScopeViewerBackgroundRender.cxx  the render on the worker thread feeding the image
//   RayScopeViewerOverlay.cxx           the 3D overlay: the picked pixel's rays, hit
//                                       points, normals, labels, the structure's boxes
//                                       and the selected ray's walk
//   RayScopeViewerTextPanel.cxx         the text: help and message lines, the inspect
//                                       panel, the legend
//   RayScopeViewerTreeDiagram.cxx       the panel's tree diagram of the ray tree (key g)
//   RayScopeViewerKeyTable.cxx          the table of keys, from which HandleKey() and
//                                       the help line are made
//   vtkRayScopeViewerStyle.h/.cxx       the interactor style
// Private header.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "vtkActor.h"
#include "vtkActor2D.h"
#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellPicker.h"
#include "vtkCommand.h"
#include "vtkCoordinate.h"
#include "vtkDataSetMapper.h"
#include "vtkDataSetSurfaceFilter.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkGlyph3D.h"
#include "vtkHedgeHog.h"
#include "vtkImageActor.h"
#include "vtkImageData.h"
#include "vtkImageMapper3D.h"
#include "vtkIntArray.h"
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
#include "vtkRenderStepsPass.h"
#include "vtkRenderWindow.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkScalarBarActor.h"
#include "vtkSmartPointer.h"
#include "vtkSphereSource.h"
#include "vtkStdString.h"
#include "vtkStringArray.h"
#include "vtkTextActor.h"
#include "vtkTextProperty.h"
#include "vtkTextRenderer.h"
#include "vtkThreshold.h"
#include "vtkTubeFilter.h"
#include "vtkUnsignedCharArray.h"
#include "vtkWindowToImageFilter.h"
#include "vtkXMLPolyDataWriter.h"

#include "RayScopeDisplay.h"
#include "rayscope/frame.h"
#include "rayscope/image.h"
#include "rayscope/packet_replay.h"
#include "rayscope/raytree_format.h"
#include "rayscope/replay.h"
#include "rayscope_vtkio/image_arrays.h"
#include "vtkRayScopeAccelSource.h"
#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopeRayTreeSource.h"
#include "vtkRayScopeViewer.h"

namespace rayscope_vtkmodule::viewer {

// Layout of the window (fractions of its size): the header on top (at least
// kHeaderBottom; taller when the help line wraps, LayoutHeader()), the image
// and the 3D view side by side, the text panel below.
inline constexpr double kHeaderBottom = 0.95;
inline constexpr double kPanelTop = 0.30;
inline constexpr int kProgressTimerMs = 40;    // how often finished tiles are shown
inline constexpr int kPanelLines = 18;         // lines of the inspect text shown at once, most
inline constexpr int kPanelLinesBefore = 4;    // of them, before the selected ray's line
inline constexpr int kPanelLeastColumns = 40;  // characters a panel line is broken at, least
inline constexpr int kGridRadius = 4;          // pixel grid shown: the picked pixel +- this
inline constexpr double kImagePlaneFraction = 0.25;  // image plane at this fraction of eye..look_at
inline constexpr double kNormalFraction = 0.04;  // normals drawn this fraction of the scene size
inline constexpr double kLightFraction = 0.015;  // light markers' radius, same
inline constexpr unsigned char kUnrenderedGray = 40;  // pixels not rendered yet
inline constexpr double kSceneZoom =
    1.6;  // the 3D view, closer than VTK's ResetCamera (a bounding sphere)
inline constexpr double kSceneViewAngle = 30.0;  // degrees: VTK's default, before the zoom

// Colors of the overlay (the ray kinds' are vtkRayScopeRayTreeSource's):
// skipped rays, markers, and the played walk's states (vtkRayScopeAccelSource
// order).
inline constexpr double kSkippedColor[3] = {0.5, 0.5, 0.5};
inline constexpr double kNormalColor[3] = {1.0, 0.55, 0.1};
inline constexpr double kPickColor[3] = {1.0, 0.1, 0.1};
inline constexpr double kSelectedColor[3] = {1.0, 1.0, 1.0};
inline constexpr double kOccluderColor[3] = {0.95, 0.2, 0.15};
inline constexpr int kEndOccluder =
    3;  // vtkRayScopeRayTreeSource's EndKind of a blocked shadow ray
// The walk's colors share no hue with the ray kinds' (yellow, blue, green,
// magenta), so that a box is never taken for a ray: boxes hit but not
// entered lavender, missed dark red, entered cyan, culled tan, the hit leaf
// white.
inline constexpr double kWalkColors[6][3] = {{0, 0, 0},          {0.7, 0.6, 1.0},
                                             {0.75, 0.15, 0.15}, {0.0, 0.85, 0.85},
                                             {0.8, 0.6, 0.35},   {1.0, 1.0, 1.0}};
inline constexpr const char* kWalkNames[6] = {"",        "box hit, not entered yet",   "box missed",
                                              "entered", "culled (early termination)", "hit leaf"};
inline constexpr int kDiagramMostLabels = 64;     // rays of a tree diagram named "#id"
inline constexpr double kDiagramDim = 0.3;        // brightness of the rays the 3D view hides
inline constexpr double kWalkCurrentWidth = 5.0;  // line width of the node entered last
inline constexpr double kWalkBoxWidth = 1.5;      // and of every other box

// The panel's line before a pick.
inline constexpr const char* kPickPrompt = "click a pixel of the image (left) or a surface (right)";

// The window's viewports, as bits of Internals::Changed.
inline constexpr unsigned kHeaderView = 1, kImageView = 2, kSceneView = 4, kPanelView = 8,
                          kAllViews = 15;

}  // namespace rayscope_vtkmodule::viewer

class vtkRayScopeViewerStyle;

struct vtkRayScopeViewer::Internals {
  vtkRayScopeViewer* Self;
  vtkSmartPointer<vtkRayScopeImageAlgorithm> Algorithm;
  vtkNew<vtkRenderWindow> Window;
  vtkNew<vtkRenderWindowInteractor> Interactor;
  vtkNew<vtkRenderer> ImageRen, SceneRen, PanelRen, HeaderRen;
  bool Initialized = false;
  std::string LastError, Message, InspectText, PanelText;
  // The picked pixel's packet (key c), replayed when shown, and its text.
  rayscope::PacketReplay Packet;
  std::string PacketText;

  // The image: the last finished render with every array, and what is shown;
  // Next is the image the running render fills, tile by tile, on the worker's
  // threads (with the arrays of the image before the last: a render allocates
  // nothing once the size is set).
  vtkNew<vtkImageData> Image, Display, Next;
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
  rayscope::RayCounters Counters;
  // The worker's framebuffer, kept from frame to frame (its pixels are copied
  // into Next as tiles finish; only the worker touches it).
  rayscope::Framebuffer Frame;
  std::string RenderError;
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
  // The shown rays as polydata, cells in the tree's order (VTK 9.1's
  // vtkGeometryFilter, threaded, orders them differently from run to run).
  vtkNew<vtkDataSetSurfaceFilter> Shown;
  vtkNew<vtkActor> TracedActor, SkippedActor, NormalActor, SelectedActor;
  vtkSmartPointer<vtkThreshold> Selected;
  vtkNew<vtkPolyData> Labels;  // a point per shown ray, at its middle, with its label
  vtkNew<vtkActor2D> LabelActor;
  vtkNew<vtkPolyData> Occluders;  // where shown shadow rays are blocked
  vtkNew<vtkActor> OccluderActor;
  vtkNew<vtkHedgeHog> Normals;
  vtkNew<vtkRayScopeAccelSource> BVH;
  vtkNew<vtkPolyData> NoBoxes;
  vtkNew<vtkPolyDataMapper> BVHMapper;
  vtkNew<vtkActor> BVHActor;
  vtkSmartPointer<vtkLookupTable> LevelTable, WalkTable;
  // The tree diagram in the panel (key g): dots and lines in the panel's
  // pixels, with cell colors; the rays' names in window pixels.
  vtkNew<vtkPolyData> Diagram, DiagramLabels;
  vtkNew<vtkActor2D> DiagramActor, DiagramLabelActor;
  // A played walk's order: each entered node's step number at a corner of
  // its box, and the node entered last (the walk's current node) drawn thick.
  vtkNew<vtkPolyData> WalkSteps, WalkCurrent;
  vtkNew<vtkActor2D> WalkStepActor;
  vtkNew<vtkActor> WalkCurrentActor;
  // The picked pixel's packet (key c): the box of each node it entered,
  // colored by the rays active there (PacketTable: 1 to 16).
  vtkNew<vtkPolyData> PacketBoxes;
  vtkNew<vtkActor> PacketBoxActor;
  vtkSmartPointer<vtkLookupTable> PacketTable;
  /// Fills PacketBoxes from Packet and shows them with ShowPacket.
  void UpdatePacketBoxes();

  // The scene in 3D.
  std::vector<vtkSmartPointer<vtkActor>> GeometryActors;
  vtkNew<vtkPolyData> CameraGeometry, PickedCell;
  vtkNew<vtkActor> CameraActor, PickedCellActor;
  vtkNew<vtkCellPicker> Picker;

  // The text: the legend of the 3D view, the help and message lines, the
  // inspect panel.
  vtkNew<vtkLegendBoxActor> Legend;
  /// What the legend shows now (label, color), to rebuild it only on a change.
  std::vector<std::pair<std::string, std::array<double, 3>>> LegendEntries;
  vtkNew<vtkTextActor> HelpActor, MessageActor;
  /// The panel's lines, one text actor each (kPanelLines): a line keeps its
  /// actor, and the texture FreeType drew for it, while it stays on the
  /// panel, even when it moves; only new lines are drawn again.
  std::vector<vtkSmartPointer<vtkTextActor>> PanelLines;
  std::vector<std::string> PanelLineText;  // what each of them shows
  int PanelLineHeight = 0;                 // pixels from one line to the next
  double PanelCharWidth = 7.0;             // pixels of one character (Courier)

  // A lecture's chapters (AddChapter()) and the caption on top of the 3D
  // view.
  struct ChapterEntry {
    vtkSmartPointer<vtkRayScopeImageAlgorithm> Source;
    std::string Title, Caption;
    int Pick[2];
    std::vector<std::string> Keys;
  };
  std::vector<ChapterEntry> Chapters;
  vtkNew<vtkTextActor> CaptionActor;
  std::string Caption;
  /// Keeps the error of a source (the scene, the ray tree, the structure) in
  /// LastError, without VTK's "ERROR: In FILE, line N" prefix.
  vtkNew<vtkCallbackCommand> OnError;

  vtkSmartPointer<vtkRayScopeViewerStyle> Style;
  int ScreenshotCount = 0, ExportCount = 0;
  /// The viewports changed since the window was last drawn (k*View bits).
  unsigned Changed = 0;

  explicit Internals(vtkRayScopeViewer* self) : Self(self) {}

  ~Internals() {
    if (this->Worker.joinable()) this->Worker.join();
  }

  rayscope::Scene* scene() { return this->Algorithm->GetCoreScene(); }
  /// Keeps `source`'s errors in LastError (OnError), once per source.
  void WatchErrors(vtkObject* source) {
    if (!source->HasObserver(vtkCommand::ErrorEvent, this->OnError))
      source->AddObserver(vtkCommand::ErrorEvent, this->OnError);
  }
  /// A text's size in points at the viewer's FontScale (`points` at 1).
  int FontSize(int points) const {
    return std::max(1, int(std::lround(points * this->Self->GetFontScale())));
  }
  /// The structure the 3D view draws, as the window names it: "BVH" (also
  /// for bvh2 and none, which show the binary BVH), else the --accel name of
  /// the structure the rays walk ("kdtree", "grid", "octree", ...).
  std::string StructureLabel() {
    const rayscope::Aggregate& a = this->scene()->accel();
    return std::holds_alternative<rayscope::BvhWalk>(a.structure()) ||
                   std::holds_alternative<rayscope::BruteForce>(a.structure())
               ? std::string("BVH")
               : std::string(rayscope::to_string(a.kind()));
  }

  // The window (RayScopeViewerWindow.cxx).
  void Build();
  void BuildSceneGeometry();
  void UpdateCameraGeometry();
  /// Points the 3D view's camera, keeping its direction of view, so that
  /// the box `bounds` (xmin, xmax, ymin, ...) fills it: VTK's ResetCamera
  /// (the box's bounding sphere in view) at kSceneViewAngle, then `zoom`.
  void AimSceneCamera(const double bounds[6], double zoom);
  /// Frames the whole scene, its objects and its camera's eye and look-at
  /// point (as at the start; key F).
  void FrameScene();
  void UpdateMarker();
  void Redraw();

  // The render on the worker thread (RayScopeViewerBackgroundRender.cxx).
  struct Policy;
  void StartProgressTimer();
  void StartRender();
  bool Restart(const std::string& message);
  void Poll();
  void ShowTiles();
  void FinishRender();
  void ShowImage();

  // The 3D overlay (RayScopeViewerOverlay.cxx).
  void BuildOverlay();
  void UpdateOverlay();
  void UpdateBVH();
  void UpdateLabels();
  void UpdateOccluders();
  /// The played walk's step numbers and current node (WalkSteps,
  /// WalkCurrent) from the structure source's output; hidden when no walk
  /// is played.
  void UpdateWalkOrder(bool played);
  /// Hides the overlay of the pick (rays, labels, markers, boxes, panel): a
  /// new scene has no picked pixel.
  void ClearOverlay();

  // The tree diagram (RayScopeViewerTreeDiagram.cxx).
  void BuildTreeDiagram();
  /// Lays out the picked pixel's tree in the panel (shown with
  /// ShowTreeDiagram, else hidden).
  void UpdateTreeDiagram();

  // The text (RayScopeViewerTextPanel.cxx).
  void BuildTextPanel();
  /// Wraps the help line at its " | " to the window's width and makes the
  /// header tall enough for it and the message line below it (the image and
  /// the 3D view take the rest): at a large FontScale or in a narrow window
  /// the help line no longer runs off the right edge.
  void LayoutHeader();
  /// `text` broken into lines no wider than `room` pixels in `prop`'s font,
  /// at each `sep` (which a broken line drops); a piece wider than `room`
  /// keeps a line of its own.
  std::string WrapText(vtkTextProperty* prop, const std::string& text, const std::string& sep,
                       int room) const;
  /// Lays out the caption (Caption) on top of the 3D view, wrapped to its
  /// width.
  void ShowCaption();
  void Say(const std::string& message);
  void UpdatePanel();
  void ShowPanelLines(const std::vector<std::string>& lines);
  void UpdateLegend();

  // The keys (RayScopeViewerKeyTable.cxx): one table, from which
  // HandleKey() and the help line are made.
  struct Key;
  struct KeyPress;
  static const std::vector<Key>& KeyTable();
  static const std::string& HelpLine();
};
