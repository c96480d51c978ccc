// The BVH walk of a packet (ray_packet.h): the rays of the packet walk the
// wide hierarchy together, one node at a time, each node's boxes tested for
// every ray of the packet with one vector operation per step.
//
// Each lane of a box test is intersect_box() for its ray, with the same
// operations in the same order as the single-ray walk (wide_bvh.h), so a ray
// enters a node in the packet exactly when its own walk would test that node's
// box as hit with the same tmax. The packet visits a node when any of its rays
// hits it, and tests a leaf's primitives only for the rays that hit the leaf's
// box. A node popped from the stack is culled for the rays whose entry
// distance is beyond their closest hit so far (the single-ray rule, per ray).
// What differs from one ray's walk is the order: the packet enters children
// nearest first for its first ray that hits them, and a ray may test a leaf
// that its own walk would have culled after a closer hit. The closest hit
// itself does not depend on the order (the aggregate's tie rule), so the
// answers are the single-ray walk's.
#pragma once

#include <algorithm>
#include <cassert>
#include <cstdint>

#include "rayscope/accel/ray_packet.h"
#include "rayscope/accel/wide_bvh.h"

namespace rayscope {

template <bool AnyHit, class LeafFn, class Cost>
unsigned WideBvh::traverse_packet(RayPacket& p, LeafFn&& leaf, Cost& cost) const {
  using packet_detail::Lanes;
  using packet_detail::lanes_le;
  if (root_child_ == kNone || p.valid == 0) return 0;
  const Lanes zero = {};
  // intersect_box() in every lane of `lanes`, given the near and far planes
  // of each axis: the lanes that hit, and their entry distances in tn.
  const auto boxes = [&](float nx, float fx, float ny, float fy, float nz, float fz, unsigned lanes,
                         Lanes& tn) __attribute__((always_inline)) {
    Lanes t = (nx - p.ox) * p.ix;
    tn = t > zero ? t : zero;
    t = (ny - p.oy) * p.iy;
    tn = t > tn ? t : tn;
    t = (nz - p.oz) * p.iz;
    tn = t > tn ? t : tn;
    Lanes tf = (fx - p.ox) * p.ix;
    tf = tf < p.tmax ? tf : p.tmax;
    t = (fy - p.oy) * p.iy;
    tf = t < tf ? t : tf;
    t = (fz - p.oz) * p.iz;
    tf = t < tf ? t : tf;
    tf = tf * kBoxFarScale;
    return lanes_le(tn, tf) & lanes;
  };

  const bool neg_x = p.negative & 1u, neg_y = p.negative & 2u, neg_z = p.negative & 4u;
  unsigned alive = p.valid;  // with AnyHit: the rays not yet occluded
  unsigned mask;             // the rays that entered the current node
  {
    Lanes tn;
    mask = boxes(neg_x ? root_hi_.x : root_lo_.x, neg_x ? root_lo_.x : root_hi_.x,
                 neg_y ? root_hi_.y : root_lo_.y, neg_y ? root_lo_.y : root_hi_.y,
                 neg_z ? root_hi_.z : root_lo_.z, neg_z ? root_lo_.z : root_hi_.z, alive, tn);
  }
  if constexpr (Cost::kActive) cost.add(cost.boxes, alive, 1);
  if (mask == 0) return 0;
  // Byte offsets of the near and far plane rows in a WideBvhNode, as in
  // wide_bvh_detail::RayBoxes.
  const wide_bvh_detail::RayBoxes rb(
      Vec3(0.0f), Vec3(neg_x ? -1.0f : 1.0f, neg_y ? -1.0f : 1.0f, neg_z ? -1.0f : 1.0f));

  // The packet's frustum, for a test of a node's child boxes against all
  // its rays at once before the rays' own tests: along each axis the range
  // of the rays' origins and of their reciprocal directions (one sign), and
  // the largest tmax. Float subtraction and multiplication round
  // monotonically, so the bounds computed from the ranges' ends bound every
  // ray's own float results, and a child the frustum misses is missed by
  // every ray's test (see frustum_misses).
  using Slots = float __attribute__((vector_size(WideBvhNode::kWidth * sizeof(float))));
  struct AxisRange {
    float olo, ohi, ilo, ihi;
  };
  auto axis_range = [&](const Lanes& o, const Lanes& i) {
    AxisRange r{o[0], o[0], i[0], i[0]};
    for (int k = 1; k < kPacketRays; ++k) {
      r.olo = std::min(r.olo, o[k]);
      r.ohi = std::max(r.ohi, o[k]);
      r.ilo = std::min(r.ilo, i[k]);
      r.ihi = std::max(r.ihi, i[k]);
    }
    return r;
  };
  const AxisRange ax = axis_range(p.ox, p.ix), ay = axis_range(p.oy, p.iy),
                  az = axis_range(p.oz, p.iz);
  float tmax_hi = p.tmax[0];
  for (int k = 1; k < kPacketRays; ++k) tmax_hi = std::max(tmax_hi, p.tmax[k]);
  const Slots inf = Slots{} + kInfinity, zero8 = {};
  // The lowest entry and highest exit distance of any ray along one axis,
  // for each slot's near planes nv and far planes fv. Where a product is
  // NaN (0 * inf) the ray's own test ignores that axis, and so does this.
  auto axis_bounds = [&](const float* nv, const float* fv, const AxisRange& r, bool neg, Slots& lo,
                         Slots& hi) __attribute__((always_inline)) {
    Slots n, f;
    __builtin_memcpy(&n, nv, sizeof n);
    __builtin_memcpy(&f, fv, sizeof f);
    const Slots x = n - (neg ? r.olo : r.ohi), y = f - (neg ? r.ohi : r.olo);
    const Slots a = x * r.ilo, b = x * r.ihi, c = y * r.ilo, d = y * r.ihi;
    lo = a < b ? a : b;
    lo = ((a == a) & (b == b)) ? lo : -inf;
    hi = c > d ? c : d;
    hi = ((c == c) & (d == d)) ? hi : inf;
  };
  // Bit k set when every ray of the packet misses child slot k.
  auto frustum_misses = [&](const float* nx, const float* fx, const float* ny, const float* fy,
                            const float* nz, const float* fz) __attribute__((always_inline)) {
    Slots lo, hi, l, h;
    axis_bounds(nx, fx, ax, neg_x, lo, hi);
    lo = lo > zero8 ? lo : zero8;
    axis_bounds(ny, fy, ay, neg_y, l, h);
    lo = l > lo ? l : lo;
    hi = h < hi ? h : hi;
    axis_bounds(nz, fz, az, neg_z, l, h);
    lo = l > lo ? l : lo;
    hi = h < hi ? h : hi;
    hi = hi < tmax_hi ? hi : tmax_hi;
    hi = hi * kBoxFarScale;
    const auto miss = lo > hi;
    unsigned m = 0;
    for (int k = 0; k < WideBvhNode::kWidth; ++k) m |= unsigned(miss[k] != 0) << k;
    return m;
  };

  struct Entry {
    uint32_t child, count;
    unsigned mask;
  };
  Entry stack[kStackSize];
  Lanes stack_tn[kStackSize];  // each entry's entry distances, per ray
  int sp = 0;
  uint32_t child = root_child_, count = root_count_;
  unsigned hits = 0;
  for (;;) {
    if (child & WideBvhNode::kLeaf) {
      if (count != 0) {
        if constexpr (Cost::kActive) {
          cost.enter(child, count, mask);
          cost.add(cost.prims, mask, count);
        }
        const unsigned found = leaf(mask, child & ~WideBvhNode::kLeaf, count);
        hits |= found;
        if constexpr (AnyHit) {
          alive &= ~found;
          if (alive == 0) return hits;
        }
      }
    } else {
      const WideBvhNode& n = nodes[child];
      const float* nx = wide_bvh_detail::plane(n, rb.near_x);
      const float* fx = wide_bvh_detail::plane(n, rb.far_x);
      const float* ny = wide_bvh_detail::plane(n, rb.near_y);
      const float* fy = wide_bvh_detail::plane(n, rb.far_y);
      const float* nz = wide_bvh_detail::plane(n, rb.near_z);
      const float* fz = wide_bvh_detail::plane(n, rb.far_z);
      Lanes tn[WideBvhNode::kWidth];
      unsigned lanes[WideBvhNode::kWidth];
      float key[WideBvhNode::kWidth];  // entry distance of the first ray that hits
      unsigned ks[WideBvhNode::kWidth];
      int m = 0;
      if constexpr (Cost::kActive) cost.enter(child, 0, mask);
      const unsigned missed = frustum_misses(nx, fx, ny, fy, nz, fz);
      for (int k = 0; k < WideBvhNode::kWidth; ++k) {
        if (n.child[k] == WideBvhNode::kLeaf && n.count[k] == 0) break;  // empty slots
        if constexpr (Cost::kActive) cost.add(cost.boxes, mask, 1);
        if ((missed >> k) & 1u) continue;
        lanes[k] = boxes(nx[k], fx[k], ny[k], fy[k], nz[k], fz[k], mask, tn[k]);
        if (lanes[k] == 0) continue;
        key[k] = tn[k][__builtin_ctz(lanes[k])];
        ks[m++] = unsigned(k);
      }
      if (m != 0) {
        if constexpr (!AnyHit) {
          // Farthest first, so that the nearest is visited next and the
          // others are pushed.
          wide_bvh_detail::sort_farthest_first(ks, m, key);
        }
        for (int a = 0; a < m - 1; ++a) {
          const unsigned k = ks[a];
          assert(sp < kStackSize);
          stack[sp] = {n.child[k], n.count[k], lanes[k]};
          stack_tn[sp] = tn[k];
          ++sp;
        }
        const unsigned kn = ks[m - 1];
        child = n.child[kn];
        count = n.count[kn];
        mask = lanes[kn];
        continue;
      }
    }
    // Pop the next node that some ray can still reach with a closer hit.
    for (;;) {
      if (sp == 0) return hits;
      --sp;
      mask = stack[sp].mask & alive;
      if constexpr (!AnyHit) {
        const Lanes reach = p.tmax * kBoxFarScale;
        const unsigned pushed = mask;
        mask &= lanes_le(stack_tn[sp], reach);
        if constexpr (Cost::kActive) cost.add(cost.culled, pushed & ~mask, 1);
      }
      if (mask != 0) {
        child = stack[sp].child;
        count = stack[sp].count;
        break;
      }
    }
  }
}

}  // namespace rayscope
