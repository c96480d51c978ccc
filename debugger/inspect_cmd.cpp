// `rayscope inspect [SCENE] --pixel X,Y`: replays one pixel and prints its ray tree.
#include <cstdio>
#include <string>
#include <vector>

#include "commands.h"
#include "rayscope/packet_replay.h"
#include "rayscope/raytree_format.h"
#include "rayscope/replay.h"
#include "scene_options.h"
#include "text_file.h"

namespace rayscope::cli {
namespace {

// At most this many pixels per --rect: the text of a few thousand ray trees is
// already more than anyone reads, and its JSON tens of megabytes.
constexpr int64_t kMaxRectPixels = 4096;

struct InspectOptions {
  SceneOptions scene;
  std::vector<std::string> pixels;
  std::string rect;
  int sample = -1;
  std::string format = "text";
  std::string output;
  bool packet = false;
};

// JSON objects, each already formatted, as {"key": [object, ...]}.
std::string json_list(const char* key, const std::vector<std::string>& objects) {
  std::string text = std::string("{\"") + key + "\": [\n";
  for (size_t i = 0; i < objects.size(); ++i)
    text += objects[i] + (i + 1 < objects.size() ? ",\n" : "\n");
  return text + "]}\n";
}

std::string concatenated(const std::vector<std::string>& texts) {
  std::string text;
  for (const std::string& t : texts) text += t;
  return text;
}

int run_inspect(const InspectOptions& o) {
  std::vector<glm::ivec2> pixels;
  for (const std::string& p : o.pixels) {
    int v[2];
    if (!parse_ints(p, 2, v)) throw std::invalid_argument("--pixel: expected X,Y, got '" + p + "'");
    pixels.emplace_back(v[0], v[1]);
  }
  if (!o.rect.empty()) {
    int v[4];
    if (!parse_ints(o.rect, 4, v) || v[2] <= 0 || v[3] <= 0)
      throw std::invalid_argument("--rect: expected X,Y,WIDTH,HEIGHT with positive size, got '" +
                                  o.rect + "'");
    if (int64_t(v[2]) * v[3] > kMaxRectPixels)
      throw std::invalid_argument("--rect: at most " + std::to_string(kMaxRectPixels) +
                                  " pixels at a time");
    for (int y = v[1]; y < v[1] + v[3]; ++y)
      for (int x = v[0]; x < v[0] + v[2]; ++x) pixels.emplace_back(x, y);
  }
  if (pixels.empty())
    throw std::invalid_argument("give --pixel X,Y (repeatable) or --rect X,Y,W,H");
  LoadedScene loaded = o.scene.load();
  for (const std::string& w : loaded.scene.summary().warnings)
    std::fprintf(stderr, "rayscope: warning: %s: %s\n",
                 o.scene.scene.empty() ? "default scene" : o.scene.scene.c_str(), w.c_str());
  prepare_frame(loaded.scene, loaded.settings);
  if (o.packet) {
    std::vector<std::string> items;
    for (const glm::ivec2& p : pixels) {
      const PacketReplay r = record_packet(loaded.scene, loaded.settings, p.x, p.y, o.sample);
      items.push_back(o.format == "json" ? format_packet_json(r, loaded.scene)
                                         : format_packet_text(r, loaded.scene));
    }
    write_text_output(o.format == "json" ? json_list("packets", items) : concatenated(items),
                      o.output);
    return 0;
  }
  std::vector<std::string> items;
  for (const glm::ivec2& p : pixels) {
    const PixelRecord r = record_pixel(loaded.scene, loaded.settings, p.x, p.y, o.sample);
    items.push_back(o.format == "json" ? format_json(r, loaded.scene)
                                       : format_text(r, loaded.scene));
  }
  std::string text;
  if (o.format != "json")
    text = concatenated(items);
  else if (items.size() == 1)
    text = items[0] + "\n";
  else
    text = json_list("pixels", items);
  write_text_output(text, o.output);
  return 0;
}

}  // namespace

void add_inspect_command(CLI::App& app, int& exit_code) {
  auto opts = std::make_shared<InspectOptions>();
  CLI::App* cmd = app.add_subcommand(
      "inspect", "Replay one pixel and print its ray tree (every ray, hit, weight and BVH walk)");
  opts->scene.add_to(cmd);
  cmd->add_option("--pixel", opts->pixels,
                  "X,Y: a pixel (0,0 is the top-left pixel; y grows downward); repeatable");
  cmd->add_option("--rect", opts->rect,
                  "X,Y,WIDTH,HEIGHT: every pixel of a rectangle whose top-left pixel is X,Y "
                  "(0,0 is the top-left pixel of the image; y grows downward), at most " +
                      std::to_string(kMaxRectPixels) + " pixels");
  // Its range (0..N*N-1) is record_pixel()'s check.
  cmd->add_option("--sample", opts->sample, "Only this sample (0..N*N-1); default: all");
  cmd->add_option("--format", opts->format, "text or json")
      ->check(CLI::IsMember({"text", "json"}))
      ->capture_default_str();
  cmd->add_flag("--packet", opts->packet,
                "Print the packet the pixel's primary ray was traced in instead of its ray tree: "
                "the block of pixels traced together, each node the packet entered with the rays "
                "active there, and where each ray left the walk (one sample: --sample, default 0; "
                "--format json: {\"packets\": [...]})");
  cmd->add_option("-o,--output", opts->output, "Write to this file instead of standard output");
  cmd->callback([opts, &exit_code]() { exit_code = run_inspect(*opts); });
}

}  // namespace rayscope::cli
