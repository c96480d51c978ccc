// `rayscope accel compare [SCENE]`: the acceleration structures side by side on
// one scene, all measured in the same run: what each costs to build and hold,
// and what it costs per ray.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#include "commands.h"
#include "rayscope/render.h"
#include "scene_options.h"
#include "text_file.h"

namespace rayscope::cli {
namespace {

/// Brute force is left out of the comparison unless --structures names it when
/// its primary rays alone would make more primitive tests than this (primitives
/// x pixels x samples): 2e7 tests take about a second here, and a frame's
/// secondary and shadow rays several times more; the bunny at 640x480 would
/// take hours.
constexpr double kCompareBruteForceBudget = 2e7;
/// Timed renders per structure at most (--runs).
constexpr int kMaxRuns = 100;
/// Seconds each structure may take by default (--budget): the render with
/// statistics is stopped there, and the timed renders stop once the
/// structure's renders have taken this long (after at least one). Slow
/// pairs (the grid or BSP tree storing each primitive in its smallest cell,
/// at 0.01 Mrays/s on the bunny) would otherwise take many minutes each.
constexpr double kDefaultBudgetSeconds = 10.0;
/// The largest --budget: a day.
constexpr double kMaxBudgetSeconds = 86400.0;

struct CompareOptions {
  SceneOptions scene;
  std::string structures;  ///< Comma-separated AccelKind names; empty: every kind.
  int runs = 3;
  double budget = kDefaultBudgetSeconds;  ///< Seconds per structure; 0: no limit.
  std::string csv;
};

/// Thrown by the progress callback of a render that has used up the budget.
struct OverBudget {
  double fraction;  ///< Of the image's tiles rendered.
};

struct Row {
  AccelKind kind;
  PrimStorage storage;
  std::string name;  ///< The kind, with the storage for a kind that has several.
  AccelFigures figures;
  RayCounters counters;  ///< From the render with statistics.
  double seconds = 0.0;  ///< Median of the timed renders (no statistics).
  int runs = 0;          ///< Timed renders made (fewer than --runs when over the budget).
  bool same_image = true;
};

std::vector<AccelKind> parse_structures(const std::string& text) {
  std::vector<AccelKind> kinds;
  std::stringstream in(text);
  std::string name;
  while (std::getline(in, name, ',')) {
    AccelKind k;
    if (!parse_accel_kind(name, k))
      throw std::invalid_argument("--structures: unknown structure '" + name +
                                  "' (known: " + accel_kind_names(", ", ", ") + ")");
    if (std::find(kinds.begin(), kinds.end(), k) == kinds.end()) kinds.push_back(k);
  }
  if (kinds.empty())
    throw std::invalid_argument("--structures: expected a list such as bvh,kdtree");
  return kinds;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

int run_compare(const CompareOptions& o) {
  std::vector<AccelKind> kinds;
  if (!o.structures.empty()) kinds = parse_structures(o.structures);
  if (!o.csv.empty()) {
    namespace fs = std::filesystem;
    const fs::path p(o.csv), dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
    if (fs::is_directory(p)) throw std::invalid_argument("--csv: " + o.csv + " is a directory");
    if (!fs::is_directory(dir))
      throw std::invalid_argument("--csv: " + o.csv + ": folder " + dir.string() +
                                  " does not exist");
  }
  LoadedScene loaded = o.scene.load();
  Scene& scene = loaded.scene;
  RenderSettings rs = loaded.settings;
  const SceneSummary& sum = scene.summary();
  const size_t bounded = sum.bounded();
  const double brute_tests =
      double(bounded) * double(rs.width) * double(rs.height) * double(rs.samples * rs.samples);
  std::vector<std::string> skipped;
  if (kinds.empty())
    for (AccelKind k : kAccelKinds) {
      if (accel_kind_name(k).brute_force && brute_tests > kCompareBruteForceBudget) {
        char why[160];
        std::snprintf(why, sizeof why,
                      "none (%zu primitives: %.2g tests for the primary rays alone; name it in "
                      "--structures to measure it anyway)",
                      bounded, brute_tests);
        skipped.push_back(why);
        continue;
      }
      kinds.push_back(k);
    }

  // One row per structure and storage choice it supports.
  std::vector<Row> rows;
  for (AccelKind k : kinds) {
    std::vector<PrimStorage> storages;
    for (PrimStorage st : kPrimStorages)
      if (accel_storage_error(k, st).empty()) storages.push_back(st);
    for (PrimStorage st : storages) {
      Row row;
      row.kind = k;
      row.storage = st;
      row.name = to_string(k);
      if (storages.size() > 1) row.name += std::string("/") + to_string(st);
      rows.push_back(row);
    }
  }
  const std::string name = o.scene.scene.empty() ? std::string("default scene") : o.scene.scene;
  std::printf(
      "%s: %zu triangles, %s%zu spheres, %zu planes; %dx%d, %dx%d samples, depth %d, %d "
      "threads; median of %d timed render%s per structure\n",
      name.c_str(), sum.triangles, sum.tubes_and_points_text().c_str(), sum.spheres, sum.planes,
      rs.width, rs.height, rs.samples, rs.samples, rs.max_depth,
      rs.threads > 0 ? rs.threads : int(std::thread::hardware_concurrency()), o.runs,
      o.runs == 1 ? "" : "s");
  std::printf("%-20s %9s %10s %9s %8s %6s %9s %10s %10s %10s %9s %8s %6s\n", "structure",
              "build ms", "memory MiB", "nodes", "leaves", "depth", "refs/prim", "nodes/ray",
              "boxes/ray", "prims/ray", "render s", "Mrays/s", "image");
  std::fflush(stdout);
  std::ostringstream csv;
  csv << "structure,build_ms,memory_bytes,nodes,leaves,depth,refs_per_prim,rays,nodes_per_ray,"
         "boxes_per_ray,prims_per_ray,render_seconds,mrays_per_s,same_image\n";

  // Progress on a terminal: which structure, and how far its render is.
  const bool show_progress = isatty(fileno(stderr)) != 0;
  auto progress_line = [&](size_t ri, const Row& row, const char* what, double fraction) {
    if (!show_progress) return;
    std::fprintf(stderr, "\r\033[K[%zu/%zu] %s: %s %3.0f%%", ri + 1, rows.size(), row.name.c_str(),
                 what, 100.0 * fraction);
    std::fflush(stderr);
  };
  std::vector<Color> first_image;
  std::vector<const Row*> measured;
  for (size_t ri = 0; ri < rows.size(); ++ri) {
    Row& row = rows[ri];
    AccelConfig config;
    config.kind = row.kind;
    config.storage = row.storage;
    progress_line(ri, row, "building", 0.0);
    scene.commit(config);
    row.figures = scene.accel().figures();
    const auto start = std::chrono::steady_clock::now();
    auto elapsed = [&] {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    // A render's progress; with `enforce`, it stops (OverBudget) once the
    // structure has used its budget.
    auto watch = [&](const char* what, bool enforce) {
      return [&, what, enforce](size_t done, size_t total) {
        const double fraction = double(done) / double(total);
        progress_line(ri, row, what, fraction);
        if (enforce && o.budget > 0.0 && done < total && elapsed() > o.budget)
          throw OverBudget{fraction};
      };
    };
    RenderSettings stats = rs;
    stats.statistics = true;
    try {
      render(scene, stats, &row.counters, watch("rendering with statistics", true));
    } catch (const OverBudget& over) {
      char why[256];
      std::snprintf(why, sizeof why,
                    "%s (its render with statistics had done %.0f%% of the image after the "
                    "budget of %g s; --budget 0 measures it to the end)",
                    row.name.c_str(), 100.0 * over.fraction, o.budget);
      skipped.push_back(why);
      continue;
    }
    std::vector<double> times;
    for (int r = 0; r < o.runs; ++r) {
      if (r > 0 && o.budget > 0.0 && elapsed() > o.budget) break;
      const auto t0 = std::chrono::steady_clock::now();
      Framebuffer fb;
      try {
        // The first timed render finishes: its time and image are the row's.
        fb = render(scene, rs, nullptr, watch("timed render", r > 0));
      } catch (const OverBudget&) {
        break;
      }
      times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      if (r == 0) {
        if (first_image.empty())
          first_image = fb.color;
        else
          row.same_image = fb.color.size() == first_image.size() &&
                           std::memcmp(fb.color.data(), first_image.data(),
                                       fb.color.size() * sizeof(Color)) == 0;
      }
    }
    row.seconds = median(times);
    row.runs = int(times.size());
    if (show_progress) std::fprintf(stderr, "\r\033[K");

    const AccelFigures& f = row.figures;
    const double rays = double(std::max<uint64_t>(1, row.counters.total_rays()));
    const double nodes = double(row.counters.nodes_visited) / rays;
    const double boxes = double(row.counters.boxes_tested) / rays;
    const double prims = double(row.counters.prims_tested) / rays;
    const double mrays = row.seconds > 0.0 ? rays / row.seconds * 1e-6 : 0.0;
    std::printf("%-20s %9.2f %10.3f %9zu %8zu %6u %9.2f %10.2f %10.2f %10.2f %9.4f %8.2f %6s\n",
                row.name.c_str(), f.build_seconds * 1e3, double(f.memory_bytes) / 1048576.0,
                f.nodes, f.leaves, f.depth, f.refs_per_prim, nodes, boxes, prims, row.seconds,
                mrays, row.same_image ? "same" : "DIFFERS");
    std::fflush(stdout);
    char line[512];
    std::snprintf(line, sizeof line,
                  "%s,%.4f,%zu,%zu,%zu,%u,%.4f,%llu,%.4f,%.4f,%.4f,%.6f,%.4f,%d\n",
                  row.name.c_str(), f.build_seconds * 1e3, f.memory_bytes, f.nodes, f.leaves,
                  f.depth, f.refs_per_prim, (unsigned long long)row.counters.total_rays(), nodes,
                  boxes, prims, row.seconds, mrays, row.same_image ? 1 : 0);
    csv << line;
    measured.push_back(&row);
  }
  if (show_progress) std::fprintf(stderr, "\r\033[K");
  for (const Row* r : measured)
    if (r->runs < o.runs)
      std::printf("%s: median of %d timed render%s (the budget of %g s was used up)\n",
                  r->name.c_str(), r->runs, r->runs == 1 ? "" : "s", o.budget);
  for (const std::string& s : skipped) std::printf("not measured: %s\n", s.c_str());
  std::printf(
      "image: whether the structure rendered the first one's image bit for bit (every "
      "structure returns the same hits)\n");
  std::fflush(stdout);
  if (!o.csv.empty()) write_text_file(o.csv, csv.str());
  for (const Row* r : measured)
    if (!r->same_image) {
      std::fprintf(stderr, "rayscope: error: %s rendered a different image than %s\n",
                   r->name.c_str(), measured.front()->name.c_str());
      return 1;
    }
  return 0;
}

}  // namespace

void add_accel_command(CLI::App& app, int& exit_code) {
  CLI::App* accel = app.add_subcommand("accel", "Acceleration structures: compare them on a scene");
  accel->require_subcommand(1);
  auto opts = std::make_shared<CompareOptions>();
  CLI::App* cmd = accel->add_subcommand(
      "compare",
      "Build every acceleration structure on one scene and render it with each, in the same "
      "run: build time, memory, nodes, depth, references per primitive, and per ray the nodes "
      "visited, boxes and primitives tested, Mrays/s");
  opts->scene.add_to(cmd, true, false);
  char budget[32];
  std::snprintf(budget, sizeof budget, "%g", kCompareBruteForceBudget);
  cmd->add_option("--structures", opts->structures,
                  "Comma-separated structures to compare (" + accel_kind_names(", ", ", ") +
                      "); default: all, brute force (none) only when its primary rays make at "
                      "most " +
                      budget + " primitive tests");
  cmd->add_option("--runs", opts->runs,
                  "Timed renders per structure; the median is reported (1.." +
                      std::to_string(kMaxRuns) + ")")
      ->check(CLI::Range(1, kMaxRuns));
  cmd->add_option("--budget", opts->budget,
                  "Seconds each structure may take (default " +
                      shortest_text(kDefaultBudgetSeconds) +
                      "; 0: no limit): a render with statistics that takes longer is stopped "
                      "and the structure reported as not measured, and timed renders stop "
                      "once it is used up (after the first)")
      ->check(CLI::Range(0.0, kMaxBudgetSeconds));
  cmd->add_option("--csv", opts->csv, "Also write the table as CSV to this file");
  cmd->callback([opts, &exit_code] { exit_code = run_compare(*opts); });
}

}  // namespace rayscope::cli
