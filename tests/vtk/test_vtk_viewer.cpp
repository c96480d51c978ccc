// vtkRayScopeViewer, driven headlessly through its interactor: synthesized
// clicks and keys (SetEventInformation + InvokeEvent), and what the window
// then shows checked against the core's recorder. Opens an OpenGL window: run
// under xvfb-run.
#include <gtest/gtest.h>

#include "needs_display.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <vtkActor2DCollection.h>
#include <vtkBoundingBox.h>
#include <vtkCamera.h>
#include <vtkCell.h>
#include <vtkCellData.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkLegendBoxActor.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkRenderWindow.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>
#include <vtkRendererCollection.h>
#include <vtkStringArray.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>
#include <vtkXMLPolyDataReader.h>

#include "rayscope/accel/accel_view.h"
#include "rayscope/image.h"
#include "rayscope/packet_replay.h"
#include "rayscope/render.h"
#include "rayscope/replay.h"
#include "rayscope/shapes.h"
#include "vtkRayScopeAccelSource.h"
#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopeRayTreeSource.h"
#include "vtkRayScopeViewer.h"

namespace {

constexpr int kW = 120, kH = 90;
// A pixel of the default scene on the glass sphere (VTK image coordinates):
// primary, shadow, reflection and refraction rays, skipped ones too.
constexpr int kGlassI = 49, kGlassJ = kH - 1 - 52;

struct Fixture {
  rayscope::Scene scene;
  rayscope::RenderSettings settings;
  vtkNew<vtkRayScopeImageAlgorithm> alg;
  vtkNew<vtkRayScopeViewer> viewer;

  explicit Fixture(int max_depth = 3, rayscope::Scene s = rayscope::make_default_scene())
      : scene(std::move(s)) {
    scene.commit();
    alg->SetSize(kW, kH);
    alg->SetSamples(1);
    alg->SetMaxDepth(max_depth);
    alg->SetThreads(2);
    alg->SetCoreScene(scene);
    viewer->SetSceneSource(alg);
    viewer->SetWindowSize(1000, 640);
    viewer->SetOutputPrefix(out("viewer").c_str());
  }

  static std::string out(const std::string& name) {
    std::filesystem::create_directories(RAYSCOPE_TEST_OUTPUT_DIR);
    return (std::filesystem::path(RAYSCOPE_TEST_OUTPUT_DIR) / name).string();
  }

  bool start() { return viewer->Initialize() && viewer->WaitForRender(); }
  // start(), then pick the glass pixel.
  bool start_on_glass() { return start() && viewer->PickPixel(kGlassI, kGlassJ); }

  // The core's record of pixel (i, j) (VTK coordinates), as the viewer has it.
  rayscope::PixelRecord record(int i, int j) {
    rayscope::RenderSettings rs = alg->GetRenderSettings();
    return rayscope::record_pixel(*alg->GetCoreScene(), rs, i, rs.height - 1 - j);
  }

  // Display position of pixel (i, j)'s center in the image viewport.
  void pixel_display(int i, int j, int& x, int& y) {
    vtkRenderer* ren = viewer->GetImageRenderer();
    ren->SetWorldPoint(i, j, 0.0, 1.0);
    ren->WorldToDisplay();
    double d[3];
    ren->GetDisplayPoint(d);
    x = int(std::lround(d[0]));
    y = int(std::lround(d[1]));
  }

  void click(int x, int y) {
    vtkRenderWindowInteractor* iren = viewer->GetInteractor();
    iren->SetEventInformation(x, y, 0, 0);
    iren->InvokeEvent(vtkCommand::LeftButtonPressEvent);
    iren->InvokeEvent(vtkCommand::LeftButtonReleaseEvent);
  }

  void key(const char* keysym) {
    vtkRenderWindowInteractor* iren = viewer->GetInteractor();
    const char code = std::strlen(keysym) == 1 ? keysym[0] : 0;
    iren->SetEventInformation(0, 0, 0, 0, code, 1, keysym);
    iren->InvokeEvent(vtkCommand::KeyPressEvent);
    iren->InvokeEvent(vtkCommand::CharEvent);
  }
};

// Line cells of the shown rays by kind, and the hit points by ray id.
std::map<int, int> lines_by_kind(vtkPolyData* pd) {
  std::map<int, int> n;
  vtkDataArray* kind = pd->GetCellData()->GetArray("Kind");
  for (vtkIdType c = 0; c < pd->GetNumberOfCells(); ++c)
    if (pd->GetCellType(c) == VTK_LINE) n[int(kind->GetTuple1(c))]++;
  return n;
}

std::map<int, int> recorded_by_kind(const rayscope::PixelRecord& rec, int max_depth = 1 << 30,
                                    int max_id = 1 << 30) {
  std::map<int, int> n;
  for (const rayscope::RayRecord& r : rec.rays)
    if (r.depth <= max_depth && r.id <= max_id) n[int(r.kind)]++;
  return n;
}

// NodeId of the boxes shown with each TraversalState.
std::map<int, std::set<int>> boxes_by_state(vtkPolyData* pd) {
  std::map<int, std::set<int>> out;
  vtkDataArray* state = pd->GetCellData()->GetArray("TraversalState");
  vtkDataArray* node = pd->GetCellData()->GetArray("NodeId");
  if (!state || !node) return out;
  for (vtkIdType c = 0; c < pd->GetNumberOfCells(); ++c)
    out[int(state->GetTuple1(c))].insert(int(node->GetTuple1(c)));
  return out;
}

bool png_varies(const std::string& file) {
  if (!std::filesystem::exists(file)) return false;
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkDataArray* a = reader->GetOutput()->GetPointData()->GetScalars();
  if (!a) return false;
  for (int k = 0; k < a->GetNumberOfComponents(); ++k) {
    double r[2];
    a->GetRange(r, k);
    if (r[1] > r[0]) return true;
  }
  return false;
}

}  // namespace

// Skipped without an X display (needs_display.h).
class Viewer : public rayscope_test::DisplayTest {};

// The progressive render shows exactly the image the image algorithm makes.
TEST_F(Viewer, ShownImageEqualsTheImageAlgorithm) {
  Fixture f;
  ASSERT_TRUE(f.start()) << f.viewer->GetMessage();
  vtkNew<vtkRayScopeImageAlgorithm> ref;
  ref->SetSize(kW, kH);
  ref->SetSamples(1);
  ref->SetMaxDepth(3);
  ref->SetThreads(2);
  ref->SetCoreScene(f.scene);
  ref->Update();
  auto* want = vtkUnsignedCharArray::SafeDownCast(ref->GetOutput()->GetPointData()->GetScalars());
  auto* got =
      vtkUnsignedCharArray::SafeDownCast(f.viewer->GetShownImage()->GetPointData()->GetScalars());
  ASSERT_NE(want, nullptr);
  ASSERT_NE(got, nullptr);
  ASSERT_EQ(got->GetNumberOfValues(), want->GetNumberOfValues());
  for (vtkIdType v = 0; v < got->GetNumberOfValues(); ++v)
    ASSERT_EQ(got->GetValue(v), want->GetValue(v)) << "value " << v;
  EXPECT_GT(f.viewer->GetLastRenderSeconds(), 0.0);
  EXPECT_NE(std::string(f.viewer->GetMessage()).find("rendered 120x90"), std::string::npos)
      << f.viewer->GetMessage();
}

// A synthesized click on the image picks that pixel; the overlay has as many
// rays of each kind as the recorder, and hit points at the recorded points.
TEST_F(Viewer, ClickOnTheImageShowsTheRecordedTree) {
  Fixture f;
  ASSERT_TRUE(f.start());
  int x, y;
  f.pixel_display(kGlassI, kGlassJ, x, y);
  f.click(x, y);
  ASSERT_EQ(f.viewer->GetPickedPixel()[0], kGlassI);
  ASSERT_EQ(f.viewer->GetPickedPixel()[1], kGlassJ);
  const rayscope::PixelRecord rec = f.record(kGlassI, kGlassJ);
  std::map<int, int> want = recorded_by_kind(rec);
  ASSERT_EQ(want.size(), 4u) << "the pixel should show every ray kind";
  int skipped = 0;
  for (const rayscope::RayRecord& r : rec.rays) skipped += r.skipped;
  EXPECT_GT(skipped, 0);
  vtkPolyData* shown = f.viewer->GetShownRays();
  EXPECT_EQ(lines_by_kind(shown), want);
  // Hit points: one vertex per closest hit, at the recorded point.
  vtkDataArray* ray_id = shown->GetCellData()->GetArray("RayId");
  int verts = 0;
  for (vtkIdType c = 0; c < shown->GetNumberOfCells(); ++c) {
    if (shown->GetCellType(c) != VTK_VERTEX) continue;
    ++verts;
    const rayscope::RayRecord& r = rec.rays[size_t(ray_id->GetTuple1(c))];
    ASSERT_TRUE(r.hit);
    double p[3];
    shown->GetPoint(shown->GetCell(c)->GetPointId(0), p);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(p[k], r.point[k], 1e-5) << "ray " << r.id;
  }
  int hits = 0;
  for (const rayscope::RayRecord& r : rec.rays)
    hits += r.kind != rayscope::RayKind::Shadow && r.hit;
  EXPECT_EQ(verts, hits);
  // A marker where each occluded shadow ray is blocked: at its line's end.
  int occluded = 0;
  for (const rayscope::RayRecord& r : rec.rays) occluded += r.occluded;
  EXPECT_GT(occluded, 0);
  vtkPolyData* markers = f.viewer->GetOccluderMarkers();
  ASSERT_EQ(markers->GetNumberOfVerts(), occluded);
  vtkDataArray* end_kind = shown->GetCellData()->GetArray("EndKind");
  std::vector<std::array<double, 3>> ends;
  for (vtkIdType c = 0; c < shown->GetNumberOfCells(); ++c)
    if (shown->GetCellType(c) == VTK_LINE && end_kind->GetTuple1(c) == 3) {
      std::array<double, 3> e;
      shown->GetPoint(shown->GetCell(c)->GetPointId(1), e.data());
      ends.push_back(e);
    }
  ASSERT_EQ(ends.size(), size_t(occluded));
  for (vtkIdType k = 0; k < markers->GetNumberOfPoints(); ++k)
    for (int d = 0; d < 3; ++d) EXPECT_EQ(markers->GetPoint(k)[d], ends[size_t(k)][d]);
  // The text panel is the inspect text.
  EXPECT_NE(std::string(f.viewer->GetInspectText()).find("pixel (49, 52)"), std::string::npos);
}

// A click outside the image (in the image viewport's margin or past the
// image) changes nothing.
TEST_F(Viewer, ClickOutsideTheImageDoesNothing) {
  Fixture f;
  ASSERT_TRUE(f.start());
  EXPECT_EQ(f.viewer->PickPixel(kW, 3), 0);
  EXPECT_EQ(f.viewer->PickPixel(-1, 3), 0);
  int x, y, clicked = 0;
  // The pixels just above and below, or left and right of the image: in its
  // viewport's margin (which sides have one depends on the viewport's shape).
  for (const std::array<int, 2> ij :
       {std::array<int, 2>{kW / 2, kH}, {kW / 2, -1}, {-1, kH / 2}, {kW, kH / 2}}) {
    f.pixel_display(ij[0], ij[1], x, y);
    if (!f.viewer->GetImageRenderer()->IsInViewport(x, y)) continue;
    f.click(x, y);
    ++clicked;
    EXPECT_EQ(f.viewer->GetPickedPixel()[0], -1) << ij[0] << ", " << ij[1];
  }
  EXPECT_GE(clicked, 2);
}

// Clicking a surface in the 3D view picks the pixel that sees that point.
TEST_F(Viewer, ClickOnASurfaceIn3DPicksItsPixel) {
  Fixture f;
  ASSERT_TRUE(f.start());
  const rayscope::PixelRecord rec = f.record(kGlassI, kGlassJ);
  ASSERT_TRUE(rec.rays[0].hit);
  vtkRenderer* ren = f.viewer->GetSceneRenderer();
  const rayscope::Vec3 p = rec.rays[0].point;
  ren->SetWorldPoint(p.x, p.y, p.z, 1.0);
  ren->WorldToDisplay();
  double d[3];
  ren->GetDisplayPoint(d);
  ASSERT_TRUE(ren->IsInViewport(int(d[0]), int(d[1])));
  f.click(int(std::lround(d[0])), int(std::lround(d[1])));
  // The 3D view's pixel grid is coarser than the image's: within a pixel.
  EXPECT_NEAR(f.viewer->GetPickedPixel()[0], kGlassI, 1);
  EXPECT_NEAR(f.viewer->GetPickedPixel()[1], kGlassJ, 1);
}

// A scene of a tube and a point over a floor: a pixel on the tube shows the
// recorded tree (its hit point on the tube, the text naming the tube set),
// and the tube and the point are drawn in the 3D view, where a click on
// either picks the pixel that sees it.
TEST_F(Viewer, TubesAndPointsAreShownAndPicked) {
  rayscope::Scene scene;
  scene.camera.eye = rayscope::Vec3(0, 0, 5);
  scene.camera.look_at = rayscope::Vec3(0);
  scene.materials.push_back(rayscope::Material{});
  rayscope::TubeSet tube;
  tube.name = "wire";
  tube.positions = {rayscope::Vec3(-1, 0.3f, 0), rayscope::Vec3(1, 0.3f, 0)};
  tube.segments = {{0, 1}};
  tube.radius = 0.15f;
  scene.tubes.push_back(tube);
  rayscope::PointSet dot;
  dot.name = "dot";
  dot.positions = {rayscope::Vec3(0, -0.5f, 0)};
  dot.radius = 0.25f;
  scene.points.push_back(dot);
  rayscope::Plane floor;
  floor.point = rayscope::Vec3(0, 0, -1);
  floor.normal = rayscope::Vec3(0, 0, 1);
  scene.planes.push_back(floor);
  rayscope::Light light;
  light.position = rayscope::Vec3(0, 3, 5);
  scene.lights.push_back(light);
  Fixture f(3, scene);
  ASSERT_TRUE(f.start()) << f.viewer->GetMessage();

  // The pixels of the middle column that see the tube and the point.
  int tube_j = -1, dot_j = -1;
  for (int j = 0; j < kH; ++j) {
    const rayscope::PixelRecord rec = f.record(kW / 2, j);
    if (!rec.rays[0].hit) continue;
    if (rec.rays[0].object == 0 && tube_j < 0) tube_j = j;
    if (rec.rays[0].object == 1 && dot_j < 0) dot_j = j;
  }
  ASSERT_GE(tube_j, 0) << "no pixel of the middle column sees the tube";
  ASSERT_GE(dot_j, 0) << "no pixel of the middle column sees the point";

  int x, y;
  f.pixel_display(kW / 2, tube_j, x, y);
  f.click(x, y);
  ASSERT_EQ(f.viewer->GetPickedPixel()[1], tube_j);
  const rayscope::PixelRecord rec = f.record(kW / 2, tube_j);
  EXPECT_EQ(lines_by_kind(f.viewer->GetShownRays()), recorded_by_kind(rec));
  // The hit lies on the tube's surface: 0.15 from its axis y = 0.3, z = 0.
  const rayscope::Vec3 p = rec.rays[0].point;
  EXPECT_NEAR(std::hypot(p.y - 0.3, p.z), 0.15, 1e-5);
  const std::string text = f.viewer->GetInspectText();
  EXPECT_NE(text.find("wire"), std::string::npos) << text;

  // Clicks on the tube and on the point in the 3D view.
  vtkRenderer* ren = f.viewer->GetSceneRenderer();
  for (int want : {tube_j, dot_j}) {
    const rayscope::Vec3 q = f.record(kW / 2, want).rays[0].point;
    ren->SetWorldPoint(q.x, q.y, q.z, 1.0);
    ren->WorldToDisplay();
    double d[3];
    ren->GetDisplayPoint(d);
    ASSERT_TRUE(ren->IsInViewport(int(d[0]), int(d[1])));
    f.click(int(std::lround(d[0])), int(std::lround(d[1])));
    EXPECT_NEAR(f.viewer->GetPickedPixel()[0], kW / 2, 1) << want;
    EXPECT_NEAR(f.viewer->GetPickedPixel()[1], want, 1) << want;
  }
}

// Up/Down grow and shrink the tree by depth, Right/Left step ray by ray, k
// shows one kind: the overlay follows, and the ends of each range say so.
TEST_F(Viewer, KeysStepThroughTheTree) {
  Fixture f;
  ASSERT_TRUE(f.start_on_glass());
  const rayscope::PixelRecord rec = f.record(kGlassI, kGlassJ);
  int deepest = 0;
  for (const rayscope::RayRecord& r : rec.rays) deepest = std::max(deepest, r.depth);
  ASSERT_EQ(f.viewer->GetShownDepth(), deepest);
  f.key("Up");
  EXPECT_EQ(f.viewer->GetShownDepth(), deepest);
  EXPECT_NE(std::string(f.viewer->GetMessage()).find("whole tree"), std::string::npos);
  for (int d = deepest - 1; d >= 0; --d) {
    f.key("Down");
    ASSERT_EQ(f.viewer->GetShownDepth(), d);
    EXPECT_EQ(lines_by_kind(f.viewer->GetShownRays()), recorded_by_kind(rec, d)) << "depth " << d;
  }
  f.key("Down");
  EXPECT_NE(std::string(f.viewer->GetMessage()).find("only the primary"), std::string::npos);
  f.key("Up");
  EXPECT_EQ(f.viewer->GetShownDepth(), 1);
  for (int k = 0; k < deepest; ++k) f.key("Up");
  // Ray by ray, in trace order.
  f.key("Left");
  EXPECT_NE(std::string(f.viewer->GetMessage()).find("no ray is selected"), std::string::npos);
  for (int id = 0; id < 3; ++id) {
    f.key("Right");
    ASSERT_EQ(f.viewer->GetSelectedRay(), id);
    EXPECT_EQ(lines_by_kind(f.viewer->GetShownRays()), recorded_by_kind(rec, 1 << 30, id));
    EXPECT_NE(std::string(f.viewer->GetPanelText()).find(">>"), std::string::npos);
  }
  while (f.viewer->GetSelectedRay() < int(rec.rays.size()) - 1) f.key("Right");
  f.key("Right");
  EXPECT_NE(std::string(f.viewer->GetMessage()).find("last ray"), std::string::npos);
  while (f.viewer->GetSelectedRay() >= 0) f.key("Left");
  // One kind at a time.
  const std::map<int, int> all = recorded_by_kind(rec);
  for (int kind = 0; kind < 4; ++kind) {
    f.key("k");
    ASSERT_EQ(f.viewer->GetShownKind(), kind);
    EXPECT_EQ(lines_by_kind(f.viewer->GetShownRays()), (std::map<int, int>{{kind, all.at(kind)}}));
  }
  f.key("k");
  EXPECT_EQ(f.viewer->GetShownKind(), -1);
  EXPECT_EQ(lines_by_kind(f.viewer->GetShownRays()), all);
}

// t plays the selected ray's walk: after N steps the entered boxes are the
// first N nodes the recorder logged; boxes missed and culled on the way are
// marked, the hit leaf when it is reached; T steps back.
TEST_F(Viewer, PlaysTheSelectedRaysBvhWalk) {
  for (bool binary : {false, true}) {
    Fixture f;
    if (binary) f.alg->SetAccelToBinaryBvh();
    ASSERT_TRUE(f.start_on_glass());
    const rayscope::PixelRecord rec = f.record(kGlassI, kGlassJ);
    const rayscope::TraversalRecord& walk = rec.rays[0].traversal;
    const std::vector<uint32_t> nodes = walk.nodes();
    ASSERT_GE(nodes.size(), 2u);
    for (size_t n = 1; n <= nodes.size(); ++n) {
      f.key("t");
      ASSERT_EQ(f.viewer->GetTraversalSteps(), int(n));
      std::map<int, std::set<int>> shown = boxes_by_state(f.viewer->GetShownBVH());
      std::set<int> entered = shown[vtkRayScopeAccelSource::ENTERED];
      entered.insert(shown[vtkRayScopeAccelSource::HIT_LEAF].begin(),
                     shown[vtkRayScopeAccelSource::HIT_LEAF].end());
      EXPECT_EQ(entered, std::set<int>(nodes.begin(), nodes.begin() + long(n))) << "step " << n;
      EXPECT_FALSE(shown[vtkRayScopeAccelSource::BOX_MISSED].empty() &&
                   shown[vtkRayScopeAccelSource::BOX_HIT].empty() && n < nodes.size())
          << "step " << n << ": the boxes tested on the way are shown";
      // The step numbers 1..n, each once, and the node entered last drawn
      // on its own: its box's cells, with the bounds of the box of the
      // walk's n-th node.
      std::multiset<int> numbers;
      vtkStringArray* steps = vtkStringArray::SafeDownCast(
          f.viewer->GetWalkSteps()->GetPointData()->GetAbstractArray("Step"));
      ASSERT_NE(steps, nullptr);
      for (vtkIdType k = 0; k < steps->GetNumberOfValues(); ++k) {
        std::istringstream list(steps->GetValue(k));
        for (std::string number; std::getline(list, number, ',');)
          numbers.insert(std::stoi(number));
      }
      std::multiset<int> expected;
      for (int k = 1; k <= int(n); ++k) expected.insert(k);
      EXPECT_EQ(numbers, expected) << "step " << n;
      vtkPolyData* boxes = f.viewer->GetShownBVH();
      vtkDataArray* order = boxes->GetCellData()->GetArray("EntryOrder");
      ASSERT_NE(order, nullptr);
      vtkBoundingBox last;
      for (vtkIdType c = 0; c < boxes->GetNumberOfCells(); ++c)
        if (int(order->GetTuple1(c)) == int(n) - 1) {
          double b[6];
          boxes->GetCell(c)->GetBounds(b);
          last.AddBounds(b);
        }
      vtkPolyData* current = f.viewer->GetWalkCurrentNode();
      EXPECT_EQ(current->GetNumberOfCells(), 12) << "step " << n;
      double b[6], want[6];
      current->GetBounds(b);
      last.GetBounds(want);
      for (int k = 0; k < 6; ++k) EXPECT_DOUBLE_EQ(b[k], want[k]) << "step " << n;
    }
    std::map<int, std::set<int>> done = boxes_by_state(f.viewer->GetShownBVH());
    if (walk.hit_leaf != rayscope::kNoNode) {
      EXPECT_EQ(done[vtkRayScopeAccelSource::HIT_LEAF], std::set<int>{int(walk.hit_leaf)});
    }
    f.key("t");
    EXPECT_NE(std::string(f.viewer->GetMessage()).find("complete"), std::string::npos);
    f.key("T");
    EXPECT_EQ(f.viewer->GetTraversalSteps(), int(nodes.size()) - 1);
  }
}

// The help line wraps at its " | " to the window's width, and the header
// grows to hold it: in a 960x600 window at font scale 1 and 2 every line of
// it fits in the window and in the header, no key is lost, and the image and
// the 3D view start below the header.
TEST_F(Viewer, TheHelpLineWrapsToTheWindowWidth) {
  int previous_lines = 0;
  for (const double scale : {1.0, 2.0}) {
    SCOPED_TRACE("font scale " + std::to_string(scale));
    Fixture f;
    f.viewer->SetWindowSize(960, 600);
    f.viewer->SetFontScale(scale);
    ASSERT_TRUE(f.start());
    vtkTextActor* help = nullptr;
    vtkRenderer* header = nullptr;
    vtkRendererCollection* renderers = f.viewer->GetRenderWindow()->GetRenderers();
    renderers->InitTraversal();
    while (vtkRenderer* ren = renderers->GetNextItem()) {
      vtkActor2DCollection* actors = ren->GetActors2D();
      actors->InitTraversal();
      while (vtkActor2D* actor = actors->GetNextActor2D()) {
        auto* t = vtkTextActor::SafeDownCast(actor);
        if (t && t->GetInput() && std::strncmp(t->GetInput(), "click: pick", 11) == 0) {
          help = t;
          header = ren;
        }
      }
    }
    ASSERT_NE(help, nullptr);
    std::string text = help->GetInput();
    const int lines = int(std::count(text.begin(), text.end(), '\n')) + 1;
    for (size_t at; (at = text.find('\n')) != std::string::npos;) text.replace(at, 1, " | ");
    EXPECT_EQ(text, vtkRayScopeViewer::GetHelpText());
    EXPECT_GE(lines, 2);  // the whole line is about 1250 pixels wide at scale 1
    EXPECT_GT(lines, previous_lines);
    previous_lines = lines;
    f.viewer->GetRenderWindow()->Render();
    double box[4];  // around the text's anchor, in pixels
    help->GetBoundingBox(header, box);
    const int* anchor = help->GetPositionCoordinate()->GetComputedViewportValue(header);
    const int* size = header->GetSize();
    EXPECT_LE(anchor[0] + box[1], 960.0);
    EXPECT_GE(anchor[1] + box[2], 0.0);  // within the header: not over the image
    EXPECT_LE(anchor[1] + box[3], double(size[1]));
    EXPECT_DOUBLE_EQ(f.viewer->GetImageRenderer()->GetViewport()[3], header->GetViewport()[1]);
  }
}

// b, l, L: the BVH and its levels; m: image modes; s: a screenshot that is
// not blank; x: the ray tree and the BVH as .vtp files that read back.
// The labels of the 3D view's legend.
std::vector<std::string> legend_labels(vtkRayScopeViewer* viewer) {
  std::vector<std::string> labels;
  vtkActor2DCollection* actors = viewer->GetSceneRenderer()->GetActors2D();
  actors->InitTraversal();
  while (vtkActor2D* actor = actors->GetNextActor2D())
    if (auto* legend = vtkLegendBoxActor::SafeDownCast(actor))
      for (int e = 0; e < legend->GetNumberOfEntries(); ++e)
        labels.push_back(legend->GetEntryString(e) ? legend->GetEntryString(e) : "");
  return labels;
}

bool has_label(const std::vector<std::string>& labels, const std::string& text) {
  return std::find(labels.begin(), labels.end(), text) != labels.end();
}

// The depth mode on the default scene, whose floor reaches the horizon,
// spans its whole scale: distances map by their logarithm (near white, far
// dark), so the nearest hit is white, the farthest the darkest shade, the one
// at their geometric mean midway, and over three times as many hits are
// darker than near-white as on a linear scale, which left nearly every hit
// within a few shades of white.
TEST_F(Viewer, DepthModeSpreadsTheDistancesOfTheDefaultScene) {
  Fixture f;
  ASSERT_TRUE(f.start());
  for (int k = 0; k < 3; ++k) f.key("m");
  ASSERT_EQ(f.viewer->GetImageMode(), 3);
  vtkDataArray* depth = f.viewer->GetLastImage()->GetPointData()->GetArray("Depth");
  ASSERT_NE(depth, nullptr);
  auto* shown =
      vtkUnsignedCharArray::SafeDownCast(f.viewer->GetShownImage()->GetPointData()->GetScalars());
  ASSERT_NE(shown, nullptr);
  double lo = INFINITY, hi = 0.0;
  for (vtkIdType i = 0; i < depth->GetNumberOfTuples(); ++i)
    if (std::isfinite(depth->GetTuple1(i))) {
      lo = std::min(lo, depth->GetTuple1(i));
      hi = std::max(hi, depth->GetTuple1(i));
    }
  ASSERT_GT(hi, 100.0 * lo);                // decades of distance
  int hits = 0, gray = 0, linear_gray = 0;  // darker than byte 230: log and linear scales
  for (vtkIdType i = 0; i < depth->GetNumberOfTuples(); ++i) {
    const double v = depth->GetTuple1(i);
    const unsigned char b = shown->GetTypedComponent(i, 0);
    if (!std::isfinite(v)) {
      EXPECT_EQ(b, 0) << i;  // a miss
      continue;
    }
    ++hits;
    const float t = float(std::log(v / lo) / std::log(hi / lo));
    EXPECT_EQ(b, rayscope::srgb_byte(1.0f - 0.85f * t)) << i;
    gray += b < 230;  // t above about 0.25
    linear_gray += rayscope::srgb_byte(1.0f - 0.85f * float((v - lo) / (hi - lo))) < 230;
  }
  EXPECT_GT(hits, 0);
  EXPECT_GT(gray, hits / 8) << hits;
  EXPECT_GT(gray, 3 * linear_gray) << hits;
}

TEST_F(Viewer, BvhLevelsImageModesScreenshotAndExport) {
  Fixture f;
  ASSERT_TRUE(f.start_on_glass());
  f.key("b");
  ASSERT_TRUE(f.viewer->GetShowBVH());
  const vtkIdType all = f.viewer->GetShownBVH()->GetNumberOfCells();
  EXPECT_EQ(all, 12 * vtkIdType(f.alg->GetCoreScene()->bvh().nodes.size()));
  // The level colors have a legend: the ramp's ends, root and deepest level.
  const int depth =
      int(f.viewer->GetShownBVH()->GetFieldData()->GetArray("TreeDepth")->GetTuple1(0));
  EXPECT_TRUE(has_label(legend_labels(f.viewer), "BVH: level 0 (root)"));
  EXPECT_TRUE(
      has_label(legend_labels(f.viewer), "BVH: level " + std::to_string(depth - 1) + " (deepest)"));
  f.key("l");
  EXPECT_EQ(f.viewer->GetBVHLevel(), 0);
  EXPECT_EQ(f.viewer->GetShownBVH()->GetNumberOfCells(), 12);  // the root's box
  f.key("l");
  EXPECT_EQ(f.viewer->GetShownBVH()->GetNumberOfCells(), 24);
  f.key("L");
  f.key("L");
  EXPECT_EQ(f.viewer->GetBVHLevel(), -1);
  f.key("L");
  EXPECT_NE(std::string(f.viewer->GetMessage()).find("every level"), std::string::npos);
  f.key("b");
  EXPECT_EQ(f.viewer->GetShownBVH()->GetNumberOfCells(), 0);
  EXPECT_FALSE(has_label(legend_labels(f.viewer), "BVH: level 0 (root)"));

  // Every image mode shows something other than the colors.
  auto* shown =
      vtkUnsignedCharArray::SafeDownCast(f.viewer->GetShownImage()->GetPointData()->GetScalars());
  const std::vector<unsigned char> color(shown->GetPointer(0),
                                         shown->GetPointer(0) + shown->GetNumberOfValues());
  for (int mode = 1; mode <= 4; ++mode) {
    f.key("m");
    ASSERT_EQ(f.viewer->GetImageMode(), mode);
    EXPECT_FALSE(std::equal(color.begin(), color.end(), shown->GetPointer(0))) << "mode " << mode;
  }
  f.key("m");
  EXPECT_EQ(f.viewer->GetImageMode(), 0);
  EXPECT_TRUE(std::equal(color.begin(), color.end(), shown->GetPointer(0)));

  const std::string png = Fixture::out("viewer_1.png");
  std::filesystem::remove(png);
  f.key("s");
  EXPECT_TRUE(png_varies(png)) << f.viewer->GetMessage();
  const std::string prefix = Fixture::out("viewer_1");
  f.key("x");
  for (const char* suffix : {"_raytree.vtp", "_bvh.vtp"}) {
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName((prefix + suffix).c_str());
    reader->Update();
    EXPECT_GT(reader->GetOutput()->GetNumberOfCells(), 0) << suffix;
  }
}

// rayscope view --accel: the viewer draws the structure the rays walk (every
// node or cell), names it in its messages and legend, walks its levels, and
// plays the selected ray's walk through its cells as through the BVH's nodes.
TEST_F(Viewer, DrawsNamesAndPlaysTheChosenStructure) {
  const std::pair<int, std::string> kinds[] = {
      {vtkRayScopeImageAlgorithm::ACCEL_KDTREE, "kdtree"},
      {vtkRayScopeImageAlgorithm::ACCEL_GRID, "grid"},
      {vtkRayScopeImageAlgorithm::ACCEL_OCTREE, "octree"},
      {vtkRayScopeImageAlgorithm::ACCEL_BSP, "bsp"},
      {vtkRayScopeImageAlgorithm::ACCEL_SPHERES, "spheres"}};
  for (const auto& [accel, name] : kinds) {
    SCOPED_TRACE(name);
    Fixture f;
    f.alg->SetAccel(accel);
    ASSERT_TRUE(f.start_on_glass());
    f.key("b");
    EXPECT_NE(std::string(f.viewer->GetMessage()).find(name + " shown"), std::string::npos)
        << f.viewer->GetMessage();
    vtkPolyData* shown = f.viewer->GetShownBVH();
    auto* structure =
        vtkStringArray::SafeDownCast(shown->GetFieldData()->GetAbstractArray("Structure"));
    ASSERT_NE(structure, nullptr);
    EXPECT_EQ(structure->GetValue(0), name);
    const rayscope::AccelView view = rayscope::make_accel_view(f.alg->GetCoreScene()->accel());
    // Every node or cell that holds something is drawn (a box as 12 edges,
    // a sphere as circles), each cell naming its node; empty leaves (a
    // grid's empty cells) are left out.
    vtkDataArray* node_ids = shown->GetCellData()->GetArray("NodeId");
    ASSERT_NE(node_ids, nullptr);
    std::set<int> drawn, occupied;
    for (vtkIdType c = 0; c < node_ids->GetNumberOfTuples(); ++c)
      drawn.insert(int(node_ids->GetTuple1(c)));
    // The BSP tree is drawn as its partition: the root's box and every split
    // polygon (OnlySplitPlanes).
    for (size_t i = 0; i < view.nodes.size(); ++i) {
      const rayscope::AccelViewNode& n = view.nodes[i];
      if (name == "bsp" ? n.parent < 0 || n.polygon_count >= 3 : !n.leaf || n.count > 0)
        occupied.insert(int(i));
    }
    EXPECT_EQ(drawn, occupied);
    if (name == "grid") {
      EXPECT_LT(occupied.size(), view.nodes.size() / 2) << "most cells are empty";
    }
    EXPECT_TRUE(has_label(legend_labels(f.viewer), name + ": level 0 (root)"));
    EXPECT_FALSE(has_label(legend_labels(f.viewer), "BVH: level 0 (root)"));
    f.key("l");
    EXPECT_NE(std::string(f.viewer->GetMessage()).find(name + ": level 0"), std::string::npos)
        << f.viewer->GetMessage();
    f.key("L");

    const rayscope::PixelRecord rec = f.record(kGlassI, kGlassJ);
    const std::vector<uint32_t> nodes = rec.rays[0].traversal.nodes();
    ASSERT_GE(nodes.size(), 1u);
    for (size_t n = 1; n <= nodes.size(); ++n) {
      f.key("t");
      std::map<int, std::set<int>> states = boxes_by_state(f.viewer->GetShownBVH());
      std::set<int> entered = states[vtkRayScopeAccelSource::ENTERED];
      entered.insert(states[vtkRayScopeAccelSource::HIT_LEAF].begin(),
                     states[vtkRayScopeAccelSource::HIT_LEAF].end());
      EXPECT_EQ(entered, std::set<int>(nodes.begin(), nodes.begin() + long(n))) << "step " << n;
    }
    EXPECT_TRUE(has_label(legend_labels(f.viewer), name + ": entered"))
        << "the walk's legend names the structure";
  }
}

// +/- and ]/[ change the samples and the depth and re-render; at the ends of
// their ranges they do nothing and say so.
TEST_F(Viewer, SamplesAndDepthKeysRerender) {
  Fixture f(1);
  ASSERT_TRUE(f.start_on_glass());
  f.key("minus");
  EXPECT_EQ(f.alg->GetSamples(), 1);
  EXPECT_NE(std::string(f.viewer->GetMessage()).find("minimum"), std::string::npos);
  f.key("plus");
  EXPECT_EQ(f.alg->GetSamples(), 2);
  ASSERT_TRUE(f.viewer->WaitForRender());
  EXPECT_NE(std::string(f.viewer->GetMessage()).find("2x2 samples"), std::string::npos);
  EXPECT_EQ(lines_by_kind(f.viewer->GetShownRays()), recorded_by_kind(f.record(kGlassI, kGlassJ)));
  f.key("bracketleft");
  EXPECT_EQ(f.alg->GetMaxDepth(), 0);
  ASSERT_TRUE(f.viewer->WaitForRender());
  f.key("bracketleft");
  EXPECT_NE(std::string(f.viewer->GetMessage()).find("already 0"), std::string::npos);
  // Depth 0: the glass pixel's secondary rays are all skipped (depth limit).
  const rayscope::PixelRecord rec = f.record(kGlassI, kGlassJ);
  int cut = 0;
  for (const rayscope::RayRecord& r : rec.rays)
    cut += r.skipped && r.skip_reason == rayscope::SkipReason::Depth;
  EXPECT_GT(cut, 0);
  EXPECT_EQ(lines_by_kind(f.viewer->GetShownRays()), recorded_by_kind(rec));
  f.key("bracketright");
  ASSERT_TRUE(f.viewer->WaitForRender());
  EXPECT_EQ(f.alg->GetMaxDepth(), 1);
}

// d labels every shown ray with its id, depth and weight; p switches to a
// parallel projection (all primary rays parallel) and back, re-rendering.
TEST_F(Viewer, LabelsAndProjectionKeys) {
  Fixture f;
  ASSERT_TRUE(f.start_on_glass());
  f.key("d");
  ASSERT_TRUE(f.viewer->GetShowLabels());
  vtkPolyData* labels = f.viewer->GetRayLabels();
  const rayscope::PixelRecord rec = f.record(kGlassI, kGlassJ);
  ASSERT_EQ(labels->GetNumberOfPoints(), vtkIdType(rec.rays.size()));
  auto* text = vtkStringArray::SafeDownCast(labels->GetPointData()->GetAbstractArray("Label"));
  ASSERT_NE(text, nullptr);
  EXPECT_EQ(text->GetValue(0), "#0 d0 w1");
  f.key("Down");  // labels follow what is shown: one depth less
  vtkIdType shown = 0;
  for (const rayscope::RayRecord& r : rec.rays) shown += r.depth < f.viewer->GetShownDepth() + 1;
  EXPECT_EQ(labels->GetNumberOfPoints(), shown);
  EXPECT_LT(shown, vtkIdType(rec.rays.size()));
  f.key("d");
  EXPECT_FALSE(f.viewer->GetShowLabels());

  f.key("p");
  ASSERT_TRUE(f.viewer->WaitForRender());
  ASSERT_TRUE(f.alg->GetParallelProjection());
  const rayscope::Vec3 a = f.record(10, 10).rays[0].dir, b = f.record(100, 70).rays[0].dir;
  EXPECT_NEAR(glm::length(glm::normalize(a) - glm::normalize(b)), 0.0f, 1e-6f);
  EXPECT_EQ(lines_by_kind(f.viewer->GetShownRays()), recorded_by_kind(f.record(kGlassI, kGlassJ)));
  f.key("p");
  ASSERT_TRUE(f.viewer->WaitForRender());
  EXPECT_FALSE(f.alg->GetParallelProjection());
  const rayscope::Vec3 c = f.record(10, 10).rays[0].dir, d = f.record(100, 70).rays[0].dir;
  EXPECT_GT(glm::length(glm::normalize(c) - glm::normalize(d)), 0.1f);
}

// r takes the 3D view's camera (after orbiting it) as the ray-tracing camera
// and re-renders: the primary ray of the picked pixel starts at that camera.
TEST_F(Viewer, CameraKeyRerendersFromThe3DView) {
  Fixture f;
  ASSERT_TRUE(f.start_on_glass());
  vtkCamera* cam = f.viewer->GetSceneRenderer()->GetActiveCamera();
  cam->Azimuth(30.0);
  cam->Elevation(10.0);
  cam->OrthogonalizeViewUp();
  double eye[3];
  cam->GetPosition(eye);
  f.key("r");
  ASSERT_TRUE(f.viewer->WaitForRender());
  for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(f.alg->GetPosition()[k], eye[k]);
  const rayscope::PixelRecord rec = f.record(kGlassI, kGlassJ);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(rec.rays[0].origin[k], eye[k], 1e-4);
  EXPECT_NE(std::string(f.viewer->GetMessage()).find("rendered"), std::string::npos);
}

// f frames the 3D view on the selected ray, which then spans a good part of
// the view with both ends in it (the shortest ray of the glass pixel's tree,
// a few dozen pixels long before), keeping the direction of view; F frames the whole scene again,
// exactly as at the start, however often it is pressed.
TEST_F(Viewer, FrameKeyFillsThe3DViewWithTheSelectedRay) {
  Fixture f;
  ASSERT_TRUE(f.start_on_glass());
  vtkRenderer* ren = f.viewer->GetSceneRenderer();
  vtkCamera* cam = ren->GetActiveCamera();
  double start_focus[3], start_position[3], start_dir[3];
  cam->GetFocalPoint(start_focus);
  cam->GetPosition(start_position);
  cam->GetDirectionOfProjection(start_dir);
  // The shortest ray after the primary one that hit something.
  const rayscope::PixelRecord rec = f.record(kGlassI, kGlassJ);
  int shortest = -1;
  for (const rayscope::RayRecord& r : rec.rays)
    if (r.id > 0 && r.hit && !r.skipped &&
        (shortest < 0 ||
         glm::length(r.point - r.origin) <
             glm::length(rec.rays[size_t(shortest)].point - rec.rays[size_t(shortest)].origin)))
      shortest = r.id;
  ASSERT_GE(shortest, 1);
  for (int k = 0; k <= shortest; ++k) f.key("Right");
  const int selected = f.viewer->GetSelectedRay();
  ASSERT_EQ(selected, shortest);
  // The selected ray's line as drawn, and its length on the screen in pixels
  // with both ends in the viewport.
  double a[3], b[3];
  {
    vtkPolyData* shown = f.viewer->GetShownRays();
    vtkDataArray* id = shown->GetCellData()->GetArray("RayId");
    ASSERT_NE(id, nullptr);
    vtkIdType c = 0;
    while (c < shown->GetNumberOfCells() &&
           !(shown->GetCellType(c) == VTK_LINE && int(id->GetTuple1(c)) == selected))
      ++c;
    ASSERT_LT(c, shown->GetNumberOfCells());
    shown->GetPoint(shown->GetCell(c)->GetPointId(0), a);
    shown->GetPoint(shown->GetCell(c)->GetPointId(1), b);
  }
  auto on_screen = [&](const double p[3], double d[3]) {
    ren->SetWorldPoint(p[0], p[1], p[2], 1.0);
    ren->WorldToDisplay();
    ren->GetDisplayPoint(d);
    return ren->IsInViewport(int(d[0]), int(d[1]));
  };
  auto pixels = [&](bool& inside) {
    double da[3], db[3];
    inside = on_screen(a, da) && on_screen(b, db);
    return std::hypot(da[0] - db[0], da[1] - db[1]);
  };
  bool inside = false;
  const double before = pixels(inside);
  f.key("f");
  const double after = pixels(inside);
  EXPECT_TRUE(inside);
  const int* size = ren->GetSize();
  EXPECT_GT(after, 0.4 * std::min(size[0], size[1])) << before;
  EXPECT_GT(after, 2.0 * before);
  double dir[3];
  cam->GetDirectionOfProjection(dir);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(dir[k], start_dir[k], 1e-9);
  for (int n = 0; n < 2; ++n) {
    f.key("F");
    double focus[3], position[3];
    cam->GetFocalPoint(focus);
    cam->GetPosition(position);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(focus[k], start_focus[k], 1e-9);
      EXPECT_NEAR(position[k], start_position[k], 1e-9);
    }
  }
}

// The panel breaks the inspect text's long lines to its width and shows the
// lines that fit its height: at font scale 2 in a 960x600 window every line
// shown lies within the panel, the selected ray's line among them.
TEST_F(Viewer, ThePanelWrapsItsLinesToItsWidth) {
  Fixture f;
  f.viewer->SetWindowSize(960, 600);
  f.viewer->SetFontScale(2.0);
  ASSERT_TRUE(f.start_on_glass());
  f.key("Right");
  const std::string panel = f.viewer->GetPanelText();
  EXPECT_NE(panel.find(">>#0 primary"), std::string::npos) << panel;
  vtkRenderer* ren = f.viewer->GetTextRenderer();
  f.viewer->GetRenderWindow()->Render();
  const int* size = ren->GetSize();
  int shown = 0;
  vtkActor2DCollection* actors = ren->GetActors2D();
  actors->InitTraversal();
  while (vtkActor2D* actor = actors->GetNextActor2D()) {
    auto* t = vtkTextActor::SafeDownCast(actor);
    if (!t || !t->GetVisibility() || !t->GetInput() || !*t->GetInput()) continue;
    ++shown;
    double box[4];
    t->GetBoundingBox(ren, box);
    const int* anchor = t->GetPositionCoordinate()->GetComputedViewportValue(ren);
    EXPECT_LE(anchor[0] + box[1], double(size[0])) << t->GetInput();
    EXPECT_GE(anchor[1] + box[2], 0.0) << t->GetInput();
  }
  EXPECT_GE(shown, 4);
  // The whole text is longer than the panel is wide: some line was broken.
  size_t longest = 0;
  std::istringstream text(f.viewer->GetInspectText());
  for (std::string line; std::getline(text, line);) longest = std::max(longest, line.size());
  double box[4];
  vtkNew<vtkTextActor> probe;
  probe->GetTextProperty()->SetFontFamilyToCourier();
  probe->GetTextProperty()->SetFontSize(24);
  probe->SetInput(std::string(longest, 'X').c_str());
  probe->GetBoundingBox(ren, box);
  EXPECT_GT(box[1] - box[0], double(size[0]));
}

// The legend names what the 3D view draws, and only that: nothing before a
// pick, the kinds of the shown rays after it (one kind after k).
TEST_F(Viewer, TheLegendNamesWhatTheViewDraws) {
  Fixture f;
  ASSERT_TRUE(f.start());
  EXPECT_TRUE(legend_labels(f.viewer).empty());
  ASSERT_TRUE(f.viewer->PickPixel(kGlassI, kGlassJ));
  const std::map<int, int> kinds = recorded_by_kind(f.record(kGlassI, kGlassJ));
  ASSERT_EQ(kinds.size(), 4u);
  for (const char* kind : {"primary ray", "shadow ray", "reflection ray", "refraction ray"})
    EXPECT_TRUE(has_label(legend_labels(f.viewer), kind)) << kind;
  f.key("k");  // the primary rays only
  EXPECT_TRUE(has_label(legend_labels(f.viewer), "primary ray"));
  for (const char* kind : {"shadow ray", "reflection ray", "refraction ray"})
    EXPECT_FALSE(has_label(legend_labels(f.viewer), kind)) << kind;
}

// A lecture's chapters: each opens its own scene (framed in 3D, rendered at
// its own size), with its pixel picked and its keys pressed, and the view
// settings of the chapter before left behind; PageDown / PageUp step through
// them and stop at either end.
TEST_F(Viewer, ChaptersOpenTheirSceneWithTheirPixelAndKeys) {
  Fixture f;  // the default scene, kW x kH
  // A second chapter: one sphere far from the default scene, 80x60.
  rayscope::Scene ball;
  ball.camera.eye = rayscope::Vec3(100, 0, 5);
  ball.camera.look_at = rayscope::Vec3(100, 0, 0);
  ball.materials.push_back(rayscope::Material{});
  rayscope::Sphere sphere;
  sphere.center = rayscope::Vec3(100, 0, 0);
  ball.spheres.push_back(sphere);
  rayscope::Light light;
  light.position = rayscope::Vec3(100, 3, 5);
  ball.lights.push_back(light);
  ball.commit();
  vtkNew<vtkRayScopeImageAlgorithm> ball_source;
  ball_source->SetSize(80, 60);
  ball_source->SetSamples(1);
  ball_source->SetThreads(2);
  ball_source->SetCoreScene(ball);
  f.viewer->AddChapter(f.alg, "Glass", "look at the glass", kGlassI, kGlassJ, "");
  f.viewer->AddChapter(ball_source, "Ball", "look at the ball", 40, 30, "b,m");
  f.viewer->AddChapter(ball_source, "Broken", "", -1, -1, "b,zz");
  ASSERT_EQ(f.viewer->GetNumberOfChapters(), 3);

  auto image_width = [&] { return f.viewer->GetShownImage()->GetDimensions()[0]; };
  auto focus_x = [&] {
    return f.viewer->GetSceneRenderer()->GetActiveCamera()->GetFocalPoint()[0];
  };
  ASSERT_EQ(f.viewer->SetChapter(0), 1) << f.viewer->GetMessage();
  EXPECT_EQ(f.viewer->GetChapter(), 0);
  EXPECT_EQ(std::string(f.viewer->GetCaption()), "1/3 Glass: look at the glass");
  EXPECT_EQ(f.viewer->GetPickedPixel()[0], kGlassI);
  EXPECT_EQ(f.viewer->GetPickedPixel()[1], kGlassJ);
  EXPECT_EQ(image_width(), kW);
  EXPECT_LT(focus_x(), 50.0);
  f.key("Right");  // a setting of this chapter's view, left behind below

  f.key("Next");
  EXPECT_EQ(f.viewer->GetChapter(), 1);
  EXPECT_EQ(f.viewer->GetSceneSource(), ball_source.Get());
  EXPECT_EQ(std::string(f.viewer->GetCaption()), "2/3 Ball: look at the ball");
  EXPECT_EQ(f.viewer->GetPickedPixel()[0], 40);
  EXPECT_EQ(f.viewer->GetPickedPixel()[1], 30);
  EXPECT_EQ(f.viewer->GetSelectedRay(), -1);
  EXPECT_TRUE(f.viewer->GetShowBVH());
  EXPECT_EQ(f.viewer->GetImageMode(), int(vtkRayScopeViewer::COST));
  EXPECT_EQ(image_width(), 80);
  EXPECT_GT(focus_x(), 50.0);  // the 3D view framed on the ball
  // The picked pixel's tree is the ball scene's: its primary ray hits the ball.
  EXPECT_NE(std::string(f.viewer->GetInspectText()).find("sphere"), std::string::npos)
      << f.viewer->GetInspectText();

  f.key("Next");  // the broken chapter: its bad key fails with a message
  EXPECT_NE(std::string(f.viewer->GetMessage()).find("'zz' is not a key"), std::string::npos)
      << f.viewer->GetMessage();
  EXPECT_EQ(f.viewer->HandleKey("Next"), 1);
  EXPECT_NE(std::string(f.viewer->GetMessage()).find("chapter 3 is the last"), std::string::npos)
      << f.viewer->GetMessage();
  f.key("Prior");
  f.key("Prior");
  EXPECT_EQ(f.viewer->GetChapter(), 0);
  EXPECT_FALSE(f.viewer->GetShowBVH());
  EXPECT_EQ(f.viewer->GetImageMode(), int(vtkRayScopeViewer::COLOR));
  EXPECT_EQ(f.viewer->GetPickedPixel()[0], kGlassI);
  EXPECT_EQ(image_width(), kW);
  EXPECT_LT(focus_x(), 50.0);
  f.key("Prior");
  EXPECT_NE(std::string(f.viewer->GetMessage()).find("the first chapter"), std::string::npos);
  EXPECT_EQ(f.viewer->SetChapter(3), 0);
  EXPECT_EQ(f.viewer->GetChapter(), 0);
}

// Without chapters, PageDown says how to open a lecture.
TEST_F(Viewer, ChapterKeysWithoutALectureSaySo) {
  Fixture f;
  ASSERT_TRUE(f.start());
  EXPECT_EQ(f.viewer->HandleKey("Next"), 1);
  EXPECT_NE(std::string(f.viewer->GetMessage()).find("--lecture"), std::string::npos);
  EXPECT_EQ(std::string(f.viewer->GetCaption()), "");
  // The keys scripts may press are the key table's, checked without a window.
  for (const char* key : {"Next", "Prior", "g", "t", "bracketright"})
    EXPECT_TRUE(vtkRayScopeViewer::IsKey(key)) << key;
  for (const char* key : {"zz", "q", ""}) EXPECT_FALSE(vtkRayScopeViewer::IsKey(key)) << key;
}

// Key g draws the picked pixel's tree as a diagram in the panel: a dot per
// ray, a line from each ray's parent to it, every ray below its parent,
// leaves left to right in trace order; the selected ray white, the rays the
// 3D view hides dimmed; g again brings the text back.
// Key c: the panel shows the packet the picked pixel's primary ray was
// traced in (the core's replay), and the image outlines the packet's block;
// g and c take turns in the panel.
TEST_F(Viewer, PacketKeyShowsThePixelsPacket) {
  Fixture f;
  ASSERT_TRUE(f.start());
  f.key("c");
  EXPECT_NE(std::string(f.viewer->GetMessage()).find("pick a pixel first"), std::string::npos);
  ASSERT_TRUE(f.viewer->PickPixel(kGlassI, kGlassJ));
  vtkPolyData* marker = f.viewer->GetPixelMarker();
  const vtkIdType plain = marker->GetNumberOfCells();
  f.key("c");
  ASSERT_TRUE(f.viewer->GetShowPacket());
  const rayscope::RenderSettings rs = f.alg->GetRenderSettings();
  const rayscope::PacketReplay r =
      rayscope::record_packet(*f.alg->GetCoreScene(), rs, kGlassI, rs.height - 1 - kGlassJ);
  const std::string panel = f.viewer->GetPanelText();
  EXPECT_EQ(panel.rfind("packet of pixel (49, 52), sample 0:", 0), 0u) << panel;
  EXPECT_NE(panel.find("lane " + std::to_string(r.lane) + " is this pixel"), std::string::npos)
      << panel;
  // The viewer renders every ray alone for its cost heat map, and says so.
  EXPECT_NE(r.every_ray_alone.find("packets are off"), std::string::npos);
  EXPECT_NE(panel.find("packets are off"), std::string::npos) << panel;
  // The block's outline: the pixels' edges, rows counted from the bottom.
  ASSERT_EQ(marker->GetNumberOfCells(), plain + 1);
  double b[6];
  marker->GetCell(plain)->GetBounds(b);
  EXPECT_DOUBLE_EQ(b[0], r.block.x0 - 0.5);
  EXPECT_DOUBLE_EQ(b[1], r.block.x1 - 0.5);
  EXPECT_DOUBLE_EQ(b[2], rs.height - r.block.y1 - 0.5);
  EXPECT_DOUBLE_EQ(b[3], rs.height - r.block.y0 - 0.5);
  EXPECT_LE(b[0], kGlassI);
  EXPECT_GE(b[1], kGlassI);
  EXPECT_LE(b[2], kGlassJ);
  EXPECT_GE(b[3], kGlassJ);
  // In 3D, the box of each node the packet entered, colored by its active
  // rays, the root's first.
  vtkPolyData* boxes = f.viewer->GetPacketBoxes();
  ASSERT_FALSE(r.steps.empty());
  ASSERT_EQ(boxes->GetNumberOfCells(), vtkIdType(12 * r.steps.size()));
  vtkDataArray* active = boxes->GetCellData()->GetArray("ActiveRays");
  ASSERT_NE(active, nullptr);
  for (size_t i = 0; i < r.steps.size(); ++i)
    EXPECT_EQ(int(active->GetTuple1(vtkIdType(12 * i))), __builtin_popcount(r.steps[i].lanes));
  double root[6];
  boxes->GetCell(0)->GetBounds(root);  // an edge along x of the root's box
  const rayscope::Bounds3 scene_box = f.alg->GetCoreScene()->bounds();
  EXPECT_FLOAT_EQ(float(root[0]), scene_box.lo.x);
  EXPECT_FLOAT_EQ(float(root[1]), scene_box.hi.x);
  f.key("g");
  EXPECT_FALSE(f.viewer->GetShowPacket());
  EXPECT_TRUE(f.viewer->GetShowTreeDiagram());
  EXPECT_EQ(marker->GetNumberOfCells(), plain);
  EXPECT_EQ(boxes->GetNumberOfCells(), 0);
  f.key("c");
  EXPECT_TRUE(f.viewer->GetShowPacket());
  EXPECT_FALSE(f.viewer->GetShowTreeDiagram());
  f.key("c");
  EXPECT_FALSE(f.viewer->GetShowPacket());
  EXPECT_EQ(std::string(f.viewer->GetPanelText()).rfind("packet", 0), std::string::npos);
}

TEST_F(Viewer, TreeDiagramPutsEachRayBelowItsParent) {
  Fixture f;
  ASSERT_TRUE(f.start());
  f.key("g");
  EXPECT_NE(std::string(f.viewer->GetMessage()).find("pick a pixel first"), std::string::npos);
  ASSERT_TRUE(f.viewer->PickPixel(kGlassI, kGlassJ));
  f.key("g");
  ASSERT_TRUE(f.viewer->GetShowTreeDiagram());
  const rayscope::PixelRecord rec = f.record(kGlassI, kGlassJ);
  const size_t n = rec.rays.size();
  ASSERT_GE(n, 4u);
  vtkPolyData* d = f.viewer->GetTreeDiagram();
  ASSERT_EQ(d->GetNumberOfVerts(), vtkIdType(n));
  auto* ids = vtkIntArray::SafeDownCast(d->GetCellData()->GetArray("RayId"));
  auto* colors = vtkUnsignedCharArray::SafeDownCast(d->GetCellData()->GetScalars());
  ASSERT_NE(ids, nullptr);
  ASSERT_NE(colors, nullptr);
  // Each ray's dot, and whether it has children.
  std::vector<std::array<double, 3>> dot(n);
  std::vector<bool> parent(n, false);
  vtkIdType lines = 0;
  for (vtkIdType c = 0; c < d->GetNumberOfCells(); ++c) {
    vtkCell* cell = d->GetCell(c);
    const int id = ids->GetValue(c);
    if (d->GetCellType(c) == VTK_VERTEX) {
      d->GetPoint(cell->GetPointId(0), dot[size_t(id)].data());
      continue;
    }
    ++lines;
    double a[3], b[3];
    d->GetPoint(cell->GetPointId(0), a);
    d->GetPoint(cell->GetPointId(1), b);
    const rayscope::RayRecord& r = rec.rays[size_t(id)];
    ASSERT_GE(r.parent, 0);
    parent[size_t(r.parent)] = true;
    EXPECT_GT(a[1], b[1]) << "ray #" << id << " below its parent #" << r.parent;
  }
  vtkIdType with_parent = 0;
  for (const rayscope::RayRecord& r : rec.rays) with_parent += r.parent >= 0;
  EXPECT_EQ(lines, with_parent);
  double last_leaf_x = -1e300;
  std::map<int, double> row;  // the dots of one depth share a row
  for (size_t k = 0; k < n; ++k) {
    const auto at = row.insert({rec.rays[k].depth, dot[k][1]});
    EXPECT_DOUBLE_EQ(dot[k][1], at.first->second) << "ray #" << k << " on its depth's row";
    if (parent[k]) continue;
    EXPECT_GT(dot[k][0], last_leaf_x) << "leaf #" << k;
    last_leaf_x = dot[k][0];
  }
  // The primary ray's dot in its kind's color; ray #1 selected: white, and
  // the rays after it dimmed.
  auto dot_color = [&](int ray) {
    for (vtkIdType c = 0; c < d->GetNumberOfCells(); ++c)
      if (d->GetCellType(c) == VTK_VERTEX && ids->GetValue(c) == ray)
        return std::array<int, 3>{colors->GetValue(3 * c), colors->GetValue(3 * c + 1),
                                  colors->GetValue(3 * c + 2)};
    return std::array<int, 3>{-1, -1, -1};
  };
  double primary[3];
  vtkRayScopeRayTreeSource::GetKindColor(0, primary);
  for (int k = 0; k < 3; ++k)
    EXPECT_EQ(dot_color(0)[size_t(k)], int(std::lround(255 * primary[k])));
  f.key("Right");
  f.key("Right");
  ASSERT_EQ(f.viewer->GetSelectedRay(), 1);
  d = f.viewer->GetTreeDiagram();
  colors = vtkUnsignedCharArray::SafeDownCast(d->GetCellData()->GetScalars());
  ids = vtkIntArray::SafeDownCast(d->GetCellData()->GetArray("RayId"));
  EXPECT_EQ(dot_color(1), (std::array<int, 3>{255, 255, 255}));
  const std::array<int, 3> after = dot_color(2);
  EXPECT_LT(std::max({after[0], after[1], after[2]}), 128) << "ray #2 is hidden in 3D: dimmed";
  f.key("g");
  EXPECT_FALSE(f.viewer->GetShowTreeDiagram());
  EXPECT_EQ(f.viewer->GetTreeDiagram()->GetNumberOfCells(), 0);
  EXPECT_NE(std::string(f.viewer->GetPanelText()).find("#1 "), std::string::npos);
}

// SetSceneView aims the 3D view (rayscope view --view-camera); f with a
// played walk frames the walk's current node, which then fills the view.
TEST_F(Viewer, TheSceneViewIsAimedAndFramesTheWalksCurrentNode) {
  Fixture f;
  const double eye[3] = {6, 3, 6}, at[3] = {0, 0.5, 0};
  EXPECT_EQ(f.viewer->SetSceneView(eye, at), 0) << "not before Initialize()";
  ASSERT_TRUE(f.start_on_glass());
  vtkCamera* cam = f.viewer->GetSceneRenderer()->GetActiveCamera();
  ASSERT_EQ(f.viewer->SetSceneView(eye, at), 1);
  for (int k = 0; k < 3; ++k) {
    EXPECT_DOUBLE_EQ(cam->GetPosition()[k], eye[k]);
    EXPECT_DOUBLE_EQ(cam->GetFocalPoint()[k], at[k]);
  }
  EXPECT_EQ(f.viewer->SetSceneView(at, at), 0);
  const double nan[3] = {0, std::nan(""), 0};
  EXPECT_EQ(f.viewer->SetSceneView(nan, at), 0);
  EXPECT_DOUBLE_EQ(cam->GetPosition()[0], eye[0]);

  f.key("Right");
  for (int k = 0; k < 3; ++k) f.key("t");
  vtkPolyData* node = f.viewer->GetWalkCurrentNode();
  ASSERT_GT(node->GetNumberOfPoints(), 0);
  f.key("f");
  const std::string node_n = "node " + std::to_string(f.viewer->GetTraversalSteps()) + " of";
  EXPECT_NE(std::string(f.viewer->GetMessage()).find(node_n), std::string::npos)
      << f.viewer->GetMessage();
  // The node's box, corner by corner on the screen: inside the view and
  // spanning at least 40% of its smaller side.
  vtkRenderer* ren = f.viewer->GetSceneRenderer();
  double b[6];
  node->GetBounds(b);
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  for (int c = 0; c < 8; ++c) {
    ren->SetWorldPoint(b[c & 1], b[2 + ((c >> 1) & 1)], b[4 + ((c >> 2) & 1)], 1.0);
    ren->WorldToDisplay();
    double d[3];
    ren->GetDisplayPoint(d);
    EXPECT_TRUE(ren->IsInViewport(int(d[0]), int(d[1]))) << "corner " << c;
    for (int k = 0; k < 2; ++k) {
      lo[k] = std::min(lo[k], d[k]);
      hi[k] = std::max(hi[k], d[k]);
    }
  }
  const int* size = ren->GetSize();
  EXPECT_GT(std::max(hi[0] - lo[0], hi[1] - lo[1]), 0.4 * std::min(size[0], size[1]));
}

// A scene source without a scene: Initialize fails with a message, no crash.
TEST_F(Viewer, NoSceneFailsCleanly) {
  vtkNew<vtkRayScopeImageAlgorithm> empty;
  vtkNew<vtkRayScopeViewer> viewer;
  viewer->SetSceneSource(empty);
  EXPECT_EQ(viewer->Initialize(), 0);
  EXPECT_NE(std::string(viewer->GetMessage()).find("no input"), std::string::npos)
      << viewer->GetMessage();
  EXPECT_EQ(viewer->PickPixel(0, 0), 0);
  EXPECT_EQ(viewer->HandleKey("Up"), 0);
}
