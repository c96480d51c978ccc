// vtkRayScopeViewer's keys, screenshots and .vtp export.
#include "rayscope/accel/accel_view.h"
#include "vtkRayScopeViewerInternals.h"

using namespace rayscope_vtk::viewer;

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
    in.Restart(m);  // drawn with the first tiles
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
    const std::string m = in.StructureLabel() + (this->ShowBVH ? " shown" : " hidden");
    if (!picked) {  // without a pick the structure is still worth seeing
      in.UpdateBVH();
      return say(m);
    }
    return refresh(m);
  }
  if (key == "l" || key == "L") {
    // The levels of the structure drawn (rayscope::AccelView: the binary BVH
    // for the BVH kinds, else the structure the rays walk).
    const int depth = rayscope::make_accel_view(in.scene()->accel()).depth;
    const std::string name = in.StructureLabel();
    if (key == "l" && this->BVHLevel >= depth - 1)
      return say("l: level " + std::to_string(this->BVHLevel) + " is the deepest of the " + name);
    if (key == "L" && this->BVHLevel < 0) return say("L: every level is shown");
    this->BVHLevel += key == "l" ? 1 : -1;
    this->ShowBVH = true;
    const std::string m = this->BVHLevel < 0 ? name + ": every level"
                                             : name + ": level " + std::to_string(this->BVHLevel);
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
