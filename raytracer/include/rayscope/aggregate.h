// The aggregate (pbrt: "the aggregate is just a primitive"): the one thing the
// integrator asks for closest hits and any hits. Behind it sits the chosen
// acceleration structure over the scene's bounded primitives (triangles and
// spheres), plus the unbounded planes, which no structure can hold.
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
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "rayscope/bsp.h"
#include "rayscope/bvh.h"
#include "rayscope/grid.h"
#include "rayscope/intersect.h"
#include "rayscope/kdtree.h"
#include "rayscope/octree.h"
#include "rayscope/prim_storage.h"
#include "rayscope/range_query.h"
#include "rayscope/sphere_tree.h"
#include "rayscope/traversal.h"
#include "rayscope/triangle_block.h"
#include "rayscope/wide_bvh.h"

namespace rayscope {

/// Which structure the aggregate walks. One is chosen per scene commit.
enum class AccelKind : uint8_t {
  /// The BVH walked through 8-wide nodes (WideBvh arity 8): what renders use.
  Bvh,
  /// The same BVH walked node by node, two child boxes per node (WideBvh
  /// arity 2): the lecture's binary walk, for teaching. Same hits; more,
  /// smaller steps, each of which the tools can show.
  BinaryBvh,
  /// No structure: every primitive is tested against every ray (O(n) per ray).
  None,
  /// The kD-tree (kdtree.h): space cut by axis-aligned planes, every primitive
  /// stored in each leaf cell it overlaps, walked front to back with
  /// mailboxing. Same hits as the BVH.
  KdTree,
  /// The uniform grid (grid.h): equal cells, their number chosen from the
  /// object count, every primitive stored in each cell it overlaps, walked
  /// cell by cell (3D-DDA) with mailboxing. Same hits as the BVH.
  Grid,
  /// The octree (octree.h): a cube cut into 8 octants, recursively; a
  /// primitive stored in every leaf cell it overlaps (PrimStorage::EveryCell)
  /// or once, in its smallest loose cell (SmallestCell). Same hits as the BVH.
  Octree,
  /// The BSP tree (bsp.h): space cut by planes of any orientation, through
  /// the triangles (autopartition); a straddler stored on both sides
  /// (EveryCell), in the node whose plane it straddles (SmallestCell) or cut
  /// into fragments (Split). Same hits as the BVH.
  Bsp,
  /// The hierarchy of bounding spheres (sphere_tree.h): the BVH's idea with
  /// the cheapest bounding volume to test, which fits worse than a box; each
  /// primitive stored once, in its triangle's smallest enclosing sphere (or
  /// the sphere itself). Same hits as the BVH.
  Spheres,
};
/// Every kind, in the order the tools list them.
inline constexpr AccelKind kAccelKinds[] = {
    AccelKind::Bvh,    AccelKind::BinaryBvh, AccelKind::KdTree,  AccelKind::Grid,
    AccelKind::Octree, AccelKind::Bsp,       AccelKind::Spheres, AccelKind::None};
/// "bvh", "bvh2", "none", "kdtree", "grid", "octree", "bsp", "spheres".
const char* to_string(AccelKind kind);
/// Parses the names to_string() gives; false for anything else.
bool parse_accel_kind(std::string_view name, AccelKind& kind);

/// How commit() builds the aggregate; every field has a documented default.
struct AccelConfig {
  AccelKind kind = AccelKind::Bvh;
  BvhBuildConfig bvh;        ///< Settings of the SAH builder (bvh.h).
  KdTreeBuildConfig kdtree;  ///< Settings of the kD-tree builder (kdtree.h), for AccelKind::KdTree.
  GridBuildConfig grid;      ///< Settings of the grid builder (grid.h), for AccelKind::Grid.
  /// Settings of the octree builder (octree.h), for AccelKind::Octree; its
  /// `storage` and `loose_factor` are replaced by the ones below (as the
  /// kD-tree's and the grid's are).
  OctreeBuildConfig octree;
  /// Settings of the BSP builder (bsp.h), for AccelKind::Bsp; its `storage`
  /// is replaced by the one below.
  BspBuildConfig bsp;
  /// Settings of the sphere tree builder (sphere_tree.h), for AccelKind::Spheres.
  SphereTreeBuildConfig spheres;
  /// How a spatial subdivision stores a primitive that straddles its cuts: the
  /// one setting for every structure, checked by accel_storage_error() (the
  /// BVH kinds and the sphere tree take only the default, every-cell; the BSP
  /// tree also takes split). Replaces the builder configs' own `storage`.
  PrimStorage storage = PrimStorage::EveryCell;
  /// SmallestCell's loose factor, the one setting for the kD-tree, grid and
  /// octree (replaces their builder configs' own `loose_factor`): each cell
  /// enlarged by this fraction of its extent on every side, 0 ..
  /// kMaxLooseFactor, checked by loose_factor_error() (Aggregate::build throws
  /// std::invalid_argument with it).
  float loose_factor = kDefaultLooseFactor;
  /// Let scenes with at most Aggregate::kBruteForceMax bounded primitives skip
  /// the structure and test them all. Off only to measure what the skip saves.
  bool allow_brute_force = true;
};

/// Why structure `kind` cannot store primitives the `storage` way, in one line
/// (no trailing period); empty when it can. The one check of the pair: the
/// CLI, the VTK image algorithm and Aggregate::build (which throws
/// std::invalid_argument with it) all ask here.
std::string accel_storage_error(AccelKind kind, PrimStorage storage);

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

/// The closest hit of a ray without any shading data: what tracing needs to
/// find, and no more (the same work as Embree's rtcIntersect1, which returns t,
/// barycentrics and ids). Scene::surface_hit() turns it into a SurfaceHit.
struct PrimHit {
  float t = kInfinity;
  float b0 = 0.0f, b1 = 0.0f, b2 = 0.0f;  ///< Barycentric weights (triangles).
  uint32_t record = ~0u;  ///< Index into Aggregate::records() (leaf order); ~0u for a plane.
  uint32_t prim = ~0u;    ///< Global primitive index (triangles mesh by mesh, then spheres).
  int plane = -1;         ///< Index of the plane hit, else -1.
};

/// One bounded primitive in leaf order: a triangle's vertices, or a sphere's
/// center and radius (in b.x). Stored inline so that leaves need no indirection.
struct PrimRecord {
  Vec3 a;
  uint32_t id;  ///< Global primitive index.
  Vec3 b;
  uint32_t pad;
  Vec3 c;
};

/// An unbounded plane (tested outside any structure).
struct PlaneRecord {
  Vec3 point, normal;  ///< normal: unit length.
};

class Aggregate {
 public:
  /// Scenes with at most this many bounded primitives skip the structure and
  /// test them all. Measured by bench_recording (default-scene spheres, one
  /// thread): 1-3 spheres render 2-8% faster without a BVH, 4 spheres 2% slower.
  static constexpr size_t kBruteForceMax = 3;

  /// Builds the chosen structure. record_of(i) is primitive i, with bounds[i]
  /// and centroids[i] (the builder sees only those); records with id <
  /// num_triangles are triangles, the others spheres. record_of is called
  /// once per primitive, in leaf order, from several threads at once: the
  /// records are made where they are kept, with no copy in the caller's order
  /// (on 1.1M triangles that copy was 53 MB to fill and reorder). Replaces
  /// what was built.
  void build(std::span<const Bounds3> bounds, std::span<const Vec3> centroids,
             const std::function<PrimRecord(size_t)>& record_of, uint32_t num_triangles,
             std::vector<PlaneRecord> planes, const AccelConfig& config = {});

  /// Closest hit within (0, ray.tmax). When several primitives are hit at
  /// exactly the same t, the result is the one a brute-force loop over all
  /// triangles, then spheres, then planes reports: the triangle with the
  /// highest global index, else the sphere with the lowest, else the first
  /// plane. The answer therefore does not depend on the structure or the order
  /// of its walk.
  template <class Observer = NullTraversalObserver>
  bool intersect(const Ray& ray, PrimHit& hit, Observer& obs) const;

  /// Any hit within (0, ray.tmax) (shadow rays): stops at the first one found
  /// and describes it in `which` (prim or plane) when not null.
  template <class Observer = NullTraversalObserver>
  bool occluded(const Ray& ray, Observer& obs, PrimHit* which = nullptr) const;

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
  size_t object_count() const { return records_.size() + planes_.size(); }

  /// The structure asked for.
  AccelKind kind() const { return config_.kind; }
  /// Whether queries walk a structure (false for AccelKind::None and for tiny
  /// scenes that skip it; see kBruteForceMax).
  bool walks_structure() const { return use_walk_; }
  /// The binary hierarchy: built for every kind (the tools show it).
  const Bvh& bvh() const { return bvh_; }
  /// The walked collapse of bvh() (arity 8 for AccelKind::Bvh, 2 for BinaryBvh;
  /// empty for None, KdTree, Grid, Octree and Bsp).
  const WideBvh& walk() const { return walk_; }
  /// The storage choice the structure was built with (AccelConfig::storage).
  PrimStorage storage() const { return config_.storage; }
  /// The whole configuration the aggregate was built with.
  const AccelConfig& config() const { return config_; }
  /// The kD-tree, over records() (its references are record indices); empty
  /// unless the kind is AccelKind::KdTree.
  const KdTree& kdtree() const { return kdtree_; }
  /// The octree, over records() like the kD-tree; empty unless the kind is
  /// AccelKind::Octree.
  const Octree& octree() const { return octree_; }
  /// The sphere tree, over records() (its prim_indices are record indices);
  /// empty unless the kind is AccelKind::Spheres.
  const SphereTree& sphere_tree() const { return sphere_tree_; }
  /// The uniform grid, over records() (its references are record indices);
  /// empty unless the kind is AccelKind::Grid.
  const UniformGrid& grid() const { return grid_; }
  /// The BSP tree, over records() (its references are record indices); empty
  /// unless the kind is AccelKind::Bsp.
  const BspTree& bsp() const { return bsp_; }
  const std::vector<PrimRecord>& records() const { return records_; }
  /// The walk's leaves by coordinate (triangle_block.h): each leaf's records
  /// from its first block on, TriangleBlock::kLanes per block (empty unless
  /// walk() is built).
  const std::vector<TriangleBlock>& triangle_blocks() const { return blocks_; }
  /// Bytes of triangle_blocks().
  size_t triangle_block_bytes() const { return blocks_.size() * sizeof(TriangleBlock); }
  /// The unbounded planes, with unit normals, in the scene's order.
  const std::vector<PlaneRecord>& plane_records() const { return planes_; }
  /// Every byte the aggregate holds: binary nodes, leaf order, wide nodes,
  /// triangle blocks, kD-tree, grid, octree or sphere tree nodes or cells and references, primitive
  /// records and planes.
  size_t memory_bytes() const;
  /// Figures of the structure the rays walk (the kind asked for, also for a
  /// tiny scene that skips it).
  AccelFigures figures() const;

 private:
  /// Whether primitive `a` wins an exact tie in t against primitive `b`:
  /// triangles beat spheres, a higher triangle index beats a lower one, a lower
  /// sphere index beats a higher one.
  bool wins_tie(uint32_t a, uint32_t b) const {
    return a < num_triangles_ ? (b >= num_triangles_ || a > b) : (b >= num_triangles_ && a < b);
  }

  /// The one primitive test: whether record r is hit within the query's range,
  /// and where (`th`: t, and the barycentrics of a triangle). Triangles are hit
  /// at t <= tmax (intersect_triangle's closed bound); spheres at t < tmax, or
  /// at t <= tmax with `sphere_closed` (so that a sphere at exactly the
  /// closest t so far is found and can win the tie).
  [[gnu::always_inline]] bool test_prim(const PrimRecord& r, const Ray& ray,
                                        const TrianglePrecomp& pre, float tmax, bool sphere_closed,
                                        TriangleHit& th) const {
    if (r.id < num_triangles_) return intersect_triangle(pre, tmax, r.a, r.b, r.c, th);
    float ts;
    if (!intersect_sphere(ray, r.a, r.b.x, sphere_closed ? next_float_up(tmax) : tmax, ts))
      return false;
    th = TriangleHit{ts, 0.0f, 0.0f, 0.0f};
    return true;
  }

  /// Tests the primitives the ray can hit with `prim(record, tmax, decided)`,
  /// which returns true on a hit (lowering tmax, or ending an any-hit query):
  /// the BVH's leaves (contiguous record ranges), the kD-tree's, grid's,
  /// octree's or BSP tree's cells (reference lists, each record once per ray
  /// except for the BSP tree's fragments), the sphere tree's leaves (each
  /// record once), or all records without a structure. `decided` is null, or
  /// the hit test_prim() would report (at t <= tmax), already found.
  ///
  /// The BVH's leaves go through their triangle blocks (triangle_block.h):
  /// `prim` is called for the records the block test hits (with the hit) or
  /// leaves undecided, in record order, so it finds what the plain loop finds.
  /// An active observer sees the plain loop, every record tested.
  /// The lambdas are forced inline so that the BVH's leaf loop compiles as
  /// one loop, as when it was written as one.
  template <bool AnyHit, class Observer, class PrimFn>
  bool walk_prims(const Ray& ray, const TrianglePrecomp& pre, float& tmax, PrimFn&& prim,
                  Observer& obs) const {
    auto range = [&prim](uint32_t first, uint32_t count, float& t) __attribute__((always_inline)) {
      bool found = false;
      for (uint32_t i = first; i < first + count; ++i)
        if (prim(i, t)) {
          found = true;
          if constexpr (AnyHit) return true;
        }
      return found;
    };
    if (!use_walk_) return range(0u, uint32_t(records_.size()), tmax);
    if (config_.kind == AccelKind::KdTree) return kdtree_.traverse<AnyHit>(ray, tmax, prim, obs);
    if (config_.kind == AccelKind::Octree) return octree_.traverse<AnyHit>(ray, tmax, prim, obs);
    if (config_.kind == AccelKind::Grid) return grid_.traverse<AnyHit>(ray, tmax, prim, obs);
    if (config_.kind == AccelKind::Bsp) return bsp_.traverse<AnyHit>(ray, tmax, prim, obs);
    if (config_.kind == AccelKind::Spheres)
      return sphere_tree_.traverse<AnyHit>(ray, tmax, prim, obs);
    // The walk's leaves are labelled by their first block (build()).
    if constexpr (Observer::kActive) {
      auto leaf = [&](uint32_t block, uint32_t count, float& t) __attribute__((always_inline)) {
        return range(blocks_[block].first, count, t);
      };
      return walk_.traverse<AnyHit>(ray, tmax, leaf, obs);
    } else {
      const TriangleBlockRay block_ray(pre);
      auto blocks = [&](uint32_t block, uint32_t count, float& t) __attribute__((always_inline)) {
        bool found = false;
        const TriangleBlock* b = &blocks_[block];
        const uint32_t first = b->first;
        TriangleBlockResult res;
        for (uint32_t base = first; base < first + count; base += TriangleBlock::kLanes, ++b) {
          test_triangle_block<!AnyHit>(*b, block_ray, t, res);
          for (unsigned m = res.hits | res.undecided; m != 0; m &= m - 1) {
            const unsigned k = unsigned(__builtin_ctz(m));
            TriangleHit th;
            const TriangleHit* decided = nullptr;
            if ((res.hits >> k) & 1u) {
              th = res.hit(k);
              if (!(th.t <= t)) continue;  // beyond a hit found in this block
              decided = &th;
            }
            if (prim(base + k, t, decided)) {
              found = true;
              if constexpr (AnyHit) return true;
            }
          }
        }
        return found;
      };
      return walk_.traverse<AnyHit>(ray, tmax, blocks, obs);
    }
  }

  /// Builds walk_ with `arity` and blocks_, from bvh_ and records_: walk_'s
  /// leaves are labelled by their first block.
  void build_walk(int arity);

  /// The one primitive test of box queries (exact, see range_query.h).
  bool record_overlaps(const PrimRecord& r, const Bounds3& box) const {
    return r.id < num_triangles_ ? triangle_overlaps_box(r.a, r.b, r.c, box)
                                 : sphere_overlaps_box(r.a, r.b.x, box);
  }
  /// The one distance of sphere and k-nearest queries (exact, see
  /// range_query.h): never below the distance to the record's bounds, so no
  /// walk prunes a node whose primitive a brute-force loop would find.
  float record_distance(const PrimRecord& r, const Vec3& p) const {
    return r.id < num_triangles_ ? point_triangle_distance(p, r.a, r.b, r.c)
                                 : point_sphere_distance(p, r.a, r.b.x);
  }

  /// Passes the records the range may hold to `prim(record)`, each once: the
  /// chosen structure's walk_range(), or every record without a structure.
  template <class Range, class Observer, class PrimFn>
  void walk_range(Range& range, PrimFn&& prim, Observer& obs) const {
    static_assert(QueryRange<Range>);
    if (!use_walk_) {
      for (uint32_t i = 0; i < uint32_t(records_.size()); ++i) prim(i);
    } else if (config_.kind == AccelKind::KdTree) {
      kdtree_.walk_range(range, prim, obs);
    } else if (config_.kind == AccelKind::Grid) {
      grid_.walk_range(range, prim, obs);
    } else if (config_.kind == AccelKind::Octree) {
      octree_.walk_range(range, prim, obs);
    } else if (config_.kind == AccelKind::Bsp) {
      bsp_.walk_range(range, prim, obs);
    } else if (config_.kind == AccelKind::Spheres) {
      sphere_tree_.walk_range(range, prim, obs);
    } else {  // Bvh and BinaryBvh: the binary tree
      bvh_.walk_range(range, prim, obs);
    }
  }

  AccelConfig config_;
  Bvh bvh_;
  WideBvh walk_;
  KdTree kdtree_;
  Octree octree_;
  UniformGrid grid_;
  BspTree bsp_;
  SphereTree sphere_tree_;
  std::vector<PrimRecord> records_;  ///< Leaf order.
  /// The records of the walk's leaves by coordinate, kLanes at a time, each
  /// leaf starting a new block (empty unless walk_ is built).
  std::vector<TriangleBlock> blocks_;
  std::vector<PlaneRecord> planes_;
  uint32_t num_triangles_ = 0;
  bool use_walk_ = false;
  double build_seconds_ = 0.0;  ///< The walked structure's build (figures()).
};

// ---------------------------------------------------------------------------

template <class Observer>
bool Aggregate::intersect(const Ray& ray, PrimHit& hit, Observer& obs) const {
  float tmax = ray.tmax;
  uint32_t best = ~0u, best_id = ~0u;
  TriangleHit best_tri{};
  const TrianglePrecomp pre(ray);
  // A hit at exactly the closest t so far replaces it only if it wins the tie
  // (spheres are tested with the closed bound once something was hit).
  auto prim = [&](uint32_t i, float& t, const TriangleHit* decided = nullptr)
      __attribute__((always_inline)) {
    const PrimRecord& r = records_[i];
    if constexpr (Observer::kActive) obs.on_prim_test(r.id);
    TriangleHit th;
    if ((decided ? (th = *decided, true) : test_prim(r, ray, pre, t, best != ~0u, th)) &&
        (th.t < t || best == ~0u || wins_tie(r.id, best_id))) {
      if constexpr (Observer::kActive) obs.on_prim_hit(r.id);
      t = th.t;
      best = i;
      best_id = r.id;
      best_tri = th;
      return true;
    }
    return false;
  };
  walk_prims<false>(ray, pre, tmax, prim, obs);
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
  if (best == ~0u) return false;
  hit.t = tmax;
  hit.b0 = best_tri.b0;
  hit.b1 = best_tri.b1;
  hit.b2 = best_tri.b2;
  hit.record = best;
  hit.prim = best_id;
  hit.plane = -1;
  return true;
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
  auto prim = [&](uint32_t i, float& t, const TriangleHit* decided = nullptr)
      __attribute__((always_inline)) {
    const PrimRecord& r = records_[i];
    if constexpr (Observer::kActive) obs.on_prim_test(r.id);
    TriangleHit th;
    if (!decided && !test_prim(r, ray, pre, t, false, th)) return false;
    if constexpr (Observer::kActive) obs.on_prim_hit(r.id);
    hit_record = i;
    return true;
  };
  if (!walk_prims<true>(ray, pre, tmax, prim, obs)) return false;
  if (which) {
    *which = PrimHit{};
    which->record = hit_record;
    which->prim = records_[hit_record].id;
  }
  return true;
}

template <class Observer>
std::vector<RangeHit> Aggregate::query_box(const Bounds3& box, Observer& obs) const {
  const BoxRange range(box);
  std::vector<RangeHit> found;
  auto prim = [&](uint32_t i) {
    const PrimRecord& r = records_[i];
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
  auto prim = [&](uint32_t i) {
    const PrimRecord& r = records_[i];
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
  auto prim = [&](uint32_t i) {
    const PrimRecord& r = records_[i];
    if constexpr (Observer::kActive) obs.on_prim_test(r.id);
    if (!range.offer({r.id, -1, record_distance(r, p)})) return;
    if constexpr (Observer::kActive) obs.on_prim_hit(r.id);
  };
  walk_range(range, prim, obs);
  return range.take_sorted();
}

}  // namespace rayscope
