// kD-tree (lecture: "Spatial data structures"): space cut by axis-aligned
// planes into cells, and the front-to-back walk with early termination. A
// primitive that straddles a plane is stored one of the lecture's two common
// ways (prim_storage.h):
//
// - PrimStorage::EveryCell ("store it multiple times", the default): in every
//   leaf cell its bounds overlap; inner nodes hold nothing; the walk orders
//   the two children by the plane and tests each primitive once per ray
//   (mailboxing).
// - PrimStorage::SmallestCell ("overlapping regions", a loose kD-tree): every
//   child cell is enlarged by loose_factor times its own extent on every side
//   (along the split axis the child's thickness, across it the parent's
//   extent, so a child's loose box always lies in its parent's), and each
//   primitive is stored once: in a child whose loose box holds its bounds
//   (the one on its center's side when both do), else in the inner node's own
//   list. The walk tests an inner node's list when it enters the node and
//   visits the children whose loose boxes the ray hits nearest entry first
//   (the octree's loose walk, cell_walk.h: the boxes overlap, the plane no
//   longer orders them).
// - PrimStorage::Split is the BSP tree's: build_accel() refuses it here.
//
// Like the BVH builder (bvh.h), the builder knows nothing about geometry: it
// takes one bounding box per primitive and a KdTreeBuildConfig. Primitives are
// named by their index in that span; the leaves hold lists of those indices
// (references), so a primitive that straddles a split plane appears in several
// leaves. The walk tests it once per ray all the same (mailboxing, see
// traverse()). Range queries (range_query.h) walk the same cells
// (walk_range()), mailboxed too.
#pragma once

#include <bit>
#include <cassert>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rayscope/accel/accel_structure.h"
#include "rayscope/accel/cell_walk.h"
#include "rayscope/accel/mailbox.h"
#include "rayscope/accel/prim_storage.h"
#include "rayscope/intersect.h"
#include "rayscope/math.h"
#include "rayscope/ray.h"
#include "rayscope/traversal.h"

namespace rayscope {

/// One node of the flattened tree, 8 bytes. An inner node holds its split
/// plane (axis and position); the child below the plane is the next node, the
/// child above it is at above(). A leaf holds the offset of its first
/// reference in KdTree::refs and how many there are.
struct KdNode {
  /// The axis value that marks a leaf.
  static constexpr uint32_t kLeafAxis = 3;
  /// Most children (node index) or references per leaf that fit in `bits`.
  static constexpr uint32_t kMaxIndex = (1u << 30) - 1;

  uint32_t payload;  ///< Inner: the split position's bits. Leaf: first reference.
  uint32_t bits;     ///< Low 2 bits: axis 0..2, or kLeafAxis. High 30: above() or count().

  bool is_leaf() const { return (bits & 3u) == kLeafAxis; }
  int axis() const { return int(bits & 3u); }
  float split() const { return std::bit_cast<float>(payload); }
  uint32_t above() const { return bits >> 2; }
  uint32_t first() const { return payload; }
  uint32_t count() const { return bits >> 2; }
};
static_assert(sizeof(KdNode) == 8);

/// How the builder chooses a node's split plane.
enum class KdSplitRule : uint8_t {
  /// Surface area heuristic over every candidate plane at a primitive bound's
  /// edge inside the cell (the default).
  Sah,
  /// The middle of the cell's longest axis (spatial median): the plain
  /// subdivision the SAH is measured against.
  Median,
  /// The lecture's rule: the axes take turns with the depth (x at the root,
  /// then y, then z, ...) and the plane lies at the median of the cell's
  /// primitives' centers along that axis (an object median), so each side
  /// gets about half of them. Where that median is not strictly inside the
  /// cell (most centers on one coordinate), the next axes in turn are tried.
  AlternatingMedian,
};

/// "sah", "median", "alternating-median".
const char* to_string(KdSplitRule rule);
/// Parses the names to_string() gives; false for anything else.
bool parse_kd_split_rule(std::string_view name, KdSplitRule& rule);

/// Settings of the kD-tree builder, with the defaults used by RayScope.
struct KdTreeBuildConfig {
  KdSplitRule rule = KdSplitRule::Sah;
  float traversal_cost = 1.0f;     ///< SAH cost of stepping through an inner node...
  float intersection_cost = 1.5f;  ///< ...relative to one primitive test.
  /// The SAH cost of a split that leaves one side empty is multiplied by
  /// (1 - empty_bonus): cutting off empty space pays, because rays cross it
  /// without testing anything.
  float empty_bonus = 0.5f;
  /// Deepest leaf level (root = 0). 0: automatic, round(8 + 1.3 log2 n) for n
  /// primitives (pbrt's rule of thumb). Always capped at KdTree::kMaxDepth.
  int max_depth = 0;
  /// Cells with at most this many primitives become leaves when the SAH says a
  /// split would not pay (a median split stops there); bigger ones are split
  /// anyway, up to KdTree::kMaxBadRefines times on one path.
  uint32_t max_leaf_size = 4;
  // How a primitive that straddles a plane is stored, and the loose factor,
  // are build()'s arguments (AccelConfig::storage and ::loose_factor).
  //
  // SmallestCell's split choice: the SAH (or median) plane is chosen with
  // the loose children. For a candidate plane the cost is
  //   traversal + intersection * (straddlers + P_below * below + P_above * above)
  // where below / above count the primitives whose bounds fit that child's
  // loose box (along the split axis; one fitting both is counted on both
  // sides, a slight overestimate), straddlers the rest, which stay in the
  // inner node and cost a test on every visit (probability 1), and P is a
  // child's loose box's surface area over the node's loose box's. No
  // empty-side bonus: a plane with every primitive on one side cuts off
  // hardly any space once the children are loose.
};

/// Quality figures of a built tree (see KdTree::quality()).
struct KdTreeQuality {
  uint32_t nodes = 0, leaves = 0, empty_leaves = 0, depth = 0;
  uint32_t max_leaf_refs = 0;
  double mean_leaf_refs = 0.0;  ///< Over the non-empty leaves.
  size_t references = 0;        ///< Primitive references in all nodes.
  /// References held by inner nodes (SmallestCell: primitives that fit no
  /// child's loose box; always 0 for EveryCell).
  size_t inner_refs = 0;
  double refs_per_prim = 0.0;  ///< references / primitives: how often one is stored.
  /// Expected cost of a random ray hitting the root cell, with the build's
  /// cost constants (cell areas relative to the root's).
  double sah_cost = 0.0;
  size_t memory_bytes = 0;  ///< Nodes and reference lists.
  double build_seconds = 0.0;
};

class KdTree {
 public:
  /// The deepest tree the walk's fixed stack can hold (one entry per level).
  static constexpr int kMaxDepth = 64;
  /// SAH splits that do not pay, allowed on one root-to-leaf path for cells
  /// bigger than max_leaf_size (a bad split is often followed by good ones).
  static constexpr int kMaxBadRefines = 3;
  /// The builder stops splitting (makes leaves) once the tree holds this many
  /// references per primitive: a guard against explosive duplication by
  /// primitives that straddle every plane (mostly for median splits).
  static constexpr size_t kMaxReferencesPerPrim = 32;

  /// Builds the tree over bounds.size() primitives (finite bounds; zero-size
  /// boxes are fine), storing a primitive that straddles a plane the
  /// `storage` way: EveryCell or SmallestCell, whose cells are enlarged by
  /// `loose_factor` times their extent on every side (the fraction of the
  /// cell's extent on that axis). An empty input gives an empty tree that
  /// every ray misses. Throws std::length_error if the tree would not fit
  /// KdNode's indices.
  ///
  /// Precondition (asserted): storage is not Split and loose_factor_error()
  /// accepts loose_factor. build_accel() (accel_build.h) checks both for
  /// AccelConfig and refuses a bad one with a message.
  void build(std::span<const Bounds3> bounds, const KdTreeBuildConfig& config = {},
             PrimStorage storage = PrimStorage::EveryCell,
             float loose_factor = kDefaultLooseFactor);

  bool empty() const { return nodes.empty(); }
  /// The root cell: the bounds of all primitives.
  Bounds3 bounds() const { return bounds_; }
  /// The depth limit the build used (config.max_depth resolved).
  int max_depth() const { return max_depth_; }
  KdTreeQuality quality() const;
  /// The AccelStructure interface (accel_structure.h): figures, teaching
  /// view (refs: the indices build() was given), the --stats line and the
  /// ray-tree legend of the walk.
  AccelFigures figures() const;
  AccelView view() const;
  std::string stats_line() const;
  std::string walk_legend() const;
  size_t memory_bytes() const {
    return nodes.size() * sizeof(KdNode) + (refs.size() + offsets.size()) * sizeof(uint32_t);
  }
  /// Whether the cells are loose (PrimStorage::SmallestCell).
  bool loose() const { return loose_; }
  /// How the tree stores straddlers: EveryCell or SmallestCell.
  PrimStorage storage() const {
    return loose_ ? PrimStorage::SmallestCell : PrimStorage::EveryCell;
  }
  /// The box the walks test for a node of cell `cell`: the cell itself, or its
  /// loose box (SmallestCell).
  Bounds3 node_box(const Bounds3& cell) const {
    return loose_ ? loose_box(cell, loose_factor_) : cell;
  }
  /// The primitives node `node` holds: a leaf's list, or (SmallestCell) an
  /// inner node's straddlers.
  std::span<const uint32_t> node_refs(uint32_t node) const {
    if (loose_) return {refs.data() + offsets[node], offsets[node + 1] - offsets[node]};
    if (!nodes[node].is_leaf()) return {};
    return {refs.data() + nodes[node].first(), nodes[node].count()};
  }
  /// The (tight) cell of every node, by node index (for tests and drawings).
  std::vector<Bounds3> cells() const;

  /// Walks the cells the ray [origin, origin + tmax * dir] crosses, nearest
  /// first. `prim(index, tmax)` tests primitive `index` and returns true on a
  /// hit, lowering tmax to the hit distance (closest hit) or ending the walk
  /// (AnyHit). Returns whether anything was hit.
  ///
  /// - Order: in an inner node the child on the ray origin's side of the plane
  ///   (by the direction's sign when the origin lies on it) is visited first;
  ///   the other is pushed when the ray's interval in the cell reaches the
  ///   plane (with the margin kBoxFarScale), and for a ray lying in the plane.
  ///   The stack has kMaxDepth entries: one per level at most.
  /// - Early termination: a pushed cell is popped only if it starts before the
  ///   closest hit so far, that is, the walk stops once the hit lies within
  ///   the cells visited. A primitive stored in several cells can be hit
  ///   beyond the cell it was tested in; that hit is kept (it may still be the
  ///   closest) and the walk goes on until a cell holding it is reached.
  ///   Distances are compared with the margin kBoxFarScale, as the BVH's box
  ///   test does, so that rounding never skips a cell the ray touches.
  /// - Mailboxing (mailbox.h): each primitive is tested at most once per ray,
  ///   however many of the leaves visited hold it.
  ///
  /// Observer hooks (traversal.h), with the kD-tree's node ids (index in
  /// nodes): on_box_test(0, hit) for the root cell's box; on_node(id) for every
  /// node entered (inner or leaf); for every inner node entered, the split
  /// plane decides which child cells the ray reaches, reported as
  /// on_box_test(child, reached) for both children (like the binary BVH's two
  /// child boxes); on_cull(id) for a pushed cell skipped by early
  /// termination. Primitive tests are the caller's (`prim`), after the
  /// mailbox: a primitive is reported at most once per ray.
  ///
  template <bool AnyHit, class Observer, class PrimFn>
  bool traverse(const Ray& ray, float& tmax, PrimFn&& prim, Observer& obs) const;

  /// The lecture's range-query algorithm (range_query.h) on the cells: from
  /// the root cell, a cell the range overlaps is entered; a leaf's references
  /// are passed to `prim(index)` (index in the span build() was given), each
  /// primitive at most once per query however many leaves hold it
  /// (mailboxing); an inner node's two child cells (its cell cut at the split
  /// plane) are tested, and those that overlap visited nearer first by
  /// range.distance() (ties: below first), the farther pushed with its cell.
  /// A pushed cell is entered only if the range still overlaps it when it is
  /// popped (a k-nearest range shrinks while it is walked); else it is culled.
  ///
  /// Observer hooks (traversal.h), with the kD-tree's node ids: on_box_test(0,
  /// hit) for the root cell; on_node(id) for every node entered (inner or
  /// leaf); on_box_test(child, overlaps) for both child cells of an inner node
  /// entered; on_cull(id) for a pushed cell the range no longer overlaps when
  /// it is popped. Primitive tests are the caller's (`prim`), after the
  /// mailbox. SmallestCell: walk_cells_range() (cell_walk.h) over the loose
  /// boxes: every node entered, inner ones too, reports its own list; no
  /// mailbox; children nearer first.
  template <class Range, class Observer, class PrimFn>
  void walk_range(Range& range, PrimFn&& prim, Observer& obs) const;

  std::vector<KdNode> nodes;   ///< nodes[0] is the root.
  std::vector<uint32_t> refs;  ///< Reference lists of the nodes: primitive indices.
  /// SmallestCell only (else empty): node i holds refs[offsets[i] ..
  /// offsets[i + 1]) (inner nodes and leaves alike; nodes are numbered in the
  /// order their lists are written).
  std::vector<uint32_t> offsets;
  KdTreeBuildConfig config;

 private:
  /// emit(child, cell) for the two children of inner node `node` of cell
  /// `cell`, below first.
  template <class Emit>
  void for_children(uint32_t node, const Bounds3& cell, Emit&& emit) const {
    const KdNode& n = nodes[node];
    if (n.is_leaf()) return;
    Bounds3 below = cell, above = cell;
    below.hi[n.axis()] = above.lo[n.axis()] = n.split();
    emit(node + 1, below);
    emit(n.above(), above);
  }

  Bounds3 bounds_;
  uint32_t num_prims_ = 0;
  int max_depth_ = 0;
  bool loose_ = false;
  float loose_factor_ = 0.0f;
  double build_seconds_ = 0.0;
};

// ---------------------------------------------------------------------------

template <bool AnyHit, class Observer, class PrimFn>
bool KdTree::traverse(const Ray& ray, float& tmax, PrimFn&& prim, Observer& obs) const {
  if (nodes.empty()) return false;
  if (loose_)
    return walk_cells<AnyHit, 2, kMaxDepth + 1>(
        ray, tmax, bounds_, true, nullptr, [&](const Bounds3& cell) { return node_box(cell); },
        [&](uint32_t node) { return node_refs(node); },
        [&](uint32_t node, const Bounds3& cell, auto&& emit) { for_children(node, cell, emit); },
        prim, obs);
  const Vec3 inv_dir = 1.0f / ray.dir;
  // The ray's interval [t0, t1] in the current cell, first the root's.
  float t0, t1;
  box_interval(bounds_.lo, bounds_.hi, ray.origin, inv_dir, tmax, t0, t1);
  const bool root_hit = t0 <= t1;
  if constexpr (Observer::kActive) obs.on_box_test(0, root_hit);
  if (!root_hit) return false;

  MailboxQuery mailbox(num_prims_);
  struct Entry {
    uint32_t node;
    float t0, t1;
  };
  Entry stack[kMaxDepth];
  int sp = 0;
  uint32_t node = 0;
  bool hit = false;
  for (;;) {
    if constexpr (Observer::kActive) obs.on_node(node);
    const KdNode& n = nodes[node];
    if (!n.is_leaf()) {
      const int axis = n.axis();
      const float split = n.split();
      const float o = ray.origin[axis];
      // The origin's side first; on the plane, the side the ray heads to
      // (below first for a ray lying in the plane).
      const bool below_first = o < split || (o == split && !(ray.dir[axis] > 0.0f));
      const uint32_t near = below_first ? node + 1 : n.above();
      const uint32_t far = below_first ? n.above() : node + 1;
      // Where the ray crosses the plane; negative: it stays on the near side.
      // A ray starting on the plane leaves it into the near side (it never
      // reaches the far one), unless it lies in the plane: then what touches
      // the plane from either side may be hit, and both children are walked
      // over the whole interval.
      const float ts = (split - o) * inv_dir[axis];
      bool go_near = true, go_far = false;
      float t_far = t0, t_near = t1;  // the far child's entry, the near child's exit
      if (o == split) {
        go_far = ray.dir[axis] == 0.0f;
      } else if (ts >= 0.0f) {
        go_near = ts * kBoxFarScale >= t0;
        go_far = ts <= std::min(t1, tmax) * kBoxFarScale;
        t_far = std::max(ts, t0);
        t_near = std::min(ts, t1);
      }
      if constexpr (Observer::kActive) {
        obs.on_box_test(near, go_near);
        obs.on_box_test(far, go_far);
      }
      if (go_near) {
        if (go_far) {
          assert(sp < kMaxDepth);
          stack[sp++] = {far, t_far, t1};
          t1 = t_near;
        }
        node = near;
      } else {
        t0 = t_far;
        node = far;
      }
      continue;
    }
    const uint32_t* r = refs.data() + n.first();
    for (const uint32_t* end = r + n.count(); r != end; ++r) {
      if (!mailbox.first_visit(*r)) continue;
      if (prim(*r, tmax)) {
        hit = true;
        if constexpr (AnyHit) return true;
      }
    }
    // Pop the next cell that can still hold a closer hit.
    for (;;) {
      if (sp == 0) return hit;
      const Entry& e = stack[--sp];
      if (e.t0 <= tmax * kBoxFarScale) {
        node = e.node;
        t0 = e.t0;
        t1 = e.t1;
        break;
      }
      if constexpr (Observer::kActive) obs.on_cull(e.node);
    }
  }
}

template <class Range, class Observer, class PrimFn>
void KdTree::walk_range(Range& range, PrimFn&& prim, Observer& obs) const {
  if (nodes.empty()) return;
  if (loose_)
    return walk_cells_range<2, kMaxDepth + 1>(
        range, bounds_, nullptr, [&](const Bounds3& cell) { return node_box(cell); },
        [&](uint32_t node) { return node_refs(node); },
        [&](uint32_t node, const Bounds3& cell, auto&& emit) { for_children(node, cell, emit); },
        prim, obs);
  const bool root_overlaps = range.overlaps(bounds_);
  if constexpr (Observer::kActive) obs.on_box_test(0, root_overlaps);
  if (!root_overlaps) return;
  MailboxQuery mailbox(num_prims_);
  struct Entry {
    uint32_t node;
    Bounds3 cell;
  };
  Entry stack[kMaxDepth];
  int sp = 0;
  uint32_t node = 0;
  Bounds3 cell = bounds_;
  for (;;) {
    if constexpr (Observer::kActive) obs.on_node(node);
    const KdNode& n = nodes[node];
    if (!n.is_leaf()) {
      Bounds3 below = cell, above = cell;
      below.hi[n.axis()] = above.lo[n.axis()] = n.split();
      const uint32_t below_node = node + 1, above_node = n.above();
      const bool ob = range.overlaps(below), oa = range.overlaps(above);
      if constexpr (Observer::kActive) {
        obs.on_box_test(below_node, ob);
        obs.on_box_test(above_node, oa);
      }
      if (ob && oa) {
        const bool above_first = range.distance(above) < range.distance(below);
        assert(sp < kMaxDepth);
        stack[sp++] = above_first ? Entry{below_node, below} : Entry{above_node, above};
        node = above_first ? above_node : below_node;
        cell = above_first ? above : below;
        continue;
      }
      if (ob || oa) {
        node = ob ? below_node : above_node;
        cell = ob ? below : above;
        continue;
      }
    } else {
      const uint32_t* r = refs.data() + n.first();
      for (const uint32_t* end = r + n.count(); r != end; ++r)
        if (mailbox.first_visit(*r)) prim(*r);
    }
    // Pop the next cell the range still overlaps.
    for (;;) {
      if (sp == 0) return;
      const Entry& e = stack[--sp];
      if (range.overlaps(e.cell)) {
        node = e.node;
        cell = e.cell;
        break;
      }
      if constexpr (Observer::kActive) obs.on_cull(e.node);
    }
  }
}

}  // namespace rayscope
