// Binned SAH builder (Wald 2007): for each node, the primitive centroids are
// sorted into equal-width bins along each axis and the split between bins with
// the lowest surface area heuristic cost is taken.
//
// One pass over a node's primitives bins them on all three axes at once; each
// bin keeps the box of its primitives and of their centroids, so that the two
// children's boxes are unions of bins (exact: min and max do not round) and no
// node walks its primitives again to bound them. The primitives are copied
// into one array of references (box, centroid, index) that the partitions
// reorder in place, so that a node reads its primitives in order instead of
// through an index. Subtrees of at least cfg.parallel_min_prims primitives
// are built in parallel (TBB) into their own node arrays, which are then spliced
// in the order the serial recursion would have made them: the tree is the
// same, node for node, whatever the number of threads.
#include "rayscope/bvh.h"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <vector>

namespace rayscope {
namespace {

/// Most bins per axis (BvhBuildConfig::bins is clamped to [2, kMaxBins]).
constexpr int kMaxBins = 256;

struct PrimRef {
  Vec3 lo;
  uint32_t id;
  Vec3 hi;
  Vec3 c;  ///< Centroid.
  Bounds3 box() const {
    Bounds3 b;
    b.lo = lo;
    b.hi = hi;
    return b;
  }
};

/// A node's primitives refs[begin, end), their box and their centroids' box.
struct Range {
  uint32_t begin = 0, end = 0;
  Bounds3 box, cbox;
  uint32_t count() const { return end - begin; }
};

struct Bin {
  Bounds3 box, cbox;
  uint32_t count = 0;
};

/// A task's scratch space: the bins of the three axes, and the SAH cost of
/// the right side of each candidate plane.
struct Scratch {
  explicit Scratch(int nb)
      : bins{std::vector<Bin>(size_t(nb)), std::vector<Bin>(size_t(nb)),
             std::vector<Bin>(size_t(nb))},
        right_cost(size_t(nb)) {}
  std::array<std::vector<Bin>, 3> bins;
  std::vector<float> right_cost;
};

struct Builder {
  std::span<PrimRef> refs;
  const BvhBuildConfig& cfg;
  int nb;  ///< Bins per axis.

  void bound(Range& r) const {
    r.box = Bounds3();
    r.cbox = Bounds3();
    for (uint32_t i = r.begin; i < r.end; ++i) {
      r.box.extend(refs[i].box());
      r.cbox.extend(refs[i].c);
    }
  }

  // Splits at the object median on the centroids' widest axis.
  void median_split(const Range& r, Range& left, Range& right) const {
    const uint32_t mid = r.begin + r.count() / 2;
    const int axis = max_dimension(r.cbox.extent());
    std::nth_element(refs.begin() + r.begin, refs.begin() + mid, refs.begin() + r.end,
                     [axis](const PrimRef& a, const PrimRef& b) { return a.c[axis] < b.c[axis]; });
    left.begin = r.begin;
    left.end = right.begin = mid;
    right.end = r.end;
    bound(left);
    bound(right);
  }

  // Splits r in two (false: r becomes a leaf).
  bool split(const Range& r, int depth, Scratch& s, Range& left, Range& right) const {
    const uint32_t count = r.count();
    if (count <= cfg.min_leaf_size) return false;
    const Vec3 ext = r.cbox.extent();
    // Bin of a centroid from its scaled offset, clamped to [0, nb - 1] before
    // converting: centroids spanning more than the float range (e.g. spheres
    // at -3e38 and 3e38) give ext = inf, scale = 0 and inf * 0 = NaN, and
    // converting NaN to int is undefined (tests/fuzz regression
    // bvh_centroids_span_beyond_float_range.json).
    auto bin_of = [nb = nb](float scaled) {
      if (!(scaled > 0.0f)) return 0;  // also NaN
      return scaled < float(nb - 1) ? int(scaled) : nb - 1;
    };

    // Bvh::traverse keeps a 64-entry stack, one entry per level at most, so no
    // leaf may lie deeper than 64 levels below the root. Median splits need
    // ceil(log2(count / max_leaf_size)) more levels; switch to them while that
    // still fits (SAH alone can peel a few primitives per level, e.g. for
    // geometrically spaced objects, and go arbitrarily deep).
    int median_levels = 0;
    while ((uint64_t(std::max(cfg.max_leaf_size, 1u)) << median_levels) < count) ++median_levels;
    if (depth >= cfg.max_depth || depth + median_levels >= 63) {
      if (count <= cfg.max_leaf_size) return false;
      median_split(r, left, right);
      return true;
    }

    Vec3 scale;
    for (int axis = 0; axis < 3; ++axis) {
      scale[axis] = ext[axis] > 0.0f ? float(nb) / ext[axis] : 0.0f;
      for (int b = 0; b < nb; ++b) s.bins[axis][b] = Bin{};
    }
    for (uint32_t i = r.begin; i < r.end; ++i) {
      const PrimRef& p = refs[i];
      for (int axis = 0; axis < 3; ++axis) {
        Bin& bin = s.bins[axis][bin_of((p.c[axis] - r.cbox.lo[axis]) * scale[axis])];
        bin.box.extend(p.box());
        bin.cbox.extend(p.c);
        bin.count++;
      }
    }

    float best_cost = kInfinity;
    int best_axis = -1, best_bin = 0;
    for (int axis = 0; axis < 3; ++axis) {
      if (!(ext[axis] > 0.0f)) continue;
      const std::vector<Bin>& bins = s.bins[axis];
      // Sweep from the right, then from the left.
      Bounds3 acc;
      uint32_t n = 0;
      for (int b = nb - 1; b > 0; --b) {
        acc.extend(bins[b].box);
        n += bins[b].count;
        s.right_cost[b] = n ? acc.half_area() * float(n) : 0.0f;
      }
      acc = Bounds3();
      n = 0;
      for (int b = 0; b < nb - 1; ++b) {
        acc.extend(bins[b].box);
        n += bins[b].count;
        if (n == 0 || n == count) continue;
        const float cost = acc.half_area() * float(n) + s.right_cost[b + 1];
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = axis;
          best_bin = b;
        }
      }
    }

    const float parent_area = r.box.half_area();
    const float leaf_cost = cfg.intersection_cost * float(count);
    if (best_axis < 0) {
      // All centroids coincide: no plane separates them.
      if (count <= cfg.max_leaf_size) return false;
      median_split(r, left, right);
      return true;
    }
    float split_cost = cfg.traversal_cost;
    if (parent_area > 0.0f) split_cost += cfg.intersection_cost * best_cost / parent_area;
    if (split_cost >= leaf_cost && count <= cfg.max_leaf_size) return false;

    const float sc = scale[best_axis];
    const float lo = r.cbox.lo[best_axis];
    const auto mid_it = std::partition(
        refs.begin() + r.begin, refs.begin() + r.end,
        [&](const PrimRef& p) { return bin_of((p.c[best_axis] - lo) * sc) <= best_bin; });
    const uint32_t mid = uint32_t(mid_it - refs.begin());
    if (mid == r.begin || mid == r.end) {
      median_split(r, left, right);
      return true;
    }
    left = Range{r.begin, mid, {}, {}};
    right = Range{mid, r.end, {}, {}};
    for (int b = 0; b < nb; ++b) {
      Range& side = b <= best_bin ? left : right;
      side.box.extend(s.bins[best_axis][b].box);
      side.cbox.extend(s.bins[best_axis][b].cbox);
    }
    return true;
  }

  // Builds the subtree of r below nodes[node], appending its nodes depth
  // first: a node's two children next to each other, then the left child's
  // subtree, then the right child's.
  void build_serial(std::vector<BvhNode>& nodes, uint32_t node, const Range& r, int depth,
                    Scratch& s) const {
    nodes[node].lo = r.box.lo;
    nodes[node].hi = r.box.hi;
    Range left, right;
    if (!split(r, depth, s, left, right)) {
      nodes[node].index = r.begin;
      nodes[node].count = r.count();
      return;
    }
    const uint32_t first = uint32_t(nodes.size());
    nodes.emplace_back();
    nodes.emplace_back();
    nodes[node].index = first;
    nodes[node].count = 0;
    build_serial(nodes, first, left, depth + 1, s);
    build_serial(nodes, first + 1, right, depth + 1, s);
  }

  // The subtree of r in its own array (its root at 0), in build_serial's
  // order; large subtrees build their two halves in parallel and splice them.
  std::vector<BvhNode> build_subtree(const Range& r, int depth) const {
    std::vector<BvhNode> nodes(1);
    Scratch scratch(nb);
    if (r.count() < cfg.parallel_min_prims) {
      nodes.reserve(2 * size_t(r.count()));
      build_serial(nodes, 0, r, depth, scratch);
      return nodes;
    }
    nodes[0].lo = r.box.lo;
    nodes[0].hi = r.box.hi;
    Range left, right;
    if (!split(r, depth, scratch, left, right)) {
      nodes[0].index = r.begin;
      nodes[0].count = r.count();
      return nodes;
    }
    std::vector<BvhNode> a, b;
    tbb::parallel_invoke([&] { a = build_subtree(left, depth + 1); },
                         [&] { b = build_subtree(right, depth + 1); });
    // The serial order: root, both children, the left child's descendants,
    // the right child's. a[i] moves to i + 2 for i >= 1 (a[0] to 1), b[i] to
    // i + a.size() + 1 for i >= 1 (b[0] to 2); inner nodes' child indices
    // move with them.
    const uint32_t shift_a = 2, shift_b = uint32_t(a.size()) + 1;
    nodes.reserve(a.size() + b.size() + 1);
    nodes[0].index = 1;
    nodes[0].count = 0;
    auto moved = [](BvhNode n, uint32_t shift) {
      if (!n.is_leaf()) n.index += shift;
      return n;
    };
    nodes.push_back(moved(a[0], shift_a));
    nodes.push_back(moved(b[0], shift_b));
    for (size_t i = 1; i < a.size(); ++i) nodes.push_back(moved(a[i], shift_a));
    for (size_t i = 1; i < b.size(); ++i) nodes.push_back(moved(b[i], shift_b));
    return nodes;
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
  std::vector<PrimRef> refs(n);
  Range all{0, uint32_t(n), {}, {}};
  for (size_t i = 0; i < n; ++i) {
    refs[i] = PrimRef{bounds[i].lo, uint32_t(i), bounds[i].hi, centroids[i]};
    all.box.extend(bounds[i]);
    all.cbox.extend(centroids[i]);
  }
  const Builder b{refs, cfg, std::clamp(cfg.bins, 2, kMaxBins)};
  nodes = b.build_subtree(all, 0);
  nodes.shrink_to_fit();
  prim_indices.resize(n);
  for (size_t i = 0; i < n; ++i) prim_indices[i] = refs[i].id;
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
