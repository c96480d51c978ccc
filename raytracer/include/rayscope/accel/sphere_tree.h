// Hierarchy of bounding spheres (lecture: "Bounding volume hierarchy: general
// definition, any bounding volumes; image: spheres"). The lecture's bounding
// sphere stores a center and a radius such that all geometry is contained.
//
// Why spheres, and what they cost: a sphere is the cheapest bounding volume to
// test (one point-line distance against one radius, the same for every ray
// direction: no slabs, no per-axis work), and it is rotation invariant. But it
// fits worse than a box: a thin triangle or a long, flat group of them fills
// a small part of its sphere, and an inner node's sphere must also contain
// its children's spheres, so the slack grows level by level. More rays enter
// nodes they then leave empty-handed, so more nodes and more primitives are
// tested than with the BVH's boxes: the trade the lecture's "simple bounding
// volume" asks us to weigh (docs/acceleration.md measures it).
//
// An object hierarchy, like the BVH: every primitive is stored exactly once
// (in one leaf); node spheres may overlap.
//
// Like the other builders, the builder knows nothing about geometry: it takes
// one bounding sphere per primitive and a SphereTreeBuildConfig, and names
// primitives by their index in that span. The aggregate computes the spheres
// (min_triangle_sphere() below for a triangle, the sphere itself for a
// sphere, enclosing_sphere() of its end balls for a capsule).
#pragma once

#include <cassert>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "rayscope/accel/accel_structure.h"
#include "rayscope/accel/binary_range_walk.h"
#include "rayscope/math.h"
#include "rayscope/range_query.h"
#include "rayscope/ray.h"
#include "rayscope/traversal.h"

namespace rayscope {

/// One node of the flattened tree, 24 bytes. Inner nodes (count == 0) store
/// the index of their first child; the second child follows it. Leaves store
/// the offset of their first primitive in SphereTree::prim_indices and how
/// many there are.
struct SphereNode {
  Vec3 center;
  float radius;
  uint32_t index;
  uint32_t count;

  bool is_leaf() const { return count != 0; }
  BoundingSphere sphere() const { return {center, radius}; }
};
static_assert(sizeof(SphereNode) == 24);

/// Settings of the sphere tree builder, with the defaults used by RayScope.
///
/// The split rule is the BVH's binned surface area heuristic with spheres:
/// the primitives' sphere centers are binned along the axis where the centers
/// spread widest, and the cut between two bins that minimizes
///   traversal_cost + intersection_cost x (R_left^2 n_left + R_right^2 n_right) / R^2
/// is taken, R_left and R_right being the spheres around each side's
/// primitives' spheres: a ray that hits a sphere of radius R hits a sphere of
/// radius R' inside it with probability about (R'/R)^2 (their surface areas).
/// A node becomes a leaf when it holds at most max_leaf_size primitives and
/// testing them all costs no more than the best cut.
struct SphereTreeBuildConfig {
  int bins = 16;                   ///< Candidate cuts per node are bins - 1 (2 .. kMaxBins).
  uint32_t max_leaf_size = 4;      ///< Leaves never hold more primitives than this (>= 1).
  float traversal_cost = 1.0f;     ///< Cost of visiting an inner node...
  float intersection_cost = 1.0f;  ///< ...relative to one primitive test.
  /// Nodes deeper than this (capped at SphereTree::kMaxCostDepth) are cut at
  /// the object median, so that the depth stays below kMaxCostDepth + 32 for
  /// any input (the walk's fixed stack).
  int max_depth = 48;
};

/// Quality figures of a built tree (see SphereTree::quality()).
struct SphereTreeQuality {
  uint32_t nodes = 0, leaves = 0, depth = 0;
  uint32_t max_leaf_prims = 0;
  double mean_leaf_prims = 0.0;
  /// Expected cost of a random ray hitting the root, by the split rule's
  /// measure: sum over nodes of (R / R_root)^2 x (traversal_cost, or
  /// intersection_cost x primitives for a leaf).
  double sah_cost = 0.0;
  /// Sum of the node spheres' volumes over the root sphere's volume: how much
  /// the levels overlap and how loosely they fit.
  double volume_ratio = 0.0;
  size_t memory_bytes = 0;  ///< Nodes and leaf order.
  double build_seconds = 0.0;
};

/// The smallest sphere that contains triangle (a, b, c): its circumsphere
/// (center in the triangle's plane) if the triangle is acute, else the sphere
/// on its longest edge (the edge's midpoint, half its length: it holds the
/// opposite vertex, which sees that edge at an angle of 90 degrees or more).
/// A degenerate triangle is obtuse (a segment: its longest edge) or a point
/// (radius 0). Computed in double; the center is rounded to float and the
/// radius rounded up so that the float sphere contains the vertices.
BoundingSphere min_triangle_sphere(const Vec3& a, const Vec3& b, const Vec3& c);

/// The smallest sphere that contains spheres a and b (exact merge): the larger
/// one if it contains the other, else the sphere whose diameter is the segment
/// through both centers from the far side of a to the far side of b. Rounded
/// like min_triangle_sphere() so that the float result contains both.
BoundingSphere enclosing_sphere(const BoundingSphere& a, const BoundingSphere& b);

class SphereTree {
 public:
  static constexpr int kMaxBins = 64;
  /// The deepest max_depth the builder uses; below it nodes are cut at the
  /// object median, which halves them, so no leaf lies deeper than
  /// kMaxCostDepth + 32 (at most 2^32 primitives).
  static constexpr int kMaxCostDepth = 64;
  /// The walks' fixed stack: one waiting sibling per level at most.
  static constexpr int kStackSize = kMaxCostDepth + 32 + 1;
  /// Relative enlargement of a node's sphere in the ray test (see
  /// ray_entry()): 2^-14, about 50 times the error bound of where a primitive
  /// test puts its hit (a few gamma(7) of the distances from the ray's origin
  /// to the primitive, at most |origin - center| + radius for anything inside
  /// the node). So rounding never lets a node's sphere reject a ray that a
  /// primitive inside it reports a hit for, nor cull it by an entry beyond
  /// that hit.
  static constexpr double kRaySlack = 1.0 / 16384.0;

  /// Builds the tree over spheres.size() primitives. Throws
  /// std::invalid_argument for a sphere that is not finite or has a negative
  /// radius (naming the primitive), for bins outside 2 .. kMaxBins or a
  /// max_leaf_size of 0, std::length_error for more than 2^32 - 1 primitives.
  /// Zero radii and coincident centers are fine. An empty input gives an empty
  /// tree that every ray misses.
  void build(std::span<const BoundingSphere> spheres, const SphereTreeBuildConfig& config = {});

  bool empty() const { return nodes.empty(); }
  /// The root's sphere (radius 0 at the origin when empty).
  BoundingSphere sphere() const { return empty() ? BoundingSphere{} : nodes[0].sphere(); }
  SphereTreeQuality quality() const;
  /// The AccelStructure interface (accel_structure.h): figures, teaching
  /// view (refs: the indices build() was given), the --stats line and the
  /// ray-tree legend of the walk.
  AccelFigures figures() const;
  AccelView view() const;
  std::string stats_line() const;
  std::string walk_legend() const;
  size_t memory_bytes() const {
    return nodes.size() * sizeof(SphereNode) + prim_indices.size() * sizeof(uint32_t);
  }
  /// The depth of every node, by node index (root: 0).
  std::vector<uint32_t> depths() const;

  /// A ray in double, for ray_entry() (converted once per walk).
  struct RayD {
    DVec3 origin, dir;
    double dd;  ///< dir . dir
    explicit RayD(const Ray& r) : origin(r.origin), dir(r.dir), dd(glm::dot(dir, dir)) {}
  };
  /// The lecture's ray-sphere test for a node, made conservative: the ray
  /// (origin + t dir) against the node's sphere with its radius enlarged by
  /// kRaySlack x (|origin - center| + radius) (the distance bounded by its
  /// 1-norm), in double. Returns whether the ray meets it within [0, tmax],
  /// and then its entry distance in `t_entry`, rounded down (0 when the
  /// origin lies inside the sphere: the ray starts within it). Roots are taken
  /// as c/q with q = -b + sqrt(...), which never subtracts nearly equal
  /// numbers.
  static bool ray_entry(const SphereNode& n, const RayD& ray, float tmax, float& t_entry);

  /// Walks the nodes whose sphere the ray [origin, origin + tmax * dir]
  /// meets, with exactly KdTree::traverse's contract: `prim(index, tmax)`
  /// tests primitive `index` and returns true on a hit, lowering tmax to the
  /// hit distance (closest hit) or ending the walk (AnyHit). Returns whether
  /// anything was hit.
  ///
  /// - An inner node entered tests both children's spheres (ray_entry()); the
  ///   ray enters the nearer entry first (ties: the first child), the other
  ///   waits on a fixed stack of kStackSize entries with its entry distance.
  /// - Early termination: a waiting node is entered only if its entry lies
  ///   within the closest hit so far; once a hit lies before every node
  ///   waiting, the walk ends.
  /// - A leaf's primitives are passed to `prim` by their index in the build's
  ///   span, each once per ray (each is stored once: no mailbox).
  ///
  /// Observer hooks (traversal.h), node ids = index in nodes, root 0:
  /// on_box_test(0, hit) for the root's sphere; on_node(id) for every node
  /// entered; on_box_test(child, hit) for both children's spheres of an inner
  /// node entered (the "box" is the node's bounding volume, here a sphere);
  /// on_cull(id) for a waiting node skipped by early termination. Primitive
  /// tests are the caller's (`prim`).
  ///
  template <bool AnyHit, class Observer, class PrimFn>
  bool traverse(const Ray& ray, float& tmax, PrimFn&& prim, Observer& obs) const;

  /// The lecture's range query (range_query.h) on the sphere tree: from the
  /// root, a node whose sphere the range overlaps (range.overlaps(sphere),
  /// exact up to a conservative margin) is entered; a leaf's primitives are
  /// passed to `prim(index)`, each exactly once; an inner node's two child
  /// spheres are tested and the children that overlap visited nearer first by
  /// range.distance(sphere) (ties: the first child), the farther pushed. A
  /// pushed node is entered only if the range still overlaps its sphere when
  /// it is popped (a k-nearest range shrinks while it is walked); else it is
  /// culled. Observer hooks as Bvh::walk_range's, with this tree's node ids.
  template <class Range, class Observer, class PrimFn>
  void walk_range(Range& range, PrimFn&& prim, Observer& obs) const;

  std::vector<SphereNode> nodes;       ///< nodes[0] is the root.
  std::vector<uint32_t> prim_indices;  ///< Leaf order -> primitive index.
  SphereTreeBuildConfig config;

 private:
  double build_seconds_ = 0.0;
};

// ---------------------------------------------------------------------------

inline bool SphereTree::ray_entry(const SphereNode& n, const RayD& ray, float tmax,
                                  float& t_entry) {
  const DVec3 f = ray.origin - DVec3(n.center);
  const double ff = glm::dot(f, f);
  // The slack's scale |f| + radius, with |f| bounded by its 1-norm (no
  // square root; at most sqrt(3) times larger).
  const double f1 = std::abs(f.x) + std::abs(f.y) + std::abs(f.z);
  const double r = double(n.radius) * (1.0 + kRaySlack) + kRaySlack * f1;
  const double c = ff - r * r;
  if (c <= 0.0) {  // the origin lies inside: the ray starts within the sphere
    t_entry = 0.0f;
    return true;
  }
  const double b = glm::dot(f, ray.dir);  // half the lecture's linear coefficient
  if (b >= 0.0) return false;             // outside and moving away (or along)
  // The discriminant as r^2 - |l|^2, l the ray's closest approach to the
  // center: accurate also for small, distant spheres (as intersect_sphere).
  const DVec3 l = f - (b / ray.dd) * ray.dir;
  const double disc = r * r - glm::dot(l, l);
  if (disc < 0.0) return false;
  const double q = -b + std::sqrt(ray.dd * disc);  // both terms >= 0
  const double t = c / q;                          // the nearer root
  float tf = float(t);
  if (double(tf) > t) tf = next_float_down(tf);
  if (!(tf <= tmax)) return false;
  t_entry = std::max(tf, 0.0f);
  return true;
}

template <bool AnyHit, class Observer, class PrimFn>
bool SphereTree::traverse(const Ray& ray, float& tmax, PrimFn&& prim, Observer& obs) const {
  if (nodes.empty()) return false;
  const RayD rd(ray);
  float t0, t1;
  const bool root_hit = ray_entry(nodes[0], rd, tmax, t0);
  if constexpr (Observer::kActive) obs.on_box_test(0, root_hit);
  if (!root_hit) return false;
  struct Entry {
    uint32_t node;
    float t;  ///< Entry distance of its sphere.
  };
  Entry stack[kStackSize];
  int sp = 0;
  uint32_t node = 0;
  bool hit = false;
  for (;;) {
    if constexpr (Observer::kActive) obs.on_node(node);
    const SphereNode& n = nodes[node];
    if (n.is_leaf()) {
      for (uint32_t i = n.index; i < n.index + n.count; ++i)
        if (prim(prim_indices[i], tmax)) {
          hit = true;
          if constexpr (AnyHit) return true;
        }
    } else {
      const uint32_t c0 = n.index, c1 = n.index + 1;
      const bool h0 = ray_entry(nodes[c0], rd, tmax, t0);
      const bool h1 = ray_entry(nodes[c1], rd, tmax, t1);
      if constexpr (Observer::kActive) {
        obs.on_box_test(c0, h0);
        obs.on_box_test(c1, h1);
      }
      if (h0 && h1) {
        const bool second_first = t1 < t0;
        assert(sp < kStackSize);
        stack[sp++] = second_first ? Entry{c0, t0} : Entry{c1, t1};
        node = second_first ? c1 : c0;
        continue;
      }
      if (h0 || h1) {
        node = h0 ? c0 : c1;
        continue;
      }
    }
    // Pop the next node whose entry lies within the closest hit so far.
    for (;;) {
      if (sp == 0) return hit;
      const Entry e = stack[--sp];
      if (e.t <= tmax) {
        node = e.node;
        break;
      }
      if constexpr (Observer::kActive) obs.on_cull(e.node);
    }
  }
}

template <class Range, class Observer, class PrimFn>
void SphereTree::walk_range(Range& range, PrimFn&& prim, Observer& obs) const {
  walk_binary_range<kStackSize>(
      nodes, [](const SphereNode& n) { return n.sphere(); }, range,
      [&](uint32_t i) { prim(prim_indices[i]); }, obs);
}

}  // namespace rayscope
