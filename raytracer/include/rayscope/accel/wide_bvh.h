// The walk of the BVH: the binary tree (bvh.h) collapsed into nodes of up to
// eight children, whose boxes are stored per axis and bound so that one AVX
// instruction (two SSE ones on a CPU without AVX) computes one slab of all
// eight boxes.
//
// This is the one BVH traversal in RayScope. Renders walk the tree collapsed
// with arity kRenderArity (AccelKind::Bvh): each wide node replaces a binary
// node and up to two or three levels of its descendants, so a wide node costs
// one visit and one 8-box test instead of up to seven visits with two scalar
// box tests each, and the tree has about a third of the levels. The teaching
// walk (AccelKind::BinaryBvh) is the same code on the tree collapsed with
// arity 2: every wide node is then exactly one binary node, and the walk is
// the lecture's binary walk, node by node. The leaves are the binary leaves,
// unchanged.
//
// Observers see binary node ids either way (see traverse()).
//
// The box test is intersect_box() exactly, eight lanes at a time: same
// sign-selected planes, same operations in the same order, NaN ignored the same
// way (min/max take the running value as the second operand), exit distance
// rounded up by kBoxFarScale. A child is hit here exactly when intersect_box()
// would report it hit, with the same entry distance.
#pragma once

#include <bit>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "rayscope/accel/bvh.h"
#include "rayscope/accel/ray_packet.h"
#include "rayscope/isa.h"
#include "rayscope/traversal.h"

namespace rayscope {

/// One node of the wide hierarchy (256 bytes, four cache lines): the boxes of up
/// to eight children, one array of eight floats per axis and bound.
struct alignas(64) WideBvhNode {
  /// Child slots per node: the lanes of one box test.
  static constexpr int kWidth = 8;
  /// Set in `child` for a leaf child: the low bits are then its label (see
  /// WideBvh::build()), and `count` the number of its primitives.
  static constexpr uint32_t kLeaf = 0x80000000u;

  float lo_x[kWidth], hi_x[kWidth], lo_y[kWidth], hi_y[kWidth], lo_z[kWidth], hi_z[kWidth];
  /// Inner child: index of its WideBvhNode. Leaf child: kLeaf | its label
  /// (WideBvh::build(): the leaf's first primitive, or what the owner maps it to).
  /// Empty slot (nodes with fewer than kWidth children; always the last
  /// slots): kLeaf with count 0 and an empty box (lo = +inf, hi = -inf) that
  /// no ray with a finite origin hits.
  uint32_t child[kWidth];
  uint32_t count[kWidth];  ///< Primitives of a leaf child; 0 for inner children and empty slots.
};
static_assert(sizeof(WideBvhNode) == 256);

class WideBvh {
 public:
  /// Most children per node (the box test's width).
  static constexpr int kMaxArity = WideBvhNode::kWidth;
  /// The arity renders walk (AccelKind::Bvh).
  static constexpr int kRenderArity = kMaxArity;
  /// Entries of the traversal stack. A wide node pushes at most kMaxArity - 1
  /// children, so a walk needs at most (kMaxArity - 1) * depth() entries;
  /// build() checks that the collapsed tree fits (Bvh's builder caps the
  /// binary depth at 64 levels, and the wide tree is never deeper than the
  /// binary one).
  static constexpr int kStackSize = (kMaxArity - 1) * 64 + 4;

  /// Collapses `bvh` into nodes of at most `arity` children (2..kMaxArity; 2
  /// keeps the binary tree's shape). Everything needed is copied. An empty
  /// `bvh` gives an empty hierarchy that every ray misses. A leaf is labelled
  /// by its first primitive `f` (the offset in Bvh::prim_indices), or by
  /// leaf_label[f] when leaf_label is given (one entry per primitive; only
  /// the leaves' first entries are read): the label is what traverse() passes
  /// to `leaf` (the aggregate labels a leaf by its first lane of triangle
  /// blocks, so that the walk reaches the block with no other load). Throws
  /// std::invalid_argument for a bad arity or a leaf_label of the wrong size,
  /// std::length_error if the tree were too deep for the traversal stack or a
  /// label did not fit beside kLeaf.
  void build(const Bvh& bvh, int arity = kMaxArity, std::span<const uint32_t> leaf_label = {});

  bool empty() const { return root_child_ == kNone; }
  /// Children per node at most (what build() was given).
  int arity() const { return arity_; }
  /// Levels of wide nodes on the longest path (0 when the root is a leaf).
  uint32_t depth() const { return depth_; }
  /// The root's box, the one the walks test first (the binary root's);
  /// empty for an empty hierarchy.
  Bounds3 root_bounds() const { return Bounds3(root_lo_, root_hi_); }
  size_t memory_bytes() const {
    return nodes.size() * sizeof(WideBvhNode) + slot_source.size() * sizeof(uint32_t);
  }

  /// Walks the nodes the ray [origin, origin + tmax * dir] can reach.
  /// `leaf(label, count, tmax)` tests the `count` primitives of the leaf
  /// labelled `label` (build(): without labels, prim_indices[label .. label +
  /// count) of the binary hierarchy) and returns true on a hit, lowering
  /// tmax to the hit distance. Children whose boxes are hit are visited nearest
  /// first (ties: in the binary tree's child order); with AnyHit the walk stops
  /// at the first hit (shadow rays) and does not order children; otherwise it
  /// skips every node whose entry distance is beyond the closest hit so far
  /// (early termination; "beyond" by more than the box test's rounding margin
  /// kBoxFarScale, so that the decision does not depend on whether a node is
  /// tested before or after the hit is found). Returns whether anything was hit.
  ///
  /// Observer hooks (traversal.h), all with ids of the *binary* hierarchy
  /// (Bvh::nodes): on_box_test(0, hit) for the root box; on_node(id) when a
  /// wide node is entered (reported as the binary node at the top of the
  /// subtree it replaces) or a leaf is tested; on_box_test(id, hit) for each
  /// child box tested (every non-empty slot of an entered wide node);
  /// on_cull(id) for a pushed node skipped by early termination. With arity 2
  /// this is exactly the binary walk: every binary node entered, both child
  /// boxes of each inner node tested. The ids are read from `sources`, laid
  /// out as slot_source (null: slot_source itself); an observer that reads
  /// no ids (TraversalHooks::kNodeIds false) is given 0 for every node.
  template <bool AnyHit, class Observer, class LeafFn>
  bool traverse(const Ray& ray, float& tmax, LeafFn&& leaf, Observer& obs,
                const uint32_t* sources = nullptr) const;

  /// traverse() for the rays of a packet at once (wide_bvh_packet.h):
  /// `leaf(lanes, label, count)` tests the leaf's primitives for the rays in
  /// `lanes`, as traverse()'s leaf does for one ray, lowers their tmax in
  /// packet.tmax at each hit, and returns the lanes that hit. Each ray tests
  /// every leaf its own walk would reach, and maybe a few more; with AnyHit a
  /// ray leaves the packet at its first hit. Returns the lanes that hit
  /// something. `cost` counts the walk's work per ray (PacketWalkCost) or
  /// nothing (NoPacketWalkCost).
  template <bool AnyHit, class LeafFn, class Cost = NoPacketWalkCost>
  unsigned traverse_packet(RayPacket& packet, LeafFn&& leaf, Cost& cost) const;

  std::vector<WideBvhNode> nodes;  ///< nodes[0] is the root unless the root is a leaf.
  /// Binary node id of child slot k of wide node n at [kWidth n + k]; ~0u for
  /// empty slots. Only observers read it (the aggregate's BVH keeps it
  /// elsewhere, made when first asked for: BvhWalk::slot_sources()).
  std::vector<uint32_t> slot_source;

 private:
  static constexpr uint32_t kNone = ~0u;
  uint32_t collapse(const Bvh& bvh, std::span<const uint32_t> leaf_label, uint32_t binary_node,
                    uint32_t level);

  Vec3 root_lo_{kInfinity}, root_hi_{-kInfinity};
  uint32_t root_child_ = kNone;  ///< 0 (wide node 0), kLeaf | label, or kNone when empty.
  uint32_t root_count_ = 0;
  uint32_t depth_ = 0;
  int arity_ = kMaxArity;
};

// ---------------------------------------------------------------------------

namespace wide_bvh_detail {

inline namespace RAYSCOPE_ISA {  // isa.h: compiled once per x86-64 level (kernels.h)

/// Per-ray constants of the 8-wide box test.
struct RayBoxes {
#if defined(__AVX__)
  __m256 ox, oy, oz, ix, iy, iz;
#endif
  Vec3 origin, inv_dir;
  // Byte offsets of the near and far plane arrays of each axis in a WideBvhNode
  // (lo_x at 0, hi_x at 32, lo_y at 64, ...), chosen by the direction's sign.
  uint32_t near_x, far_x, near_y, far_y, near_z, far_z;

  RayBoxes(const Vec3& o, const Vec3& inv) : origin(o), inv_dir(inv) {
#if defined(__AVX__)
    ox = _mm256_set1_ps(o.x);
    oy = _mm256_set1_ps(o.y);
    oz = _mm256_set1_ps(o.z);
    ix = _mm256_set1_ps(inv.x);
    iy = _mm256_set1_ps(inv.y);
    iz = _mm256_set1_ps(inv.z);
#endif
    constexpr uint32_t row = WideBvhNode::kWidth * sizeof(float);
    near_x = std::signbit(inv.x) ? row : 0;
    near_y = std::signbit(inv.y) ? 3 * row : 2 * row;
    near_z = std::signbit(inv.z) ? 5 * row : 4 * row;
    far_x = near_x ^ row;
    far_y = near_y ^ row;
    far_z = near_z ^ row;
  }
};
static_assert(std::has_single_bit(WideBvhNode::kWidth * sizeof(float)),
              "far = near ^ row needs rows of a power-of-two size");

inline const float* plane(const WideBvhNode& n, uint32_t offset) {
  return reinterpret_cast<const float*>(reinterpret_cast<const char*>(&n) + offset);
}

/// intersect_box() for the children of `n`, one lane at a time: the portable
/// fallback of intersect_boxes() (and its reference in the tests). Returns a
/// bit mask of the children hit within [0, tmax] and stores their entry
/// distances in tnear.
inline unsigned intersect_boxes_scalar(const WideBvhNode& n, const RayBoxes& r, float tmax,
                                       float tnear[WideBvhNode::kWidth]) {
  unsigned mask = 0;
  const float* nx = plane(n, r.near_x);
  const float* fx = plane(n, r.far_x);
  const float* ny = plane(n, r.near_y);
  const float* fy = plane(n, r.far_y);
  const float* nz = plane(n, r.near_z);
  const float* fz = plane(n, r.far_z);
  for (int k = 0; k < WideBvhNode::kWidth; ++k) {
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
}

#if defined(__SSE2__)
/// Four lanes of intersect_boxes() from lane `first` on, with SSE: the
/// fallback where AVX is missing (and a reference for the AVX test).
[[gnu::always_inline]] inline unsigned intersect_boxes_sse(const WideBvhNode& n, const RayBoxes& r,
                                                           float tmax, float* tnear, int first) {
  auto at = [&](uint32_t offset) { return _mm_load_ps(plane(n, offset) + first); };
  const __m128 ox = _mm_set1_ps(r.origin.x), oy = _mm_set1_ps(r.origin.y),
               oz = _mm_set1_ps(r.origin.z);
  const __m128 ix = _mm_set1_ps(r.inv_dir.x), iy = _mm_set1_ps(r.inv_dir.y),
               iz = _mm_set1_ps(r.inv_dir.z);
  const __m128 tnx = _mm_mul_ps(_mm_sub_ps(at(r.near_x), ox), ix);
  const __m128 tfx = _mm_mul_ps(_mm_sub_ps(at(r.far_x), ox), ix);
  const __m128 tny = _mm_mul_ps(_mm_sub_ps(at(r.near_y), oy), iy);
  const __m128 tfy = _mm_mul_ps(_mm_sub_ps(at(r.far_y), oy), iy);
  const __m128 tnz = _mm_mul_ps(_mm_sub_ps(at(r.near_z), oz), iz);
  const __m128 tfz = _mm_mul_ps(_mm_sub_ps(at(r.far_z), oz), iz);
  __m128 tn = _mm_max_ps(tnx, _mm_setzero_ps());
  tn = _mm_max_ps(tny, tn);
  tn = _mm_max_ps(tnz, tn);
  __m128 tf = _mm_min_ps(tfx, _mm_set1_ps(tmax));
  tf = _mm_min_ps(tfy, tf);
  tf = _mm_min_ps(tfz, tf);
  tf = _mm_mul_ps(tf, _mm_set1_ps(kBoxFarScale));
  _mm_storeu_ps(tnear + first, tn);
  return unsigned(_mm_movemask_ps(_mm_cmple_ps(tn, tf))) << first;
}
#endif

/// intersect_box() for the children of `n`: AVX where the compiler targets it
/// (eight lanes at once), else SSE (two halves of four), else
/// intersect_boxes_scalar(). Same mask and distances.
[[gnu::always_inline]] inline unsigned intersect_boxes(const WideBvhNode& n, const RayBoxes& r,
                                                       float tmax,
                                                       float tnear[WideBvhNode::kWidth]) {
#if defined(__AVX__)
  const __m256 tnx = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(plane(n, r.near_x)), r.ox), r.ix);
  const __m256 tfx = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(plane(n, r.far_x)), r.ox), r.ix);
  const __m256 tny = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(plane(n, r.near_y)), r.oy), r.iy);
  const __m256 tfy = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(plane(n, r.far_y)), r.oy), r.iy);
  const __m256 tnz = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(plane(n, r.near_z)), r.oz), r.iz);
  const __m256 tfz = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(plane(n, r.far_z)), r.oz), r.iz);
  // max(a, b) is a > b ? a : b and min(a, b) is a < b ? a : b: with the
  // running value as b, a NaN slab (ray in a face plane) leaves it alone,
  // exactly like intersect_box's "if (tn > tnear) tnear = tn".
  __m256 tn = _mm256_max_ps(tnx, _mm256_setzero_ps());
  tn = _mm256_max_ps(tny, tn);
  tn = _mm256_max_ps(tnz, tn);
  __m256 tf = _mm256_min_ps(tfx, _mm256_set1_ps(tmax));
  tf = _mm256_min_ps(tfy, tf);
  tf = _mm256_min_ps(tfz, tf);
  tf = _mm256_mul_ps(tf, _mm256_set1_ps(kBoxFarScale));
  _mm256_storeu_ps(tnear, tn);
  return unsigned(_mm256_movemask_ps(_mm256_cmp_ps(tn, tf, _CMP_LE_OQ)));
#elif defined(__SSE2__)
  static_assert(WideBvhNode::kWidth == 8);
  return intersect_boxes_sse(n, r, tmax, tnear, 0) | intersect_boxes_sse(n, r, tmax, tnear, 4);
#else
  return intersect_boxes_scalar(n, r, tmax, tnear);
#endif
}

/// Sorts the child slots ks[0 .. m) by key[slot], farthest first; of equal
/// keys the later slot first, so that the earlier is visited first (the
/// binary tree's order). Insertion sort: m is at most eight.
[[gnu::always_inline]] inline void sort_farthest_first(unsigned* ks, int m, const float* key) {
  for (int a = 1; a < m; ++a) {
    const unsigned x = ks[a];
    int b = a - 1;
    while (b >= 0 && key[ks[b]] <= key[x]) {
      ks[b + 1] = ks[b];
      --b;
    }
    ks[b + 1] = x;
  }
}

}  // namespace RAYSCOPE_ISA
}  // namespace wide_bvh_detail

template <bool AnyHit, class Observer, class LeafFn>
bool WideBvh::traverse(const Ray& ray, float& tmax, LeafFn&& leaf, Observer& obs,
                       [[maybe_unused]] const uint32_t* sources) const {
  if (root_child_ == kNone) return false;
  // The binary ids, for an observer that reads them.
  constexpr bool kIds = Observer::kActive && Observer::kNodeIds;
  if constexpr (kIds)
    if (sources == nullptr) sources = slot_source.data();
  const Vec3 inv_dir = 1.0f / ray.dir;
  const bool root_hit = intersect_box(root_lo_, root_hi_, ray.origin, inv_dir, tmax) != kInfinity;
  if constexpr (Observer::kActive) obs.on_box_test(0, root_hit);
  if (!root_hit) return false;
  const wide_bvh_detail::RayBoxes rb(ray.origin, inv_dir);

  struct Entry {
    uint32_t child, count;
    float tnear;
  };
  Entry stack[kStackSize];
  [[maybe_unused]] uint32_t source_stack[kIds ? kStackSize : 1];
  int sp = 0;
  uint32_t child = root_child_, count = root_count_;
  [[maybe_unused]] uint32_t source = 0;  // binary node id of `child`, for the observer
  bool hit = false;
  for (;;) {
    if (child & WideBvhNode::kLeaf) {
      // (count == 0: an empty slot, reached only by rays with a NaN origin.)
      if (count != 0) {
        if constexpr (Observer::kActive) obs.on_node(source);
        if (leaf(child & ~WideBvhNode::kLeaf, count, tmax)) {
          hit = true;
          if constexpr (AnyHit) return true;
        }
      }
    } else {
      if constexpr (Observer::kActive) obs.on_node(source);
      const WideBvhNode& n = nodes[child];
      alignas(32) float d[WideBvhNode::kWidth];
      unsigned mask = wide_bvh_detail::intersect_boxes(n, rb, tmax, d);
      const uint32_t* src = nullptr;
      if constexpr (kIds) {
        src = &sources[WideBvhNode::kWidth * size_t(child)];
        for (int k = 0; k < WideBvhNode::kWidth; ++k)
          if (src[k] != ~0u) obs.on_box_test(src[k], (mask >> k) & 1u);
      } else if constexpr (Observer::kActive) {
        for (int k = 0; k < WideBvhNode::kWidth; ++k)
          if (!((n.child[k] & WideBvhNode::kLeaf) && n.count[k] == 0))  // not an empty slot
            obs.on_box_test(0, (mask >> k) & 1u);
      }
      if constexpr (AnyHit) {
        if (mask != 0) {
          // Any hit: no ordering, visit the first child hit, push the others.
          unsigned k = unsigned(__builtin_ctz(mask));
          child = n.child[k];
          count = n.count[k];
          if constexpr (kIds) source = src[k];
          for (mask &= mask - 1; mask != 0; mask &= mask - 1) {
            k = unsigned(__builtin_ctz(mask));
            assert(sp < kStackSize);
            stack[sp] = {n.child[k], n.count[k], d[k]};
            if constexpr (kIds) source_stack[sp] = src[k];
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
          if constexpr (kIds) source = src[k0];
          continue;
        }
        const unsigned k1 = unsigned(__builtin_ctz(mask));
        mask &= mask - 1;
        if (mask == 0) {  // two: push the farther, visit the nearer
          const bool swap = d[k1] < d[k0];
          const unsigned kn = swap ? k1 : k0, kf = swap ? k0 : k1;
          assert(sp < kStackSize);
          stack[sp] = {n.child[kf], n.count[kf], d[kf]};
          if constexpr (kIds) source_stack[sp] = src[kf];
          ++sp;
          child = n.child[kn];
          count = n.count[kn];
          if constexpr (kIds) source = src[kn];
          continue;
        }
        // Three or more: sort by entry distance, farthest first (of equal
        // distances the later slot first, so that the earlier is visited
        // first, as in the binary tree's order), push all but the nearest.
        unsigned ks[WideBvhNode::kWidth] = {k0, k1};
        int m = 2;
        for (; mask != 0; mask &= mask - 1) ks[m++] = unsigned(__builtin_ctz(mask));
        wide_bvh_detail::sort_farthest_first(ks, m, d);
        for (int a = 0; a < m - 1; ++a) {
          const unsigned k = ks[a];
          assert(sp < kStackSize);
          stack[sp] = {n.child[k], n.count[k], d[k]};
          if constexpr (kIds) source_stack[sp] = src[k];
          ++sp;
        }
        const unsigned kn = ks[m - 1];
        child = n.child[kn];
        count = n.count[kn];
        if constexpr (kIds) source = src[kn];
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
        if constexpr (kIds) source = source_stack[sp];
        break;
      }
      if constexpr (kIds)
        obs.on_cull(source_stack[sp]);
      else if constexpr (Observer::kActive)
        obs.on_cull(0);
    }
  }
}

}  // namespace rayscope
