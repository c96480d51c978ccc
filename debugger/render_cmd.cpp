// `rayscope render [SCENE] -o OUT`: renders a scene file or the built-in default scene.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "commands.h"
#include "rayscope/kernels.h"
#include "rayscope/ray_estimate.h"
#include "rayscope/render.h"
#include "scene_options.h"

namespace rayscope::cli {
namespace {

struct RenderOptions {
  SceneOptions scene;
  std::string output = "rayscope.png";
  std::string pixel;
  std::vector<std::string> aovs;
  bool stats = false;
  bool explain = false;
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

// load_s: reading the scene and its meshes and building the structures;
// render_s: the render.
void print_stats(const Scene& scene, const RenderSettings& rs, const RayCounters& c, double load_s,
                 double render_s) {
  BvhQuality q = scene.bvh().quality();
  const SceneSummary& sum = scene.summary();
  std::printf("Scene:     %zu triangles, %s%zu spheres, %zu planes, %zu lights\n", sum.triangles,
              sum.tubes_and_points_text().c_str(), sum.spheres, sum.planes, sum.lights);
  std::printf("Image:     %dx%d, %dx%d samples per pixel%s, max depth %d, %d threads\n", rs.width,
              rs.height, rs.sample_grid(), rs.sample_grid(),
              rs.max_samples > 0 ? " at most (adaptive)" : "", rs.max_depth,
              rs.threads > 0 ? rs.threads : int(std::thread::hardware_concurrency()));
  const Isa isa = kernels().isa;
  std::printf("Kernels:   %s (this CPU runs up to %s; %s= chooses a lower level)\n",
              std::string(isa_name(isa)).c_str(), std::string(isa_name(best_cpu_isa())).c_str(),
              kIsaVariable);
  const Aggregate& accel = scene.accel();
  // The build time is the walked structure's: the BVH's (with its walk) when
  // renders walk it, else on that structure's line below.
  char built[48] = "";
  if (std::holds_alternative<BvhWalk>(accel.structure()))
    std::snprintf(built, sizeof built, ", built in %.3f s", accel.figures().build_seconds);
  std::printf("BVH:       %u nodes, %u leaves, depth %u, %.1f prims/leaf, SAH cost %.2f%s\n",
              q.nodes, q.leaves, q.depth, q.mean_leaf_prims, q.sah_cost, built);
  std::printf("Walk:      %s\n", accel.stats_line().c_str());
  std::printf(
      "Memory:    %.2f MiB for the binary BVH, the structure walked and the primitive records\n",
      double(accel.memory_bytes()) / (1024.0 * 1024.0));
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
  if (rs.statistics) {
    const double rays = double(std::max<uint64_t>(1, c.total_rays()));
    std::printf("%-22s %14s %10s\n", "Traversal", "count", "per ray");
    auto row = [&](const char* name, uint64_t v) {
      std::printf("  %-20s %14llu %10.2f\n", name, (unsigned long long)v, double(v) / rays);
    };
    row("nodes visited", c.nodes_visited);
    row("boxes tested", c.boxes_tested);
    row("primitives tested", c.prims_tested);
    row("nodes culled", c.nodes_culled);
    row("hits", c.hits);
    row("shadow skipped N.L<=0", c.shadow_skipped_backfacing);
    if (c.packets > 0) {
      std::printf("%-22s %14s\n", "Packets", "count");
      std::printf("  %-20s %14llu\n", "traced", (unsigned long long)c.packets);
      std::printf("  %-20s %14llu\n", "as single rays", (unsigned long long)c.packet_fallbacks);
      std::printf("  %-20s %14llu\n", "node visits", (unsigned long long)c.packet_node_visits);
      std::printf(
          "  %-20s %14.2f\n", "rays per node visit",
          double(c.packet_active_lanes) / double(std::max<uint64_t>(1, c.packet_node_visits)));
    }
  }
  std::printf(
      "Time:      %.3f s loading (scene, meshes, structures), %.3f s render, %.2f Mrays/s\n",
      load_s, render_s, render_s > 0 ? double(c.total_rays()) / render_s * 1e-6 : 0.0);
  std::fflush(stdout);
}

void print_explain(const Scene& scene, const RenderSettings& rs, const RayCounters& c,
                   const RayEstimate& estimate) {
  const SceneSummary& s = scene.summary();
  std::vector<std::string> refl, refr;
  for (const Material& m : scene.materials) {
    if (m.reflective()) refl.push_back(m.name);
    if (m.refractive()) refr.push_back(m.name);
  }
  auto join = [](const std::vector<std::string>& v) {
    std::string o;
    for (const std::string& x : v) o += (o.empty() ? "" : ", ") + x;
    return o;
  };
  auto u = [](uint64_t v) { return (unsigned long long)v; };
  const unsigned long long pixels = (unsigned long long)rs.width * (unsigned long long)rs.height;
  std::printf("Scene analysis: %zu triangles, %s%zu spheres, %zu planes, %zu lights\n", s.triangles,
              s.tubes_and_points_text().c_str(), s.spheres, s.planes, s.lights);
  if (s.lights == 0)
    std::printf(
        "- shadow rays: none; the scene has no lights, so the integrator is compiled "
        "without the light loop (ambient only)\n");
  else
    std::printf(
        "- shadow rays: %llu traced (%llu occluded); %llu skipped because the light is "
        "behind the surface (N.L <= 0)\n",
        u(c.rays[int(RayKind::Shadow)]), u(c.shadow_occluded), u(c.shadow_skipped_backfacing));
  if (!s.reflective && !s.refractive)
    std::printf(
        "- secondary rays: none; no reflective or refractive material, so the integrator "
        "is compiled without reflection and refraction\n");
  else
    std::printf(
        "- secondary rays: %llu reflection (materials: %s), %llu refraction (materials: "
        "%s); not traced: %llu at max depth %d, %llu below min contribution %g\n",
        u(c.rays[int(RayKind::Reflection)]), refl.empty() ? "none" : join(refl).c_str(),
        u(c.rays[int(RayKind::Refraction)]), refr.empty() ? "none" : join(refr).c_str(),
        u(c.depth_cutoffs), rs.max_depth, u(c.weight_cutoffs), double(rs.min_contribution));
  const size_t bounded = s.bounded();
  if (s.walks_structure)
    std::printf("- BVH: used for %zu bounded primitives (%u nodes)\n", bounded,
                scene.bvh().quality().nodes);
  else
    std::printf(
        "- BVH: skipped; %zu bounded primitives (<= %zu) are tested directly, which is "
        "cheaper than walking a hierarchy\n",
        bounded, Aggregate::kBruteForceMax);
  if (s.planes) std::printf("- planes: %zu unbounded, tested outside the BVH\n", s.planes);
  if (s.degenerate_triangles || s.skipped_triangles)
    std::printf(
        "- triangles: %zu zero-area (kept, never hit); %zu with non-finite vertices left out\n",
        s.degenerate_triangles, s.skipped_triangles);
  if (rs.max_samples > 0)
    std::printf(
        "- sampling: adaptive, %dx%d stratified samples at a time from a %dx%d grid until a "
        "pixel's standard error is below %s (%llu primary rays, %.2f per pixel of at most "
        "%d)\n",
        rs.samples, rs.samples, rs.max_samples, rs.max_samples,
        shortest_text(rs.target_error).c_str(), u(c.rays[int(RayKind::Primary)]),
        double(c.rays[int(RayKind::Primary)]) / double(pixels), rs.max_samples * rs.max_samples);
  else if (rs.samples == 1)
    std::printf(
        "- sampling: 1 sample per pixel at the pixel center (%llu primary rays = "
        "width x height, no jitter)\n",
        u(c.rays[int(RayKind::Primary)]));
  else
    std::printf(
        "- sampling: %dx%d stratified samples per pixel (%llu primary rays = %llu pixels "
        "x %d)\n",
        rs.samples, rs.samples, u(c.rays[int(RayKind::Primary)]), pixels, rs.samples * rs.samples);
  std::printf("- worst case (the lecture's O(n m 2^r), every ray hitting): %s; traced %llu\n",
              estimate.text(rs).c_str(), u(c.total_rays()));
  std::fflush(stdout);
}

int run_render(const RenderOptions& o) {
  namespace fs = std::filesystem;
  int pxy[2] = {-1, -1};
  if (!o.pixel.empty()) parse_pixel_option(o.pixel, pxy);
  const int px = pxy[0], py = pxy[1];
  // Fail on an output that cannot be written before loading and rendering.
  fs::path out(o.output);
  check_image_path(out);
  // The image module (OpenImageIO) loads on the other core while the scene
  // loads: it took longer than the bunny scene's render (image.h). A PNG
  // without heat maps does not need it.
  if (image_needs_module(o.output) || !o.aovs.empty()) preload_image_files();
  auto t0 = std::chrono::steady_clock::now();
  LoadedScene loaded = o.scene.load();
  auto t1 = std::chrono::steady_clock::now();
  RenderSettings& rs = loaded.settings;
  if (!o.pixel.empty()) check_pixel_option(o.pixel, pxy, rs);

  bool cost_aov = false, samples_aov = false;
  for (const std::string& a : o.aovs) {
    if (a == "cost")
      cost_aov = true;
    else if (a == "samples")
      samples_aov = true;
    else
      throw std::invalid_argument("--aov: unknown AOV '" + a + "' (known: cost, samples)");
  }
  if (samples_aov && rs.max_samples == 0)
    throw std::invalid_argument("--aov samples: needs adaptive sampling (--max-spp)");
  rs.statistics = o.stats || cost_aov;
  Scene& scene = loaded.scene;
  // What commit() worked around in the input (non-finite mesh data), one line each.
  for (const std::string& w : scene.summary().warnings)
    std::fprintf(stderr, "rayscope: warning: %s: %s\n",
                 o.scene.scene.empty() ? "default scene" : o.scene.scene.c_str(), w.c_str());
  // The lecture's worst case, announced before a render that may take long.
  const RayEstimate estimate = estimate_rays(scene, rs);
  if (estimate.rays > kRayBudget)
    std::fprintf(stderr, "rayscope: warning: this render may trace %s, over the budget of %.3g\n",
                 estimate.text(rs).c_str(), kRayBudget);
  RayCounters counters;
  ProgressFn progress;
  if (!o.quiet && ::isatty(STDERR_FILENO)) progress = print_progress;
  Framebuffer fb = render(scene, rs, &counters, progress);
  auto t2 = std::chrono::steady_clock::now();
  // --stats counts the traversal, which fills the cost AOVs too; only --aov
  // cost puts them in the output file.
  if (!cost_aov) fb.cost.clear();
  if (!samples_aov) fb.samples.clear();
  write_image(out, fb);
  if (samples_aov) {
    fs::path heat = out;
    heat.replace_extension(".samples.png");
    write_heatmap(heat, fb.samples, fb.width, fb.height, "samples per pixel (adaptive)");
    if (!o.quiet) std::fprintf(stderr, "wrote %s\n", heat.string().c_str());
  }
  if (cost_aov) {
    fs::path heat = out;
    heat.replace_extension(".cost.png");
    std::vector<float> nodes(fb.cost.size());
    for (size_t i = 0; i < nodes.size(); ++i) nodes[i] = float(fb.cost[i].nodes);
    write_heatmap(heat, nodes, fb.width, fb.height, "BVH nodes visited per pixel");
    if (!o.quiet) std::fprintf(stderr, "wrote %s\n", heat.string().c_str());
  }
  if (o.explain) print_explain(scene, rs, counters, estimate);
  if (o.stats)
    print_stats(scene, rs, counters, std::chrono::duration<double>(t1 - t0).count(),
                std::chrono::duration<double>(t2 - t1).count());
  // A pixel that went wrong (non-finite color) is reported with its replay command.
  for (int y = 0; y < rs.height; ++y)
    for (int x = 0; x < rs.width; ++x)
      if (!all_finite(fb.color[fb.index(x, y)])) {
        std::fprintf(stderr,
                     "rayscope: warning: pixel (%d, %d) is not finite; replay it with:\n  "
                     "rayscope inspect %s --pixel %d,%d\n",
                     x, y,
                     SceneOptions::replay_args(o.scene.scene, rs, scene.accel().config()).c_str(),
                     x, y);
        y = rs.height;
        break;
      }
  if (!o.pixel.empty()) {
    // Shortest round-trip text: the replay's color can be compared bit for bit.
    Color c = fb.color[fb.index(px, py)];
    std::printf(
        "pixel (%d, %d) = (%s, %s, %s); its ray tree:\n  rayscope inspect %s --pixel %d,%d\n", px,
        py, shortest_text(c.r).c_str(), shortest_text(c.g).c_str(), shortest_text(c.b).c_str(),
        SceneOptions::replay_args(o.scene.scene, rs, scene.accel().config()).c_str(), px, py);
  }
  if (!o.quiet) std::fprintf(stderr, "wrote %s (%dx%d)\n", o.output.c_str(), rs.width, rs.height);
  return 0;
}

}  // namespace

void add_render_command(CLI::App& app, int& exit_code) {
  auto opts = std::make_shared<RenderOptions>();
  CLI::App* cmd = app.add_subcommand("render", "Render a scene (or the built-in default scene)");
  opts->scene.add_to(cmd);
  cmd->add_option("-o,--output", opts->output,
                  "Output image: .png or .jpg (8-bit sRGB color), .exr (32-bit float linear color "
                  "plus Z, N.x N.y N.z and objectId channels)")
      ->capture_default_str();
  cmd->add_option("--pixel", opts->pixel,
                  "X,Y: print this pixel's value and its inspect command (0,0 is the top-left "
                  "pixel; y grows downward)");
  cmd->add_flag("--stats", opts->stats,
                "Print ray counts, traversal counts, BVH figures, time and Mrays/s (the image "
                "file is the same as without it)");
  cmd->add_option("--aov", opts->aovs,
                  "Extra outputs: 'cost' writes OUT.cost.png (heat map of BVH nodes visited, with "
                  "legend) and adds cost.* channels to .exr output; 'samples' (with --max-spp) "
                  "writes OUT.samples.png (heat map of the samples each pixel took) and adds a "
                  "samples channel to .exr output");
  cmd->add_flag("--explain", opts->explain,
                "Print what the renderer skipped for this scene and why, with counts");
  cmd->add_flag("-q,--quiet", opts->quiet, "No progress bar or messages");
  cmd->callback([opts, &exit_code]() { exit_code = run_render(*opts); });
}

}  // namespace rayscope::cli
