// 4-wide bounding volume hierarchy, collapsed from the binary one (bvh.h).
//
// The binary hierarchy is what RayScope builds, tests and visualises; for
// tracing it is collapsed into nodes of up to four children (each wide node
// replaces a binary node and up to two levels of its descendants), whose boxes
// are stored per axis and bound so that one SSE instruction computes one slab
// of all four boxes. A wide node costs one visit and one 4-box test instead of
// up to three visits with two scalar box tests each, and the tree has about
// half the levels. The leaves are the binary leaves, unchanged, so the leaf
// function of Bvh::traverse works here as it is.
//
// The box test is intersect_box() exactly, four lanes at a time: same
// sign-selected planes, same operations in the same order, NaN ignored the same
// way (min/max take the running value as the second operand), exit distance
// rounded up by kBoxFarScale. A child is hit here exactly when intersect_box()
// would report it hit, with the same entry distance.
#pragma once

#include <cassert>
#include <cmath>
#include <cstdint>
#include <vector>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "rayscope/bvh.h"

namespace rayscope {

/// One node of the 4-wide hierarchy (128 bytes, two cache lines): the boxes of
/// up to four children, one array of four floats per axis and bound.
struct alignas(64) Bvh4Node {
  /// Set in `child` for a leaf child: the low bits are then the offset of its
  /// first primitive in Bvh::prim_indices, and `count` the number of them.
  static constexpr uint32_t kLeaf = 0x80000000u;

  float lo_x[4], hi_x[4], lo_y[4], hi_y[4], lo_z[4], hi_z[4];
  /// Inner child: index of its Bvh4Node. Leaf child: kLeaf | first primitive.
  /// Empty slot (nodes with fewer than four children; always the last slots):
  /// kLeaf with count 0 and an empty box (lo = +inf, hi = -inf) that no ray
  /// with a finite origin hits.
  uint32_t child[4];
  uint32_t count[4];  ///< Primitives of a leaf child; 0 for inner children and empty slots.
};
static_assert(sizeof(Bvh4Node) == 128);

class Bvh4 {
 public:
  /// Entries of the traversal stack. A wide node pushes at most three children,
  /// so a walk needs at most 3 * depth() entries; build() checks that the
  /// collapsed tree fits (Bvh's builder caps the binary depth at 64 levels, and
  /// the wide tree is never deeper than the binary one).
  static constexpr int kStackSize = 3 * 64 + 4;

  /// Collapses `bvh` (which must outlive nothing: everything needed is copied).
  /// An empty `bvh` gives an empty hierarchy that every ray misses. Throws
  /// std::length_error if the tree were too deep for the traversal stack.
  void build(const Bvh& bvh);

  bool empty() const { return root_child_ == kNone; }
  /// Levels of wide nodes on the longest path (0 when the root is a leaf).
  uint32_t depth() const { return depth_; }
  size_t memory_bytes() const {
    return nodes.size() * sizeof(Bvh4Node) + slot_source.size() * sizeof(uint32_t);
  }

  /// Same contract as Bvh::traverse: `leaf(first, count, tmax)` tests the
  /// primitives prim_indices[first .. first + count) of the binary hierarchy
  /// and returns true on a hit, lowering tmax. Children whose boxes are hit are
  /// visited nearest first; with AnyHit the walk stops at the first hit,
  /// otherwise nodes whose entry distance exceeds tmax * kBoxFarScale are
  /// skipped (early termination).
  ///
  /// Observer hooks: on_box_test() once for the root box and once for each
  /// child box tested (every non-empty slot of a visited wide node); on_node(id)
  /// and on_cull(id) with ids of the *binary* hierarchy (Bvh::nodes): a wide
  /// node is reported as the binary node at the top of the subtree it
  /// replaces, a leaf as the binary leaf, so that recorded walks can be drawn
  /// on the boxes of the binary hierarchy. (Scene's observed queries walk the
  /// binary hierarchy itself; see Scene::intersect.)
  template <bool AnyHit, class Observer, class LeafFn>
  bool traverse(const Ray& ray, float& tmax, LeafFn&& leaf, Observer& obs) const;

  std::vector<Bvh4Node> nodes;  ///< nodes[0] is the root unless the root is a leaf.
  /// Binary node id of child slot k of wide node n at [4 n + k]; ~0u for empty
  /// slots. Only observers read it.
  std::vector<uint32_t> slot_source;

 private:
  static constexpr uint32_t kNone = ~0u;
  uint32_t collapse(const Bvh& bvh, uint32_t binary_node, uint32_t level);

  Vec3 root_lo_{kInfinity}, root_hi_{-kInfinity};
  uint32_t root_child_ = kNone;  ///< 0 (wide node 0), kLeaf | first, or kNone when empty.
  uint32_t root_count_ = 0;
  uint32_t depth_ = 0;
};

// ---------------------------------------------------------------------------

namespace bvh4_detail {

/// Per-ray constants of the 4-wide box test.
struct RayBoxes {
#if defined(__SSE2__)
  __m128 ox, oy, oz, ix, iy, iz;
#endif
  Vec3 origin, inv_dir;
  // Byte offsets of the near and far plane arrays of each axis in a Bvh4Node
  // (lo_x at 0, hi_x at 16, lo_y at 32, ...), chosen by the direction's sign.
  uint32_t near_x, far_x, near_y, far_y, near_z, far_z;

  RayBoxes(const Vec3& o, const Vec3& inv) : origin(o), inv_dir(inv) {
#if defined(__SSE2__)
    ox = _mm_set1_ps(o.x);
    oy = _mm_set1_ps(o.y);
    oz = _mm_set1_ps(o.z);
    ix = _mm_set1_ps(inv.x);
    iy = _mm_set1_ps(inv.y);
    iz = _mm_set1_ps(inv.z);
#endif
    near_x = std::signbit(inv.x) ? 16 : 0;
    near_y = std::signbit(inv.y) ? 48 : 32;
    near_z = std::signbit(inv.z) ? 80 : 64;
    far_x = near_x ^ 16;
    far_y = near_y ^ 16;
    far_z = near_z ^ 16;
  }
};

inline const float* plane(const Bvh4Node& n, uint32_t offset) {
  return reinterpret_cast<const float*>(reinterpret_cast<const char*>(&n) + offset);
}

/// intersect_box() for the four children of `n`: returns a bit mask of the
/// children hit within [0, tmax] and stores their entry distances in tnear.
[[gnu::always_inline]] inline unsigned intersect_boxes(const Bvh4Node& n, const RayBoxes& r,
                                                       float tmax, float tnear[4]) {
#if defined(__SSE2__)
  const __m128 tnx = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(plane(n, r.near_x)), r.ox), r.ix);
  const __m128 tfx = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(plane(n, r.far_x)), r.ox), r.ix);
  const __m128 tny = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(plane(n, r.near_y)), r.oy), r.iy);
  const __m128 tfy = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(plane(n, r.far_y)), r.oy), r.iy);
  const __m128 tnz = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(plane(n, r.near_z)), r.oz), r.iz);
  const __m128 tfz = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(plane(n, r.far_z)), r.oz), r.iz);
  // _mm_max_ps(a, b) is a > b ? a : b, _mm_min_ps(a, b) is a < b ? a : b: with
  // the running value as b, a NaN slab (ray in a face plane) leaves it alone,
  // exactly like intersect_box's "if (tn > tnear) tnear = tn".
  __m128 tn = _mm_max_ps(tnx, _mm_setzero_ps());
  tn = _mm_max_ps(tny, tn);
  tn = _mm_max_ps(tnz, tn);
  __m128 tf = _mm_min_ps(tfx, _mm_set1_ps(tmax));
  tf = _mm_min_ps(tfy, tf);
  tf = _mm_min_ps(tfz, tf);
  tf = _mm_mul_ps(tf, _mm_set1_ps(kBoxFarScale));
  _mm_storeu_ps(tnear, tn);
  return unsigned(_mm_movemask_ps(_mm_cmple_ps(tn, tf)));
#else
  unsigned mask = 0;
  const float* nx = plane(n, r.near_x);
  const float* fx = plane(n, r.far_x);
  const float* ny = plane(n, r.near_y);
  const float* fy = plane(n, r.far_y);
  const float* nz = plane(n, r.near_z);
  const float* fz = plane(n, r.far_z);
  for (int k = 0; k < 4; ++k) {
    float tn = 0.0f, tf = tmax;
    const float t[6] = {(nx[k] - r.origin.x) * r.inv_dir.x, (fx[k] - r.origin.x) * r.inv_dir.x,
                        (ny[k] - r.origin.y) * r.inv_dir.y, (fy[k] - r.origin.y) * r.inv_dir.y,
                        (nz[k] - r.origin.z) * r.inv_dir.z, (fz[k] - r.origin.z) * r.inv_dir.z};
    for (int a = 0; a < 3; ++a) {
      if (t[2 * a] > tn) tn = t[2 * a];
      if (t[2 * a + 1] < tf) tf = t[2 * a + 1];
    }
    tf *= kBoxFarScale;
    tnear[k] = tn;
    if (tn <= tf) mask |= 1u << k;
  }
  return mask;
#endif
}

}  // namespace bvh4_detail

template <bool AnyHit, class Observer, class LeafFn>
bool Bvh4::traverse(const Ray& ray, float& tmax, LeafFn&& leaf, Observer& obs) const {
  if (root_child_ == kNone) return false;
  const Vec3 inv_dir = 1.0f / ray.dir;
  if constexpr (Observer::kActive) obs.on_box_test();
  if (intersect_box(root_lo_, root_hi_, ray.origin, inv_dir, tmax) == kInfinity) return false;
  const bvh4_detail::RayBoxes rb(ray.origin, inv_dir);

  struct Entry {
    uint32_t child, count;
    float tnear;
  };
  Entry stack[kStackSize];
  [[maybe_unused]] uint32_t source_stack[Observer::kActive ? kStackSize : 1];
  int sp = 0;
  uint32_t child = root_child_, count = root_count_;
  [[maybe_unused]] uint32_t source = 0;  // binary node id of `child`, for the observer
  bool hit = false;
  for (;;) {
    if (child & Bvh4Node::kLeaf) {
      // (count == 0: an empty slot, reached only by rays with a NaN origin.)
      if (count != 0) {
        if constexpr (Observer::kActive) obs.on_node(source);
        if (leaf(child & ~Bvh4Node::kLeaf, count, tmax)) {
          hit = true;
          if constexpr (AnyHit) return true;
        }
      }
    } else {
      if constexpr (Observer::kActive) obs.on_node(source);
      const Bvh4Node& n = nodes[child];
      alignas(16) float d[4];
      unsigned mask = bvh4_detail::intersect_boxes(n, rb, tmax, d);
      const uint32_t* src = nullptr;
      if constexpr (Observer::kActive) {
        src = &slot_source[4 * size_t(child)];
        for (int k = 0; k < 4; ++k)
          if (src[k] != ~0u) obs.on_box_test();
      }
      if constexpr (AnyHit) {
        if (mask != 0) {
          // Any hit: no ordering, visit the first child hit, push the others.
          unsigned k = unsigned(__builtin_ctz(mask));
          child = n.child[k];
          count = n.count[k];
          if constexpr (Observer::kActive) source = src[k];
          for (mask &= mask - 1; mask != 0; mask &= mask - 1) {
            k = unsigned(__builtin_ctz(mask));
            assert(sp < kStackSize);
            stack[sp] = {n.child[k], n.count[k], d[k]};
            if constexpr (Observer::kActive) source_stack[sp] = src[k];
            ++sp;
          }
          continue;
        }
      } else if (mask != 0) {
        const unsigned k0 = unsigned(__builtin_ctz(mask));
        mask &= mask - 1;
        if (mask == 0) {  // one child hit: go there
          child = n.child[k0];
          count = n.count[k0];
          if constexpr (Observer::kActive) source = src[k0];
          continue;
        }
        const unsigned k1 = unsigned(__builtin_ctz(mask));
        mask &= mask - 1;
        if (mask == 0) {  // two: push the farther, visit the nearer
          const bool swap = d[k1] < d[k0];
          const unsigned kn = swap ? k1 : k0, kf = swap ? k0 : k1;
          assert(sp < kStackSize);
          stack[sp] = {n.child[kf], n.count[kf], d[kf]};
          if constexpr (Observer::kActive) source_stack[sp] = src[kf];
          ++sp;
          child = n.child[kn];
          count = n.count[kn];
          if constexpr (Observer::kActive) source = src[kn];
          continue;
        }
        // Three or four: sort by entry distance, farthest first, push all but
        // the nearest.
        unsigned ks[4] = {k0, k1, unsigned(__builtin_ctz(mask)), 0};
        mask &= mask - 1;
        int m = 3;
        if (mask != 0) ks[m++] = unsigned(__builtin_ctz(mask));
        for (int a = 1; a < m; ++a) {
          const unsigned x = ks[a];
          int b = a - 1;
          while (b >= 0 && d[ks[b]] < d[x]) {
            ks[b + 1] = ks[b];
            --b;
          }
          ks[b + 1] = x;
        }
        for (int a = 0; a < m - 1; ++a) {
          const unsigned k = ks[a];
          assert(sp < kStackSize);
          stack[sp] = {n.child[k], n.count[k], d[k]};
          if constexpr (Observer::kActive) source_stack[sp] = src[k];
          ++sp;
        }
        const unsigned kn = ks[m - 1];
        child = n.child[kn];
        count = n.count[kn];
        if constexpr (Observer::kActive) source = src[kn];
        continue;
      }
    }
    // Pop the next node that can still hold a closer hit.
    for (;;) {
      if (sp == 0) return hit;
      --sp;
      const Entry& e = stack[sp];
      if (AnyHit || e.tnear <= tmax * kBoxFarScale) {
        child = e.child;
        count = e.count;
        if constexpr (Observer::kActive) source = source_stack[sp];
        break;
      }
      if constexpr (Observer::kActive) obs.on_cull(source_stack[sp]);
    }
  }
}

}  // namespace rayscope
