// What data-parallel tracing would cost in messages: every ray a Whitted
// render of a scene traces (primary, shadow, reflection, refraction), replayed
// against the scene split into P spatial pieces, one per rank, counting how
// often each ray would move from one rank to another. See docs/scaling.md.
//
// The split: the bounded primitives (triangles and spheres; tube and point
// sets are refused) by recursive median bisection of their centroids along the
// longest axis of the current set's centroid bounds (a k-d split, P a power of
// two gives equal halves at every level); each piece's box bounds its
// primitives. Planes are unbounded and small: every rank holds them.
//
// The protocol simulated, ray by ray in each pixel's recorded ray tree
// (record_pixel(), the frame loop's own per-pixel body):
//  - A primary ray starts on the first piece it enters, for free (every rank
//    knows the camera and the pieces' boxes, so each can make the camera rays
//    whose first piece is its own). Any other ray starts on the rank that
//    shaded its parent's hit: the owner of the hit primitive; for a hit on a
//    plane the rank the parent ended on, or, when the parent met no piece (a
//    primary ray seen only by the floor), the owner of the pixel's tile in an
//    image-parallel render (tile % P).
//  - It visits that rank first (it is there), then every other piece whose box
//    meets the segment [0, t_end], in order of entry distance: t_end is the
//    closest hit's t (any piece entered before it may hold a closer hit, and
//    one entered at it may win the tie), the ray's tmax for a miss and for a
//    shadow ray. An occluded shadow ray stops at the first piece holding an
//    occluder (tested against that piece's own structure).
//  - A closest hit is shaded by the rank owning the hit primitive: when the
//    ray's last visit was elsewhere (boxes overlap), it goes back there, one
//    more move.
//  A crossing is each move to another rank: visits - 1, plus the move back.
//  Not counted: a shadow ray's answer and a ray's color going to the rank that
//  holds the image (they carry their pixel and weight, so nothing returns to
//  the rank that spawned them).
//
// Usage: bench_ray_crossings [--scene FILE] [--size WxH] [--pieces 2,4,8] [--stride N] [--boxes]
//   Defaults: data/scenes/bunny.json, 800x600, 2,4,8, stride 1 (every pixel;
//   N: the pixels whose x and y are multiples of N). The scene's own camera and
//   render settings, 1 sample per pixel (no adaptive sampling), one thread.
//   --boxes lists each piece's box. Meshes are read as `rayscope render`
//   reads them (rayscope_vtkio::load_meshes).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "rayscope/render.h"
#include "rayscope/replay.h"
#include "rayscope/scene_io.h"
#include "rayscope_vtkio/mesh_files.h"

using namespace rayscope;

namespace {

constexpr int kNone = -1;  ///< No rank.

// --- Scene -----------------------------------------------------------------

// --- The split ---------------------------------------------------------------

/// A bounded primitive: a triangle (object = its mesh) or a sphere.
struct Prim {
  uint32_t object, index;  ///< As hits name them: object id, index within the object.
  Bounds3 box;
  Vec3 centroid;
};

/// One split of the scene into pieces.
struct Split {
  int pieces = 0;
  std::vector<int> piece_of;  ///< Per Prim (index into the prims).
  std::vector<Bounds3> boxes;
  std::vector<size_t> counts;  ///< Primitives per piece.
  /// Each piece's primitives and every plane, committed: the rank's own structure.
  std::vector<std::unique_ptr<Scene>> scenes;
};

std::vector<Prim> bounded_prims(const Scene& s) {
  std::vector<Prim> prims;
  for (uint32_t o = 0; o < s.meshes.size(); ++o) {
    const TriangleMesh& m = s.meshes[o];
    for (uint32_t t = 0; t < m.triangles.size(); ++t) {
      const glm::uvec3& tri = m.triangles[t];
      if (!m.finite(tri)) continue;  // never traced
      Bounds3 b(m.positions[tri.x]);
      b.extend(m.positions[tri.y]);
      b.extend(m.positions[tri.z]);
      const Vec3 c = Vec3((glm::dvec3(m.positions[tri.x]) + glm::dvec3(m.positions[tri.y]) +
                           glm::dvec3(m.positions[tri.z])) /
                          3.0);
      prims.push_back({o, t, b, c});
    }
  }
  const uint32_t first_sphere = uint32_t(s.meshes.size() + s.tubes.size() + s.points.size());
  for (uint32_t k = 0; k < s.spheres.size(); ++k) {
    const Sphere& sp = s.spheres[k];
    const BoundingSphere ball{sp.center, sp.radius};
    prims.push_back({first_sphere + k, 0, ball.box(), sp.center});
  }
  return prims;
}

/// Recursive median bisection of ids[begin, end) into `parts` pieces
/// numbered from `first`.
void bisect(const std::vector<Prim>& prims, std::vector<uint32_t>& ids, size_t begin, size_t end,
            int parts, int first, std::vector<int>& piece_of) {
  if (parts == 1) {
    for (size_t i = begin; i < end; ++i) piece_of[ids[i]] = first;
    return;
  }
  Bounds3 c;
  for (size_t i = begin; i < end; ++i) c.extend(prims[ids[i]].centroid);
  const Vec3 e = c.extent();
  const int axis = e.x >= e.y && e.x >= e.z ? 0 : e.y >= e.z ? 1 : 2;
  const int left = parts / 2;
  const size_t mid = begin + (end - begin) * size_t(left) / size_t(parts);
  std::nth_element(ids.begin() + long(begin), ids.begin() + long(mid), ids.begin() + long(end),
                   [&](uint32_t a, uint32_t b) {
                     const float ca = prims[a].centroid[axis], cb = prims[b].centroid[axis];
                     return ca < cb || (ca == cb && a < b);
                   });
  bisect(prims, ids, begin, mid, left, first, piece_of);
  bisect(prims, ids, mid, end, parts - left, first + left, piece_of);
}

Split make_split(const Scene& s, const std::vector<Prim>& prims, int pieces) {
  Split sp;
  sp.pieces = pieces;
  sp.piece_of.assign(prims.size(), kNone);
  std::vector<uint32_t> ids(prims.size());
  for (uint32_t i = 0; i < ids.size(); ++i) ids[i] = i;
  bisect(prims, ids, 0, ids.size(), pieces, 0, sp.piece_of);
  sp.boxes.assign(size_t(pieces), Bounds3{});
  sp.counts.assign(size_t(pieces), 0);
  for (size_t i = 0; i < prims.size(); ++i) {
    sp.boxes[size_t(sp.piece_of[i])].extend(prims[i].box);
    sp.counts[size_t(sp.piece_of[i])]++;
  }
  const uint32_t first_sphere = uint32_t(s.meshes.size() + s.tubes.size() + s.points.size());
  for (int p = 0; p < pieces; ++p) {
    auto piece = std::make_unique<Scene>();
    piece->materials = s.materials;
    piece->planes = s.planes;
    std::vector<TriangleMesh> meshes(s.meshes.size());
    for (size_t i = 0; i < prims.size(); ++i) {
      if (sp.piece_of[i] != p) continue;
      const Prim& pr = prims[i];
      if (pr.object >= first_sphere) {
        piece->spheres.push_back(s.spheres[pr.object - first_sphere]);
      } else {
        TriangleMesh& m = meshes[pr.object];
        if (m.triangles.empty()) {
          m.positions = s.meshes[pr.object].positions;
          m.material = s.meshes[pr.object].material;
        }
        m.triangles.push_back(s.meshes[pr.object].triangles[pr.index]);
      }
    }
    for (TriangleMesh& m : meshes)
      if (!m.triangles.empty()) piece->meshes.push_back(std::move(m));
    piece->commit();
    sp.scenes.push_back(std::move(piece));
  }
  return sp;
}

/// Slab test in double: whether the ray's segment [0, t_end] meets the box,
/// and where it enters it (0 when it starts inside).
bool enters(const Bounds3& b, const Vec3& origin, const Vec3& dir, double t_end, double& entry) {
  double t0 = 0.0, t1 = t_end;
  for (int a = 0; a < 3; ++a) {
    const double o = origin[a], d = dir[a], lo = b.lo[a], hi = b.hi[a];
    if (d == 0.0) {
      if (o < lo || o > hi) return false;
      continue;
    }
    double n = (lo - o) / d, f = (hi - o) / d;
    if (n > f) std::swap(n, f);
    t0 = std::max(t0, n);
    t1 = std::min(t1, f);
    if (t0 > t1) return false;
  }
  entry = t0;
  return true;
}

// --- Counting ------------------------------------------------------------------

struct Tally {
  uint64_t rays = 0;
  uint64_t crossings = 0;
  uint64_t crossed = 0;   ///< Rays with at least one crossing.
  uint64_t visits = 0;    ///< Pieces visited, summed over rays.
  uint64_t returns = 0;   ///< Closest-hit rays that go back to the hit's owner to be shaded.
  uint64_t no_piece = 0;  ///< Rays that meet no piece's box (planes and background only).
  int max = 0;
};

struct Checks {
  uint64_t hit_piece_missed = 0;  ///< Hit primitive's piece not met by the slab test.
  uint64_t shadow_mismatch = 0;   ///< Pieces' occlusion differs from the recorded answer.
};

class Counter {
 public:
  Counter(const Scene& scene, const std::vector<Prim>& prims, Split& split)
      : scene_(scene), split_(split) {
    // (object, index) -> Prim index.
    base_.assign(scene.object_count() + 1, 0);
    for (uint32_t o = 0; o < scene.object_count(); ++o) {
      uint32_t n = 0;
      if (o < scene.meshes.size())
        n = uint32_t(scene.meshes[o].triangles.size());
      else if (scene.object_type(o) == ObjectType::Sphere)
        n = 1;
      base_[o + 1] = base_[o] + n;
    }
    piece_visits.assign(size_t(split.pieces), 0);
    slot_.assign(base_.back(), kNone);
    for (size_t i = 0; i < prims.size(); ++i)
      slot_[base_[prims[i].object] + prims[i].index] = int(i);
  }

  std::array<Tally, kRayKindCount> tally{};
  Checks checks;
  /// Per piece: ray visits (the rank's tracing work, in rays).
  std::vector<uint64_t> piece_visits;

  /// The piece holding a hit's primitive; kNone for a plane.
  int piece_of_hit(uint32_t object, uint32_t prim) const {
    if (scene_.object_type(object) == ObjectType::Plane) return kNone;
    const int i = slot_[base_[object] + prim];
    return i < 0 ? kNone : split_.piece_of[size_t(i)];
  }

  /// The longest chain of moves in one pixel's ray tree (a ray's own and its
  /// ancestors'): a tracer exchanging rays in rounds (trace every queue, then
  /// send) finishes the pixel in chain + 1 rounds. Largest and sum over pixels.
  int chain_max = 0;
  uint64_t chain_sum = 0;

  /// Counts the rays of one pixel of image tile `tile` (row by row): its
  /// owner, tile % P as in an image-parallel render, shades the hits no piece
  /// saw (a primary ray's on a plane).
  void pixel(const std::vector<RayRecord>& rays, size_t tile) {
    fallback_ = int(tile % size_t(split_.pieces));
    shaded_on_.assign(rays.size(), kNone);
    chain_.assign(rays.size(), 0);
    int chain = 0;
    for (const RayRecord& r : rays) {
      if (r.skipped) continue;
      const int c = (r.parent >= 0 ? chain_[size_t(r.parent)] : 0) + ray(r);
      chain_[size_t(r.id)] = c;
      chain = std::max(chain, c);
    }
    chain_max = std::max(chain_max, chain);
    chain_sum += uint64_t(chain);
  }

 private:
  /// Counts ray r; returns its crossings.
  int ray(const RayRecord& r) {
    const int home = r.parent >= 0 ? shaded_on_[size_t(r.parent)] : kNone;
    const bool shadow = r.kind == RayKind::Shadow;
    const double t_end = !shadow && r.hit ? double(r.t) : double(r.tmax);
    order_.clear();
    bool met = false;  // whether the segment meets any piece's box
    for (int p = 0; p < split_.pieces; ++p) {
      double entry;
      if (!enters(split_.boxes[size_t(p)], r.origin, r.dir, t_end, entry)) continue;
      met = true;
      if (p != home) order_.push_back({entry, p});
    }
    std::sort(order_.begin(), order_.end());
    path_.clear();
    if (home != kNone) path_.push_back(home);
    for (const auto& [entry, p] : order_) path_.push_back(p);

    size_t visited = path_.size();
    int returns = 0;
    if (shadow) {
      const Ray ray{r.origin, r.dir, r.tmax};
      bool occluded = false;
      for (size_t k = 0; k < path_.size() && !occluded; ++k) {
        occluded = split_.scenes[size_t(path_[k])]->occluded(ray);
        visited = k + 1;
      }
      checks.shadow_mismatch += occluded != r.occluded;
    } else {
      const int owner = r.hit ? piece_of_hit(r.object, r.prim) : kNone;
      if (owner != kNone && std::find(path_.begin(), path_.end(), owner) == path_.end()) {
        checks.hit_piece_missed++;
        path_.push_back(owner);
        visited = path_.size();
      }
      if (owner != kNone && path_[visited - 1] != owner) returns = 1;
      shaded_on_[size_t(r.id)] = owner != kNone ? owner
                                 : visited > 0  ? path_[visited - 1]
                                                : fallback_;
    }
    const int crossings = (visited > 0 ? int(visited) - 1 : 0) + returns;
    for (size_t k = 0; k < visited; ++k) piece_visits[size_t(path_[k])]++;
    Tally& t = tally[int(r.kind)];
    t.rays++;
    t.crossings += uint64_t(crossings);
    t.crossed += crossings > 0;
    t.visits += visited;
    t.returns += uint64_t(returns);
    t.no_piece += !met;
    t.max = std::max(t.max, crossings);
    return crossings;
  }

  const Scene& scene_;
  Split& split_;
  std::vector<uint32_t> base_;
  std::vector<int> slot_;
  int fallback_ = 0;
  std::vector<int> shaded_on_;  ///< Per ray of the pixel: the rank that shades its hit.
  std::vector<int> chain_;      ///< Per ray of the pixel: moves from the primary ray to it.
  std::vector<std::pair<double, int>> order_;
  std::vector<int> path_;
};

std::vector<int> parse_list(const std::string& s) {
  std::vector<int> v;
  std::stringstream in(s);
  for (std::string w; std::getline(in, w, ',');) v.push_back(std::stoi(w));
  return v;
}

int usage() {
  std::fprintf(stderr,
               "usage: bench_ray_crossings [--scene FILE] [--size WxH] [--pieces 2,4,8] "
               "[--stride N] [--boxes]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string scene_file = RAYSCOPE_SOURCE_DIR "/data/scenes/bunny.json";
  int width = 800, height = 600, stride = 1;
  bool show_boxes = false;
  std::vector<int> piece_counts = {2, 4, 8};
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "--boxes") {
        show_boxes = true;
        continue;
      }
      if (i + 1 >= argc) return usage();
      if (a == "--scene")
        scene_file = argv[++i];
      else if (a == "--size") {
        if (std::sscanf(argv[++i], "%dx%d", &width, &height) != 2) return usage();
      } else if (a == "--pieces")
        piece_counts = parse_list(argv[++i]);
      else if (a == "--stride")
        stride = std::stoi(argv[++i]);
      else
        return usage();
    }
  } catch (const std::exception&) {
    return usage();
  }
  if (width < 1 || height < 1 || stride < 1 || piece_counts.empty()) return usage();
  for (int p : piece_counts)
    if (p < 1 || p > 1024) return usage();

  LoadedScene loaded;
  RenderSettings rs;
  try {
    loaded = load_scene(scene_file, rayscope_vtkio::load_meshes);
    if (!loaded.scene.tubes.empty() || !loaded.scene.points.empty())
      throw std::runtime_error(scene_file + ": tube and point sets are not split by this program");
    loaded.scene.commit();
    rs = loaded.settings;
    rs.width = width;
    rs.height = height;
    rs.samples = 1;
    rs.max_samples = 0;
    rs.target_error = 0.0f;
    rs.threads = 1;
    rs.validate();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  Scene& scene = loaded.scene;

  const std::vector<Prim> prims = bounded_prims(scene);
  std::vector<Split> splits;
  std::vector<std::unique_ptr<Counter>> counters;
  splits.reserve(piece_counts.size());
  for (int p : piece_counts) splits.push_back(make_split(scene, prims, p));
  for (Split& s : splits) counters.push_back(std::make_unique<Counter>(scene, prims, s));

  // Every recorded pixel's ray tree, exactly as the render traces it.
  const auto t0 = std::chrono::steady_clock::now();
  prepare_frame(scene, rs);
  const int tiles_x = (width + rs.tile_size - 1) / rs.tile_size;
  uint64_t pixels = 0;
  for (int y = 0; y < height; y += stride)
    for (int x = 0; x < width; x += stride) {
      const PixelRecord rec = record_pixel(scene, rs, x, y);
      const size_t tile = size_t(y / rs.tile_size) * size_t(tiles_x) + size_t(x / rs.tile_size);
      for (auto& c : counters) c->pixel(rec.rays, tile);
      pixels++;
    }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // The render's own counters, to check that the records hold every ray.
  std::string check = "not made (stride > 1)";
  std::vector<Tally> totals;
  if (stride == 1) {
    RayCounters rc;
    render(scene, rs, &rc);
    bool same = true;
    for (int k = 0; k < kRayKindCount; ++k) same &= rc.rays[k] == counters[0]->tally[k].rays;
    check = same ? "the recorded rays of each kind equal render()'s counters"
                 : "MISMATCH: recorded rays differ from render()'s counters";
  }

  const SceneSummary& sum = scene.summary();
  const std::string recorded =
      stride == 1 ? "every pixel"
                  : "the pixels whose x and y are multiples of " + std::to_string(stride);
  std::printf("# Ray crossings of a data-parallel split\n\n");
  std::printf("- scene: %s (%zu triangles, %zu spheres, %zu planes, %zu lights)\n",
              scene_file.c_str(), sum.triangles, sum.spheres, sum.planes, sum.lights);
  std::printf("- image: %dx%d, 1 sample, max_depth %d, min_contribution %s; %llu pixels (%s)\n",
              width, height, rs.max_depth, shortest_text(rs.min_contribution).c_str(),
              (unsigned long long)pixels, recorded.c_str());
  std::printf(
      "- split: recursive median bisection of the primitives' centroids along the longest "
      "axis; planes on every rank\n");
  std::printf("- check: %s\n", check.c_str());
  std::printf("- recording and counting took %.1f s\n\n", seconds);

  std::printf(
      "| P | rays | count | meeting a piece | mean crossings | crossing >= 1 | crossings / pixel "
      "| max |\n");
  std::printf("| ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: |\n");
  for (size_t i = 0; i < splits.size(); ++i) {
    const Counter& c = *counters[i];
    auto row = [&](const char* name, const Tally& t) {
      const double n = double(std::max<uint64_t>(t.rays, 1));
      std::printf("| %d | %s | %llu | %.1f%% | %.3f | %.1f%% | %.3f | %d |\n", splits[i].pieces,
                  name, (unsigned long long)t.rays, 100.0 * double(t.rays - t.no_piece) / n,
                  double(t.crossings) / n, 100.0 * double(t.crossed) / n,
                  double(t.crossings) / double(pixels), t.max);
    };
    Tally all;
    for (int k = 0; k < kRayKindCount; ++k) {
      const Tally& t = c.tally[k];
      row(to_string(RayKind(k)), t);
      all.rays += t.rays;
      all.crossings += t.crossings;
      all.crossed += t.crossed;
      all.visits += t.visits;
      all.returns += t.returns;
      all.no_piece += t.no_piece;
      all.max = std::max(all.max, t.max);
    }
    row("all", all);
    totals.push_back(all);
  }

  std::printf("\n");
  for (size_t i = 0; i < splits.size(); ++i) {
    const Split& s = splits[i];
    const Counter& c = *counters[i];
    const Tally& all = totals[i];
    const auto [lo, hi] = std::minmax_element(s.counts.begin(), s.counts.end());
    const auto [vlo, vhi] = std::minmax_element(c.piece_visits.begin(), c.piece_visits.end());
    std::printf(
        "- P = %d: %zu..%zu primitives a piece; %.3f pieces visited a ray; ray visits a piece "
        "%llu..%llu (busiest / mean %.2f); longest chain of moves in a pixel's ray tree %d (mean "
        "over pixels %.3f): %d rounds of exchange\n",
        s.pieces, *lo, *hi, double(all.visits) / double(std::max<uint64_t>(all.rays, 1)),
        (unsigned long long)*vlo, (unsigned long long)*vhi,
        double(*vhi) * double(s.pieces) / double(std::max<uint64_t>(all.visits, 1)), c.chain_max,
        double(c.chain_sum) / double(pixels), c.chain_max + 1);
    std::printf(
        "  %llu moves back to the hit's owner (counted); checks: %llu hits outside their piece's "
        "box, %llu shadow answers differing\n",
        (unsigned long long)all.returns, (unsigned long long)c.checks.hit_piece_missed,
        (unsigned long long)c.checks.shadow_mismatch);
    if (show_boxes)
      for (int p = 0; p < s.pieces; ++p) {
        const Bounds3& b = s.boxes[size_t(p)];
        std::printf("  - piece %d: %zu primitives, box (%.3f, %.3f, %.3f) .. (%.3f, %.3f, %.3f)\n",
                    p, s.counts[size_t(p)], b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z);
      }
  }
  return 0;
}
