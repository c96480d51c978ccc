// Octree (lecture: "Quadtrees / Octrees: divide into 8 cubes"): a cube around
// the scene, cut into 8 equal octants, each cut again while it holds too many
// primitives. An extended primitive that straddles a cut is stored one of the
// lecture's two common ways (prim_storage.h):
//
// - PrimStorage::EveryCell ("store multiple times"): a reference in every leaf
//   cell its bounds overlap; inner nodes hold nothing. The walk tests each
//   primitive once per ray all the same (mailbox.h). Cells need no stored box:
//   the walk halves its parent's.
// - PrimStorage::SmallestCell ("overlapping regions", the loose octree): every
//   cell's box is enlarged by loose_factor times the cell's size on each side
//   (the lecture's 10%: 1.2^3 = 1.73x the volume), and each primitive is stored
//   exactly once, in the deepest cell whose loose box holds its bounds. One
//   that fits no child stays in the inner node, so inner nodes hold primitives
//   too. Loose boxes of neighbors overlap: the walk visits the children a ray
//   hits nearest entry first and skips those whose entry lies beyond the
//   closest hit so far.
// - PrimStorage::Split is the BSP tree's (not the octree's): build_accel()
//   refuses it here.
//
// Like the BVH and kD-tree builders, the builder knows nothing about geometry:
// it takes one bounding box per primitive and an OctreeBuildConfig, and names
// primitives by their index in that span.
#pragma once

#include <bit>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
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

/// One node of the flattened tree, 16 bytes. Octant o of a cell is its upper
/// half in x if bit 0 of o is set, in y for bit 1, in z for bit 2. Only the
/// octants that hold something have a child node; the children of a node are
/// consecutive, in octant order, from first_child. Any node (inner nodes of a
/// loose octree too) may hold references: refs[first .. first + count).
struct OctNode {
  uint32_t first_child = 0;  ///< The child of the lowest octant in mask.
  uint32_t first = 0;        ///< First reference in Octree::refs.
  uint32_t count = 0;        ///< References held by this node.
  uint8_t mask = 0;          ///< Bit o: octant o has a child. 0: a leaf.
  uint8_t pad[3] = {};

  bool is_leaf() const { return mask == 0; }
  bool has_child(int octant) const { return (mask >> octant) & 1u; }
  /// The node index of octant `octant`'s child (has_child(octant) must hold).
  uint32_t child(int octant) const {
    return first_child + uint32_t(std::popcount(unsigned(mask) & ((1u << octant) - 1u)));
  }
};
static_assert(sizeof(OctNode) == 16);

/// Settings of the octree builder, with the defaults used by RayScope.
struct OctreeBuildConfig {
  /// Deepest level (root = 0), capped at Octree::kMaxDepth. A level-10 cell is
  /// 1/1024 of the root cube's side. 10 rather than 12: on the bunny scene
  /// (data/scenes/bunny.json, one sample per pixel) every-cell storage tests
  /// exactly as many nodes, boxes and primitives per ray at 10 as at 12 (3.05,
  /// 11.67, 1.66) with 9.7 instead of 10.8 references per primitive (5.20
  /// against 5.67 MiB); 8 halves the memory (3.02 MiB) for 7% more primitive
  /// tests (1.77). Smallest-cell stops at depth 8 there by itself.
  int max_depth = 10;
  /// A cell holding more primitives than this is cut into octants (until
  /// max_depth).
  uint32_t max_leaf_size = 8;
};

/// Quality figures of a built tree (see Octree::quality()).
struct OctreeQuality {
  uint32_t nodes = 0, leaves = 0;
  /// Octants of inner nodes that hold nothing, so get no node (no memory, no
  /// box test): the empty leaves of the full 8-way subdivision.
  uint32_t empty_leaves = 0;
  uint32_t depth = 0;
  size_t references = 0;       ///< Primitive references in all nodes.
  double refs_per_prim = 0.0;  ///< references / primitives: how often one is stored.
  /// References held by inner nodes (SmallestCell: primitives that fit no
  /// child; always 0 for EveryCell).
  size_t inner_refs = 0;
  uint32_t max_leaf_refs = 0;
  double mean_leaf_refs = 0.0;  ///< Over the leaves.
  size_t memory_bytes = 0;      ///< Nodes and reference lists.
  double build_seconds = 0.0;
};

class Octree {
 public:
  /// The deepest level the walk's fixed stack can hold; below it a float cell
  /// would be too small to halve anyway (24-bit mantissa).
  static constexpr int kMaxDepth = 24;
  /// The walks' fixed stack: entering a node pushes at most 8 children and
  /// pops one, so at most 7 siblings wait per level, plus the deepest's 8th.
  static constexpr int kStackSize = 7 * kMaxDepth + 1;
  /// The builder stops cutting (makes leaves) once the tree holds this many
  /// references per primitive (EveryCell): a guard against primitives that
  /// straddle every cut.
  static constexpr size_t kMaxReferencesPerPrim = 32;

  /// Builds the tree over bounds.size() primitives (finite bounds; zero-size
  /// boxes are fine). The root cell is the cube centered on the bounds of all
  /// primitives, with their largest extent as its side (grown by rounding so
  /// that it holds them all). A primitive that straddles a cut is stored the
  /// `storage` way: EveryCell or SmallestCell, whose cells' boxes are
  /// enlarged by `loose_factor` times their side on every side (0.1, the
  /// lecture's 10%, makes a loose cell 1.2 times the side, 1.2^3 = 1.73 times
  /// the volume; 0 is a plain octree where a primitive that straddles a cut
  /// stays above it). An empty input gives an empty tree that every ray
  /// misses. Throws std::length_error for more than 2^32 - 1 primitives or
  /// references.
  ///
  /// Precondition (asserted): storage is not Split and loose_factor_error()
  /// accepts loose_factor. build_accel() (accel_build.h) checks both for
  /// AccelConfig and refuses a bad one with a message.
  void build(std::span<const Bounds3> bounds, const OctreeBuildConfig& config = {},
             PrimStorage storage = PrimStorage::EveryCell,
             float loose_factor = kDefaultLooseFactor);

  bool empty() const { return nodes.empty(); }
  /// The root cell (a cube, up to rounding).
  Bounds3 bounds() const { return bounds_; }
  /// Whether the cells are loose (PrimStorage::SmallestCell).
  bool loose() const { return loose_; }
  /// How the tree stores straddlers: EveryCell or SmallestCell.
  PrimStorage storage() const {
    return loose_ ? PrimStorage::SmallestCell : PrimStorage::EveryCell;
  }
  int max_depth() const { return max_depth_; }
  OctreeQuality quality() const;
  /// The AccelStructure interface (accel_structure.h): figures, teaching
  /// view (refs: the indices build() was given), the --stats line and the
  /// ray-tree legend of the walk.
  AccelFigures figures() const;
  AccelView view() const;
  std::string stats_line() const;
  std::string walk_legend() const;
  size_t memory_bytes() const {
    return nodes.size() * sizeof(OctNode) + refs.size() * sizeof(uint32_t);
  }

  /// Octant `octant` of `cell`: its halves meet at the midpoint. The build and
  /// the walks compute cells only this way, so they agree bit for bit.
  static Bounds3 octant_cell(const Bounds3& cell, int octant) {
    const Vec3 mid = 0.5f * cell.lo + 0.5f * cell.hi;
    Bounds3 c;
    for (int a = 0; a < 3; ++a) {
      const bool upper = (octant >> a) & 1;
      c.lo[a] = upper ? mid[a] : cell.lo[a];
      c.hi[a] = upper ? cell.hi[a] : mid[a];
    }
    return c;
  }
  /// `cell` enlarged by `factor` times its extent on every side (loose_box()).
  static Bounds3 enlarge(const Bounds3& cell, float factor) { return loose_box(cell, factor); }
  /// The box the walks test for a node of cell `cell`: the cell itself, or its
  /// loose box (SmallestCell).
  Bounds3 node_box(const Bounds3& cell) const {
    return loose_ ? loose_box(cell, loose_factor_) : cell;
  }
  /// The primitives node `node` holds (inner nodes too, in a loose octree).
  std::span<const uint32_t> node_refs(uint32_t node) const {
    return {refs.data() + nodes[node].first, nodes[node].count};
  }
  /// The cell of every node, by node index (for tests and drawings).
  std::vector<Bounds3> cells() const;
  /// The depth of every node, by node index (root: 0).
  std::vector<uint32_t> depths() const;

  /// Walks the nodes whose box the ray [origin, origin + tmax * dir] crosses,
  /// nearest first, with exactly KdTree::traverse's contract: `prim(index,
  /// tmax)` tests primitive `index` and returns true on a hit, lowering tmax to
  /// the hit distance (closest hit) or ending the walk (AnyHit). Returns
  /// whether anything was hit.
  ///
  /// - A node entered tests its own references first (inner nodes hold some in
  ///   a loose octree), then the boxes of its children; those the ray hits are
  ///   pushed so that the nearest is entered next: for tight cells in the
  ///   ray's octant order (octant o ^ the direction's sign bits: a cell the ray
  ///   enters earlier always comes first), for loose boxes, which overlap,
  ///   sorted by entry distance. A fixed stack of kStackSize entries.
  /// - Early termination: a pushed node is entered only if its box's entry
  ///   distance is within the closest hit so far (with the margin
  ///   kBoxFarScale, as the BVH's box test, so that rounding never skips a node
  ///   the ray touches); once a hit lies before every node waiting, the walk
  ///   ends.
  /// - EveryCell: a primitive stored in several leaves is tested at most once
  ///   per ray (mailbox.h). SmallestCell stores each once: no mailbox.
  ///
  /// Observer hooks (traversal.h), node ids = index in nodes, root 0:
  /// on_box_test(0, hit) for the root's box; on_node(id) for every node
  /// entered; on_box_test(child, hit) for every child box tested (empty
  /// octants have no node and are not tested); on_cull(id) for a pushed node
  /// skipped by early termination. Primitive tests are the caller's (`prim`),
  /// after the mailbox.
  ///
  template <bool AnyHit, class Observer, class PrimFn>
  bool traverse(const Ray& ray, float& tmax, PrimFn&& prim, Observer& obs) const;

  /// The lecture's range query: from the root, wherever `range` overlaps a
  /// node's box (loose box for SmallestCell), report the node's primitives
  /// with `prim(index)` and go on into its children, nearer ones first;
  /// elsewhere stop. `Range` provides `bool overlaps(const Bounds3&) const`
  /// and `float distance(const Bounds3&) const` (a lower bound of the
  /// distance from the range's center to the box). The range may shrink
  /// between calls (k nearest neighbors): a pushed node is checked again when
  /// popped and skipped (on_cull) if the range no longer overlaps it. Each
  /// primitive is reported at most once (mailboxed for EveryCell); the caller
  /// tests the primitives themselves. Observer: on_box_test for the root's and
  /// every child's box tested, on_node for every node entered, on_cull.
  template <class Range, class Observer, class PrimFn>
  void walk_range(Range& range, PrimFn&& prim, Observer& obs) const;

  std::vector<OctNode> nodes;  ///< nodes[0] is the root.
  std::vector<uint32_t> refs;  ///< Reference lists of the nodes: primitive indices.
  OctreeBuildConfig config;

 private:
  /// emit(child, cell) for the children of `node` (of cell `cell`), octant
  /// first_octant ^ i for i = 0..7.
  template <class Emit>
  void for_children(uint32_t node, const Bounds3& cell, int first_octant, Emit&& emit) const;

  Bounds3 bounds_;
  uint32_t num_prims_ = 0;
  int max_depth_ = 0;
  bool loose_ = false;
  float loose_factor_ = 0.0f;
  double build_seconds_ = 0.0;
};

// ---------------------------------------------------------------------------

template <class Emit>
void Octree::for_children(uint32_t node, const Bounds3& cell, int first_octant, Emit&& emit) const {
  const OctNode& n = nodes[node];
  for (int i = 0; i < 8; ++i) {
    const int o = i ^ first_octant;
    if (n.has_child(o)) emit(n.child(o), octant_cell(cell, o));
  }
}

template <bool AnyHit, class Observer, class PrimFn>
bool Octree::traverse(const Ray& ray, float& tmax, PrimFn&& prim, Observer& obs) const {
  if (nodes.empty()) return false;
  // The loose octree stores every primitive once: no mailbox.
  MailboxQuery mailbox(loose_ ? 0u : num_prims_);
  // The ray's octant: visiting octants o ^ dir_octant for o = 0..7 meets the
  // cells a ray crosses in the order it crosses them (loose boxes, which
  // overlap, are sorted by entry distance instead).
  const int dir_octant = int(std::signbit(ray.dir.x)) | int(std::signbit(ray.dir.y)) << 1 |
                         int(std::signbit(ray.dir.z)) << 2;
  return walk_cells<AnyHit, 8, kStackSize>(
      ray, tmax, bounds_, loose_, loose_ ? nullptr : &mailbox,
      [&](const Bounds3& cell) { return node_box(cell); },
      [&](uint32_t node) { return node_refs(node); },
      [&](uint32_t node, const Bounds3& cell, auto&& emit) {
        for_children(node, cell, dir_octant, emit);
      },
      prim, obs);
}

template <class Range, class Observer, class PrimFn>
void Octree::walk_range(Range& range, PrimFn&& prim, Observer& obs) const {
  if (nodes.empty()) return;
  MailboxQuery mailbox(loose_ ? 0u : num_prims_);
  walk_cells_range<8, kStackSize>(
      range, bounds_, loose_ ? nullptr : &mailbox,
      [&](const Bounds3& cell) { return node_box(cell); },
      [&](uint32_t node) { return node_refs(node); },
      [&](uint32_t node, const Bounds3& cell, auto&& emit) { for_children(node, cell, 0, emit); },
      prim, obs);
}

}  // namespace rayscope
