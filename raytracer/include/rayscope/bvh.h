// Bounding volume hierarchy (lecture: "Spatial data structures").
//
// The builder knows nothing about geometry: it takes one bounding box and one
// centroid per primitive and returns a flat array of 32-byte nodes plus the
// permutation of primitive indices the leaves refer to. Traversal is a template
// with two hooks: a leaf function supplied by the caller (which intersects the
// primitives) and an observer that sees every node visit, box test and
// early-terminated node. The default observer is empty and compiled out, so
// recording and statistics cost nothing unless a caller asks for them.
//
// For tracing, Scene collapses this hierarchy into a 4-wide one (bvh4.h) and
// walks that when nobody observes; observed queries (ray-tree recording,
// statistics, cost AOVs) walk this binary hierarchy, so the node ids, box tests
// and culls they report are those of Bvh::nodes, as visualised. Both walks
// return the same hit (see Scene::intersect). Bvh4::traverse has the same
// observer hooks; it reports binary node ids too (the top binary node of each
// wide node, and the leaves), and one box test per child box it tests.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

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
  int bins = 16;                   ///< Candidate split planes per axis are bins - 1.
  uint32_t max_leaf_size = 8;      ///< Leaves never hold more primitives than this...
  uint32_t min_leaf_size = 1;      ///< ...nor fewer, unless the node is that small.
  float traversal_cost = 1.0f;     ///< SAH cost of visiting an inner node...
  float intersection_cost = 1.0f;  ///< ...relative to one primitive test.
  int max_depth = 56;              ///< Deeper nodes are split at the object median.
};

/// Quality figures of a built hierarchy (see Bvh::quality()).
struct BvhQuality {
  uint32_t nodes = 0, leaves = 0, depth = 0;
  uint32_t min_leaf_prims = 0, max_leaf_prims = 0;
  double mean_leaf_prims = 0.0;
  double sah_cost = 0.0;  ///< Expected cost of a random ray, with the build's cost constants.
  size_t memory_bytes = 0;
};

/// Hooks that traversal calls. An observer with kActive == false is never
/// called, so an empty observer costs nothing.
struct NullTraversalObserver {
  static constexpr bool kActive = false;
  void on_node(uint32_t /*node*/) {}
  void on_box_test() {}
  void on_cull(uint32_t /*node*/) {}
  void on_prim_test(uint32_t /*prim*/) {}
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

  /// Walks the nodes the ray [origin, origin + tmax * dir] can reach, nearer child
  /// first. `leaf(first, count, tmax)` tests the primitives prim_indices[first ..
  /// first + count) and returns true on a hit, lowering tmax to the hit distance.
  /// With AnyHit the walk stops at the first hit (shadow rays); otherwise it
  /// skips every node whose entry distance is beyond the closest hit so far
  /// (early termination; "beyond" by more than the box test's rounding margin
  /// kBoxFarScale, so that the decision does not depend on whether a node is
  /// tested before or after the hit is found). Returns whether anything was hit.
  template <bool AnyHit, class Observer, class LeafFn>
  bool traverse(const Ray& ray, float& tmax, LeafFn&& leaf, Observer& obs) const {
    if (nodes.empty()) return false;
    const Vec3 inv_dir = 1.0f / ray.dir;
    struct Entry {
      uint32_t node;
      float tnear;
    };
    Entry stack[64];
    int sp = 0;
    if constexpr (Observer::kActive) obs.on_box_test();
    float troot = intersect_box(nodes[0].lo, nodes[0].hi, ray.origin, inv_dir, tmax);
    if (troot == kInfinity) return false;
    uint32_t current = 0;
    bool hit = false;
    for (;;) {
      const BvhNode& n = nodes[current];
      if constexpr (Observer::kActive) obs.on_node(current);
      if (n.is_leaf()) {
        if (leaf(n.index, n.count, tmax)) {
          hit = true;
          if constexpr (AnyHit) return true;
        }
      } else {
        uint32_t c0 = n.index, c1 = n.index + 1;
        if constexpr (Observer::kActive) {
          obs.on_box_test();
          obs.on_box_test();
        }
        float d0 = intersect_box(nodes[c0].lo, nodes[c0].hi, ray.origin, inv_dir, tmax);
        float d1 = intersect_box(nodes[c1].lo, nodes[c1].hi, ray.origin, inv_dir, tmax);
        if (d1 < d0) {
          std::swap(d0, d1);
          std::swap(c0, c1);
        }
        if (d0 != kInfinity) {
          if (d1 != kInfinity) stack[sp++] = {c1, d1};
          current = c0;
          continue;
        }
      }
      // Pop the next node that can still hold a closer hit.
      for (;;) {
        if (sp == 0) return hit;
        Entry e = stack[--sp];
        if (e.tnear <= tmax * kBoxFarScale) {
          current = e.node;
          break;
        }
        if constexpr (Observer::kActive) obs.on_cull(e.node);
      }
    }
  }

  std::vector<BvhNode> nodes;          ///< nodes[0] is the root.
  std::vector<uint32_t> prim_indices;  ///< Leaf order -> primitive index.
  BvhBuildConfig config;
};

}  // namespace rayscope
