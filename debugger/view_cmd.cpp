// `rayscope view [SCENE] [--pixel X,Y] [--accel ...]`: the interactive ray-tree
// and acceleration-structure debugger, a thin client of vtkRayScopeViewer
// (vtkplugin/module). The scene is built with the chosen structure, which the
// viewer draws and whose walks it plays.
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <vtkNew.h>

#include "commands.h"
#include "scene_options.h"
#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopeViewer.h"

namespace rayscope::cli {
namespace {

struct ViewOptions {
  SceneOptions scene;
  std::string pixel;
  std::string screenshot;
  std::vector<std::string> keys;
};

int run_view(const ViewOptions& o) {
  // Everything that can be wrong with the input fails here, before a window
  // opens, with the one-line errors of `render`.
  int pxy[2] = {-1, -1};
  if (!o.pixel.empty()) parse_pixel_option(o.pixel, pxy);
  LoadedScene loaded = o.scene.load();
  const RenderSettings& rs = loaded.settings;
  if (!o.pixel.empty()) check_pixel_option(o.pixel, pxy, rs);

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
  scene->SetCoreScene(loaded.scene);
  vtkNew<vtkRayScopeViewer> viewer;
  viewer->SetSceneSource(scene);
  if (!viewer->Initialize()) throw std::runtime_error(viewer->GetMessage());
  if (!o.pixel.empty()) {
    viewer->WaitForRender();
    viewer->PickPixel(pxy[0], rs.height - 1 - pxy[1]);  // the viewer counts from the bottom
  }
  for (const std::string& key : o.keys) {
    viewer->WaitForRender();  // keys that re-render finish before the next key
    if (!viewer->HandleKey(key.c_str()))
      throw std::invalid_argument("--keys: '" + key + "' is not a key of the viewer");
  }
  if (!o.screenshot.empty()) {
    viewer->WaitForRender();
    if (!viewer->SaveScreenshot(o.screenshot.c_str()))
      throw std::runtime_error(o.screenshot + ": " + viewer->GetMessage());
    return 0;
  }
  viewer->Start();
  return 0;
}

}  // namespace

void add_view_command(CLI::App& app, int& exit_code) {
  auto opts = std::make_shared<ViewOptions>();
  CLI::App* cmd = app.add_subcommand(
      "view",
      std::string("Open the interactive debugger: the image, the scene in 3D, a picked pixel's "
                  "ray tree, and the structure chosen by --accel with the selected ray's walk "
                  "through it. Keys: ") +
          vtkRayScopeViewer::GetHelpText());
  opts->scene.add_to(cmd);
  cmd->add_option("--pixel", opts->pixel,
                  "X,Y: pick this pixel at the start (0,0 is the top-left pixel; y grows "
                  "downward, as for render and inspect)");
  cmd->add_option("--keys", opts->keys,
                  "KEY...: keys to press after the render and the pick, as the window names "
                  "them (Up, Right, t, b, plus, bracketright, ...), e.g. for --screenshot")
      ->delimiter(',');
  cmd->add_option("--screenshot", opts->screenshot,
                  "FILE.png: wait for the render, save the window and exit (no event loop)");
  cmd->callback([opts, &exit_code]() { exit_code = run_view(*opts); });
}

}  // namespace rayscope::cli
