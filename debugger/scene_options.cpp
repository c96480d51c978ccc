#include "scene_options.h"

#include "rayscope/shapes.h"
#include "rayscope_vtk/mesh_files.h"

namespace rayscope::cli {
namespace {

void parse_size(const std::string& s, int& w, int& h) {
  auto x = s.find('x');
  std::size_t pw = 0, ph = 0;
  try {
    if (x == std::string::npos) throw std::invalid_argument("");
    w = std::stoi(s.substr(0, x), &pw);
    h = std::stoi(s.substr(x + 1), &ph);
  } catch (const std::exception&) {
    throw std::invalid_argument("--size: expected WIDTHxHEIGHT, got '" + s + "'");
  }
  if (pw != x || ph != s.size() - x - 1)
    throw std::invalid_argument("--size: expected WIDTHxHEIGHT, got '" + s + "'");
}

}  // namespace

bool parse_ints(const std::string& s, int n, int* out) {
  size_t pos = 0;
  for (int i = 0; i < n; ++i) {
    size_t end = i + 1 < n ? s.find(',', pos) : s.size();
    if (end == std::string::npos || end == pos) return false;
    try {
      size_t used = 0;
      out[i] = std::stoi(s.substr(pos, end - pos), &used);
      if (used != end - pos) return false;
    } catch (const std::exception&) {
      return false;
    }
    pos = end + 1;
  }
  return true;
}

void SceneOptions::add_to(CLI::App* cmd) {
  cmd->add_option("scene", scene, "Scene file (JSON); omit for the default scene");
  cmd->add_option("--size", size, "Image size WIDTHxHEIGHT");
  cmd->add_option("-W,--width", width, "Image width in pixels")->check(CLI::Range(1, 32768));
  cmd->add_option("-H,--height", height, "Image height in pixels")->check(CLI::Range(1, 32768));
  cmd->add_option("-s,--spp", samples, "N: N x N stratified samples per pixel")
      ->check(CLI::Range(1, 64));
  cmd->add_option("-d,--max-depth", max_depth, "Maximum recursion depth")->check(CLI::Range(0, 64));
  cmd->add_option("--min-contribution", min_contribution,
                  "Skip secondary rays whose weight within their sample is below this")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--seed", seed, "Seed of the sample jitter")->check(CLI::Range(0, 2147483647));
  cmd->add_option("-t,--threads", threads, "Threads (0: all)")->check(CLI::Range(0, 1024));
}

LoadedScene SceneOptions::load() const {
  LoadedScene loaded;
  if (scene.empty()) {
    loaded.scene = make_default_scene();
    loaded.settings.samples = 2;
  } else {
    loaded = load_scene(scene, rayscope_vtk::load_mesh);
  }
  RenderSettings& rs = loaded.settings;
  if (!size.empty()) parse_size(size, rs.width, rs.height);
  if (width) rs.width = *width;
  if (height) rs.height = *height;
  if (samples) rs.samples = *samples;
  if (max_depth) rs.max_depth = *max_depth;
  if (seed) rs.seed = uint32_t(*seed);
  if (min_contribution) rs.min_contribution = *min_contribution;
  rs.threads = threads;
  rs.validate();
  try {
    loaded.scene.commit();
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error((scene.empty() ? std::string("default scene") : scene) + ": " +
                             e.what());
  }
  return loaded;
}

std::string SceneOptions::replay_args(const std::string& scene, const RenderSettings& s) {
  std::string a = scene.empty() ? std::string() : "'" + scene + "' ";
  a += "--size " + std::to_string(s.width) + "x" + std::to_string(s.height);
  a += " --spp " + std::to_string(s.samples);
  a += " --max-depth " + std::to_string(s.max_depth);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g", double(s.min_contribution));
  a += " --min-contribution " + std::string(buf);
  a += " --seed " + std::to_string(s.seed);
  return a;
}

}  // namespace rayscope::cli
