// vtkRayScopeViewer's keys: one table whose rows name a key (or the keys of
// one action, such as Up/Down), what the help line says it does, and its
// action. HandleKey() finds a key's action there and the help line
// (GetHelpText(): the window's header, `rayscope view --help`) is made from
// it, so the two name the same keys.
#include "rayscope/accel/accel_view.h"
#include "vtkBoundingBox.h"
#include "vtkRayScopeViewerInternals.h"
#include "vtkUnstructuredGrid.h"

using namespace rayscope_vtkmodule::viewer;
using RS = rayscope::RenderSettings;

// A key pressed: the viewer, its private state, the key, and the actions of
// the key table (each returns 1: the key was the viewer's).
struct vtkRayScopeViewer::Internals::KeyPress {
  vtkRayScopeViewer* self;
  Internals& in;
  std::string key;  // the keysym, as VTK names it
  bool picked;      // a pixel is picked and its tree recorded
  int nrays;        // the rays of that tree

  // The actions (below the table).
  int Depth();
  int Ray();
  int Walk();
  int Structure();
  int Level();
  int Kind();
  int Labels();
  int Diagram();
  int Packet();
  int NextImageMode();
  int Samples();
  int MaxDepth();
  int Projection();
  int Camera();
  int Frame();
  int Chapter();
  int Screenshot();
  int Export();

  /// Says `m` in the message line.
  int say(const std::string& m) {
    in.Say(m);
    in.Redraw();
    return 1;
  }
  /// Says that the key needs a picked pixel.
  int need_pick() { return say(key + ": pick a pixel first (click the image)"); }
  /// Shows the picked pixel's overlay and the legend as the changed settings
  /// select them, and says `m`.
  int refresh(const std::string& m) {
    in.UpdateOverlay();
    in.UpdateLegend();
    return say(m);
  }
  /// Re-renders with the changed settings; `m` is drawn with the first tiles.
  int rerender(const std::string& m) {
    in.Restart(m);
    return 1;
  }
};

// A row of the key table.
struct vtkRayScopeViewer::Internals::Key {
  const char* keys;                  // as the help line names them: "Up/Down"
  std::vector<std::string> keysyms;  // as VTK names them: "Up", "Down" (none: the mouse)
  const char* help;                  // what the help line says they do
  bool joined;                       // in the help line: ", " after the row before, not " | "
  int (KeyPress::*action)();         // nullptr: the interactor style's, not HandleKey()'s
};

// The keys, in the order of the help line.
const std::vector<vtkRayScopeViewer::Internals::Key>& vtkRayScopeViewer::Internals::KeyTable() {
  static const std::vector<Key> table = {
      {"click", {}, "pick", false, nullptr},  // the interactor style: PickAtDisplay()
      {"Up/Down", {"Up", "Down"}, "depth", false, &KeyPress::Depth},
      {"Right/Left", {"Right", "Left"}, "ray", false, &KeyPress::Ray},
      {"t/T", {"t", "T"}, "walk", false, &KeyPress::Walk},
      {"b", {"b"}, "structure", false, &KeyPress::Structure},
      {"l/L", {"l", "L"}, "level", true, &KeyPress::Level},
      {"k", {"k"}, "kind", false, &KeyPress::Kind},
      {"d", {"d"}, "labels", false, &KeyPress::Labels},
      {"g", {"g"}, "tree diagram", false, &KeyPress::Diagram},
      {"c", {"c"}, "packet", true, &KeyPress::Packet},
      {"m", {"m"}, "image", false, &KeyPress::NextImageMode},
      {"+/-", {"plus", "KP_Add", "minus", "KP_Subtract"}, "spp", false, &KeyPress::Samples},
      {"]/[", {"bracketright", "bracketleft"}, "depth", true, &KeyPress::MaxDepth},
      {"p", {"p"}, "projection", true, &KeyPress::Projection},
      {"r", {"r"}, "3D camera", true, &KeyPress::Camera},
      {"f/F", {"f", "F"}, "frame node/ray/scene", true, &KeyPress::Frame},
      {"PgDn/PgUp",
       {"Next", "Prior", "Page_Down", "Page_Up"},
       "chapter",
       false,
       &KeyPress::Chapter},
      {"s", {"s"}, "screenshot", false, &KeyPress::Screenshot},
      {"x", {"x"}, ".vtp", true, &KeyPress::Export},
      {"q", {"q"}, "quit", false, nullptr},  // the interactor style: VTK's trackball quits
  };
  return table;
}

// "click: pick | Up/Down: depth | ...": each row's keys and help, a group of
// rows joined by ", ".
const std::string& vtkRayScopeViewer::Internals::HelpLine() {
  static const std::string line = [] {
    std::string s;
    for (const Key& k : KeyTable()) {
      if (!s.empty()) s += k.joined ? ", " : " | ";
      s += std::string(k.keys) + ": " + k.help;
    }
    return s;
  }();
  return line;
}

bool vtkRayScopeViewer::IsKey(const char* keysym) {
  if (!keysym) return false;
  for (const Internals::Key& k : Internals::KeyTable())
    if (k.action && std::find(k.keysyms.begin(), k.keysyms.end(), keysym) != k.keysyms.end())
      return true;
  return false;
}

int vtkRayScopeViewer::HandleKey(const char* keysym) {
  Internals& in = *this->Internal;
  if (!keysym || !in.Initialized) return 0;
  for (const Internals::Key& k : Internals::KeyTable()) {
    if (!k.action || std::find(k.keysyms.begin(), k.keysyms.end(), keysym) == k.keysyms.end())
      continue;
    const bool picked = in.HasRecord && this->PickedPixel[0] >= 0;
    Internals::KeyPress press{this, in, keysym, picked, picked ? int(in.Record.rays.size()) : 0};
    return (press.*k.action)();
  }
  return 0;
}

// --- The actions -------------------------------------------------------------------

// The next / previous chapter of a lecture.
int vtkRayScopeViewer::Internals::KeyPress::Chapter() {
  const int n = int(in.Chapters.size());
  const bool next = key == "Next" || key == "Page_Down";
  if (n == 0)
    return say("PgDn/PgUp: no lecture (rayscope view --lecture data/lecture/course.json)");
  if (next && self->Chapter >= n - 1)
    return say("PgDn: chapter " + std::to_string(n) + " is the last");
  if (!next && self->Chapter <= 0) return say("PgUp: this is the first chapter");
  self->SetChapter(self->Chapter + (next ? 1 : -1));
  return 1;
}

// One recursion depth more / less of the picked pixel's tree.
int vtkRayScopeViewer::Internals::KeyPress::Depth() {
  if (!picked) return need_pick();
  const bool up = key == "Up";
  if (up && self->ShownDepth >= in.RecordDepth)
    return say("Up: the whole tree is shown (its deepest ray has depth " +
               std::to_string(in.RecordDepth) + ")");
  if (!up && self->ShownDepth <= 0) return say("Down: only the primary rays are shown");
  self->ShownDepth += up ? 1 : -1;
  return refresh("showing rays up to depth " + std::to_string(self->ShownDepth));
}

// The next / previous ray in trace order; rays after it are hidden.
int vtkRayScopeViewer::Internals::KeyPress::Ray() {
  if (!picked) return need_pick();
  if (key == "Right" && self->SelectedRay >= nrays - 1)
    return say("Right: ray #" + std::to_string(nrays - 1) + " is the last ray traced");
  if (key == "Left" && self->SelectedRay < 0)
    return say("Left: no ray is selected (every ray is shown); Right selects the first");
  self->SelectedRay += key == "Right" ? 1 : -1;
  self->TraversalSteps = -1;
  return refresh(self->SelectedRay < 0
                     ? std::string("every ray shown")
                     : "ray #" + std::to_string(self->SelectedRay) + " selected (" +
                           rayscope::to_string(in.Record.rays[size_t(self->SelectedRay)].kind) +
                           "); rays after it are hidden");
}

// The selected ray's walk through the structure, one node forward /
// back (t with no ray selected selects the first).
int vtkRayScopeViewer::Internals::KeyPress::Walk() {
  if (!picked) return need_pick();
  if (self->SelectedRay < 0) self->SelectedRay = 0;
  const rayscope::RayRecord& r = in.Record.rays[size_t(self->SelectedRay)];
  const int entries = int(r.traversal.nodes().size());
  const std::string ray = "ray #" + std::to_string(r.id);
  if (r.skipped) return say("t: " + ray + " was not traced, so it has no walk");
  if (key == "t") {
    if (self->TraversalSteps >= entries)
      return say("t: the walk of " + ray + " is complete (" + std::to_string(entries) +
                 " nodes entered)");
    self->TraversalSteps = std::max(0, self->TraversalSteps) + 1;
  } else {
    if (self->TraversalSteps < 0) return say("T: no walk is playing (t plays one)");
    --self->TraversalSteps;  // from 0: the walk is no longer played
  }
  return refresh(self->TraversalSteps < 0
                     ? std::string("walk hidden")
                     : "walk of " + ray + ": " + std::to_string(self->TraversalSteps) + " of " +
                           std::to_string(entries) + " nodes entered");
}

// The whole structure shown / hidden, colored by level.
int vtkRayScopeViewer::Internals::KeyPress::Structure() {
  self->ShowBVH = !self->ShowBVH;
  const std::string m =
      in.StructureLabel() + (self->ShowBVH ? " shown (its empty leaves left out)" : " hidden");
  if (!picked) {  // without a pick the structure is still worth seeing
    in.UpdateBVH();
    return say(m);
  }
  return refresh(m);
}

// The next / previous level of the structure only (L from level 0:
// every level).
int vtkRayScopeViewer::Internals::KeyPress::Level() {
  // The levels of the structure drawn (rayscope::AccelView: the binary
  // BVH for the BVH kinds, else the structure the rays walk).
  const int depth = rayscope::make_accel_view(in.scene()->accel()).depth;
  const std::string name = in.StructureLabel();
  if (key == "l" && self->BVHLevel >= depth - 1)
    return say("l: level " + std::to_string(self->BVHLevel) + " is the deepest of the " + name);
  if (key == "L" && self->BVHLevel < 0) return say("L: every level is shown");
  self->BVHLevel += key == "l" ? 1 : -1;
  self->ShowBVH = true;
  const std::string m = self->BVHLevel < 0 ? name + ": every level"
                                           : name + ": level " + std::to_string(self->BVHLevel);
  if (picked) return refresh(m);
  in.UpdateBVH();
  return say(m);
}

// One ray kind only: primary, shadow, reflection, refraction, then all.
int vtkRayScopeViewer::Internals::KeyPress::Kind() {
  self->ShownKind = self->ShownKind >= 3 ? -1 : self->ShownKind + 1;
  const std::string m = self->ShownKind < 0
                            ? std::string("every ray kind shown")
                            : std::string("only ") +
                                  rayscope::to_string(rayscope::RayKind(self->ShownKind)) +
                                  " rays shown";
  return picked ? refresh(m) : say(m);
}

// Labels "#id dDEPTH wWEIGHT" on the shown rays, or none.
int vtkRayScopeViewer::Internals::KeyPress::Labels() {
  self->ShowLabels = !self->ShowLabels;
  const std::string m = self->ShowLabels ? "ray labels: #id, depth, weight" : "ray labels hidden";
  if (!picked) return say(m);
  return refresh(m);
}

// The panel's tree diagram instead of its text, or the text again.
int vtkRayScopeViewer::Internals::KeyPress::Diagram() {
  if (!picked) return need_pick();
  self->ShowTreeDiagram = !self->ShowTreeDiagram;
  self->ShowPacket = false;
  in.UpdatePanel();
  in.UpdateMarker();
  in.UpdatePacketBoxes();
  in.UpdateLegend();
  return say(self->ShowTreeDiagram ? "tree diagram: each ray below its parent" : "tree as text");
}

// The packet the picked pixel's primary ray was traced in, or the tree again.
int vtkRayScopeViewer::Internals::KeyPress::Packet() {
  if (!picked) return need_pick();
  self->ShowPacket = !self->ShowPacket;
  self->ShowTreeDiagram = false;
  return refresh(self->ShowPacket
                     ? "packet: the block of pixels traced together; '#': rays active in each node"
                     : "tree as text");
}

// The next image mode (one the image has data for).
int vtkRayScopeViewer::Internals::KeyPress::NextImageMode() {
  const int mode = (self->ImageMode + 1) % rayscope_vtkmodule::kDisplayModes;
  if (in.HasImage && rayscope_vtkmodule::display_pixels(in.Image, mode).empty())
    return say(std::string("m: the image has no data for ") +
               rayscope_vtkmodule::display_mode_name(mode));
  self->SetImageMode(mode);
  return say(std::string("image: ") + rayscope_vtkmodule::display_mode_name(mode));
}

// One more / fewer samples per pixel per axis, and a render.
int vtkRayScopeViewer::Internals::KeyPress::Samples() {
  vtkRayScopeImageAlgorithm* alg = in.Algorithm;
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

// The maximum depth one more / less, and a render.
int vtkRayScopeViewer::Internals::KeyPress::MaxDepth() {
  vtkRayScopeImageAlgorithm* alg = in.Algorithm;
  const bool up = key == "bracketright";
  const int d = alg->GetMaxDepth();
  if (up && d >= RS::kMaxDepth) return say("]: maximum depth at its limit, " + std::to_string(d));
  if (!up && d <= 0) return say("[: maximum depth already 0 (primary rays only)");
  alg->SetMaxDepth(d + (up ? 1 : -1));
  self->ShownDepth = VTK_INT_MAX;
  return rerender("re-rendering with maximum depth " + std::to_string(alg->GetMaxDepth()));
}

// Central <-> parallel projection, for contrast, and a render; the
// parallel view shows what the central one shows at the focal point.
int vtkRayScopeViewer::Internals::KeyPress::Projection() {
  vtkRayScopeImageAlgorithm* alg = in.Algorithm;
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

// The 3D view's camera as the ray-tracing camera, and a render.
int vtkRayScopeViewer::Internals::KeyPress::Camera() {
  in.Algorithm->CopyCamera(in.SceneRen->GetActiveCamera());
  return rerender("re-rendering from the 3D view's camera");
}

// f: the 3D view framed on the selected ray, or else on the hit points of
// the picked pixel's shown rays (where the tree bounces, without the eye and
// the lights the primary and shadow rays reach), so that rays a few pixels
// long fill the view and their labels stand apart; it keeps its direction of
// view. F: on the whole scene again.
int vtkRayScopeViewer::Internals::KeyPress::Frame() {
  if (key == "F") {
    in.FrameScene();
    return say("3D view: the whole scene");
  }
  if (!picked) return need_pick();
  vtkBoundingBox box;
  std::string what;
  if (in.WalkCurrent->GetNumberOfPoints() > 0) {
    // The walk's current node, which deep in the tree is a few pixels wide.
    double bounds[6];
    in.WalkCurrent->GetBounds(bounds);
    box.SetBounds(bounds);
    what = "node " + std::to_string(self->TraversalSteps) + " of the walk";
  } else if (self->SelectedRay >= 0) {
    in.Selected->Update();
    vtkDataSet* ray = in.Selected->GetOutput();
    for (vtkIdType p = 0; p < ray->GetNumberOfPoints(); ++p) box.AddPoint(ray->GetPoint(p));
    what = "ray #" + std::to_string(self->SelectedRay);
  } else {
    vtkPolyData* shown = in.Shown->GetOutput();
    for (vtkIdType c = 0; c < shown->GetNumberOfCells(); ++c)
      if (shown->GetCellType(c) == VTK_VERTEX)
        box.AddPoint(shown->GetPoint(shown->GetCell(c)->GetPointId(0)));
    what = "the shown rays' hits";
  }
  if (!box.IsValid()) return say("f: nothing shown to frame");
  double bounds[6];
  box.GetBounds(bounds);
  in.AimSceneCamera(bounds, 1.0);
  return say("3D view: " + what + " (F: the whole scene)");
}

// The window saved as PREFIX_N.png.
int vtkRayScopeViewer::Internals::KeyPress::Screenshot() {
  const std::string file =
      std::string(self->OutputPrefix) + "_" + std::to_string(++in.ScreenshotCount) + ".png";
  return say(self->SaveScreenshot(file.c_str()) ? "screenshot: " + file
                                                : "screenshot failed: " + in.Message);
}

// The shown ray tree and the structure written as PREFIX_N_raytree.vtp
// and PREFIX_N_bvh.vtp.
int vtkRayScopeViewer::Internals::KeyPress::Export() {
  const std::string prefix =
      std::string(self->OutputPrefix) + "_" + std::to_string(++in.ExportCount);
  if (!picked) return need_pick();
  return say(self->ExportVTP(prefix.c_str())
                 ? "exported " + prefix + "_raytree.vtp and " + prefix + "_bvh.vtp"
                 : "export failed: " + in.Message);
}
