// BSP tree (lecture: "BSP-tree: split planes (half-spaces), binary space
// partition tree, arbitrary planes"): space cut recursively by planes of any
// orientation. The kD-tree is its axis-aligned special case; here the planes
// go through the primitives themselves, as in the classic autopartition: a
// node's candidate planes are the planes of (a sample of) the triangles it
// holds, and the builder takes the one that cuts fewest triangles while
// keeping the two sides balanced.
//
// Build rule (BspBuildConfig): at a node with more than max_leaf_size
// primitives, up to `candidates` triangles (evenly spaced through the node's
// list) each propose their plane; each plane is scored by
//   cost = split_weight x straddlers + |front - back|
// (the lecture's "aim at few splits", with balance so that the tree stays
// O(log n) deep) and the cheapest one is taken. A plane that does not cut the
// node's cell is skipped (with EveryCell a node's primitives reach out of its
// cell, where a plane could separate them without dividing the cell). Spheres
// never give a plane (they have none); a node with no usable triangle plane is
// cut by the axis-aligned plane through the median of its primitives' centers
// on their widest axis. A plane that leaves every primitive on one side (as
// the plane of coplanar triangles does for all of them) is refused; with none
// left the node is a leaf, so the recursion always ends.
//
// Classification: a primitive's signed distances to the plane (triangle:
// its three vertices; sphere: its center -/+ its radius; capsule: its two
// ends -/+ its radius) are computed in double. It is behind (back child) if its lowest distance is
// <= +tolerance, in front if its highest is >= -tolerance: one within tolerance of the plane is on
// both sides ("straddles"). The tolerance is one per tree, kClassifyEpsilon times the size of the
// scene's box, far above the double rounding of the distances, so no rounding ever puts a primitive
// on the wrong side only.
//
// A straddler is stored one of the lecture's three ways (prim_storage.h):
//
// - EveryCell ("store multiple times"): referenced on both sides; the walk
//   tests it once per ray all the same (mailbox.h). Only leaves hold
//   references.
// - SmallestCell: the classic BSP node list: a straddler stays in the node
//   whose plane it straddles, every primitive is stored exactly once; the
//   walk tests a node's list when it enters the node.
// - Split ("split objects"): a straddling triangle is clipped by the plane
//   into two convex fragments, one per side; each fragment is classified
//   again further down (so it is cut again only where it straddles). A
//   triangle lying in the plane (within tolerance) stays in the node, as the
//   classic BSP keeps coincident polygons in the node. A fragment refers to
//   its original primitive and the walk tests that primitive with the
//   aggregate's one exact test, so hits stay bit for bit those of the BVH (a
//   fragment's own polygon, rounded to float, is for counting and drawing
//   only). There is no mailbox: each fragment is its own object; a ray that
//   reaches two fragments of one triangle tests the triangle twice, gets the
//   same answer twice, and the aggregate's tie rule keeps the first (that
//   repeated test is the price of splitting that the counts show). A
//   straddling sphere cannot be clipped into a sphere: it goes whole to both
//   sides and counts as two pieces.
//
// The walk (traverse()) is the kD-tree's, with a plane of any orientation:
// the ray's interval [t0, t1] in a node's cell is split at the plane's t,
// the origin's side first, the far side pushed. It is conservative so it
// never misses a hit: a ray starting within tolerance of the plane visits
// both sides over its whole interval; the split t is widened by the relative
// margin kSplitTEpsilon on either side (near side up to t (1 + eps), far side
// from t (1 - eps)); a ray parallel to the plane stays on its origin's side.
//
// Cells: every node keeps its cell's bounding box (the root box cut by the
// ancestors' half-spaces, widened by the tolerance) for range queries, and
// every inner node its split plane clipped to its cell, a convex polygon, for
// drawing ("BSP planes as clipped polygons").
#pragma once

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "rayscope/accel/accel_structure.h"
#include "rayscope/accel/mailbox.h"
#include "rayscope/accel/prim_storage.h"
#include "rayscope/intersect.h"
#include "rayscope/math.h"
#include "rayscope/ray.h"
#include "rayscope/traversal.h"

namespace rayscope {

/// One primitive as the builder sees it: a triangle's vertices (a, b, c), or
/// a round one, the points within `radius` of the segment a b: a sphere
/// (a == b) or a capsule (c == b).
struct BspPrim {
  Vec3 a, b, c;
  float radius = 0.0f;
  bool round = false;

  static BspPrim triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
    return BspPrim{a, b, c, 0.0f, false};
  }
  static BspPrim make_sphere(const Vec3& center, float radius) {
    return BspPrim{center, center, center, radius, true};
  }
  static BspPrim make_capsule(const Vec3& a, const Vec3& b, float radius) {
    return BspPrim{a, b, b, radius, true};
  }
};

/// One node of the flattened tree, 32 bytes. An inner node holds its plane
/// {x : dot(normal, x) = offset} (the normal in float, of unit length up to
/// rounding; the offset in double, so that a plane through a vertex holds it
/// up to double rounding); the back child (dot < offset) is the next node, the
/// front child is at `front`. Any node may hold references:
/// refs[first .. first + count) (inner nodes only with SmallestCell, and with
/// Split the triangles lying in their plane).
struct BspNode {
  Vec3 normal{0.0f};
  uint32_t front = 0;  ///< Index of the front child; 0 for a leaf.
  double offset = 0.0;
  uint32_t first = 0, count = 0;

  bool is_leaf() const { return front == 0; }
  /// Signed distance of p from the plane (times |normal|), in double.
  double distance(const Vec3& p) const {
    return double(normal.x) * p.x + double(normal.y) * p.y + double(normal.z) * p.z - offset;
  }
};
static_assert(sizeof(BspNode) == 32);

/// Settings of the BSP builder, with the defaults used by RayScope.
struct BspBuildConfig {
  /// Triangle planes tried per node (evenly spaced through its list): more
  /// finds fewer cuts, at build time linear in it. >= 1.
  uint32_t candidates = 16;
  /// What one straddler costs against one primitive of imbalance |front -
  /// back|. 4: a plane is worth a cut if it balances the sides by 4 more
  /// primitives; higher values give fewer fragments and deeper trees. >= 0.
  float split_weight = 4.0f;
  /// Deepest level (root = 0), capped at BspTree::kMaxDepth.
  int max_depth = 24;
  /// Nodes with at most this many primitives become leaves.
  uint32_t max_leaf_size = 4;
};

/// Quality figures of a built tree (see BspTree::quality()).
struct BspQuality {
  uint32_t nodes = 0, leaves = 0, depth = 0;
  size_t references = 0;       ///< References (Split: fragments) in all nodes.
  double refs_per_prim = 0.0;  ///< references / primitives.
  /// Split: pieces stored (clipped triangle fragments, whole triangles and
  /// spheres, one per node holding them; coplanar triangles in inner
  /// nodes); else 0.
  size_t fragments = 0;
  /// Split: triangles cut at least once.
  size_t split_prims = 0;
  /// References held by inner nodes (SmallestCell; Split: coplanar ones).
  size_t inner_refs = 0;
  uint32_t max_leaf_refs = 0;
  double mean_leaf_refs = 0.0;  ///< Over the leaves.
  size_t memory_bytes = 0;      ///< Nodes, reference lists, cell boxes, planes, fragments.
  double build_seconds = 0.0;
};

/// A fragment (Split storage): a convex polygon, part of primitive `prim`,
/// vertices fragment_vertices[first .. first + count) (count 0 for a sphere).
struct BspFragment {
  uint32_t prim = 0;
  uint32_t first = 0, count = 0;
};

class BspTree {
 public:
  /// The deepest level the walk's fixed stack holds (one entry per level).
  static constexpr int kMaxDepth = 48;
  /// The classification tolerance: this times the size of the scene's box
  /// (its largest coordinate magnitude plus its diagonal).
  static constexpr double kClassifyEpsilon = 1e-6;
  /// Relative margin of the walk around a plane's split t (see traverse()),
  /// far above the float rounding of a primitive test's t.
  static constexpr double kSplitTEpsilon = 1e-5;
  /// The builder stops cutting (makes leaves) once the tree holds this many
  /// references (fragments) per primitive: a guard against the O(n^2) worst
  /// case.
  static constexpr size_t kMaxReferencesPerPrim = 32;

  /// Builds the tree over prims.size() primitives, storing a straddler the
  /// `storage` way: EveryCell, SmallestCell or Split (AccelConfig::storage).
  /// Zero-area triangles and zero-radius spheres are fine (they never give a
  /// plane). An empty input gives an empty tree that every ray misses. Throws
  /// std::invalid_argument for a non-finite coordinate or radius, a negative
  /// radius, candidates = 0 or a negative or non-finite split_weight;
  /// std::length_error for more than 2^32 - 2 primitives or references.
  void build(std::span<const BspPrim> prims, const BspBuildConfig& config = {},
             PrimStorage storage = PrimStorage::EveryCell);

  bool empty() const { return nodes.empty(); }
  /// The root cell: the box around all primitives.
  Bounds3 bounds() const { return bounds_; }
  /// The classification tolerance in use (distance units).
  double tolerance() const { return tolerance_; }
  PrimStorage storage() const { return storage_; }
  BspQuality quality() const;
  /// The AccelStructure interface (accel_structure.h): figures, teaching
  /// view (refs: the indices build() was given), the --stats line and the
  /// ray-tree legend of the walk.
  AccelFigures figures() const;
  AccelView view() const;
  std::string stats_line() const;
  std::string walk_legend() const;
  size_t memory_bytes() const {
    return nodes.size() * sizeof(BspNode) + refs.size() * sizeof(uint32_t) +
           cell_boxes.size() * sizeof(Bounds3) + plane_polygons.size() * sizeof(Range32) +
           plane_vertices.size() * sizeof(Vec3) + fragments.size() * sizeof(BspFragment) +
           fragment_vertices.size() * sizeof(Vec3);
  }
  /// The depth of every node, by node index (root: 0).
  std::vector<uint32_t> depths() const;

  /// Walks the cells the ray [origin, origin + tmax * dir] crosses, nearest
  /// first, with KdTree::traverse's contract: `prim(index, tmax)` tests
  /// primitive `index` and returns true on a hit, lowering tmax (closest hit)
  /// or ending the walk (AnyHit). Returns whether anything was hit.
  ///
  /// A node entered tests its own references (EveryCell: mailboxed; inner
  /// nodes hold some with SmallestCell and Split), then, if
  /// inner, splits the ray's interval at its plane: the child on the origin's
  /// side is entered next, the other pushed with its entry t (see the header
  /// comment for the conservative margins). A pushed child is entered only if
  /// its entry is within the closest hit so far (times kBoxFarScale).
  ///
  /// Observer hooks (traversal.h), node ids = index in nodes: on_box_test(0,
  /// hit) for the root box; on_node(id) for every node entered;
  /// on_box_test(child, reached) for both children of an inner node entered;
  /// on_cull(id) for a pushed child skipped by early termination.
  template <bool AnyHit, class Observer, class PrimFn>
  bool traverse(const Ray& ray, float& tmax, PrimFn&& prim, Observer& obs) const;

  /// The lecture's range query over the cells (range_query.h, as
  /// Octree::walk_range): a node is entered if the range's bounds reach its
  /// side of the parent's plane (within the tolerance) and the range overlaps
  /// its cell's bounding box; its references are reported with `prim(index)`
  /// (each primitive once per query), its children tested, nearer first; a
  /// pushed child is checked again when popped (the range may shrink) and
  /// culled if missed.
  template <class Range, class Observer, class PrimFn>
  void walk_range(Range& range, PrimFn&& prim, Observer& obs) const;

  std::vector<BspNode> nodes;  ///< nodes[0] is the root.
  std::vector<uint32_t> refs;  ///< Reference lists: primitive indices.
  /// cell_boxes[id]: the bounding box of node id's cell, widened by the
  /// tolerance.
  std::vector<Bounds3> cell_boxes;
  /// plane_polygons[id]: the range of plane_vertices holding inner node id's
  /// split plane clipped to its cell (a convex polygon; count 0 for leaves).
  struct Range32 {
    uint32_t first = 0, count = 0;
  };
  std::vector<Range32> plane_polygons;
  std::vector<Vec3> plane_vertices;
  /// Split only: fragments[i] is the piece refs[i] stands for.
  std::vector<BspFragment> fragments;
  std::vector<Vec3> fragment_vertices;
  BspBuildConfig config;

 private:
  PrimStorage storage_ = PrimStorage::EveryCell;
  Bounds3 bounds_;
  double tolerance_ = 0.0;
  uint32_t num_prims_ = 0;
  size_t split_prims_ = 0;
  double build_seconds_ = 0.0;
};

/// The part of the plane through `point` with normal `normal` that lies in
/// the box [lo, hi]: a convex polygon, in order around it (empty when the
/// plane misses the box). The BSP tree clips its split planes to its cells
/// this way; the VTK range query clips scene planes to the range's box.
std::vector<glm::dvec3> plane_in_box(const glm::dvec3& point, const glm::dvec3& normal,
                                     const glm::dvec3& lo, const glm::dvec3& hi);

// ---------------------------------------------------------------------------

template <bool AnyHit, class Observer, class PrimFn>
bool BspTree::traverse(const Ray& ray, float& tmax, PrimFn&& prim, Observer& obs) const {
  if (nodes.empty()) return false;
  const Vec3 inv_dir = 1.0f / ray.dir;
  float f0, f1;
  box_interval(bounds_.lo, bounds_.hi, ray.origin, inv_dir, tmax, f0, f1);
  const bool root_hit = f0 <= f1;
  if constexpr (Observer::kActive) obs.on_box_test(0, root_hit);
  if (!root_hit) return false;

  // SmallestCell and Split test each stored object once per visit: no mailbox.
  const bool mailboxed = storage_ == PrimStorage::EveryCell;
  MailboxQuery mailbox(mailboxed ? num_prims_ : 0u);
  struct Entry {
    uint32_t node;
    double t0, t1;
  };
  Entry stack[kMaxDepth];
  int sp = 0;
  uint32_t node = 0;
  double t0 = f0, t1 = f1;
  bool hit = false;
  for (;;) {
    if constexpr (Observer::kActive) obs.on_node(node);
    const BspNode& n = nodes[node];
    const uint32_t* r = refs.data() + n.first;
    for (const uint32_t* end = r + n.count; r != end; ++r) {
      if (mailboxed && !mailbox.first_visit(*r)) continue;
      if (prim(*r, tmax)) {
        hit = true;
        if constexpr (AnyHit) return true;
      }
    }
    if (!n.is_leaf()) {
      const double s = n.distance(ray.origin);
      const double denom = double(n.normal.x) * ray.dir.x + double(n.normal.y) * ray.dir.y +
                           double(n.normal.z) * ray.dir.z;
      // The origin's side first; within tolerance of the plane: back first,
      // and both sides over the whole interval.
      const bool back_first = s <= 0.0;
      const uint32_t near = back_first ? node + 1 : n.front;
      const uint32_t far = back_first ? n.front : node + 1;
      bool go_near = true, go_far = false;
      double near_t1 = t1, far_t0 = t0;
      if (std::abs(s) <= tolerance_) {
        go_far = true;
      } else if (denom != 0.0) {
        const double ts = -s / denom;  // < 0: the ray heads away from the plane
        if (ts >= 0.0) {
          const double lo = ts * (1.0 - kSplitTEpsilon), hi = ts * (1.0 + kSplitTEpsilon);
          go_near = hi >= t0;
          go_far = lo <= std::min(t1, double(tmax) * kBoxFarScale);
          near_t1 = std::min(hi, t1);
          far_t0 = std::max(lo, t0);
        }
      }
      if constexpr (Observer::kActive) {
        obs.on_box_test(near, go_near);
        obs.on_box_test(far, go_far);
      }
      if (go_near) {
        if (go_far) {
          assert(sp < kMaxDepth);
          stack[sp++] = {far, far_t0, t1};
          t1 = near_t1;
        }
        node = near;
      } else {
        t0 = far_t0;
        node = far;
      }
      if (go_near || go_far) continue;
    }
    // Pop the next cell that can still hold a closer hit.
    for (;;) {
      if (sp == 0) return hit;
      const Entry& e = stack[--sp];
      if (e.t0 <= double(tmax) * kBoxFarScale) {
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
void BspTree::walk_range(Range& range, PrimFn&& prim, Observer& obs) const {
  if (nodes.empty()) return;
  const bool root_hit = range.overlaps(cell_boxes[0]);
  if constexpr (Observer::kActive) obs.on_box_test(0, root_hit);
  if (!root_hit) return;
  MailboxQuery mailbox(storage_ == PrimStorage::SmallestCell ? 0u : num_prims_);
  uint32_t stack[kMaxDepth + 1];
  int sp = 0;
  stack[sp++] = 0u;
  while (sp > 0) {
    const uint32_t id = stack[--sp];
    // The range may have shrunk since the node was pushed.
    if (id != 0 && !range.overlaps(cell_boxes[id])) {
      if constexpr (Observer::kActive) obs.on_cull(id);
      continue;
    }
    if constexpr (Observer::kActive) obs.on_node(id);
    const BspNode& n = nodes[id];
    const Bounds3 rb = range.bounds();  // it may have shrunk
    for (uint32_t i = n.first; i < n.first + n.count; ++i)
      if (storage_ == PrimStorage::SmallestCell || mailbox.first_visit(refs[i])) prim(refs[i]);
    if (n.is_leaf()) continue;
    const uint32_t back = id + 1, front = n.front;
    // A child is reached if the range's bounds reach its side of the plane
    // (within the tolerance) and the range overlaps its cell's box.
    bool reach_back = true, reach_front = true;
    if (all_finite(rb.lo) && all_finite(rb.hi)) {
      // The lowest and highest signed distance over the bounds' corners, in
      // double (products of floats are exact there).
      double lo = -n.offset, hi = -n.offset;
      for (int a = 0; a < 3; ++a) {
        const double p = double(n.normal[a]) * rb.lo[a], q = double(n.normal[a]) * rb.hi[a];
        lo += std::min(p, q);
        hi += std::max(p, q);
      }
      reach_back = lo <= tolerance_;
      reach_front = hi >= -tolerance_;
    }
    const bool ob = reach_back && range.overlaps(cell_boxes[back]);
    const bool of = reach_front && range.overlaps(cell_boxes[front]);
    if constexpr (Observer::kActive) {
      obs.on_box_test(back, ob);
      obs.on_box_test(front, of);
    }
    const bool front_first =
        of && ob && range.distance(cell_boxes[front]) < range.distance(cell_boxes[back]);
    assert(sp + 2 <= kMaxDepth + 1);
    // Pushed farther first, so that the nearer is popped next.
    if (front_first) {
      stack[sp++] = back;
      stack[sp++] = front;
    } else {
      if (of) stack[sp++] = front;
      if (ob) stack[sp++] = back;
    }
  }
}

}  // namespace rayscope
