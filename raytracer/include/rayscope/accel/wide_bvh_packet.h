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
          cost.enter(mask);
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
      if constexpr (Cost::kActive) cost.enter(mask);
      for (int k = 0; k < WideBvhNode::kWidth; ++k) {
        if (n.child[k] == WideBvhNode::kLeaf && n.count[k] == 0) break;  // empty slots
        if constexpr (Cost::kActive) cost.add(cost.boxes, mask, 1);
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
