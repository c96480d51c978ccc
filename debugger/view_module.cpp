// The viewer module behind `rayscope view` (see view_module.h): opens
// vtkRayScopeViewer (vtkplugin/module) on the checked request.
#include <exception>
#include <stdexcept>
#include <string>

#include <vtkNew.h>

#include "view_module.h"
#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopeViewer.h"

namespace {

using rayscope::cli::ViewRequest;

int run(const ViewRequest& r) {
  const rayscope::RenderSettings& rs = r.loaded->settings;
  vtkNew<vtkRayScopeImageAlgorithm> scene;
  scene->SetSize(rs.width, rs.height);
  scene->SetSamples(rs.samples);
  scene->SetMaxDepth(rs.max_depth);
  scene->SetMinContribution(rs.min_contribution);
  scene->SetMaxSamples(rs.max_samples);
  scene->SetTargetError(rs.target_error);
  scene->SetTextureFilter(rs.texture_filter);
  scene->SetThreads(rs.threads);
  scene->SetSeed(int(rs.seed));
  scene->SetCoreScene(r.loaded->scene);
  vtkNew<vtkRayScopeViewer> viewer;
  if (r.window[0] > 0) viewer->SetWindowSize(r.window[0], r.window[1]);
  viewer->SetFontScale(r.font_scale);
  if (const std::string e = viewer->SettingsError(); !e.empty()) throw std::invalid_argument(e);
  viewer->SetSceneSource(scene);
  if (!viewer->Initialize()) throw std::runtime_error(viewer->GetMessage());
  if (r.pick) {
    viewer->WaitForRender();
    viewer->PickPixel(r.pixel[0], rs.height - 1 - r.pixel[1]);  // the viewer counts from the bottom
  }
  for (const std::string& key : r.keys) {
    viewer->WaitForRender();  // keys that re-render finish before the next key
    if (!viewer->HandleKey(key.c_str()))
      throw std::invalid_argument("--keys: '" + key + "' is not a key of the viewer");
  }
  if (!r.screenshot.empty()) {
    viewer->WaitForRender();
    if (!viewer->SaveScreenshot(r.screenshot.c_str()))
      throw std::runtime_error(r.screenshot + ": " + viewer->GetMessage());
    return 0;
  }
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
