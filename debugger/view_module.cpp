// The viewer module behind `rayscope view` (see view_module.h): opens
// vtkRayScopeViewer (vtkplugin/module) on the checked request.
#include <algorithm>
#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkRenderWindow.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowToImageFilter.h>

#include "rayscope/image.h"

#include "view_module.h"
#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopeViewer.h"

namespace {

using rayscope::cli::ViewRequest;

// The window once its render is done: 8-bit RGB, rows from the top.
rayscope::Rgb8Image grab(vtkRayScopeViewer* viewer) {
  viewer->WaitForRender();
  vtkRenderWindow* window = viewer->GetRenderWindow();
  window->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  grab->SetInputBufferTypeToRGB();
  grab->Update();
  vtkImageData* image = grab->GetOutput();
  int dims[3];
  image->GetDimensions(dims);
  vtkUnsignedCharArray* px =
      vtkUnsignedCharArray::SafeDownCast(image->GetPointData()->GetScalars());
  rayscope::Rgb8Image f;
  if (!px || px->GetNumberOfComponents() != 3) return f;
  f.width = dims[0];
  f.height = dims[1];
  f.rgb.resize(size_t(f.width) * size_t(f.height) * 3);
  const size_t row = size_t(f.width) * 3;
  for (int y = 0; y < f.height; ++y)  // VTK's row 0 is the bottom one
    std::copy_n(px->GetPointer(0) + size_t(f.height - 1 - y) * row, row,
                f.rgb.data() + size_t(y) * row);
  return f;
}

// The viewer's scene source for a loaded scene and its settings.
vtkSmartPointer<vtkRayScopeImageAlgorithm> scene_source(const rayscope::LoadedScene& loaded) {
  const rayscope::RenderSettings& rs = loaded.settings;
  auto scene = vtkSmartPointer<vtkRayScopeImageAlgorithm>::New();
  scene->SetSize(rs.width, rs.height);
  scene->SetSamples(rs.samples);
  scene->SetMaxDepth(rs.max_depth);
  scene->SetMinContribution(rs.min_contribution);
  scene->SetMaxSamples(rs.max_samples);
  scene->SetTargetError(rs.target_error);
  scene->SetTextureFilter(rs.texture_filter);
  scene->SetThreads(rs.threads);
  scene->SetSeed(int(rs.seed));
  scene->SetCoreScene(loaded.scene);
  return scene;
}

// A pixel counted from the top (as the command takes it) counted from the
// bottom, as the viewer counts it.
int viewer_row(const rayscope::LoadedScene& loaded, int y) {
  return loaded.settings.height - 1 - y;
}

int run(const ViewRequest& r) {
  // Scripted keys are checked before a window opens.
  for (const std::string& key : r.keys)
    if (!vtkRayScopeViewer::IsKey(key.c_str()))
      throw std::invalid_argument("--keys: '" + key + "' is not a key of the viewer");
  for (size_t n = 0; n < r.chapters.size(); ++n)
    for (const std::string& key : r.chapters[n].keys)
      if (!vtkRayScopeViewer::IsKey(key.c_str()))
        throw std::invalid_argument("chapter " + std::to_string(n + 1) + " (" +
                                    r.chapters[n].title + "): --keys: '" + key +
                                    "' is not a key of the viewer");
  vtkNew<vtkRayScopeViewer> viewer;
  if (r.window[0] > 0) viewer->SetWindowSize(r.window[0], r.window[1]);
  viewer->SetFontScale(r.font_scale);
  if (const std::string e = viewer->SettingsError(); !e.empty()) throw std::invalid_argument(e);
  if (!r.chapters.empty()) {
    for (const rayscope::cli::ViewChapter& c : r.chapters) {
      std::string keys;
      for (const std::string& k : c.keys) keys += (keys.empty() ? "" : ",") + k;
      viewer->AddChapter(scene_source(c.loaded), c.title.c_str(), c.caption.c_str(),
                         c.pick ? c.pixel[0] : -1, c.pick ? viewer_row(c.loaded, c.pixel[1]) : -1,
                         keys.c_str());
    }
    if (!viewer->SetChapter(r.chapter)) throw std::runtime_error(viewer->GetMessage());
  } else {
    viewer->SetSceneSource(scene_source(*r.loaded));
    if (!viewer->Initialize()) throw std::runtime_error(viewer->GetMessage());
    if (r.pick) {
      viewer->WaitForRender();
      viewer->PickPixel(r.pixel[0], viewer_row(*r.loaded, r.pixel[1]));
    }
  }
  if (r.aim && !viewer->SetSceneView(r.view_camera, r.view_camera + 3))
    throw std::invalid_argument("--view-camera: the 3D view cannot look from a point at itself");
  std::vector<rayscope::Rgb8Image> frames;
  const bool record = !r.record.empty();
  if (record) frames.push_back(grab(viewer));
  for (const std::string& key : r.keys) {
    viewer->WaitForRender();  // keys that re-render finish before the next key
    viewer->HandleKey(key.c_str());
    if (record) frames.push_back(grab(viewer));
  }
  if (record) rayscope::write_animation(r.record, frames, r.fps);
  if (!r.screenshot.empty()) {
    viewer->WaitForRender();
    if (!viewer->SaveScreenshot(r.screenshot.c_str()))
      throw std::runtime_error(r.screenshot + ": " + viewer->GetMessage());
  }
  if (record || !r.screenshot.empty()) return 0;
  viewer->Start();
  return 0;
}

}  // namespace

extern "C" {

__attribute__((visibility("default"))) const char* rayscope_view_help() {
  return vtkRayScopeViewer::GetHelpText();
}

// Exceptions stay in the module: the error comes back as text, exit status 1.
__attribute__((visibility("default"))) int rayscope_view_run(const ViewRequest& request,
                                                             std::string& error) {
  try {
    return run(request);
  } catch (const std::exception& e) {
    error = e.what();
    return 1;
  }
}

}  // extern "C"
