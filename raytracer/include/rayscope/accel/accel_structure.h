// What every acceleration structure offers the aggregate (aggregate.h): the
// one interface that brute force, the BVH walk (bvh_walk.h), the kD-tree, the
// grid, the octree, the BSP tree and the sphere tree each satisfy, checked by
// the AccelStructure concept below.
//
// A structure is built over the aggregate's primitive records in leaf order
// (accel_build.h) and names them by record index: its walks pass record
// indices to the aggregate's primitive test, which owns what a hit is (the one
// primitive test, the one tie rule), so every structure returns the same hit.
#pragma once

#include <concepts>
#include <cstddef>
#include <cstdint>
#include <string>

#include "rayscope/accel/accel_view.h"
#include "rayscope/intersect.h"
#include "rayscope/range_query.h"
#include "rayscope/ray.h"
#include "rayscope/traversal.h"

namespace rayscope {

/// Figures of the structure the rays walk, the same for every kind: what
/// `rayscope accel compare` puts side by side (Aggregate::figures()).
struct AccelFigures {
  /// Building it: the SAH build and the collapse into the walked nodes for
  /// bvh and bvh2; the structure's own build for the others (the binary BVH
  /// the tools show is built for every kind and not counted there); 0 for
  /// none.
  double build_seconds = 0.0;
  /// What its queries read: nodes or cells, reference lists and the primitive
  /// records (not the teaching BVH when another structure is walked).
  size_t memory_bytes = 0;
  size_t nodes = 0;   ///< Nodes or cells, leaves included (0 for none).
  size_t leaves = 0;  ///< Leaves or cells that hold primitives (0 for none).
  uint32_t depth = 0;
  /// References stored per bounded primitive: 1 when each is stored once (the
  /// BVH, none), more when a primitive is stored in every cell it overlaps
  /// (for the BSP tree with split storage: fragments per primitive).
  double refs_per_prim = 0.0;
  /// BSP tree with split storage: the pieces in its leaves (see
  /// BspQuality::fragments); 0 otherwise.
  size_t fragments = 0;
};

/// The figures a structure's quality record holds under the names every one
/// uses (build_seconds, memory_bytes, nodes, leaves, depth), with
/// `refs_per_prim` references per primitive: the start of each figures().
template <class Quality>
AccelFigures figures_of(const Quality& q, double refs_per_prim) {
  AccelFigures f;
  f.build_seconds = q.build_seconds;
  f.memory_bytes = q.memory_bytes;
  f.nodes = q.nodes;
  f.leaves = q.leaves;
  f.depth = q.depth;
  f.refs_per_prim = refs_per_prim;
  return f;
}

namespace accel_probe {
// Stand-ins for the aggregate's callbacks, only for the concept's checks.
struct RayPrim {  // closest-hit / any-hit test of one record
  bool operator()(uint32_t record, float& tmax, const TriangleHit* decided = nullptr) const;
};
struct RangePrim {  // range test of one record
  void operator()(uint32_t record) const;
};
struct CountingObserver : TraversalHooks {
  static constexpr bool kActive = true;
};
}  // namespace accel_probe

/// `prim(record, tmax)` for records [first, first + count), in order, until
/// a hit with AnyHit: brute force's loop and a BVH leaf's, written once.
/// Returns whether anything was hit.
template <bool AnyHit, class PrimFn>
[[gnu::always_inline]] inline bool test_records(uint32_t first, uint32_t count, float& tmax,
                                                PrimFn&& prim) {
  bool found = false;
  for (uint32_t i = first; i < first + count; ++i)
    if (prim(i, tmax)) {
      found = true;
      if constexpr (AnyHit) return true;
    }
  return found;
}

/// The interface of an acceleration structure:
/// - traverse<AnyHit>(ray, tmax, prim, obs): the ray walk, nearest cells or
///   nodes first; `prim(record, tmax)` tests one record and returns true on a
///   hit (lowering tmax, or ending an any-hit walk); returns whether anything
///   was hit. The walk reports to the observer (traversal.h) with the ids of
///   its teaching view.
/// - walk_range(range, prim, obs): the range walk (range_query.h), passing
///   each record the range may hold to `prim(record)` once.
/// - figures() (AccelFigures; memory without the records, which the
///   aggregate adds), memory_bytes() (everything it holds).
/// - view(): its teaching view (accel_view.h), refs naming records.
/// - stats_line(): what `rayscope render --stats` prints after "Walk:".
/// - walk_legend(): what the ray-tree text says the "walk:" counts are for
///   this structure (after "walk: ").
template <class S>
concept AccelStructure = requires(const S& s, const Ray& ray, float& tmax,
                                  accel_probe::RayPrim ray_prim, accel_probe::RangePrim range_prim,
                                  NullTraversalObserver& quiet,
                                  accel_probe::CountingObserver& counting, BoxRange& box,
                                  SphereRange& sphere, KnnRange& knn) {
  { s.template traverse<false>(ray, tmax, ray_prim, quiet) } -> std::same_as<bool>;
  { s.template traverse<true>(ray, tmax, ray_prim, quiet) } -> std::same_as<bool>;
  { s.template traverse<false>(ray, tmax, ray_prim, counting) } -> std::same_as<bool>;
  s.walk_range(box, range_prim, quiet);
  s.walk_range(sphere, range_prim, counting);
  s.walk_range(knn, range_prim, quiet);
  { s.figures() } -> std::same_as<AccelFigures>;
  { s.memory_bytes() } -> std::same_as<size_t>;
  { s.view() } -> std::same_as<AccelView>;
  { s.stats_line() } -> std::same_as<std::string>;
  { s.walk_legend() } -> std::same_as<std::string>;
};

}  // namespace rayscope
