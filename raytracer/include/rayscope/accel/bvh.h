// Bounding volume hierarchy (lecture: "Spatial data structures"): the binned
// SAH builder and the binary tree it makes.
//
// The builder knows nothing about geometry: it takes one bounding box and one
// centroid per primitive and returns a flat array of 32-byte nodes plus the
// permutation of primitive indices the leaves refer to. This binary tree is the
// hierarchy RayScope builds, measures (quality()) and shows: its node ids are
// the ones every walk reports to observers and the VTK sources draw. Rays walk
// it through WideBvh (wide_bvh.h), which collapses it into nodes of up to eight
// children for rendering, or of exactly two for the teaching walk.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "rayscope/accel/accel_view.h"
#include "rayscope/accel/binary_range_walk.h"
#include "rayscope/intersect.h"
#include "rayscope/math.h"
#include "rayscope/ray.h"

namespace rayscope {

/// One node of the flattened hierarchy. Inner nodes (count == 0) store the index
/// of their first child; the second child follows it. Leaves store the offset of
/// their first primitive in Bvh::prim_indices and how many there are.
struct BvhNode {
  Vec3 lo;
  uint32_t index;
  Vec3 hi;
  uint32_t count;

  bool is_leaf() const { return count != 0; }
  Bounds3 bounds() const {
    Bounds3 b;
    b.lo = lo;
    b.hi = hi;
    return b;
  }
};
static_assert(sizeof(BvhNode) == 32);

/// Settings of the binned SAH builder, with the defaults used by RayScope.
struct BvhBuildConfig {
  int bins = 16;                ///< Candidate split planes per axis are bins - 1.
  uint32_t max_leaf_size = 8;   ///< Leaves never hold more primitives than this...
  uint32_t min_leaf_size = 1;   ///< ...nor fewer, unless the node is that small.
  float traversal_cost = 1.0f;  ///< SAH cost of visiting an inner node...
  /// ...relative to one primitive test. 0.5, not 1: the render walk tests a
  /// leaf's triangles four at a time (triangle_block.h). Its leaves of about
  /// 2.8 triangles (1.9 at 1) traced bunny rays 13% (primary) and 7% (shadow)
  /// faster than at 1, and 7% and 5% faster than at 0.3 (4.8 per leaf), same
  /// runs (bench_trace --leaf-cost, docs/performance.md).
  float intersection_cost = 0.5f;
  int max_depth = 56;  ///< Deeper nodes are split at the object median.
  /// Subtrees of at least this many primitives are built as parallel tasks
  /// (TBB), each task's subtree then placed in the serial order: the tree is
  /// the same for every value and thread count (~0u: one task).
  uint32_t parallel_min_prims = 4096;
  /// The instructions that bin and bound the boxes: every choice builds the
  /// same tree, bit for bit (the tests compare them). Best: the widest of the
  /// level the hot loops run with (kernels.h: AVX for avx2 and avx512, else
  /// SSE2); Sse: SSE2; Scalar: none, as on a CPU without SIMD.
  enum class Simd { Best, Sse, Scalar } simd = Simd::Best;
};

/// Quality figures of a built hierarchy (see Bvh::quality()).
struct BvhQuality {
  uint32_t nodes = 0, leaves = 0, depth = 0;
  uint32_t min_leaf_prims = 0, max_leaf_prims = 0;
  double mean_leaf_prims = 0.0;
  double sah_cost = 0.0;  ///< Expected cost of a random ray, with the build's cost constants.
  /// The same with a primitive test costing as much as a node visit (1:1):
  /// comparable between trees built with different constants.
  double sah_cost_1to1 = 0.0;
  size_t memory_bytes = 0;
};

class Bvh {
 public:
  /// Builds the hierarchy. bounds.size() == centroids.size() primitives; an
  /// empty input gives an empty hierarchy that every ray misses.
  void build(std::span<const Bounds3> bounds, std::span<const Vec3> centroids,
             const BvhBuildConfig& config = {});

  bool empty() const { return nodes.empty(); }
  Bounds3 bounds() const { return empty() ? Bounds3() : nodes[0].bounds(); }
  BvhQuality quality() const;
  /// The teaching view (accel_view.h): every node, refs naming positions in
  /// leaf order (prim_indices).
  AccelView view() const;

  /// Entries of walk_range()'s stack: one per level at most (the builder
  /// keeps every leaf within 64 levels of the root).
  static constexpr int kRangeStackSize = 64;

  /// The lecture's range-query algorithm (range_query.h) on the binary tree:
  /// from the root, a node whose box the range overlaps is entered; a leaf's
  /// primitives are passed to `prim(i)`, i being their position in leaf order
  /// (prim_indices[i] is the primitive), each exactly once; an inner node's
  /// two child boxes are tested, and the children that overlap are visited
  /// nearer first by range.distance() (ties: the binary tree's order), the
  /// farther pushed. A pushed node is entered only if the range still overlaps
  /// its box when it is popped (a k-nearest range shrinks while it is walked);
  /// else it is culled. Nothing else is pruned: every primitive of every leaf
  /// whose box overlaps the range is passed.
  ///
  /// Observer hooks (traversal.h), with Bvh::nodes ids: on_box_test(0, hit) for
  /// the root's box; on_node(id) for every node entered (inner or leaf);
  /// on_box_test(child, overlaps) for both child boxes of an inner node
  /// entered; on_cull(id) for a pushed node the range no longer overlaps when
  /// it is popped. Primitive tests are the caller's (`prim`).
  template <class Range, class Observer, class PrimFn>
  void walk_range(Range& range, PrimFn&& prim, Observer& obs) const;

  std::vector<BvhNode> nodes;          ///< nodes[0] is the root.
  std::vector<uint32_t> prim_indices;  ///< Leaf order -> primitive index.
  BvhBuildConfig config;
};

// ---------------------------------------------------------------------------

template <class Range, class Observer, class PrimFn>
void Bvh::walk_range(Range& range, PrimFn&& prim, Observer& obs) const {
  walk_binary_range<kRangeStackSize>(
      nodes, [](const BvhNode& n) { return n.bounds(); }, range, prim, obs);
}

}  // namespace rayscope
