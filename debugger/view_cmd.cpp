// `rayscope view [SCENE] [--pixel X,Y] [--accel ...]`: the interactive ray-tree
// and acceleration-structure debugger, a thin client of vtkRayScopeViewer
// (vtkplugin/module). The scene is built with the chosen structure, which the
// viewer draws and whose walks it plays. The options are checked and the
// scene is loaded here; the window is the viewer module's (view_module.h),
// loaded when `view` is the command.
#include <dlfcn.h>

#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.h"
#include "rayscope/image.h"
#include "scene_options.h"
#include "view_module.h"

namespace rayscope::cli {
namespace {

struct ViewOptions {
  SceneOptions scene;
  std::string pixel;
  std::string screenshot;
  std::string record;
  double fps = 1.0;
  std::vector<std::string> keys;
  std::string window;
  double font_scale = 1.0;
};

struct ViewModule {
  ViewHelpFn help = nullptr;
  ViewRunFn run = nullptr;
};

// The module beside the executable (the build tree), else where `install`
// puts it relative to the executable. Loaded once; a module that cannot be
// loaded is one error line naming it.
const ViewModule& view_module() {
  static const ViewModule module = [] {
    const std::filesystem::path exe_dir =
        std::filesystem::read_symlink("/proc/self/exe").parent_path();
    std::filesystem::path path = exe_dir / RAYSCOPE_VIEW_MODULE_NAME;
    if (!std::filesystem::exists(path))
      path = exe_dir / RAYSCOPE_VIEW_MODULE_INSTALL_RELDIR / RAYSCOPE_VIEW_MODULE_NAME;
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle)
      throw std::runtime_error("view: cannot load the viewer module " + path.string() + ": " +
                               dlerror());
    ViewModule m;
    m.help = reinterpret_cast<ViewHelpFn>(dlsym(handle, kViewHelpSymbol));
    m.run = reinterpret_cast<ViewRunFn>(dlsym(handle, kViewRunSymbol));
    if (!m.help || !m.run)
      throw std::runtime_error("view: " + path.string() + " is not RayScope's viewer module");
    return m;
  }();
  return module;
}

int run_view(const ViewOptions& o) {
  // Everything that can be wrong with the input fails here, before a window
  // opens, with the one-line errors of `render`.
  ViewRequest request;
  if (!o.pixel.empty()) parse_pixel_option(o.pixel, request.pixel);
  if (!o.window.empty()) parse_size("--window", o.window, request.window[0], request.window[1]);
  request.font_scale = o.font_scale;
  LoadedScene loaded = o.scene.load();
  if (!o.pixel.empty()) check_pixel_option(o.pixel, request.pixel, loaded.settings);
  request.loaded = &loaded;
  request.pick = !o.pixel.empty();
  request.keys = o.keys;
  request.screenshot = o.screenshot;
  if (!o.record.empty()) check_animation(o.record, o.fps);
  request.record = o.record;
  request.fps = o.fps;
  std::string error;
  const int status = view_module().run(request, error);
  if (status != 0) throw std::runtime_error(error);
  return 0;
}

}  // namespace

void add_view_command(CLI::App& app, int& exit_code) {
  auto opts = std::make_shared<ViewOptions>();
  static const std::string kDescription =
      "Open the interactive debugger: the image, the scene in 3D, a picked pixel's ray tree, and "
      "the structure chosen by --accel with the selected ray's walk through it. Keys: ";
  CLI::App* cmd = app.add_subcommand("view", kDescription + "(rayscope view --help lists them)");
  // Once `view` is the command, its help names the viewer's keys.
  cmd->preparse_callback([cmd](size_t) { cmd->description(kDescription + view_module().help()); });
  opts->scene.add_to(cmd);
  cmd->add_option("--pixel", opts->pixel,
                  "X,Y: pick this pixel at the start (0,0 is the top-left pixel; y grows "
                  "downward, as for render and inspect)");
  cmd->add_option("--keys", opts->keys,
                  "KEY...: keys to press after the render and the pick, as the window names "
                  "them (Up, Right, t, b, plus, bracketright, ...), e.g. for --screenshot")
      ->delimiter(',');
  cmd->add_option("--window", opts->window,
                  "WIDTHxHEIGHT: the window's size in pixels (e.g. 1920x1080 for a projector)");
  cmd->add_option("--font-scale", opts->font_scale,
                  "S: scale every text of the window (help, panel, labels, legend) by S (default "
                  "1; 2 for a lecture hall)");
  cmd->add_option("--screenshot", opts->screenshot,
                  "FILE.png: wait for the render, save the window and exit (no event loop)");
  cmd->add_option("--record", opts->record,
                  "FILE.gif: save the window after the render and pick, and after each key of "
                  "--keys, as the frames of a looping animated GIF, and exit (no event loop)");
  cmd->add_option("--fps", opts->fps, "F: frames per second of --record (0.1..50, default 1)");
  cmd->callback([opts, &exit_code]() { exit_code = run_view(*opts); });
}

}  // namespace rayscope::cli
