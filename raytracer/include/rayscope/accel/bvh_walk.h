// The BVH as rays walk it (AccelKind::Bvh and BinaryBvh): the binary tree
// (bvh.h) collapsed into wide nodes (wide_bvh.h), arity 8 for renders or 2 for
// the lecture's binary walk, and each leaf's triangles stored by coordinate in
// blocks (triangle_block.h) that one SSE instruction tests four at a time.
// Range queries walk the binary tree itself, and the tools show it; both it
// and the binary node ids of the wide nodes' slots, which only observers
// read, are made when first asked for (bvh_on_demand.h), not for renders.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <new>
#include <span>
#include <string>
#include <vector>

#include "rayscope/accel/accel_kind.h"
#include "rayscope/accel/accel_structure.h"
#include "rayscope/accel/bvh.h"
#include "rayscope/accel/bvh_on_demand.h"
#include "rayscope/accel/prim_record.h"
#include "rayscope/accel/triangle_block.h"
#include "rayscope/accel/triangle_packet.h"
#include "rayscope/accel/wide_bvh.h"
#include "rayscope/accel/wide_bvh_packet.h"

namespace rayscope {

class BvhWalk {
 public:
  /// Collapses `built` into nodes of 8 children (AccelKind::Bvh) or 2
  /// (BinaryBvh) and fills the leaves' triangle blocks from record_at(i), the
  /// record at position i of its leaf order (called once for each, from
  /// several threads at once); records with id >= num_triangles (spheres,
  /// points, capsules) are left to the scalar test. `hierarchy` gives `built`
  /// again when the tools ask for it.
  void build(AccelKind kind, const Bvh& built, std::shared_ptr<const BvhOnDemand> hierarchy,
             const RecordSource& record_at, uint32_t num_triangles);
  /// Asks `hierarchy` for the binary tree from now on (a copy of the
  /// aggregate's, over the same records).
  void share_hierarchy(std::shared_ptr<const BvhOnDemand> hierarchy) {
    hierarchy_ = std::move(hierarchy);
  }
  /// What figures() reports as the build time (the caller times the binary
  /// build and this collapse together).
  void set_build_seconds(double s) { build_seconds_ = s; }

  /// The wide walk. Without an observer each leaf goes through its triangle
  /// blocks, and the walk decides every triangle (decide_lane): `prim(record,
  /// tmax, decided)` is called for the triangles hit within tmax (`decided`:
  /// the hit) and for the other primitives (null), in record order, so it
  /// finds what the plain loop finds. An active observer sees the plain loop,
  /// every record tested.
  template <bool AnyHit, class Observer, class PrimFn>
  [[gnu::always_inline]] bool traverse(const Ray& ray, float& tmax, PrimFn&& prim,
                                       Observer& obs) const {
    return traverse<AnyHit>(ray, TrianglePrecomp(ray), tmax, prim, obs);
  }
  /// The same with the ray's triangle-test constants already computed (the
  /// aggregate's, which its own primitive test uses too).
  template <bool AnyHit, class Observer, class PrimFn>
  [[gnu::always_inline]] bool traverse(const Ray& ray, const TrianglePrecomp& pre, float& tmax,
                                       PrimFn&& prim, Observer& obs) const;
  /// traverse() for the rays of a packet (wide_bvh_packet.h), with each
  /// lane's triangle-test constants (pre[lane]): `prim(lane, record, tmax,
  /// decided)` is traverse()'s prim for the ray in `lane`. Returns the lanes
  /// that hit something; packet.tmax holds their closest hits.
  /// `cost` counts the walk's work per ray (PacketWalkCost), or nothing.
  template <bool AnyHit, class PrimFn, class Cost>
  unsigned traverse_packet(RayPacket& packet, const TrianglePrecomp* pre, PrimFn&& prim,
                           Cost& cost) const;
  template <bool AnyHit, class PrimFn>
  unsigned traverse_packet(RayPacket& packet, const TrianglePrecomp* pre, PrimFn&& prim) const {
    NoPacketWalkCost none;
    return traverse_packet<AnyHit>(packet, pre, prim, none);
  }
  /// The binary tree's range walk (Bvh::walk_range).
  template <class Range, class Observer, class PrimFn>
  void walk_range(Range& range, PrimFn&& prim, Observer& obs) const {
    hierarchy_->get().walk_range(range, prim, obs);
  }

  AccelFigures figures() const;
  /// The wide nodes and triangle blocks, and the slot sources when made.
  size_t memory_bytes() const;
  /// The binary tree, node by node: the ids the walk reports.
  AccelView view() const;
  std::string stats_line() const;
  std::string walk_legend() const;

  /// The walked collapse of the binary tree (its slot_source is empty: see
  /// slot_sources()).
  const WideBvh& walk() const { return walk_; }
  /// The binary node id of each wide node's child slots, laid out as
  /// WideBvh::slot_source: made from the binary tree when first asked for
  /// (once, whichever thread asks first). Throws std::logic_error if the
  /// binary tree built again did not collapse into walk()'s nodes.
  std::span<const uint32_t> slot_sources() const;
  /// The leaves' records by coordinate, TriangleBlock::kLanes per block, in
  /// leaf order: lane k of a block holds record first + k; a leaf of up to
  /// kLanes records lies in one block, which it may share with the leaves
  /// before and after it.
  const std::vector<TriangleBlock>& triangle_blocks() const { return blocks_; }
  /// The records in leaf order made again from a walk's `blocks`
  /// (triangle_blocks()): each triangle's vertices from its lane, the other
  /// primitives' records from `others` (record id - num_triangles), every
  /// record's id from `ids` (leaf order). Static, so that a copy or move of
  /// the aggregate can make them from its own blocks.
  static std::vector<PrimRecord> records_from_blocks(std::span<const TriangleBlock> blocks,
                                                     std::span<const uint32_t> ids,
                                                     std::span<const PrimRecord> others,
                                                     uint32_t num_triangles);

 private:
  /// A leaf's `count` records from its first lane `start` on (the walk's
  /// label: block * kLanes + lane), through the block test: `prim(record,
  /// tmax, decided)` as traverse() says, in record order, so that it finds
  /// what the plain loop finds.
  template <bool AnyHit, class PrimFn>
  [[gnu::always_inline]] bool test_blocks(uint32_t block, uint32_t count,
                                          const TriangleBlockRay& block_ray, float& tmax,
                                          PrimFn&& prim) const;

  /// The record in lane `start` (a leaf's label): its first record.
  uint32_t first_record(uint32_t start) const {
    return blocks_[start / TriangleBlock::kLanes].first + start % TriangleBlock::kLanes;
  }

  /// slot_sources(), made once.
  struct SlotSources {
    std::once_flag once;
    std::atomic<bool> made{false};
    std::vector<uint32_t> ids;
  };

  AccelKind kind_ = AccelKind::Bvh;
  std::shared_ptr<const BvhOnDemand> hierarchy_ = std::make_shared<const BvhOnDemand>();
  std::shared_ptr<SlotSources> sources_ = std::make_shared<SlotSources>();
  WideBvh walk_;
  /// The leaves' records in leaf order, a leaf sharing the block before it
  /// when it fits in its lanes left; the walk's leaves are labelled by their
  /// first lane (block * kLanes + lane).
  std::vector<TriangleBlock> blocks_;
  double build_seconds_ = 0.0;
};

// ---------------------------------------------------------------------------

template <bool AnyHit, class Observer, class PrimFn>
inline bool BvhWalk::traverse(const Ray& ray, const TrianglePrecomp& pre, float& tmax,
                              PrimFn&& prim, Observer& obs) const {
  if constexpr (Observer::kActive) {
    auto leaf = [&](uint32_t start, uint32_t count, float& t) __attribute__((always_inline)) {
      return test_records<AnyHit>(first_record(start), count, t, prim);
    };
    const uint32_t* sources = nullptr;
    if constexpr (Observer::kNodeIds) sources = slot_sources().data();
    return walk_.traverse<AnyHit>(ray, tmax, leaf, obs, sources);
  } else {
    const TriangleBlockRay block_ray(pre);
    auto blocks = [&](uint32_t start, uint32_t count, float& t) __attribute__((always_inline)) {
      return test_blocks<AnyHit>(start, count, block_ray, t, prim);
    };
    return walk_.traverse<AnyHit>(ray, tmax, blocks, obs);
  }
}

// Lane `lane` of block `b` for the ray in lane k of a block or packet test's
// result `res`, as the walk passes it to prim(): a triangle the test hit, or
// left undecided and the whole test (TriangleBlock::test_lane) hits, within
// tmax (its hit in `th`, `decided` = &th); another primitive (`decided` =
// null), which prim() tests. Returns false for a triangle not hit within
// tmax: the walk decides every triangle, so the aggregate needs the records
// only of the other primitives.
template <class Result>
[[gnu::always_inline]] inline bool decide_lane(const TriangleBlock& b, unsigned lane,
                                               const Result& res, unsigned k,
                                               const TrianglePrecomp& pre, float tmax,
                                               TriangleHit& th, const TriangleHit*& decided) {
  decided = nullptr;
  if ((res.hits >> k) & 1u)
    th = res.hit(k);  // only triangles are hit
  else if (!((b.triangles >> lane) & 1u))
    return true;
  else if (!b.test_lane(lane, pre, tmax, th))
    return false;
  if (!(th.t <= tmax)) return false;  // beyond a hit found in this block
  decided = &th;
  return true;
}

template <bool AnyHit, class PrimFn>
[[gnu::always_inline]] inline bool BvhWalk::test_blocks(uint32_t start, uint32_t count,
                                                        const TriangleBlockRay& block_ray,
                                                        float& tmax, PrimFn&& prim) const {
  constexpr uint32_t kLanes = TriangleBlock::kLanes;
  bool found = false;
  const TriangleBlock* b = &blocks_[start / kLanes];
  TriangleBlockResult res;
  // The leaf's lanes of each of its blocks: from its first lane on (a leaf
  // that starts past lane 0 ends in that block), as many as it has left.
  for (uint32_t lo = start % kLanes, left = count; left != 0; ++b, lo = 0) {
    const uint32_t n = std::min(left, kLanes - lo);
    const unsigned lanes = ((1u << n) - 1u) << lo;
    left -= n;
    test_triangle_block<!AnyHit>(*b, block_ray, tmax, res);
    for (unsigned m = (res.hits | res.undecided) & lanes; m != 0; m &= m - 1) {
      const unsigned k = unsigned(__builtin_ctz(m));
      TriangleHit th;
      const TriangleHit* decided;
      if (!decide_lane(*b, k, res, k, block_ray.pre, tmax, th, decided)) continue;
      if (prim(b->first + k, tmax, decided)) {
        found = true;
        if constexpr (AnyHit) return true;
      }
    }
  }
  return found;
}

template <bool AnyHit, class PrimFn, class Cost>
inline unsigned BvhWalk::traverse_packet(RayPacket& packet, const TrianglePrecomp* pre,
                                         PrimFn&& prim, Cost& cost) const {
  TrianglePacketRays together;
  if (together.load(pre, packet.valid)) {
    // The rays share the triangle test's axes: each triangle is tested for
    // all of them at once, in record order.
    auto leaf = [&](unsigned lanes, uint32_t start, uint32_t count) __attribute__((always_inline)) {
      unsigned found = 0;
      const uint32_t first = first_record(start);
      TrianglePacketResult res;
      for (uint32_t j = 0; j < count; ++j) {
        const TriangleBlock& b = blocks_[(start + j) / TriangleBlock::kLanes];
        const unsigned lane = (start + j) % TriangleBlock::kLanes;
        test_triangle_packet(b, lane, together, packet.tmax, lanes, res);
        for (unsigned m = res.hits | res.undecided; m != 0; m &= m - 1) {
          const unsigned k = unsigned(__builtin_ctz(m));
          TriangleHit th;
          const TriangleHit* decided;
          float t = packet.tmax[k];
          if (!decide_lane(b, lane, res, k, pre[k], t, th, decided)) continue;
          if (prim(k, first + j, t, decided)) {
            packet.tmax[k] = t;
            found |= 1u << k;
            if constexpr (AnyHit) lanes &= ~(1u << k);
          }
        }
        if constexpr (AnyHit)
          if (lanes == 0) break;
      }
      return found;
    };
    return walk_.traverse_packet<AnyHit>(packet, leaf, cost);
  }
  // Otherwise each ray's leaves go through the block test, ray by ray, with
  // each lane's block-test constants made once per packet.
  union Lane {
    TriangleBlockRay ray;
    Lane() {}
  } rays[kPacketRays];
  for (unsigned m = packet.valid; m != 0; m &= m - 1) {
    const unsigned k = unsigned(__builtin_ctz(m));
    new (&rays[k].ray) TriangleBlockRay(pre[k]);
  }
  auto leaf = [&](unsigned lanes, uint32_t start, uint32_t count) __attribute__((always_inline)) {
    unsigned found = 0;
    for (; lanes != 0; lanes &= lanes - 1) {
      const unsigned k = unsigned(__builtin_ctz(lanes));
      auto lane_prim = [&](uint32_t record, float& t, const TriangleHit* decided)
          __attribute__((always_inline)) {
        return prim(k, record, t, decided);
      };
      float t = packet.tmax[k];
      if (test_blocks<AnyHit>(start, count, rays[k].ray, t, lane_prim)) {
        packet.tmax[k] = t;
        found |= 1u << k;
      }
    }
    return found;
  };
  return walk_.traverse_packet<AnyHit>(packet, leaf, cost);
}

}  // namespace rayscope
