// `rayscope view [SCENE] [--pixel X,Y] [--accel ...]` and `rayscope view
// --lecture COURSE.json`: the interactive ray-tree and acceleration-structure
// debugger, a thin client of vtkRayScopeViewer (vtkplugin/module). The scene
// (or each chapter's) is built with the chosen structure, which the viewer
// draws and whose walks it plays. The options are checked and the scenes are
// loaded here; the window is the viewer module's (view_module.h), loaded when
// `view` is the command.
#include <dlfcn.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.h"
#include "lecture_course.h"
#include "rayscope/image.h"
#include "scene_options.h"
#include "view_module.h"

namespace rayscope::cli {
namespace {

// What one view shows: the scene, the pixel picked and the keys pressed.
// A lecture's chapter takes the same options (data/lecture/course.json).
struct ShownOptions {
  SceneOptions scene;
  std::string pixel;
  std::vector<std::string> keys;

  /// Adds the scene's options, --pixel and --keys; returns the options
  /// added, which --lecture excludes except --keys.
  std::vector<CLI::Option*> add_to(CLI::App* cmd) {
    const size_t before = cmd->get_options().size();
    scene.add_to(cmd);
    cmd->add_option("--pixel", pixel,
                    "X,Y: pick this pixel at the start (0,0 is the top-left pixel; y grows "
                    "downward, as for render and inspect)");
    std::vector<CLI::Option*> added = cmd->get_options();
    added.erase(added.begin(), added.begin() + std::ptrdiff_t(before));
    cmd->add_option("--keys", keys,
                    "KEY...: keys to press after the render and the pick, as the window names "
                    "them (Up, Right, t, b, plus, bracketright, Next, ...), e.g. for --screenshot")
        ->delimiter(',');
    return added;
  }
  /// The scene loaded and the pixel checked against it: everything that can
  /// be wrong fails here, before a window opens, with the one-line errors
  /// of `render`.
  ViewChapter load() const {
    ViewChapter c;
    if (!pixel.empty()) parse_pixel_option(pixel, c.pixel);
    c.loaded = scene.load();
    if (!pixel.empty()) check_pixel_option(pixel, c.pixel, c.loaded.settings);
    c.pick = !pixel.empty();
    c.keys = keys;
    return c;
  }
};

struct ViewOptions {
  ShownOptions shown;
  std::string lecture;
  int chapter = 1;
  std::string screenshot;
  std::string record;
  double fps = 1.0;
  std::string window;
  double font_scale = 1.0;
  std::string view_camera;
};

// --view-camera EX,EY,EZ,AX,AY,AZ: six finite numbers, the eye apart from
// the point it looks at.
void parse_view_camera(const std::string& text, double out[6]) {
  if (!parse_numbers(text, 6, out))
    throw std::invalid_argument("--view-camera: expected EX,EY,EZ,AX,AY,AZ, got '" + text + "'");
  for (int k = 0; k < 6; ++k)
    if (!std::isfinite(out[k]))
      throw std::invalid_argument("--view-camera: '" + text + "' is not six finite numbers");
  if (out[0] == out[3] && out[1] == out[4] && out[2] == out[5])
    throw std::invalid_argument("--view-camera: the eye and the point it looks at are the same");
}

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

// A course file's chapters, each loaded as its own `rayscope view` command
// line would load it.
std::vector<ViewChapter> load_course(const std::string& path) {
  std::vector<ViewChapter> chapters;
  const std::vector<CourseChapter> course = read_course(path);
  for (size_t k = 0; k < course.size(); ++k) {
    const std::string where = path + ": chapter " + std::to_string(k + 1) + ": ";
    CLI::App parser;
    ShownOptions shown;
    shown.add_to(&parser);
    std::vector<std::string> args(course[k].view_args.rbegin(), course[k].view_args.rend());
    try {
      parser.parse(args);  // CLI11 takes the arguments last first
    } catch (const CLI::ParseError& e) {
      throw std::runtime_error(where + e.what());
    }
    try {
      ViewChapter c = shown.load();
      c.title = course[k].title;
      c.caption = course[k].caption;
      chapters.push_back(std::move(c));
    } catch (const std::exception& e) {
      throw std::runtime_error(where + e.what());
    }
  }
  return chapters;
}

int run_view(const ViewOptions& o) {
  ViewRequest request;
  if (!o.window.empty()) parse_size("--window", o.window, request.window[0], request.window[1]);
  request.font_scale = o.font_scale;
  if (!o.view_camera.empty()) {
    parse_view_camera(o.view_camera, request.view_camera);
    request.aim = true;
  }
  ViewChapter shown;
  if (!o.lecture.empty()) {
    request.chapters = load_course(o.lecture);
    if (o.chapter < 1 || o.chapter > int(request.chapters.size()))
      throw std::invalid_argument("--chapter: " + o.lecture + " has chapters 1 to " +
                                  std::to_string(request.chapters.size()) + ", not " +
                                  std::to_string(o.chapter));
    request.chapter = o.chapter - 1;
    request.keys = o.shown.keys;
  } else {
    shown = o.shown.load();
    request.loaded = &shown.loaded;
    request.pick = shown.pick;
    std::copy_n(shown.pixel, 2, request.pixel);
    request.keys = shown.keys;
  }
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
  const std::vector<CLI::Option*> scene_options = opts->shown.add_to(cmd);
  CLI::Option* lecture = cmd->add_option(
      "--lecture", opts->lecture,
      "COURSE.json: lecture mode: the chapters of the course file (data/lecture/course.json), "
      "each with its scene, its pixel picked and a caption of what to look at; PageDown/PageUp "
      "go to the next/previous chapter");
  for (CLI::Option* o : scene_options) lecture->excludes(o);
  cmd->add_option("--chapter", opts->chapter, "N: the chapter --lecture opens (from 1; default 1)")
      ->needs(lecture);
  cmd->add_option("--window", opts->window,
                  "WIDTHxHEIGHT: the window's size in pixels (e.g. 1920x1080 for a projector)");
  cmd->add_option("--view-camera", opts->view_camera,
                  "EX,EY,EZ,AX,AY,AZ: point the 3D view from the eye (EX,EY,EZ) at (AX,AY,AZ), "
                  "in the scene's coordinates (default: framing the whole scene)")
      ->excludes(lecture);
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
