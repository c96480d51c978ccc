#include "scene_options.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <vtkDataObject.h>
#include <vtkSmartPointer.h>
#include <glm/gtc/matrix_transform.hpp>

#include "rayscope/input_file.h"
#include "rayscope/intersect_capsule.h"
#include "rayscope/render_block.h"
#include "rayscope/shapes.h"
#include "rayscope_vtkio/dataset_leaves.h"
#include "rayscope_vtkio/mesh_conversion.h"
#include "rayscope_vtkio/mesh_files.h"

namespace rayscope::cli {

void parse_size(const std::string& option, const std::string& s, int& w, int& h) {
  auto x = s.find('x');
  std::size_t pw = 0, ph = 0;
  try {
    if (x == std::string::npos) throw std::invalid_argument("");
    w = std::stoi(s.substr(0, x), &pw);
    h = std::stoi(s.substr(x + 1), &ph);
  } catch (const std::exception&) {
    throw std::invalid_argument(option + ": expected WIDTHxHEIGHT, got '" + s + "'");
  }
  if (pw != x || ph != s.size() - x - 1)
    throw std::invalid_argument(option + ": expected WIDTHxHEIGHT, got '" + s + "'");
}

namespace {

// " (LO..HI)" for the help text, from the named limits.
std::string in(long long lo, long long hi) {
  return " (" + std::to_string(lo) + ".." + std::to_string(hi) + ")";
}

// A scene argument that is not a .json file is a mesh file.
bool is_mesh_path(const std::string& path) {
  return lower_extension(path) != ".json";
}

// The view of a mesh file: its mesh in the default material, seen from the
// front (+z), a little from the right and above, so that no axis-aligned face
// is seen edge-on; the camera frames it (frame_bounds, once the image size is
// known) and a headlight (rayscope::headlight: a light at the eye) lights it,
// as VTK's default light does.
void frame_mesh(Scene& s, const RenderSettings& rs) {
  Bounds3 b;
  for (const TriangleMesh& m : s.meshes)
    for (const Vec3& p : m.positions)
      if (all_finite(p)) b.extend(p);
  for (const TubeSet& t : s.tubes)
    for (size_t k = 0; k < t.segments.size(); ++k)
      if (t.traced(k))
        b.extend(capsule_bounds(t.positions[t.segments[k].x], t.positions[t.segments[k].y],
                                t.segment_radius(k)));
  for (const PointSet& p : s.points)
    for (size_t i = 0; i < p.positions.size(); ++i)
      if (p.traced(i)) b.extend(capsule_bounds(p.positions[i], p.positions[i], p.point_radius(i)));
  Camera view;
  view.look_at = Vec3(0.0f);
  view.eye = Vec3(0.5f, 0.5f, 1.0f);
  s.camera = frame_bounds(b, float(rs.width) / float(rs.height), view);
  s.lights = {headlight(s.camera)};
}

}  // namespace

std::string accel_kind_names(const char* sep, const char* last_sep) {
  std::string s;
  const size_t n = std::size(kAccelKinds);
  for (size_t i = 0; i < n; ++i)
    s += std::string(i == 0 ? "" : i + 1 == n ? last_sep : sep) + to_string(kAccelKinds[i]);
  return s;
}

bool parse_numbers(const std::string& s, int n, double* out) {
  size_t pos = 0;
  for (int i = 0; i < n; ++i) {
    const size_t end = i + 1 < n ? s.find(',', pos) : s.size();
    if (end == std::string::npos || end == pos) return false;
    const std::string part = s.substr(pos, end - pos);
    char* stop = nullptr;
    out[i] = std::strtod(part.c_str(), &stop);
    if (stop != part.c_str() + part.size()) return false;
    pos = end + 1;
  }
  return true;
}

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

void SceneOptions::add_to(CLI::App* cmd, bool render_settings, bool walk_option) {
  using RS = RenderSettings;
  cmd->add_option("scene", scene,
                  "Scene file (.json), or a mesh file (" + rayscope_vtkio::mesh_file_extensions() +
                      ") shown in the default material with a camera that frames it and a "
                      "headlight (each block of a composite file its own object); omit for the "
                      "default scene");
  if (render_settings) {
    cmd->add_option("--size", size, "Image size WIDTHxHEIGHT");
    const std::string pixels = ", at most " + std::to_string(RS::kMaxPixels) + " pixels in all";
    cmd->add_option("-W,--width", width,
                    "Image width in pixels" + in(1, RS::kMaxImageSide) + pixels);
    cmd->add_option("-H,--height", height,
                    "Image height in pixels" + in(1, RS::kMaxImageSide) + pixels);
    cmd->add_option("-s,--spp", samples,
                    "N: N x N stratified samples per pixel" + in(1, RS::kMaxSamples));
    cmd->add_option("-d,--max-depth", max_depth, "Maximum recursion depth" + in(0, RS::kMaxDepth));
    cmd->add_option("--min-contribution", min_contribution,
                    "Skip secondary rays whose weight within their sample is below this (0.." +
                        shortest_text(RS::kMaxMinContribution) + ")");
    cmd->add_option("--max-spp", max_samples,
                    "Adaptive sampling: M, a multiple of --spp N" + in(1, RS::kMaxSamples) +
                        ": each pixel takes N x N samples at a time from an M x M grid until "
                        "its estimated error is below --target-error or all M x M are taken");
    cmd->add_option("--target-error", target_error,
                    "Adaptive sampling: the standard error of a pixel's mean (linear RGB, "
                    "largest channel) below which it stops (0.." +
                        shortest_text(RS::kMaxTargetError) +
                        "; 0: take all M x M; needs --max-spp)");
    cmd->add_flag("--texture-filter", texture_filter,
                  "Box-filter the checkerboard over each primary sample's footprint (ray "
                  "differentials) instead of point sampling it");
    cmd->add_flag("--single-rays", single_rays,
                  "Trace every ray alone, not the primary rays of " + std::to_string(kBlockSide) +
                      "x" + std::to_string(kBlockSide) +
                      " pixel blocks and their shadow rays as packets (the same image, slower; "
                      "for comparing the walks)");
    cmd->add_option("--seed", seed, "Seed of the sample jitter" + in(0, RS::kMaxSeed));
    cmd->add_option("-t,--threads", threads, "Threads, 0: all" + in(0, RS::kMaxThreads));
  }
  if (!walk_option) return;
  cmd->add_option("--accel", accel,
                  "Structure the rays walk: bvh (the BVH in 8-wide nodes, what renders use; "
                  "default), bvh2 (the same BVH node by node, two boxes per node: the "
                  "lecture's walk, for teaching; same image), kdtree (the SAH kD-tree, every "
                  "primitive stored in each cell it overlaps; same image), grid (the uniform "
                  "grid, cells chosen from the object count, every primitive stored in each "
                  "cell it overlaps; same image), octree (cubes cut into 8 octants, see "
                  "--storage; same image), bsp (the BSP tree: planes of any orientation "
                  "through the triangles, see --storage; same image), spheres (the hierarchy "
                  "of bounding spheres, each primitive once; same image), none (every "
                  "primitive tested)")
      ->check(CLI::Validator(
          [](std::string& name) {
            AccelKind k;
            return parse_accel_kind(name, k)
                       ? std::string()
                       : "expected " + accel_kind_names(", ", " or ") + ", got '" + name + "'";
          },
          accel_kind_names("|", "|")));
  cmd->add_option("--storage", storage,
                  "How a spatial subdivision stores a primitive that straddles its cuts: "
                  "every-cell (a reference in every cell it overlaps, tested once per ray; "
                  "default; kdtree, grid, octree and bsp), smallest-cell (each primitive once: "
                  "kdtree, grid and octree cells enlarged by --loose-factor on each side, the "
                  "smallest that holds it, else an inner node or the grid's list; the BSP node "
                  "whose plane it straddles), split (a straddling triangle cut into fragments, "
                  "one per side; bsp)")
      ->check(CLI::Validator(
          [](std::string& name) {
            PrimStorage s;
            return parse_prim_storage(name, s)
                       ? std::string()
                       : "expected every-cell, smallest-cell or split, got '" + name + "'";
          },
          "every-cell|smallest-cell|split"));
  cmd->add_option("--loose-factor", loose_factor,
                  "--storage smallest-cell: each cell enlarged by this fraction of its size on "
                  "every side (0.." +
                      shortest_text(kMaxLooseFactor) + "; default " +
                      shortest_text(kDefaultLooseFactor) + ", the lecture's 10%)");
  cmd->add_option("--kd-split", kd_split,
                  "How the kdtree chooses its split planes: sah (surface area heuristic; "
                  "default), median (the middle of the cell's longest axis: a spatial "
                  "median) or alternating-median (the lecture's rule: the axes x, y, z in "
                  "turn with the depth, the plane at the median of the primitives' centers)")
      ->check(CLI::Validator(
          [](std::string& name) {
            KdSplitRule r;
            return parse_kd_split_rule(name, r)
                       ? std::string()
                       : "expected sah, median or alternating-median, got '" + name + "'";
          },
          "sah|median|alternating-median"));
  cmd->add_option("--grid-resolution", grid_resolution,
                  "The grid's cells per axis: N, or NX,NY,NZ (0 on an axis: chosen from the "
                  "object count, the default; at most " +
                      std::to_string(UniformGrid::kMaxResolution) + " per axis)");
}

void parse_pixel_option(const std::string& text, int xy[2]) {
  if (!parse_ints(text, 2, xy))
    throw std::invalid_argument("--pixel: expected X,Y, got '" + text + "'");
}

void check_pixel_option(const std::string& text, const int xy[2], const RenderSettings& rs) {
  if (xy[0] < 0 || xy[1] < 0 || xy[0] >= rs.width || xy[1] >= rs.height)
    throw std::out_of_range("--pixel: (" + text + ") is outside the " + std::to_string(rs.width) +
                            "x" + std::to_string(rs.height) + " image");
}

LoadedScene SceneOptions::load() const {
  const std::string name = scene.empty() ? std::string("default scene") : scene;
  const bool mesh = !scene.empty() && is_mesh_path(scene);
  LoadedScene loaded;
  if (scene.empty()) {
    loaded.scene = make_default_scene();
    loaded.settings.samples = 2;
  } else if (mesh) {
    // The mesh as a scene file's mesh object with default options gives it,
    // around a local origin at the center of its bounds when it lies far from
    // the world's origin (Scene::origin), so that such data keeps its
    // precision.
    // A composite file's blocks are meshes named "FILE block N (NAME)".
    rayscope::MeshOptions options;
    options.file = scene;
    vtkSmartPointer<vtkDataObject> data = rayscope_vtkio::read_mesh_data_file(options.file);
    loaded.scene.origin = rayscope_vtkio::local_origin(
        rayscope_vtkio::leaf_datasets(rayscope_vtkio::dataset_leaves(data).leaves));
    options.to_scene = glm::translate(glm::dmat4(1.0), -loaded.scene.origin);
    loaded.warnings =
        add_mesh_file_objects(loaded.scene, rayscope_vtkio::load_meshes_from(options, data),
                              options.file.filename().string(), 0);
  } else {
    loaded = load_scene(scene, rayscope_vtkio::load_meshes);
  }
  // What the mesh reader left out (a composite file's blocks without
  // triangles), one line each, whatever the command.
  for (const std::string& w : loaded.warnings)
    std::fprintf(stderr, "rayscope: warning: %s\n", w.c_str());
  // The options override the scene's settings one by one; after each, the one
  // RenderSettings::validate() checks the result, so that its message (the
  // setting, its range, the value) comes with the option that broke it.
  RenderSettings& rs = loaded.settings;
  auto set = [&rs](const char* option, auto apply) {
    apply();
    try {
      rs.validate();
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string(option) + ": " + e.what());
    }
  };
  if (!size.empty()) set("--size", [&] { parse_size("--size", size, rs.width, rs.height); });
  if (width) set("--width", [&] { rs.width = *width; });
  if (height) set("--height", [&] { rs.height = *height; });
  if (samples) set("--spp", [&] { rs.samples = *samples; });
  if (max_depth) set("--max-depth", [&] { rs.max_depth = *max_depth; });
  if (min_contribution) set("--min-contribution", [&] { rs.min_contribution = *min_contribution; });
  if (seed) set("--seed", [&] { rs.seed = *seed; });
  if (max_samples) set("--max-spp", [&] { rs.max_samples = *max_samples; });
  if (target_error) set("--target-error", [&] { rs.target_error = *target_error; });
  if (texture_filter) rs.texture_filter = true;
  if (single_rays) rs.packets = false;
  set("--threads", [&] { rs.threads = threads; });
  if (mesh) frame_mesh(loaded.scene, rs);
  AccelConfig accel_config;
  parse_accel_kind(accel, accel_config.kind);         // checked by the option's validator
  parse_prim_storage(storage, accel_config.storage);  // likewise
  if (const std::string e = accel_storage_error(accel_config.kind, accel_config.storage);
      !e.empty())
    throw std::invalid_argument("--storage: " + e);
  if (loose_factor) accel_config.loose_factor = *loose_factor;
  if (const std::string e = loose_factor_error(accel_config.loose_factor); !e.empty())
    throw std::invalid_argument("--loose-factor: " + e);
  parse_kd_split_rule(kd_split, accel_config.kdtree.rule);  // checked by the option's validator
  if (!grid_resolution.empty()) {
    int r[3];
    const bool one = parse_ints(grid_resolution, 1, r);
    if (one) r[1] = r[2] = r[0];
    if (!(one || parse_ints(grid_resolution, 3, r)) || r[0] < 0 || r[1] < 0 || r[2] < 0)
      throw std::invalid_argument(
          "--grid-resolution: expected N or NX,NY,NZ (cells per axis, 0: "
          "automatic), got '" +
          grid_resolution + "'");
    accel_config.grid.resolution = glm::uvec3(uint32_t(r[0]), uint32_t(r[1]), uint32_t(r[2]));
  }
  if (const std::string e = grid_resolution_error(accel_config.grid.resolution); !e.empty())
    throw std::invalid_argument("--grid-resolution: " + e);
  try {
    loaded.scene.commit(accel_config);
    // The camera checks render() runs, here with the file's name (a framed
    // mesh of float-overflowing extent gets a camera that cannot be prepared).
    Camera probe = loaded.scene.camera;
    probe.prepare(rs.width, rs.height);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(name + ": " + e.what());
  }
  return loaded;
}

std::string SceneOptions::replay_args(const std::string& scene, const RenderSettings& s,
                                      const AccelConfig& accel) {
  std::string a = scene.empty() ? std::string() : "'" + scene + "' ";
  a += "--size " + std::to_string(s.width) + "x" + std::to_string(s.height);
  a += " --spp " + std::to_string(s.samples);
  a += " --max-depth " + std::to_string(s.max_depth);
  a += " --min-contribution " + shortest_text(s.min_contribution);
  a += " --seed " + std::to_string(s.seed);
  if (s.max_samples > 0)
    a += " --max-spp " + std::to_string(s.max_samples) + " --target-error " +
         shortest_text(s.target_error);
  if (s.texture_filter) a += " --texture-filter";
  if (accel.kind != AccelConfig{}.kind) a += std::string(" --accel ") + to_string(accel.kind);
  if (accel.storage != PrimStorage::EveryCell)
    a += std::string(" --storage ") + to_string(accel.storage);
  if (accel.loose_factor != kDefaultLooseFactor)
    a += " --loose-factor " + shortest_text(accel.loose_factor);
  if (accel.kdtree.rule != KdSplitRule::Sah)
    a += std::string(" --kd-split ") + to_string(accel.kdtree.rule);
  if (accel.grid.resolution != glm::uvec3(0u))
    a += " --grid-resolution " + std::to_string(accel.grid.resolution.x) + "," +
         std::to_string(accel.grid.resolution.y) + "," + std::to_string(accel.grid.resolution.z);
  return a;
}

}  // namespace rayscope::cli
