// The packet calls of the aggregate (Aggregate::intersect_packet and
// occluded_packet): inline, so that each translation unit, and each copy of
// the hot loops (kernels.h), walks packets with the instructions it is
// compiled for. Included by aggregate.h.
#pragma once

#include <stdexcept>
#include <string>

#include "rayscope/aggregate.h"

namespace rayscope {

inline const BvhWalk* Aggregate::packet_walk(std::span<const Ray> rays, RayPacket& packet) const {
  if (rays.size() > size_t(kPacketRays))
    throw std::invalid_argument("Aggregate: " + std::to_string(rays.size()) +
                                " rays for a packet of at most " + std::to_string(kPacketRays));
  const BvhWalk* w = use_walk_ ? std::get_if<BvhWalk>(&structure_) : nullptr;
  return w != nullptr && packet.load(rays) ? w : nullptr;
}

namespace packet_detail {
inline namespace RAYSCOPE_ISA {  // isa.h

// A packet's lane as a single-ray observer: the walk of a ray traced alone,
// counted in its lane of a PacketWalkCost.
struct LaneCost : TraversalHooks {
  static constexpr bool kActive = true;
  static constexpr bool kNodeIds = false;
  PacketWalkCost* c;
  unsigned lane;
  void on_node(uint32_t) { c->nodes[lane]++; }
  void on_box_test(uint32_t, bool) { c->boxes[lane]++; }
  void on_cull(uint32_t) { c->culled[lane]++; }
  void on_prim_test(uint32_t) { c->prims[lane]++; }
};

// The single-ray observer of lane k: a LaneCost, or none.
template <class Cost>
auto lane_observer(Cost& cost, size_t k) {
  if constexpr (Cost::kActive) {
    cost.fell_back = true;
    return LaneCost{{}, &cost, unsigned(k)};
  } else {
    return NullTraversalObserver{};
  }
}

// The packet calls' fallback: one(k, observer) traces rays[k] alone with its
// lane's observer and says whether it hit; returns the lanes that did.
template <class Cost, class One>
unsigned each_ray_alone(std::span<const Ray> rays, Cost& cost, One&& one) {
  unsigned found = 0;
  for (size_t k = 0; k < rays.size(); ++k) {
    auto lane = lane_observer(cost, k);
    if (one(k, lane)) found |= 1u << k;
  }
  return found;
}

}  // namespace RAYSCOPE_ISA
}  // namespace packet_detail

template <class Cost>
unsigned Aggregate::intersect_packet(std::span<const Ray> rays, PrimHit* hits, Cost& cost) const {
  NullTraversalObserver obs;
  RayPacket packet;
  const BvhWalk* w = packet_walk(rays, packet);
  if (w == nullptr)
    return packet_detail::each_ray_alone(
        rays, cost, [&](size_t k, auto& lane) { return intersect(rays[k], hits[k], lane); });
  unsigned found = 0;
  TrianglePrecomp pre[kPacketRays];
  ClosestSoFar closest[kPacketRays];
  for (size_t k = 0; k < rays.size(); ++k) pre[k] = TrianglePrecomp(rays[k]);
  const TestedRecords recs = tested_records<NullTraversalObserver>();
  auto prim = [&](unsigned lane, uint32_t i, float& t, const TriangleHit* decided)
      __attribute__((always_inline)) {
    return offer_closest(i, rays[lane], pre[lane], t, decided, recs, closest[lane], obs);
  };
  w->traverse_packet<false>(packet, pre, prim, cost);
  for (size_t k = 0; k < rays.size(); ++k)
    if (closest_with_planes(rays[k], packet.tmax[k], closest[k], hits[k], obs)) found |= 1u << k;
  return found;
}

template <class Cost>
unsigned Aggregate::occluded_packet(std::span<const Ray> rays, Cost& cost) const {
  RayPacket packet;
  const BvhWalk* w = packet_walk(rays, packet);
  if (w == nullptr)
    return packet_detail::each_ray_alone(
        rays, cost, [&](size_t k, auto& lane) { return occluded(rays[k], lane); });
  unsigned found = 0;
  TrianglePrecomp pre[kPacketRays];
  for (size_t k = 0; k < rays.size(); ++k) {
    float tp;
    if (first_plane_hit(rays[k], tp) >= 0) found |= 1u << k;
    pre[k] = TrianglePrecomp(rays[k]);
  }
  packet.valid &= ~found;
  const TestedRecords recs = tested_records<NullTraversalObserver>();
  auto prim = [&](unsigned lane, uint32_t i, float& t, const TriangleHit* decided)
      __attribute__((always_inline)) {
    TriangleHit th;
    return decided != nullptr || test_prim(recs(i, ids_[i]), rays[lane], pre[lane], t, false, th);
  };
  return found | w->traverse_packet<true>(packet, pre, prim, cost);
}

inline unsigned Aggregate::intersect_packet(std::span<const Ray> rays, PrimHit* hits,
                                            PacketWalkCost* cost) const {
  if (cost) return intersect_packet(rays, hits, *cost);
  NoPacketWalkCost none;
  return intersect_packet(rays, hits, none);
}

inline unsigned Aggregate::occluded_packet(std::span<const Ray> rays, PacketWalkCost* cost) const {
  if (cost) return occluded_packet(rays, *cost);
  NoPacketWalkCost none;
  return occluded_packet(rays, none);
}

}  // namespace rayscope
