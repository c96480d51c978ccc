// Binned SAH builder (Wald 2007): for each node, the primitive centroids are
// sorted into equal-width bins along each axis and the split between bins with
// the lowest surface area heuristic cost is taken.
#include "rayscope/bvh.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <functional>
#include <numeric>

namespace rayscope {
namespace {

struct Builder {
  std::span<const Bounds3> bounds;
  std::span<const Vec3> centroids;
  const BvhBuildConfig& cfg;
  std::vector<BvhNode>& nodes;
  std::vector<uint32_t>& idx;

  struct Bin {
    Bounds3 box;
    uint32_t count = 0;
  };

  void make_leaf(uint32_t node, uint32_t begin, uint32_t end) {
    nodes[node].index = begin;
    nodes[node].count = end - begin;
  }

  Bounds3 range_bounds(uint32_t begin, uint32_t end) const {
    Bounds3 b;
    for (uint32_t i = begin; i < end; ++i) b.extend(bounds[idx[i]]);
    return b;
  }

  // Splits [begin, end) in two; returns the split position or `begin` for a leaf.
  uint32_t find_split(uint32_t begin, uint32_t end, const Bounds3& node_box, int depth) {
    const uint32_t count = end - begin;
    if (count <= cfg.min_leaf_size) return begin;
    Bounds3 cbox;
    for (uint32_t i = begin; i < end; ++i) cbox.extend(centroids[idx[i]]);
    const Vec3 ext = cbox.extent();
    const int nb = std::clamp(cfg.bins, 2, 256);
    // Bin of a centroid from its scaled offset, clamped to [0, nb - 1] before
    // converting: centroids spanning more than the float range (e.g. spheres
    // at -3e38 and 3e38) give ext = inf, scale = 0 and inf * 0 = NaN, and
    // converting NaN to int is undefined (tests/fuzz regression
    // bvh_centroids_span_beyond_float_range.json).
    auto bin_of = [nb](float scaled) {
      if (!(scaled > 0.0f)) return 0;  // also NaN
      return scaled < float(nb - 1) ? int(scaled) : nb - 1;
    };

    auto median_split = [&]() -> uint32_t {
      uint32_t mid = begin + count / 2;
      int axis = max_dimension(ext);
      std::nth_element(
          idx.begin() + begin, idx.begin() + mid, idx.begin() + end,
          [&](uint32_t a, uint32_t b) { return centroids[a][axis] < centroids[b][axis]; });
      return mid;
    };

    // Bvh::traverse keeps a 64-entry stack, one entry per level at most, so no
    // leaf may lie deeper than 64 levels below the root. Median splits need
    // ceil(log2(count / max_leaf_size)) more levels; switch to them while that
    // still fits (SAH alone can peel a few primitives per level, e.g. for
    // geometrically spaced objects, and go arbitrarily deep).
    int median_levels = 0;
    while ((uint64_t(std::max(cfg.max_leaf_size, 1u)) << median_levels) < count) ++median_levels;
    if (depth >= cfg.max_depth || depth + median_levels >= 63)
      return count <= cfg.max_leaf_size ? begin : median_split();

    float best_cost = kInfinity;
    int best_axis = -1, best_bin = 0;
    std::array<Bin, 256> bins;
    std::array<float, 256> right_cost;
    for (int axis = 0; axis < 3; ++axis) {
      if (!(ext[axis] > 0.0f)) continue;
      const float scale = float(nb) / ext[axis];
      for (int b = 0; b < nb; ++b) bins[b] = Bin{};
      for (uint32_t i = begin; i < end; ++i) {
        uint32_t p = idx[i];
        int b = bin_of((centroids[p][axis] - cbox.lo[axis]) * scale);
        bins[b].box.extend(bounds[p]);
        bins[b].count++;
      }
      // Sweep from the right, then from the left.
      Bounds3 acc;
      uint32_t n = 0;
      for (int b = nb - 1; b > 0; --b) {
        acc.extend(bins[b].box);
        n += bins[b].count;
        right_cost[b] = n ? acc.half_area() * float(n) : 0.0f;
      }
      acc = Bounds3();
      n = 0;
      for (int b = 0; b < nb - 1; ++b) {
        acc.extend(bins[b].box);
        n += bins[b].count;
        if (n == 0 || n == count) continue;
        float cost = acc.half_area() * float(n) + right_cost[b + 1];
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = axis;
          best_bin = b;
        }
      }
    }

    const float parent_area = node_box.half_area();
    const float leaf_cost = cfg.intersection_cost * float(count);
    if (best_axis < 0) {
      // All centroids coincide: no plane separates them.
      return count <= cfg.max_leaf_size ? begin : median_split();
    }
    float split_cost = cfg.traversal_cost;
    if (parent_area > 0.0f) split_cost += cfg.intersection_cost * best_cost / parent_area;
    if (split_cost >= leaf_cost && count <= cfg.max_leaf_size) return begin;

    const float scale = float(nb) / ext[best_axis];
    const float lo = cbox.lo[best_axis];
    auto mid_it = std::partition(idx.begin() + begin, idx.begin() + end, [&](uint32_t p) {
      return bin_of((centroids[p][best_axis] - lo) * scale) <= best_bin;
    });
    uint32_t mid = uint32_t(mid_it - idx.begin());
    if (mid == begin || mid == end) return median_split();
    return mid;
  }

  void build(uint32_t node, uint32_t begin, uint32_t end, int depth) {
    Bounds3 box = range_bounds(begin, end);
    nodes[node].lo = box.lo;
    nodes[node].hi = box.hi;
    uint32_t mid = find_split(begin, end, box, depth);
    if (mid == begin) {
      make_leaf(node, begin, end);
      return;
    }
    uint32_t left = uint32_t(nodes.size());
    nodes.emplace_back();
    nodes.emplace_back();
    nodes[node].index = left;
    nodes[node].count = 0;
    build(left, begin, mid, depth + 1);
    build(left + 1, mid, end, depth + 1);
  }
};

}  // namespace

void Bvh::build(std::span<const Bounds3> bounds, std::span<const Vec3> centroids,
                const BvhBuildConfig& cfg) {
  assert(bounds.size() == centroids.size());
  config = cfg;
  nodes.clear();
  prim_indices.clear();
  const size_t n = bounds.size();
  if (n == 0) return;
  prim_indices.resize(n);
  std::iota(prim_indices.begin(), prim_indices.end(), 0u);
  nodes.reserve(2 * n);
  nodes.emplace_back();
  Builder b{bounds, centroids, cfg, nodes, prim_indices};
  b.build(0, 0, uint32_t(n), 0);
  nodes.shrink_to_fit();
}

BvhQuality Bvh::quality() const {
  BvhQuality q;
  if (nodes.empty()) return q;
  q.nodes = uint32_t(nodes.size());
  q.min_leaf_prims = ~0u;
  q.memory_bytes = nodes.size() * sizeof(BvhNode) + prim_indices.size() * sizeof(uint32_t);
  const double root_area = std::max(1e-30, double(nodes[0].bounds().half_area()));
  uint64_t leaf_prims = 0;
  std::vector<std::pair<uint32_t, uint32_t>> stack{{0u, 1u}};
  while (!stack.empty()) {
    auto [i, d] = stack.back();
    stack.pop_back();
    const BvhNode& n = nodes[i];
    q.depth = std::max(q.depth, d);
    double rel = double(n.bounds().half_area()) / root_area;
    if (n.is_leaf()) {
      q.leaves++;
      leaf_prims += n.count;
      q.min_leaf_prims = std::min(q.min_leaf_prims, n.count);
      q.max_leaf_prims = std::max(q.max_leaf_prims, n.count);
      q.sah_cost += rel * config.intersection_cost * n.count;
    } else {
      q.sah_cost += rel * config.traversal_cost;
      stack.push_back({n.index, d + 1});
      stack.push_back({n.index + 1, d + 1});
    }
  }
  q.mean_leaf_prims = q.leaves ? double(leaf_prims) / q.leaves : 0.0;
  return q;
}

}  // namespace rayscope
