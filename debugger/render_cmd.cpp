// `rayscope render [SCENE] -o OUT`: renders a scene file or the built-in default scene.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <thread>

#include "commands.h"
#include "rayscope/render.h"
#include "rayscope/scene_io.h"
#include "rayscope/shapes.h"
#include "rayscope/vtk_mesh.h"

namespace rayscope::cli {
namespace {

struct RenderOptions {
  std::string scene;
  std::string output = "rayscope.png";
  std::string size;
  std::optional<int> width, height, samples, max_depth, seed;
  std::optional<float> min_contribution;
  int threads = 0;
  bool stats = false;
  bool quiet = false;
};

void print_progress(size_t done, size_t total) {
  const int bar = 40;
  int filled = int(double(done) / double(total) * bar);
  std::fprintf(stderr, "\r[%.*s%*s] %3d%%", filled, "########################################",
               bar - filled, "", int(100.0 * double(done) / double(total)));
  if (done == total) std::fputc('\n', stderr);
  std::fflush(stderr);
}

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

void print_stats(const Scene& scene, const RenderSettings& rs, const RayCounters& c, double build_s,
                 double render_s) {
  BvhQuality q = scene.bvh().quality();
  const SceneSummary& sum = scene.summary();
  std::printf("Scene:     %zu triangles, %zu spheres, %zu planes, %zu lights\n", sum.triangles,
              sum.spheres, sum.planes, sum.lights);
  std::printf("Image:     %dx%d, %dx%d samples per pixel, max depth %d, %d threads\n", rs.width,
              rs.height, rs.samples, rs.samples, rs.max_depth,
              rs.threads > 0 ? rs.threads : int(std::thread::hardware_concurrency()));
  std::printf(
      "BVH:       %u nodes, %u leaves, depth %u, %.1f prims/leaf, SAH cost %.2f, %.2f MiB, "
      "built in %.3f s\n",
      q.nodes, q.leaves, q.depth, q.mean_leaf_prims, q.sah_cost,
      double(q.memory_bytes) / (1024.0 * 1024.0), build_s);
  std::printf("%-22s %14s\n", "Rays", "count");
  for (int k = 0; k < kRayKindCount; ++k)
    std::printf("  %-20s %14llu\n", to_string(RayKind(k)), (unsigned long long)c.rays[size_t(k)]);
  std::printf("  %-20s %14llu\n", "total", (unsigned long long)c.total_rays());
  std::printf("  %-20s %14llu\n", "shadow occluded", (unsigned long long)c.shadow_occluded);
  std::printf("  %-20s %14llu\n", "primary hits", (unsigned long long)c.primary_hits);
  std::printf("  %-20s %14llu\n", "total internal refl.",
              (unsigned long long)c.total_internal_reflections);
  std::printf("  %-20s %14llu\n", "cut by depth", (unsigned long long)c.depth_cutoffs);
  std::printf("  %-20s %14llu\n", "cut by weight", (unsigned long long)c.weight_cutoffs);
  std::printf("Time:      %.3f s render, %.2f Mrays/s\n", render_s,
              render_s > 0 ? double(c.total_rays()) / render_s * 1e-6 : 0.0);
}

int run_render(const RenderOptions& o) {
  namespace fs = std::filesystem;
  LoadedScene loaded;
  if (o.scene.empty()) {
    loaded.scene = make_default_scene();
    loaded.settings.samples = 2;
  } else {
    loaded = load_scene(o.scene, read_mesh_file);
  }
  RenderSettings& rs = loaded.settings;
  if (!o.size.empty()) parse_size(o.size, rs.width, rs.height);
  if (o.width) rs.width = *o.width;
  if (o.height) rs.height = *o.height;
  if (o.samples) rs.samples = *o.samples;
  if (o.max_depth) rs.max_depth = *o.max_depth;
  if (o.seed) rs.seed = uint32_t(*o.seed);
  if (o.min_contribution) rs.min_contribution = *o.min_contribution;
  rs.threads = o.threads;
  rs.validate();

  // Fail on an unwritable output before spending time on the render.
  fs::path out(o.output);
  fs::path dir = out.parent_path().empty() ? fs::path(".") : out.parent_path();
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw std::runtime_error(o.output + ": folder '" + dir.string() + "' does not exist");
  std::string ext = out.extension().string();
  if (ext.empty()) throw std::runtime_error(o.output + ": no file extension (use .png or .exr)");

  Scene& scene = loaded.scene;
  auto t0 = std::chrono::steady_clock::now();
  try {
    scene.commit();
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error((o.scene.empty() ? std::string("default scene") : o.scene) + ": " +
                             e.what());
  }
  auto t1 = std::chrono::steady_clock::now();
  if (scene.summary().skipped_triangles)
    std::fprintf(stderr, "rayscope: warning: %s: %zu triangles with non-finite vertices skipped\n",
                 o.scene.c_str(), scene.summary().skipped_triangles);
  RayCounters counters;
  ProgressFn progress;
  if (!o.quiet && ::isatty(STDERR_FILENO)) progress = print_progress;
  Framebuffer fb = render(scene, rs, &counters, progress);
  auto t2 = std::chrono::steady_clock::now();
  write_image(out, fb);
  if (o.stats)
    print_stats(scene, rs, counters, std::chrono::duration<double>(t1 - t0).count(),
                std::chrono::duration<double>(t2 - t1).count());
  if (!o.quiet) std::fprintf(stderr, "wrote %s (%dx%d)\n", o.output.c_str(), rs.width, rs.height);
  return 0;
}

}  // namespace

void add_render_command(CLI::App& app, int& exit_code) {
  auto opts = std::make_shared<RenderOptions>();
  CLI::App* cmd = app.add_subcommand("render", "Render a scene (or the built-in default scene)");
  cmd->add_option("scene", opts->scene, "Scene file (JSON); omit for the default scene");
  cmd->add_option("-o,--output", opts->output, "Output image (.png, .exr)")->capture_default_str();
  cmd->add_option("--size", opts->size, "Image size WIDTHxHEIGHT");
  cmd->add_option("-W,--width", opts->width, "Image width in pixels")->check(CLI::Range(1, 32768));
  cmd->add_option("-H,--height", opts->height, "Image height in pixels")
      ->check(CLI::Range(1, 32768));
  cmd->add_option("-s,--spp", opts->samples, "N: N x N stratified samples per pixel")
      ->check(CLI::Range(1, 64));
  cmd->add_option("-d,--max-depth", opts->max_depth, "Maximum recursion depth")
      ->check(CLI::Range(0, 64));
  cmd->add_option("--min-contribution", opts->min_contribution,
                  "Skip secondary rays whose weight is below this")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--seed", opts->seed, "Seed of the sample jitter")
      ->check(CLI::Range(0, 2147483647));
  cmd->add_option("-t,--threads", opts->threads, "Threads (0: all)")->check(CLI::Range(0, 1024));
  cmd->add_flag("--stats", opts->stats, "Print ray counts, BVH figures, time and Mrays/s");
  cmd->add_flag("-q,--quiet", opts->quiet, "No progress bar or messages");
  cmd->callback([opts, &exit_code]() { exit_code = run_render(*opts); });
}

}  // namespace rayscope::cli
