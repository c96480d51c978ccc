// vtkRayScopeViewer's text: the help line (made from the key table) and the
// message line on top, the panel below with the picked pixel's tree as
// `rayscope inspect` prints it, and the legend of the 3D view.
#include <set>

#include "vtkRayScopeViewerInternals.h"

using namespace rayscope_vtkmodule::viewer;

namespace {

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

}  // namespace

// The text actors, in the header, the panel and the 3D view.
void vtkRayScopeViewer::Internals::BuildTextPanel() {
  // Help and message lines on top (LayoutHeader()), the inspect text below.
  this->HelpActor->GetTextProperty()->SetFontSize(this->FontSize(13));
  this->HelpActor->GetTextProperty()->SetColor(0.8, 0.8, 0.8);
  this->HelpActor->GetTextProperty()->SetVerticalJustificationToTop();
  this->HelpActor->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  this->HeaderRen->AddActor2D(this->HelpActor);
  this->MessageActor->GetTextProperty()->SetFontSize(this->FontSize(13));
  this->MessageActor->GetTextProperty()->SetColor(1.0, 0.85, 0.3);
  this->MessageActor->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  this->HeaderRen->AddActor2D(this->MessageActor);
  this->LayoutHeader();
  // The panel: a text actor per line, from the top left corner down, a line
  // height apart (FreeType's own spacing of the lines of one text: drawn
  // so, the panel is pixel for pixel the text drawn by one actor).
  vtkNew<vtkTextProperty> panel_text;
  panel_text->SetFontFamilyToCourier();
  panel_text->SetFontSize(this->FontSize(12));
  panel_text->SetVerticalJustificationToTop();
  int one[4], two[4];
  vtkTextRenderer* text = vtkTextRenderer::GetInstance();
  this->PanelLineHeight =
      text && text->GetBoundingBox(panel_text, vtkStdString("Xg"), one, this->Window->GetDPI()) &&
              text->GetBoundingBox(panel_text, vtkStdString("Xg\nXg"), two, this->Window->GetDPI())
          ? (two[3] - two[2]) - (one[3] - one[2])
          : 14;
  // Courier: every character as wide as one tenth of ten.
  int ten[4];
  this->PanelCharWidth = text && text->GetBoundingBox(panel_text, vtkStdString("XXXXXXXXXX"), ten,
                                                      this->Window->GetDPI())
                             ? std::max(1.0, (ten[1] - ten[0]) / 10.0)
                             : 0.6 * this->FontSize(12);
  vtkNew<vtkCoordinate> panel_corner;
  panel_corner->SetCoordinateSystemToNormalizedViewport();
  panel_corner->SetValue(0.005, 0.98);
  for (int k = 0; k < kPanelLines; ++k) {
    auto line = vtkSmartPointer<vtkTextActor>::New();
    line->GetTextProperty()->ShallowCopy(panel_text);
    line->GetPositionCoordinate()->SetCoordinateSystemToViewport();
    line->GetPositionCoordinate()->SetReferenceCoordinate(panel_corner);
    this->PanelRen->AddActor2D(line);
    this->PanelLines.push_back(line);
  }
  this->PanelLineText.assign(size_t(kPanelLines), std::string());
  this->ShowPanelLines({kPickPrompt});
  // The caption of a lecture's chapter, on top of the 3D view (ShowCaption()),
  // as large as the help line and on a dark band, to read from the back of
  // a lecture hall.
  vtkTextProperty* caption = this->CaptionActor->GetTextProperty();
  caption->SetFontSize(this->FontSize(16));
  caption->SetColor(1.0, 1.0, 1.0);
  caption->SetBackgroundColor(0.0, 0.0, 0.0);
  caption->SetBackgroundOpacity(0.75);
  caption->SetVerticalJustificationToTop();
  this->CaptionActor->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  this->CaptionActor->GetPositionCoordinate()->SetValue(0.01, 0.985);
  this->CaptionActor->VisibilityOff();
  this->SceneRen->AddActor2D(this->CaptionActor);
  // The legend, in the 3D view's bottom left corner.
  this->Legend->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  this->Legend->GetPositionCoordinate()->SetValue(0.0, 0.0);
  this->Legend->UseBackgroundOn();
  this->Legend->SetBackgroundColor(0.0, 0.0, 0.0);
  this->SceneRen->AddActor2D(this->Legend);
  this->UpdateLegend();
}

std::string vtkRayScopeViewer::Internals::WrapText(vtkTextProperty* prop, const std::string& text,
                                                   const std::string& sep, int room) const {
  vtkTextRenderer* renderer = vtkTextRenderer::GetInstance();
  const int dpi = this->Window->GetDPI();
  auto too_wide = [&](const std::string& s) {
    int box[4] = {0, 0, 0, 0};
    return renderer && renderer->GetBoundingBox(prop, vtkStdString(s), box, dpi) &&
           box[1] - box[0] > room;
  };
  std::string wrapped, line;
  for (size_t at = 0; at <= text.size();) {
    const size_t end = std::min(text.find(sep, at), text.size());
    const std::string item = text.substr(at, end - at);
    if (!line.empty() && too_wide(line + sep + item)) {
      wrapped += (wrapped.empty() ? "" : "\n") + line;
      line = item;
    } else {
      line += (line.empty() ? "" : sep) + item;
    }
    at = end + sep.size();
  }
  return wrapped + (wrapped.empty() ? "" : "\n") + line;
}

void vtkRayScopeViewer::Internals::LayoutHeader() {
  const int* size = this->Self->GetWindowSize();
  const int width = size[0], height = size[1];
  vtkTextProperty* prop = this->HelpActor->GetTextProperty();
  vtkTextRenderer* text = vtkTextRenderer::GetInstance();
  const int dpi = this->Window->GetDPI();
  // Width and height in pixels of `s` in the header's font.
  auto extent = [&](const std::string& s, int& w, int& h) {
    int box[4] = {0, 0, 0, 0};
    if (!text || !text->GetBoundingBox(prop, vtkStdString(s), box, dpi)) return false;
    w = box[1] - box[0];
    h = box[3] - box[2];
    return true;
  };
  // The help line, broken at its " | " within the left margin and as much on
  // the right.
  const std::string wrapped =
      this->WrapText(prop, HelpLine(), " | ", width - int(0.01 * width) - 4);
  this->HelpActor->SetInput(wrapped.c_str());
  // FreeType's spacing of the lines of one text, as for the panel.
  int w = 0, one = 14, two = 28, help_height = 14;
  if (extent("Xg", w, one) && extent("Xg\nXg", w, two)) {
    extent(wrapped, w, help_height);
  } else {
    help_height = one * int(std::count(wrapped.begin(), wrapped.end(), '\n') + 1);
  }
  const int pad = std::max(2, (two - one) / 4);
  const int header = help_height + (two - one) + 3 * pad;  // help, message, margins
  const double bottom = std::min(kHeaderBottom, 1.0 - double(header) / double(height));
  const double rows = double(height) * (1.0 - bottom);  // the header's height in pixels
  this->HelpActor->GetPositionCoordinate()->SetValue(0.005, 1.0 - pad / rows);
  this->MessageActor->GetPositionCoordinate()->SetValue(0.005, pad / rows);
  this->HeaderRen->SetViewport(0.0, bottom, 1.0, 1.0);
  this->ImageRen->SetViewport(0.0, kPanelTop, 0.5, bottom);
  this->SceneRen->SetViewport(0.5, kPanelTop, 1.0, bottom);
}

void vtkRayScopeViewer::Internals::ShowCaption() {
  this->CaptionActor->SetVisibility(!this->Caption.empty());
  if (!this->Caption.empty()) {
    // The 3D view's width, less the caption's margin on either side.
    const int room = int(this->Self->GetWindowSize()[0] * 0.5 * 0.96);
    this->CaptionActor->SetInput(
        this->WrapText(this->CaptionActor->GetTextProperty(), this->Caption, " ", room).c_str());
  }
  this->Changed |= kSceneView;
}

// The message line: what the last key did, the end of a key's range, render
// progress, errors.
void vtkRayScopeViewer::Internals::Say(const std::string& message) {
  this->Message = message;
  this->MessageActor->SetInput(message.c_str());
  this->Changed |= kHeaderView;
}

// The panel: the inspect text from a few lines before the selected ray,
// that ray's line marked ">>".
void vtkRayScopeViewer::Internals::UpdatePanel() {
  this->UpdateTreeDiagram();
  if (this->Self->ShowTreeDiagram) {
    // The diagram below one line that says what it shows.
    const int* pixel = this->Self->PickedPixel;
    // (Counted from the top, as the text and the rayscope command count.)
    this->PanelText = "ray tree of pixel (" + std::to_string(pixel[0]) + ", " +
                      std::to_string(this->Settings.height - 1 - pixel[1]) +
                      "): " + std::to_string(this->Record.rays.size()) +
                      " rays, depth 0 (top) to " + std::to_string(this->RecordDepth) +
                      "; dimmed: hidden in 3D; g: the text again";
    this->ShowPanelLines({this->PanelText});
    return;
  }
  std::vector<std::string> lines;
  std::istringstream text(this->Self->ShowPacket ? this->PacketText : this->InspectText);
  for (std::string l; std::getline(text, l);) lines.push_back(l);
  int selected = -1;
  if (this->Self->SelectedRay >= 0 && !this->Self->ShowPacket) {
    // (Appended, not "#" + std::to_string(...): GCC 12 warns falsely on that
    // operator+ here, -Wrestrict.)
    std::string tag = "#";
    tag += std::to_string(this->Self->SelectedRay);
    tag += ' ';
    for (size_t k = 0; k < lines.size(); ++k) {
      const size_t at = lines[k].find_first_not_of(' ');
      if (at != std::string::npos && lines[k].compare(at, tag.size(), tag) == 0) {
        selected = int(k);
        lines[k].replace(0, std::min<size_t>(2, at), ">>");
        break;
      }
    }
  }
  // Lines longer than the panel is wide are broken at a space, the rest
  // indented under the line's own text (a lecture hall's font scale makes
  // the long ones, such as the lecture's tests, run off the right edge);
  // the panel shows as many lines as fit its height.
  const int* size = this->PanelRen->GetSize();
  // (FreeType's box of ten characters is a little narrower than ten
  // advances: 5% spare.)
  const int columns =
      std::max(kPanelLeastColumns, int(0.95 * (size[0] - 8) / this->PanelCharWidth));
  const int rows =
      std::clamp(int((size[1] * 0.98) / std::max(1, this->PanelLineHeight)), 1, kPanelLines);
  std::vector<std::string> wrapped;
  int selected_row = -1;
  for (size_t k = 0; k < lines.size(); ++k) {
    if (int(k) == selected) selected_row = int(wrapped.size());
    std::string rest = lines[k];
    // The continuation's indent: under the line's text, at most half a line.
    const size_t text = std::min(rest.find_first_not_of(" >"), rest.size());
    const std::string indent(std::min(text + 4, size_t(columns / 2)), ' ');
    while (int(rest.size()) > columns) {
      size_t cut = rest.rfind(' ', size_t(columns));
      if (cut == std::string::npos || cut <= indent.size()) cut = size_t(columns);
      wrapped.push_back(rest.substr(0, cut));
      const size_t next = rest.find_first_not_of(' ', cut);
      rest = indent + (next == std::string::npos ? std::string() : rest.substr(next));
    }
    wrapped.push_back(rest);
  }
  const int first =
      std::max(0, std::min(selected_row - kPanelLinesBefore, int(wrapped.size()) - rows));
  const std::vector<std::string> shown(
      wrapped.begin() + first, wrapped.begin() + std::min<int>(int(wrapped.size()), first + rows));
  this->PanelText.clear();
  for (const std::string& line : shown) this->PanelText += line + "\n";
  this->ShowPanelLines(shown);
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

void vtkRayScopeViewer::Internals::UpdateLegend() {
  // The entries for what the 3D view draws now: the kinds of the shown rays
  // and the markers among them, then the played walk's states or the BVH's
  // level ramp (root to deepest level). Only those: at a lecture hall's font
  // scale a legend of everything covered half the view.
  std::vector<std::pair<std::string, std::array<double, 3>>> entries;
  auto add = [&](std::string label, const double(&c)[3]) {
    entries.push_back({std::move(label), {c[0], c[1], c[2]}});
  };
  if (this->HasRecord && this->Self->PickedPixel[0] >= 0) {
    vtkPolyData* rays = this->Shown->GetOutput();
    vtkDataArray* kind = rays->GetCellData()->GetArray("Kind");
    vtkDataArray* skipped = rays->GetCellData()->GetArray("Skipped");
    std::set<int> kinds;
    bool any_skipped = false, any_hit = false;
    for (vtkIdType c = 0; kind && skipped && c < rays->GetNumberOfCells(); ++c) {
      if (rays->GetCellType(c) != VTK_LINE) {
        any_hit = true;  // a hit point
      } else if (skipped->GetTuple1(c) != 0) {
        any_skipped = true;
      } else {
        kinds.insert(int(kind->GetTuple1(c)));
      }
    }
    for (int k : kinds) {
      double c[3];
      vtkRayScopeRayTreeSource::GetKindColor(k, c);
      add(std::string(rayscope::to_string(rayscope::RayKind(k))) + " ray", c);
    }
    if (any_skipped) add("skipped (not traced)", kSkippedColor);
    if (any_hit) add("shading normal", kNormalColor);
    if (this->Occluders->GetNumberOfVerts() > 0) add("shadow ray blocked here", kOccluderColor);
  }
  if (this->Self->TraversalSteps >= 0) {
    const std::string name = this->StructureLabel();
    for (int k = 1; k < 6; ++k) add(name + ": " + kWalkNames[k], kWalkColors[k]);
    add(name + ": 1 2 3.. order entered, thick: last", kWalkColors[3]);
  } else if (this->Self->ShowBVH) {
    vtkDataArray* depth = this->BVH->GetOutput()->GetFieldData()->GetArray("TreeDepth");
    const int deepest = depth ? std::max(0, int(depth->GetTuple1(0)) - 1) : 0;
    const vtkIdType n = this->LevelTable->GetNumberOfTableValues();
    double root[4], leaves[4];
    this->LevelTable->GetTableValue(0, root);
    this->LevelTable->GetTableValue(n - 1, leaves);
    const std::string name = this->StructureLabel();
    add(name + ": level 0 (root)", {root[0], root[1], root[2]});
    add(name + ": level " + std::to_string(deepest) + " (deepest)",
        {leaves[0], leaves[1], leaves[2]});
  }
  if (this->PacketBoxActor->GetVisibility()) {
    double one[4], all[4];
    this->PacketTable->GetTableValue(0, one);
    this->PacketTable->GetTableValue(rayscope::kPacketRays - 1, all);
    add("packet: node entered by 1 ray", {one[0], one[1], one[2]});
    add("packet: by all " + std::to_string(rayscope::kPacketRays) + " rays",
        {all[0], all[1], all[2]});
  }
  // Rebuilt only when its entries change: each entry is text to rasterize.
  if (entries == this->LegendEntries) return;
  this->LegendEntries = entries;
  this->Changed |= kSceneView;
  this->Legend->SetVisibility(!entries.empty());
  // Its entries' text fills the box: the box is as tall as its entries at
  // the viewer's font size and as wide as the longest, so that it covers no
  // more of the view than it needs.
  vtkNew<vtkTextProperty> text;
  text->SetFontSize(this->FontSize(12));
  vtkTextRenderer* renderer = vtkTextRenderer::GetInstance();
  int widest = 0;
  for (const auto& [label, color] : entries) {
    int box[4] = {0, 0, 0, 0};
    if (renderer &&
        renderer->GetBoundingBox(text, vtkStdString(label), box, this->Window->GetDPI()))
      widest = std::max(widest, box[1] - box[0]);
  }
  const int* view = this->SceneRen->GetSize();
  const double line = 1.5 * this->FontSize(12), mark = 2.5 * this->FontSize(12);
  this->Legend->GetPosition2Coordinate()->SetValue(
      std::min(0.6, (widest + mark) / std::max(1, view[0])),
      std::min(0.9, line * double(entries.size()) / std::max(1, view[1])));
  this->Legend->SetNumberOfEntries(int(entries.size()));
  vtkSmartPointer<vtkPolyData> symbol = legend_symbol();
  for (size_t e = 0; e < entries.size(); ++e)
    this->Legend->SetEntry(int(e), symbol, entries[e].first.c_str(), entries[e].second.data());
}
