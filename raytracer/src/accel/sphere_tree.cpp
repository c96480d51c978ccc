// Sphere tree builder: top down by the binned split rule of
// SphereTreeBuildConfig, then bottom up the node spheres:
//
// - a leaf's sphere is the tighter of two that both contain every primitive
//   sphere it holds: the spheres merged one by one (enclosing_sphere), and the
//   sphere centered on the middle of their bounding box with the radius that
//   reaches the farthest of them (better for many small, even spheres, where
//   one-by-one merging drifts);
// - an inner node's sphere is the exact merge of its two children's spheres,
//   so every node's sphere contains its children's (and, by induction, every
//   primitive sphere below it).
//
// All geometry is computed in double; a float sphere is then rounded outward
// (center rounded to float, radius recomputed from it and rounded up), so
// that containment holds for the float spheres the walks test.
#include "rayscope/accel/sphere_tree.h"

#include <cstdio>

#include <algorithm>
#include <chrono>
#include <limits>
#include <stdexcept>
#include <string>

namespace rayscope {
namespace {

struct DSphere {
  DVec3 c{0.0};
  double r = -1.0;  ///< < 0: empty (merging with it gives the other).
};

DSphere merge(const DSphere& a, const DSphere& b) {
  if (a.r < 0.0) return b;
  if (b.r < 0.0) return a;
  const DVec3 ab = b.c - a.c;
  const double d = std::sqrt(glm::dot(ab, ab));
  if (d + b.r <= a.r) return a;
  if (d + a.r <= b.r) return b;
  const double r = 0.5 * (d + a.r + b.r);
  // d > 0 here: with d == 0 one of them contains the other.
  return {a.c + ab * ((r - a.r) / d), r};
}

/// The float sphere centered at (the rounding of) `center` that contains
/// every sphere in `parts`: its radius reaches the farthest of them from the
/// rounded center, raised by a double rounding and rounded up to float.
template <class Parts>
BoundingSphere round_out(const DVec3& center, const Parts& parts) {
  BoundingSphere s;
  s.center = Vec3(center);
  const DVec3 cf(s.center);
  double reach = 0.0;
  for (const DSphere& p : parts) {
    // Exact for a sphere centered on the rounded center; else raised by the
    // double evaluation's own rounding.
    const DVec3 d = p.c - cf;
    reach = std::max(reach,
                     d == DVec3(0.0) ? p.r : (std::sqrt(glm::dot(d, d)) + p.r) * (1.0 + 0x1p-50));
  }
  float r = float(reach);
  if (double(r) < reach) r = next_float_up(r);
  s.radius = r;
  return s;
}

DSphere to_d(const BoundingSphere& s) {
  return {DVec3(s.center), double(s.radius)};
}

std::string text(const BoundingSphere& s) {
  return "center (" + std::to_string(s.center.x) + ", " + std::to_string(s.center.y) + ", " +
         std::to_string(s.center.z) + "), radius " + std::to_string(s.radius);
}

struct Builder {
  std::span<const BoundingSphere> spheres;
  const SphereTreeBuildConfig& cfg;
  int max_depth;
  std::vector<SphereNode>& nodes;
  std::vector<uint32_t>& ids;  ///< The tree's prim_indices, permuted in place.
  uint32_t depth = 0;

  BoundingSphere leaf(uint32_t node, uint32_t begin, uint32_t end) {
    std::vector<DSphere> parts;
    parts.reserve(end - begin);
    DSphere merged;
    DVec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
    for (uint32_t i = begin; i < end; ++i) {
      const DSphere s = to_d(spheres[ids[i]]);
      parts.push_back(s);
      merged = merge(merged, s);
      lo = glm::min(lo, s.c - s.r);
      hi = glm::max(hi, s.c + s.r);
    }
    const BoundingSphere a = round_out(merged.c, parts);
    const BoundingSphere b = round_out(0.5 * (lo + hi), parts);
    const BoundingSphere s = b.radius < a.radius ? b : a;
    SphereNode& n = nodes[node];
    n.center = s.center;
    n.radius = s.radius;
    n.index = begin;
    n.count = end - begin;
    return s;
  }

  /// Cuts [begin, end) at the object median along `axis` (ties by index, so
  /// the build is deterministic); returns the cut.
  uint32_t median(uint32_t begin, uint32_t end, int axis) {
    const uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(ids.begin() + begin, ids.begin() + mid, ids.begin() + end,
                     [&](uint32_t a, uint32_t b) {
                       const float ca = spheres[a].center[axis], cb = spheres[b].center[axis];
                       return ca < cb || (ca == cb && a < b);
                     });
    return mid;
  }

  BoundingSphere build(uint32_t node, uint32_t begin, uint32_t end, int level) {
    depth = std::max(depth, uint32_t(level));
    const uint32_t n = end - begin;
    if (n == 1) return leaf(node, begin, end);
    Bounds3 cb;
    for (uint32_t i = begin; i < end; ++i) cb.extend(spheres[ids[i]].center);
    const int axis = max_dimension(cb.extent());
    const float lo = cb.lo[axis], extent = cb.extent()[axis];
    uint32_t cut;
    if (level >= max_depth || !(extent > 0.0f)) {
      // Past the cost depth, or every center at one point: no plane separates
      // them, so the object median (by index when the centers coincide).
      if (n <= cfg.max_leaf_size) return leaf(node, begin, end);
      cut = median(begin, end, axis);
    } else {
      const int k = cfg.bins;
      auto bin_of = [&](uint32_t p) {
        const int b = int(float(k) * ((spheres[p].center[axis] - lo) / extent));
        return std::clamp(b, 0, k - 1);
      };
      DSphere bins[SphereTree::kMaxBins];
      uint32_t counts[SphereTree::kMaxBins] = {};
      for (uint32_t i = begin; i < end; ++i) {
        const int b = bin_of(ids[i]);
        bins[b] = merge(bins[b], to_d(spheres[ids[i]]));
        counts[b]++;
      }
      // Right-to-left sweep: the sphere around bins i+1 .. k-1.
      double right_r2[SphereTree::kMaxBins];
      uint32_t right_n[SphereTree::kMaxBins];
      DSphere acc;
      uint32_t cnt = 0;
      for (int i = k - 1; i > 0; --i) {
        acc = merge(acc, bins[i]);
        cnt += counts[i];
        right_r2[i - 1] = acc.r * acc.r;
        right_n[i - 1] = cnt;
      }
      const DSphere all = merge(acc, bins[0]);
      const double root_r2 = std::max(all.r * all.r, 1e-300);
      double best = std::numeric_limits<double>::infinity();
      int best_bin = -1;
      acc = DSphere{};
      cnt = 0;
      for (int i = 0; i < k - 1; ++i) {
        acc = merge(acc, bins[i]);
        cnt += counts[i];
        if (cnt == 0 || right_n[i] == 0) continue;
        const double cost =
            cfg.traversal_cost +
            cfg.intersection_cost * (acc.r * acc.r * cnt + right_r2[i] * right_n[i]) / root_r2;
        if (cost < best) {
          best = cost;
          best_bin = i;
        }
      }
      if (n <= cfg.max_leaf_size && double(cfg.intersection_cost) * n <= best)
        return leaf(node, begin, end);
      if (best_bin < 0) {
        cut = median(begin, end, axis);
      } else {
        cut = uint32_t(std::partition(ids.begin() + begin, ids.begin() + end,
                                      [&](uint32_t p) { return bin_of(p) <= best_bin; }) -
                       ids.begin());
      }
    }
    if (nodes.size() + 2 > size_t(~0u))
      throw std::length_error("SphereTree::build: too many nodes");
    const uint32_t first = uint32_t(nodes.size());
    nodes.resize(nodes.size() + 2);
    nodes[node].index = first;
    nodes[node].count = 0;
    const BoundingSphere s0 = build(first, begin, cut, level + 1);
    const BoundingSphere s1 = build(first + 1, cut, end, level + 1);
    const BoundingSphere s = enclosing_sphere(s0, s1);
    nodes[node].center = s.center;
    nodes[node].radius = s.radius;
    return s;
  }
};

}  // namespace

BoundingSphere min_triangle_sphere(const Vec3& af, const Vec3& bf, const Vec3& cf) {
  const DVec3 v[3] = {DVec3(af), DVec3(bf), DVec3(cf)};
  const DSphere parts[3] = {{v[0], 0.0}, {v[1], 0.0}, {v[2], 0.0}};
  // The angle at vertex i is acute when its two edges point the same way.
  bool acute = true;
  for (int i = 0; i < 3; ++i)
    acute = acute && glm::dot(v[(i + 1) % 3] - v[i], v[(i + 2) % 3] - v[i]) > 0.0;
  if (acute) {
    // Circumcenter: c + ((|a|^2 b - |b|^2 a) x (a x b)) / (2 |a x b|^2), with
    // a, b the edges from vertex c (non-zero: an acute triangle is not flat).
    const DVec3 a = v[0] - v[2], b = v[1] - v[2];
    const DVec3 axb = glm::cross(a, b);
    const DVec3 center = v[2] + glm::cross(glm::dot(a, a) * b - glm::dot(b, b) * a, axb) /
                                    (2.0 * glm::dot(axb, axb));
    return round_out(center, parts);
  }
  // Right, obtuse or degenerate: the sphere on the longest edge.
  int longest = 0;
  double len2 = -1.0;
  for (int i = 0; i < 3; ++i) {
    const DVec3 e = v[(i + 1) % 3] - v[i];
    if (glm::dot(e, e) > len2) {
      len2 = glm::dot(e, e);
      longest = i;
    }
  }
  return round_out(0.5 * (v[longest] + v[(longest + 1) % 3]), parts);
}

BoundingSphere enclosing_sphere(const BoundingSphere& a, const BoundingSphere& b) {
  const DSphere parts[2] = {to_d(a), to_d(b)};
  // Also when one contains the other, the result is rounded out again: the
  // double test of containment may round in its favor. Two equal spheres
  // give that sphere exactly.
  return round_out(merge(parts[0], parts[1]).c, parts);
}

void SphereTree::build(std::span<const BoundingSphere> spheres, const SphereTreeBuildConfig& cfg) {
  const auto start = std::chrono::steady_clock::now();
  if (cfg.bins < 2 || cfg.bins > kMaxBins)
    throw std::invalid_argument("sphere tree bins must be 2 .. " + std::to_string(kMaxBins) +
                                ", got " + std::to_string(cfg.bins));
  if (cfg.max_leaf_size == 0)
    throw std::invalid_argument("sphere tree max leaf size must be at least 1");
  if (!std::isfinite(cfg.traversal_cost) || !std::isfinite(cfg.intersection_cost) ||
      !(cfg.traversal_cost >= 0.0f) || !(cfg.intersection_cost > 0.0f))
    throw std::invalid_argument(
        "sphere tree costs must be finite, traversal >= 0 and intersection > 0");
  const size_t n = spheres.size();
  if (n > size_t(~0u) - 1) throw std::length_error("SphereTree::build: too many primitives");
  for (size_t i = 0; i < n; ++i) {
    const BoundingSphere& s = spheres[i];
    if (!all_finite(s.center) || !std::isfinite(s.radius) || !(s.radius >= 0.0f))
      throw std::invalid_argument("SphereTree::build: primitive " + std::to_string(i) +
                                  " has a non-finite or negative bounding sphere (" + text(s) +
                                  ")");
  }
  config = cfg;
  nodes.clear();
  prim_indices.resize(n);
  for (uint32_t i = 0; i < n; ++i) prim_indices[i] = i;
  if (n > 0) {
    nodes.reserve(2 * n - 1);
    nodes.emplace_back();
    Builder b{spheres, cfg, std::clamp(cfg.max_depth, 0, kMaxCostDepth), nodes, prim_indices};
    b.build(0, 0, uint32_t(n), 0);
  }
  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::vector<uint32_t> SphereTree::depths() const {
  std::vector<uint32_t> d(nodes.size(), 0u);
  for (size_t i = 0; i < nodes.size(); ++i)
    if (!nodes[i].is_leaf()) d[nodes[i].index] = d[nodes[i].index + 1] = d[i] + 1;
  return d;
}

SphereTreeQuality SphereTree::quality() const {
  SphereTreeQuality q;
  q.build_seconds = build_seconds_;
  if (nodes.empty()) return q;
  q.nodes = uint32_t(nodes.size());
  q.memory_bytes = memory_bytes();
  const std::vector<uint32_t> d = depths();
  const double root_r = std::max(double(nodes[0].radius), 1e-300);
  size_t leaf_prims = 0;
  for (size_t i = 0; i < nodes.size(); ++i) {
    const SphereNode& n = nodes[i];
    q.depth = std::max(q.depth, d[i]);
    const double rel = double(n.radius) / root_r;
    q.volume_ratio += rel * rel * rel;
    if (n.is_leaf()) {
      q.leaves++;
      q.max_leaf_prims = std::max(q.max_leaf_prims, n.count);
      leaf_prims += n.count;
      q.sah_cost += rel * rel * config.intersection_cost * n.count;
    } else {
      q.sah_cost += rel * rel * config.traversal_cost;
    }
  }
  q.mean_leaf_prims = double(leaf_prims) / q.leaves;
  return q;
}

AccelFigures SphereTree::figures() const {
  return figures_of(quality(), prim_indices.empty() ? 0.0 : 1.0);
}

AccelView SphereTree::view() const {
  AccelView v;
  v.structure = "spheres";
  v.traversal_cost = config.traversal_cost;
  v.intersection_cost = config.intersection_cost;
  add_binary_nodes(v, nodes, [](const SphereNode& n, AccelViewNode& o) {
    o.sphere = n.sphere();
    o.box = n.sphere().box();
  });
  v.refs = prim_indices;
  finish_levels(v);
  return v;
}

std::string SphereTree::stats_line() const {
  const SphereTreeQuality q = quality();
  char line[512];
  std::snprintf(line, sizeof line,
                "spheres: %u nodes, %u leaves, depth %u, %.1f prims/leaf (max %u), SAH cost %.2f "
                "(sphere areas), node volumes %.1fx the root's, %.2f MiB, built in %.3f s",
                q.nodes, q.leaves, q.depth, q.mean_leaf_prims, q.max_leaf_prims, q.sah_cost,
                q.volume_ratio, double(q.memory_bytes) / (1024.0 * 1024.0), q.build_seconds);
  return line;
}

std::string SphereTree::walk_legend() const {
  return "the sphere tree (--accel spheres); nodes are named by their sphere tree ids, a "
         "node's two child \"boxes\" are its children's bounding spheres (entered nearer "
         "entry first), and every primitive is stored once";
}

}  // namespace rayscope
