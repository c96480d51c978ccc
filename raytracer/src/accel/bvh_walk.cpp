#include "rayscope/accel/bvh_walk.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "rayscope/huge_pages.h"

namespace rayscope {
namespace {

// Blocks per task of the parallel block fill and of records_from_blocks():
// large enough that a task's work dwarfs TBB's cost of handing it out.
constexpr size_t kBlockGrain = 4096;

// How the leaves' records lie in triangle blocks. A leaf shares the block of
// the leaf before it when it fits in the lanes left and its records follow
// that leaf's: a leaf of up to kLanes records still takes one block test, and
// the blocks are fuller (leaves average under three records).
struct BlockLayout {
  /// Each leaf's first lane (block * kLanes + lane), the label the walk gives
  /// the leaf: [first record of a leaf], other entries ~0u.
  std::vector<uint32_t> leaf_lane;
  /// Each block's first record, and how many lanes from lane 0 it fills.
  std::vector<uint32_t> block_first;
  std::vector<uint8_t> block_lanes;
};

BlockLayout lay_out_blocks(const Bvh& bvh) {
  constexpr uint32_t kLanes = TriangleBlock::kLanes;
  BlockLayout l;
  assign_huge(l.leaf_lane, bvh.prim_indices.size(), ~0u);
  // At most one block per leaf (a leaf starting a block) plus one per full
  // four lanes, and a binary tree of n nodes has (n + 1) / 2 leaves.
  const size_t most_blocks = (bvh.nodes.size() + 1) / 2 + bvh.prim_indices.size() / kLanes;
  l.block_first.reserve(most_blocks);
  l.block_lanes.reserve(most_blocks);
  uint32_t lane = 0, next_record = 0;
  for (const BvhNode& n : bvh.nodes) {
    if (!n.is_leaf() || n.index >= l.leaf_lane.size()) continue;
    const uint32_t room = kLanes - lane % kLanes;
    if (room < kLanes && (n.count > room || n.index != next_record)) lane += room;
    l.leaf_lane[n.index] = lane;
    for (uint32_t j = 0; j < n.count; ++j, ++lane) {
      if (lane % kLanes == 0) {
        l.block_first.push_back(n.index + j);
        l.block_lanes.push_back(0);
      }
      ++l.block_lanes.back();
    }
    next_record = n.index + n.count;
  }
  return l;
}

int arity_of(AccelKind kind) {
  return kind == AccelKind::BinaryBvh ? 2 : WideBvh::kRenderArity;
}

}  // namespace

void BvhWalk::build(AccelKind kind, const Bvh& bvh, std::shared_ptr<const BvhOnDemand> hierarchy,
                    const RecordSource& record_at, uint32_t num_triangles) {
  kind_ = kind;
  hierarchy_ = std::move(hierarchy);
  sources_ = std::make_shared<SlotSources>();
  // The walk labelled with each leaf's first lane, then the blocks filled on
  // every core, block by block.
  const BlockLayout layout = lay_out_blocks(bvh);
  walk_.build(bvh, arity_of(kind), layout.leaf_lane);
  // The binary ids of the slots are made again when an observer asks.
  std::vector<uint32_t>().swap(walk_.slot_source);
  assign_huge(blocks_, layout.block_first.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, blocks_.size(), kBlockGrain),
                    [&](const tbb::blocked_range<size_t>& range) {
                      for (size_t j = range.begin(); j < range.end(); ++j) {
                        TriangleBlock& b = blocks_[j];
                        b.first = layout.block_first[j];
                        for (unsigned lane = 0; lane < layout.block_lanes[j]; ++lane) {
                          const PrimRecord r = record_at(b.first + lane);
                          if (r.id >= num_triangles) {
                            b.others |= uint8_t(1u << lane);
                            continue;
                          }
                          b.triangles |= uint8_t(1u << lane);
                          const Vec3* p[3] = {&r.a, &r.b, &r.c};
                          for (int i = 0; i < 3; ++i)
                            for (int axis = 0; axis < 3; ++axis) b.v[i][axis][lane] = (*p[i])[axis];
                        }
                      }
                    });
}

std::span<const uint32_t> BvhWalk::slot_sources() const {
  SlotSources& s = *sources_;
  std::call_once(s.once, [&] {
    const Bvh& bvh = hierarchy_->get();
    WideBvh again;
    again.build(bvh, walk_.arity(), lay_out_blocks(bvh).leaf_lane);
    if (again.nodes.size() != walk_.nodes.size() ||
        !std::equal(again.nodes.begin(), again.nodes.end(), walk_.nodes.begin(),
                    [](const WideBvhNode& a, const WideBvhNode& b) {
                      return std::memcmp(&a, &b, sizeof a) == 0;
                    }))
      throw std::logic_error("BvhWalk: the binary BVH built again collapses into other nodes");
    s.ids = std::move(again.slot_source);
    s.made = true;
  });
  return s.ids;
}

std::vector<PrimRecord> BvhWalk::records_from_blocks(std::span<const TriangleBlock> blocks,
                                                     std::span<const uint32_t> ids,
                                                     std::span<const PrimRecord> others,
                                                     uint32_t num_triangles) {
  std::vector<PrimRecord> records;
  assign_huge(records, ids.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, blocks.size(), kBlockGrain),
                    [&](const tbb::blocked_range<size_t>& range) {
                      for (size_t j = range.begin(); j < range.end(); ++j) {
                        const TriangleBlock& b = blocks[j];
                        for (unsigned k = 0; k < unsigned(TriangleBlock::kLanes); ++k) {
                          if (!(((b.triangles | b.others) >> k) & 1u)) continue;
                          const uint32_t i = b.first + k;
                          PrimRecord& r = records[i];
                          if ((b.others >> k) & 1u) {
                            r = others[ids[i] - num_triangles];
                            continue;
                          }
                          r.a = b.vertex(0, k);
                          r.id = ids[i];
                          r.b = b.vertex(1, k);
                          r.shape = PrimShape::Triangle;
                          r.c = b.vertex(2, k);
                        }
                      }
                    });
  return records;
}

size_t BvhWalk::memory_bytes() const {
  return walk_.memory_bytes() + blocks_.size() * sizeof(TriangleBlock) +
         (sources_->made ? sources_->ids.size() * sizeof(uint32_t) : 0);
}

AccelFigures BvhWalk::figures() const {
  AccelFigures f;
  const Bvh& bvh = hierarchy_->get();
  const BvhQuality q = bvh.quality();
  f.build_seconds = build_seconds_;
  f.memory_bytes = memory_bytes();
  f.nodes = walk_.nodes.size() + q.leaves;  // inner wide nodes and the leaves they hold
  f.leaves = q.leaves;
  f.depth = walk_.depth();
  f.refs_per_prim = bvh.prim_indices.empty() ? 0.0 : 1.0;
  return f;
}

AccelView BvhWalk::view() const {
  return hierarchy_->get().view();
}

std::string BvhWalk::stats_line() const {
  char line[160];
  std::snprintf(line, sizeof line, "%s: %zu %d-wide nodes, depth %u%s", to_string(kind_),
                walk_.nodes.size(), walk_.arity(), walk_.depth(),
                kind_ == AccelKind::Bvh ? " (what renders walk)" : "");
  return line;
}

std::string BvhWalk::walk_legend() const {
  if (kind_ == AccelKind::BinaryBvh)
    return std::string("the binary BVH, node by node (--accel ") + to_string(kind_) + ")";
  return std::string("the 8-wide BVH, as renders walk it (--accel ") + to_string(kind_) +
         "); nodes are named by their binary BVH ids";
}

}  // namespace rayscope
