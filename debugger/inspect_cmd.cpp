// `rayscope inspect [SCENE] --pixel X,Y`: replays one pixel and prints its ray tree.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "commands.h"
#include "rayscope/recorder.h"
#include "scene_options.h"

namespace rayscope::cli {
namespace {

struct InspectOptions {
  SceneOptions scene;
  std::string pixel;
  int sample = -1;
  std::string format = "text";
  std::string output;
};

int run_inspect(const InspectOptions& o) {
  auto c = o.pixel.find(',');
  int x = 0, y = 0;
  bool ok = c != std::string::npos;
  if (ok) {
    try {
      std::size_t px = 0, py = 0;
      x = std::stoi(o.pixel.substr(0, c), &px);
      y = std::stoi(o.pixel.substr(c + 1), &py);
      ok = px == c && py == o.pixel.size() - c - 1;
    } catch (const std::exception&) {
      ok = false;
    }
  }
  if (!ok) throw std::invalid_argument("--pixel: expected X,Y, got '" + o.pixel + "'");
  LoadedScene loaded = o.scene.load();
  prepare_for_replay(loaded.scene, loaded.settings);
  PixelRecord rec = record_pixel(loaded.scene, loaded.settings, x, y, o.sample);
  std::string text =
      o.format == "json" ? format_json(rec, loaded.scene) + "\n" : format_text(rec, loaded.scene);
  if (o.output.empty()) {
    std::fwrite(text.data(), 1, text.size(), stdout);
    return 0;
  }
  namespace fs = std::filesystem;
  fs::path out(o.output);
  fs::path tmp = out;
  tmp += ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary);
    if (!f) throw std::runtime_error(o.output + ": cannot write");
    f << text;
    if (!f.flush()) throw std::runtime_error(o.output + ": write failed");
  }
  std::error_code ec;
  fs::rename(tmp, out, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw std::runtime_error(o.output + ": cannot rename temporary file");
  }
  return 0;
}

}  // namespace

void add_inspect_command(CLI::App& app, int& exit_code) {
  auto opts = std::make_shared<InspectOptions>();
  CLI::App* cmd = app.add_subcommand(
      "inspect", "Replay one pixel and print its ray tree (every ray, hit, weight and BVH walk)");
  opts->scene.add_to(cmd);
  cmd->add_option("--pixel", opts->pixel, "X,Y: the pixel (0,0 is the top-left)")->required();
  cmd->add_option("--sample", opts->sample, "Only this sample (0..N*N-1); default: all")
      ->check(CLI::Range(0, 4095));
  cmd->add_option("--format", opts->format, "text or json")
      ->check(CLI::IsMember({"text", "json"}))
      ->capture_default_str();
  cmd->add_option("-o,--output", opts->output, "Write to this file instead of standard output");
  cmd->callback([opts, &exit_code]() { exit_code = run_inspect(*opts); });
}

}  // namespace rayscope::cli
