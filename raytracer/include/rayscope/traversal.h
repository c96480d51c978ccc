// What an acceleration structure's walk reports, and to whom.
//
// Every structure behind the Aggregate (aggregate.h) reports its walk to an
// observer through the hooks below; ray-tree recording, statistics, cost AOVs
// and the VTK BVH source are observers. The ids are those of the structure's
// teaching view, the nodes the tools draw (for the BVH: Bvh::nodes, the binary
// tree), whichever walk renders use. An observer never selects a walk: observed
// and plain queries walk the same nodes in the same order.
//
// Observers are compile-time policies: with kActive == false no hook is ever
// called and the walk compiles to the plain one, at no cost.
#pragma once

#include <cstdint>

namespace rayscope {

/// The "primitive" of on_prim_hit for a hit outside the structure (an unbounded
/// plane, tested beside it).
inline constexpr uint32_t kPrimOutsideStructure = ~0u;

/// Every hook, each doing nothing. An observer derives from this and defines
/// kActive = true and the hooks it needs (the others stay no-ops).
struct TraversalHooks {
  /// Whether the observer reads the node ids the hooks pass (false: it only
  /// counts, and a walk may pass any id; the BVH then need not name its wide
  /// nodes by their binary ids, which are made only when asked for).
  static constexpr bool kNodeIds = true;
  /// The walk enters node (or cell) `node`: its children or primitives are
  /// tested next.
  void on_node(uint32_t /*node*/) {}
  /// The box of node `node` was tested against the ray; `hit`: it overlaps the
  /// ray's current [0, tmax] (and the node will be entered or pushed).
  void on_box_test(uint32_t /*node*/, bool /*hit*/) {}
  /// Node `node`, whose box was hit, is skipped without being entered: a
  /// closer hit was found after it was pushed (early termination).
  void on_cull(uint32_t /*node*/) {}
  /// Primitive `prim` (global primitive index) is tested against the ray.
  void on_prim_test(uint32_t /*prim*/) {}
  /// Primitive `prim`, just tested, is now the query's hit: the closest so far
  /// (a later call replaces it) or, for an any-hit query, the occluder. The
  /// leaf that holds it is the node entered last. kPrimOutsideStructure: a
  /// plane beside the structure became the hit. In a range query (range
  /// queries walk with the same hooks, see range_query.h): the primitive lies
  /// in the range (for k nearest: it is among the k best so far, and may be
  /// pushed out later).
  void on_prim_hit(uint32_t /*prim*/) {}
};

/// The observer of plain queries: compiled out.
struct NullTraversalObserver : TraversalHooks {
  static constexpr bool kActive = false;
};

}  // namespace rayscope
