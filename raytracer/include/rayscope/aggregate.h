// The aggregate (pbrt: "the aggregate is just a primitive"): the one thing the
// integrator asks for closest hits and any hits. Behind it sits the chosen
// acceleration structure over the scene's bounded primitives (triangles,
// spheres and capsules), plus the unbounded planes, which no structure can hold. The
// structure is one of the AccelStructure alternatives (accel_structure.h),
// built by the one factory (accel_build.h) and dispatched here, in one place.
//
// Whatever the structure, the aggregate owns the two rules that decide a hit:
// the one primitive test (test_prim) and the one tie rule (wins_tie), so every
// structure returns the same hit, bit for bit, for every ray. Observers
// (traversal.h) see the walk of the chosen structure: the very walk a plain
// query does (statistics and recording may cost time; they never change it).
//
// Range queries (range_query.h: box, sphere, k nearest) go through the same
// structures, each walked by its one walk_range(), with one primitive test per
// range (record_overlaps, record_distance) and one order of results, so every
// structure finds the same objects in the same order.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "rayscope/accel/accel_build.h"
#include "rayscope/accel/accel_config.h"
#include "rayscope/accel/accel_kind.h"
#include "rayscope/accel/accel_structure.h"
#include "rayscope/accel/leaf_records.h"
#include "rayscope/accel/prim_record.h"
#include "rayscope/intersect.h"
#include "rayscope/intersect_capsule.h"
#include "rayscope/range_query.h"
#include "rayscope/traversal.h"

namespace rayscope {

class Aggregate {
 public:
  /// Scenes with at most this many bounded primitives skip the structure and
  /// test them all. Measured by bench_recording (default-scene spheres, one
  /// thread): 1-3 spheres render 2-8% faster without a BVH, 4 spheres 2% slower.
  static constexpr size_t kBruteForceMax = 3;

  Aggregate() = default;
  /// A copy's binary BVH and records are made on demand from the copy's own
  /// blocks (moves keep them where they are).
  Aggregate(const Aggregate& other);
  Aggregate& operator=(const Aggregate& other);
  Aggregate(Aggregate&&) = default;
  Aggregate& operator=(Aggregate&&) = default;

  /// Builds the chosen structure. record_of(i) is primitive i, with bounds[i]
  /// and centroids[i] (the builder sees only those), which must be
  /// prim_box(record_of(i)) (bvh_on_demand.h: the hierarchy is built again
  /// from the records when a tool asks for it), ids increasing with i;
  /// records with id < num_triangles are triangles, the others spheres,
  /// points or capsules (their PrimRecord::shape). record_of is called once
  /// per primitive (and once more for the last one), in leaf order, from
  /// several threads at once: the records are made where they are kept (the
  /// BVH's triangle blocks, or the other structures' records), with no copy
  /// in the caller's order. Replaces what was built.
  void build(std::span<const Bounds3> bounds, std::span<const Vec3> centroids,
             const RecordSource& record_of, uint32_t num_triangles, std::vector<PlaneRecord> planes,
             const AccelConfig& config = {});

  /// Closest hit within (0, ray.tmax). When several primitives are hit at
  /// exactly the same t, the result is the one a brute-force loop over all
  /// records by global index, then planes, reports: the triangle with the
  /// highest global index (triangles are hit at t <= the closest so far),
  /// else the other primitive (sphere or capsule, hit at t < the closest so
  /// far) with the lowest, else the first plane. The answer therefore does not
  /// depend on the structure or the order of its walk.
  template <class Observer = NullTraversalObserver>
  bool intersect(const Ray& ray, PrimHit& hit, Observer& obs) const;

  /// Any hit within (0, ray.tmax) (shadow rays): stops at the first one found
  /// and describes it in `which` (prim or plane) when not null.
  template <class Observer = NullTraversalObserver>
  bool occluded(const Ray& ray, Observer& obs, PrimHit* which = nullptr) const;

  /// intersect() for up to kPacketRays rays at once (ray_packet.h): hits[k]
  /// is rays[k]'s closest hit, bit for bit the one intersect() finds. Coherent
  /// rays (primary rays of a block of pixels) walk the 8-wide BVH as a packet
  /// (wide_bvh_packet.h); rays that disagree on a direction component's sign,
  /// and every other structure, are traced one at a time. Returns the rays
  /// that hit something, bit k for rays[k]. Throws std::invalid_argument for
  /// more than kPacketRays rays. With `cost`, the walk's work for each ray
  /// is added to it (PacketWalkCost, which must start cleared).
  unsigned intersect_packet(std::span<const Ray> rays, PrimHit* hits,
                            PacketWalkCost* cost = nullptr) const;
  /// occluded() for up to kPacketRays rays at once (shadow rays of neighbouring
  /// hits toward one light): bit k set when rays[k] is occluded.
  unsigned occluded_packet(std::span<const Ray> rays, PacketWalkCost* cost = nullptr) const;

  /// Range queries (range_query.h): the objects (bounded primitives, then the
  /// planes beside the structure) that intersect the closed box, in
  /// before_in_box_order(): primitives by global index, then planes (RangeHit
  /// names a plane by its index, with prim = ~0u); distance 0. Throws
  /// std::invalid_argument for a box BoxRange refuses (non-finite, lo > hi).
  template <class Observer>
  std::vector<RangeHit> query_box(const Bounds3& box, Observer& obs) const;
  /// The objects within distance `radius` of `center` (closed), with their
  /// distances, in the order nearer(). Throws std::invalid_argument for a
  /// range SphereRange refuses (non-finite, radius < 0).
  template <class Observer>
  std::vector<RangeHit> query_sphere(const Vec3& center, float radius, Observer& obs) const;
  /// The k objects nearest to `p` (all of them when there are fewer), nearest
  /// first in the order nearer(): distance, then primitives by global index,
  /// then planes. Throws std::invalid_argument for a non-finite point or k = 0.
  template <class Observer>
  std::vector<RangeHit> nearest(const Vec3& p, uint32_t k, Observer& obs) const;
  std::vector<RangeHit> query_box(const Bounds3& box) const {
    NullTraversalObserver obs;
    return query_box(box, obs);
  }
  std::vector<RangeHit> query_sphere(const Vec3& center, float radius) const {
    NullTraversalObserver obs;
    return query_sphere(center, radius, obs);
  }
  std::vector<RangeHit> nearest(const Vec3& p, uint32_t k) const {
    NullTraversalObserver obs;
    return nearest(p, k, obs);
  }
  /// Bounded primitives plus planes: what a k-nearest query can return at most.
  size_t object_count() const { return ids_.size() + planes_.size(); }
  /// The bounded primitives (the records, without making them).
  size_t prim_count() const { return ids_.size(); }

  /// The structure asked for.
  AccelKind kind() const { return config_.kind; }
  /// Whether queries walk a structure (false for brute force and for tiny
  /// scenes that skip it; see kBruteForceMax).
  bool walks_structure() const { return use_walk_; }
  /// The binary hierarchy: built for every kind (it sets the records' leaf
  /// order, and the tools show it), then dropped, and built again when first
  /// asked for here (bvh_on_demand.h).
  const Bvh& bvh() const { return hierarchy_->get(); }
  /// The box of every bounded primitive (kept when the hierarchy is dropped).
  Bounds3 bounds() const { return hierarchy_->bounds(); }
  /// The structure built for kind() (accel_build.h), walked unless
  /// walks_structure() is false.
  const AccelStructureVariant& structure() const { return structure_; }
  /// The structure as an `S` (BvhWalk, KdTree, UniformGrid, Octree, BspTree,
  /// SphereTree, BruteForce), or an empty one when another kind was built.
  template <class S>
  const S& structure_as() const {
    if (const S* s = std::get_if<S>(&structure_)) return *s;
    static const S kEmpty{};
    return kEmpty;
  }
  /// The storage choice the structure was built with (AccelConfig::storage).
  PrimStorage storage() const { return config_.storage; }
  /// The whole configuration the aggregate was built with.
  const AccelConfig& config() const { return config_; }
  /// The bounded primitives' records in leaf order (leaf_records.h): held,
  /// or made again from the BVH's blocks on the first call.
  const std::vector<PrimRecord>& records() const { return records_->get(); }
  /// Each record's global primitive index, in leaf order (what a render
  /// keeps of the records behind the BVH).
  const std::vector<uint32_t>& record_ids() const { return ids_; }
  /// The records of the primitives other than triangles, by id -
  /// num_triangles, kept when the BVH's blocks stand in for the records
  /// (empty otherwise).
  const std::vector<PrimRecord>& other_records() const { return others_; }
  /// The unbounded planes, with unit normals, in the scene's order.
  const std::vector<PlaneRecord>& plane_records() const { return planes_; }
  /// Every byte the aggregate holds now: the structure, the primitive records
  /// (or their ids and the other primitives' records) and planes, and what
  /// only the tools need while it is made (the records behind the BVH, the
  /// binary hierarchy and its leaf order, the wide BVH's binary node ids).
  size_t memory_bytes() const;
  /// Figures of the structure the rays walk (the kind asked for, also for a
  /// tiny scene that skips it).
  AccelFigures figures() const;
  /// The walk's line of `rayscope render --stats` (after "Walk:"): the
  /// structure's own figures, or brute force's line when nothing is walked.
  std::string stats_line() const;
  /// What the walk counts of a ray tree are for (AccelStructure::walk_legend).
  std::string walk_legend() const;

 private:
  /// Whether primitive `a` wins an exact tie in t against primitive `b`:
  /// triangles beat the other primitives, a higher triangle index beats a
  /// lower one, and among the others (spheres and capsules alike, which the
  /// brute-force loop tests with an open bound) a lower index beats a higher
  /// one.
  bool wins_tie(uint32_t a, uint32_t b) const {
    return a < num_triangles_ ? (b >= num_triangles_ || a > b) : (b >= num_triangles_ && a < b);
  }

  /// Whether the BVH's blocks stand in for the records: a walked BvhWalk.
  bool blocks_hold_records() const {
    return use_walk_ && std::holds_alternative<BvhWalk>(structure_);
  }
  /// The records made again from the BVH's blocks (BvhWalk::records_from_blocks)
  /// with this aggregate's own blocks, ids and other records.
  LeafRecords::Make make_records() const;
  /// Points the structure's walk at hierarchy_ (BvhWalk, BruteForce).
  void share_hierarchy();
  /// Bytes of the records (held or made), their ids, the other primitives'
  /// records and the planes.
  size_t records_bytes() const;

  /// The walk a packet of `rays` takes: the BVH's, with the rays loaded into
  /// `packet`; null when they are traced one at a time (another structure,
  /// or rays that disagree on a direction sign). Throws std::invalid_argument
  /// for more than kPacketRays rays.
  const BvhWalk* packet_walk(std::span<const Ray> rays, RayPacket& packet) const;
  /// intersect_packet() and occluded_packet() counting with `cost`
  /// (PacketWalkCost or NoPacketWalkCost).
  template <class Cost>
  unsigned intersect_packet(std::span<const Ray> rays, PrimHit* hits, Cost& cost) const;
  template <class Cost>
  unsigned occluded_packet(std::span<const Ray> rays, Cost& cost) const;

  /// The records test_prim() tests in one query, fetched once per query by
  /// tested_records(): record i (global index `id`) is walk[i], or, when the
  /// walk decides every triangle itself (behind the BVH, bvh_walk.h) and walk
  /// is null, the other primitive's record others[id - num_triangles].
  struct TestedRecords {
    const PrimRecord* walk;
    const PrimRecord* others;
    uint32_t num_triangles;
    [[gnu::always_inline]] const PrimRecord& operator()(uint32_t i, uint32_t id) const {
      return walk ? walk[i] : others[id - num_triangles];
    }
  };
  /// With an active observer, which counts every record it tests, the
  /// records (made, if need be); else the records the walk tests.
  template <class Observer>
  TestedRecords tested_records() const {
    if constexpr (Observer::kActive) return {records().data(), nullptr, num_triangles_};
    return {walk_records_, others_.data(), num_triangles_};
  }

  /// The closest hit so far of one ray: its record, global primitive index
  /// and triangle hit (record ~0u: nothing yet).
  struct ClosestSoFar {
    uint32_t record = ~0u, id = ~0u;
    TriangleHit tri{};
  };
  /// Record i as intersect()'s walk tests it: test_prim() (or the hit the
  /// block test `decided`), kept in `c` and lowering t when it is closer than
  /// the closest hit so far or wins the tie at the same t.
  template <class Observer>
  bool offer_closest(uint32_t i, const Ray& ray, const TrianglePrecomp& pre, float& t,
                     const TriangleHit* decided, const TestedRecords& recs, ClosestSoFar& c,
                     Observer& obs) const;
  /// intersect()'s answer from the walk's closest hit `c` at `tmax`: the
  /// planes, which beat it when closer, then the hit.
  template <class Observer>
  bool closest_with_planes(const Ray& ray, float tmax, const ClosestSoFar& c, PrimHit& hit,
                           Observer& obs) const;

  /// The first plane (in the scene's order) the ray hits within (0, ray.tmax),
  /// at tp; -1 when none: occluded_packet()'s test. occluded() writes the
  /// same loop out: calling this from it made the bunny's single shadow rays
  /// 10% slower (bench_trace, same run, no planes in the scene).
  int first_plane_hit(const Ray& ray, float& tp) const {
    for (size_t k = 0; k < planes_.size(); ++k)
      if (intersect_plane(ray, planes_[k].point, planes_[k].normal, ray.tmax, tp)) return int(k);
    return -1;
  }

  /// The one primitive test: whether record r is hit within the query's range,
  /// and where (`th`: t, and the barycentrics of a triangle). Triangles are hit
  /// at t <= tmax (intersect_triangle's closed bound); spheres and capsules at
  /// t < tmax, or at t <= tmax with `sphere_closed` (so that one at exactly
  /// the closest t so far is found and can win the tie).
  [[gnu::always_inline]] bool test_prim(const PrimRecord& r, const Ray& ray,
                                        const TrianglePrecomp& pre, float tmax, bool sphere_closed,
                                        TriangleHit& th) const {
    if (r.id < num_triangles_) return intersect_triangle(pre, tmax, r.a, r.b, r.c, th);
    float ts;
    const float limit = sphere_closed ? next_float_up(tmax) : tmax;
    if (!(r.shape == PrimShape::Capsule ? intersect_capsule(ray, r.a, r.b, r.c.x, limit, ts)
                                        : intersect_sphere(ray, r.a, r.b.x, limit, ts)))
      return false;
    th = TriangleHit{ts, 0.0f, 0.0f, 0.0f};
    return true;
  }

  /// Tests the primitives the ray can hit with `prim(record, tmax, decided)`,
  /// which returns true on a hit (lowering tmax, or ending an any-hit query):
  /// the chosen structure's walk (AccelStructure::traverse), or every record
  /// without a structure. `decided` is null, or the hit test_prim() would
  /// report (at t <= tmax), already found (BvhWalk's triangle blocks).
  template <bool AnyHit, class Observer, class PrimFn>
  [[gnu::always_inline]] bool walk_prims(const Ray& ray, const TrianglePrecomp& pre, float& tmax,
                                         PrimFn&& prim, Observer& obs) const {
    if (!use_walk_) return test_records<AnyHit>(0u, uint32_t(ids_.size()), tmax, prim);
    // The BVH first, without a visit and with the primitive test's
    // constants: it is what renders walk.
    if (const BvhWalk* w = std::get_if<BvhWalk>(&structure_)) [[likely]]
      return w->traverse<AnyHit>(ray, pre, tmax, prim, obs);
    return std::visit(
        [&](const auto& s) {
          using S = std::decay_t<decltype(s)>;
          if constexpr (std::is_same_v<S, BvhWalk>) {
            __builtin_unreachable();  // walked above: not compiled a second time
            return false;
          } else {
            return s.template traverse<AnyHit>(ray, tmax, prim, obs);
          }
        },
        structure_);
  }

  /// The one primitive test of box queries (exact, see range_query.h).
  bool record_overlaps(const PrimRecord& r, const Bounds3& box) const {
    if (r.id < num_triangles_) return triangle_overlaps_box(r.a, r.b, r.c, box);
    return r.shape == PrimShape::Capsule ? capsule_overlaps_box(r.a, r.b, r.c.x, box)
                                         : sphere_overlaps_box(r.a, r.b.x, box);
  }
  /// The one distance of sphere and k-nearest queries (exact, see
  /// range_query.h): never below the distance to the record's bounds, so no
  /// walk prunes a node whose primitive a brute-force loop would find.
  float record_distance(const PrimRecord& r, const Vec3& p) const {
    if (r.id < num_triangles_) return point_triangle_distance(p, r.a, r.b, r.c);
    return r.shape == PrimShape::Capsule ? point_capsule_distance(p, r.a, r.b, r.c.x)
                                         : point_sphere_distance(p, r.a, r.b.x);
  }

  /// Passes the records the range may hold to `prim(record)`, each once: the
  /// chosen structure's walk_range(), or every record without a structure.
  template <class Range, class Observer, class PrimFn>
  void walk_range(Range& range, PrimFn&& prim, Observer& obs) const {
    static_assert(QueryRange<Range>);
    if (!use_walk_) {
      for (uint32_t i = 0; i < uint32_t(ids_.size()); ++i) prim(i);
      return;
    }
    std::visit([&](const auto& s) { s.walk_range(range, prim, obs); }, structure_);
  }

  AccelConfig config_;
  /// Shared with the structures that walk or show it (BvhWalk, BruteForce).
  std::shared_ptr<const BvhOnDemand> hierarchy_ = std::make_shared<const BvhOnDemand>();
  AccelStructureVariant structure_;
  /// Shared with the hierarchy, which is built again from them.
  std::shared_ptr<const LeafRecords> records_ = std::make_shared<const LeafRecords>();
  /// The records the walk tests by index: records_'s, held; null behind the
  /// BVH, whose walk decides every triangle from its blocks (others_ then).
  const PrimRecord* walk_records_ = nullptr;
  std::vector<uint32_t> ids_;       ///< record_ids().
  std::vector<PrimRecord> others_;  ///< other_records().
  std::vector<PlaneRecord> planes_;
  uint32_t num_triangles_ = 0;
  bool use_walk_ = false;
};

// ---------------------------------------------------------------------------

template <class Observer>
[[gnu::always_inline]] inline bool Aggregate::offer_closest(uint32_t i, const Ray& ray,
                                                            const TrianglePrecomp& pre, float& t,
                                                            const TriangleHit* decided,
                                                            const TestedRecords& recs,
                                                            ClosestSoFar& c, Observer& obs) const {
  const uint32_t id = ids_[i];
  if constexpr (Observer::kActive) obs.on_prim_test(id);
  // A hit at exactly the closest t so far replaces it only if it wins the tie
  // (spheres are tested with the closed bound once something was hit).
  TriangleHit th;
  if ((decided ? (th = *decided, true)
               : test_prim(recs(i, id), ray, pre, t, c.record != ~0u, th)) &&
      (th.t < t || c.record == ~0u || wins_tie(id, c.id))) {
    if constexpr (Observer::kActive) obs.on_prim_hit(id);
    t = th.t;
    c.record = i;
    c.id = id;
    c.tri = th;
    return true;
  }
  return false;
}

template <class Observer>
bool Aggregate::closest_with_planes(const Ray& ray, float tmax, const ClosestSoFar& c, PrimHit& hit,
                                    Observer& obs) const {
  int best_plane = -1;
  for (size_t k = 0; k < planes_.size(); ++k) {
    float tp;
    if (intersect_plane(ray, planes_[k].point, planes_[k].normal, tmax, tp)) {
      tmax = tp;
      best_plane = int(k);
    }
  }
  if (best_plane >= 0) {
    if constexpr (Observer::kActive) obs.on_prim_hit(kPrimOutsideStructure);
    hit = PrimHit{};
    hit.t = tmax;
    hit.plane = best_plane;
    return true;
  }
  if (c.record == ~0u) return false;
  hit.t = tmax;
  hit.b0 = c.tri.b0;
  hit.b1 = c.tri.b1;
  hit.b2 = c.tri.b2;
  hit.record = c.record;
  hit.prim = c.id;
  hit.plane = -1;
  return true;
}

template <class Observer>
bool Aggregate::intersect(const Ray& ray, PrimHit& hit, Observer& obs) const {
  float tmax = ray.tmax;
  ClosestSoFar c;
  const TrianglePrecomp pre(ray);
  const TestedRecords recs = tested_records<Observer>();
  auto prim = [&](uint32_t i, float& t, const TriangleHit* decided = nullptr)
      __attribute__((always_inline)) {
    return offer_closest(i, ray, pre, t, decided, recs, c, obs);
  };
  walk_prims<false>(ray, pre, tmax, prim, obs);
  return closest_with_planes(ray, tmax, c, hit, obs);
}

template <class Observer>
bool Aggregate::occluded(const Ray& ray, Observer& obs, PrimHit* which) const {
  for (size_t k = 0; k < planes_.size(); ++k) {
    float tp;
    if (intersect_plane(ray, planes_[k].point, planes_[k].normal, ray.tmax, tp)) {
      if constexpr (Observer::kActive) obs.on_prim_hit(kPrimOutsideStructure);
      if (which) {
        *which = PrimHit{};
        which->t = tp;
        which->plane = int(k);
      }
      return true;
    }
  }
  float tmax = ray.tmax;
  const TrianglePrecomp pre(ray);
  uint32_t hit_record = ~0u;
  const TestedRecords recs = tested_records<Observer>();
  auto prim = [&](uint32_t i, float& t, const TriangleHit* decided = nullptr)
      __attribute__((always_inline)) {
    const uint32_t id = ids_[i];
    if constexpr (Observer::kActive) obs.on_prim_test(id);
    TriangleHit th;
    if (!decided && !test_prim(recs(i, id), ray, pre, t, false, th)) return false;
    if constexpr (Observer::kActive) obs.on_prim_hit(id);
    hit_record = i;
    return true;
  };
  if (!walk_prims<true>(ray, pre, tmax, prim, obs)) return false;
  if (which) {
    *which = PrimHit{};
    which->record = hit_record;
    which->prim = ids_[hit_record];
  }
  return true;
}

template <class Observer>
std::vector<RangeHit> Aggregate::query_box(const Bounds3& box, Observer& obs) const {
  const BoxRange range(box);
  std::vector<RangeHit> found;
  const std::vector<PrimRecord>& records = this->records();
  auto prim = [&](uint32_t i) {
    const PrimRecord& r = records[i];
    if constexpr (Observer::kActive) obs.on_prim_test(r.id);
    if (!record_overlaps(r, box)) return;
    if constexpr (Observer::kActive) obs.on_prim_hit(r.id);
    found.push_back({r.id, -1, 0.0f});
  };
  walk_range(range, prim, obs);
  std::sort(found.begin(), found.end(), before_in_box_order);
  for (size_t k = 0; k < planes_.size(); ++k)
    if (plane_overlaps_box(planes_[k].point, planes_[k].normal, box)) {
      if constexpr (Observer::kActive) obs.on_prim_hit(kPrimOutsideStructure);
      found.push_back({~0u, int(k), 0.0f});
    }
  return found;
}

template <class Observer>
std::vector<RangeHit> Aggregate::query_sphere(const Vec3& center, float radius,
                                              Observer& obs) const {
  const SphereRange range(center, radius);
  std::vector<RangeHit> found;
  const std::vector<PrimRecord>& records = this->records();
  auto prim = [&](uint32_t i) {
    const PrimRecord& r = records[i];
    if constexpr (Observer::kActive) obs.on_prim_test(r.id);
    const float d = record_distance(r, center);
    if (!(d <= radius)) return;
    if constexpr (Observer::kActive) obs.on_prim_hit(r.id);
    found.push_back({r.id, -1, d});
  };
  walk_range(range, prim, obs);
  for (size_t k = 0; k < planes_.size(); ++k) {
    const float d = point_plane_distance(center, planes_[k].point, planes_[k].normal);
    if (!(d <= radius)) continue;
    if constexpr (Observer::kActive) obs.on_prim_hit(kPrimOutsideStructure);
    found.push_back({~0u, int(k), d});
  }
  std::sort(found.begin(), found.end(), nearer);
  return found;
}

template <class Observer>
std::vector<RangeHit> Aggregate::nearest(const Vec3& p, uint32_t k, Observer& obs) const {
  KnnRange range(p, k);
  // The planes first: a near plane shrinks the range before the walk starts.
  for (size_t j = 0; j < planes_.size(); ++j) {
    const float d = point_plane_distance(p, planes_[j].point, planes_[j].normal);
    if (!range.offer({~0u, int(j), d})) continue;
    if constexpr (Observer::kActive) obs.on_prim_hit(kPrimOutsideStructure);
  }
  const std::vector<PrimRecord>& records = this->records();
  auto prim = [&](uint32_t i) {
    const PrimRecord& r = records[i];
    if constexpr (Observer::kActive) obs.on_prim_test(r.id);
    if (!range.offer({r.id, -1, record_distance(r, p)})) return;
    if constexpr (Observer::kActive) obs.on_prim_hit(r.id);
  };
  walk_range(range, prim, obs);
  return range.take_sorted();
}

}  // namespace rayscope

#include "rayscope/aggregate_packet.h"  // the packet calls, inline (see there)
