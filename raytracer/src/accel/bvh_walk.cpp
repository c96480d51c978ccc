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

// Leaves per task of the parallel block fill: large enough that a task's work
// dwarfs TBB's cost of handing it out.
constexpr size_t kLeafGrain = 4096;

// Each leaf's first triangle block, the label the walk gives the leaf:
// [first record of a leaf] (other entries ~0u), leaves in node order, each
// leaf's records in blocks of TriangleBlock::kLanes. `leaves` gets the leaves'
// node ids, `blocks` how many blocks there are.
std::vector<uint32_t> leaf_first_blocks(const Bvh& bvh, std::vector<uint32_t>& leaves,
                                        uint32_t& blocks) {
  constexpr int kLanes = TriangleBlock::kLanes;
  std::vector<uint32_t> first;
  assign_huge(first, bvh.prim_indices.size(), ~0u);
  leaves.clear();
  blocks = 0;
  for (uint32_t i = 0; i < bvh.nodes.size(); ++i) {
    const BvhNode& n = bvh.nodes[i];
    if (!n.is_leaf()) continue;
    leaves.push_back(i);
    first[n.index] = blocks;
    blocks += (n.count + kLanes - 1) / kLanes;
  }
  return first;
}

int arity_of(AccelKind kind) {
  return kind == AccelKind::BinaryBvh ? 2 : WideBvh::kRenderArity;
}

}  // namespace

void BvhWalk::build(AccelKind kind, const Bvh& bvh, std::shared_ptr<const BvhOnDemand> hierarchy,
                    std::span<const PrimRecord> records, uint32_t num_triangles) {
  constexpr int kLanes = TriangleBlock::kLanes;
  kind_ = kind;
  hierarchy_ = std::move(hierarchy);
  sources_ = std::make_shared<SlotSources>();
  // The walk labelled with each leaf's first block, then the blocks filled
  // leaf by leaf on every core: each leaf writes only its own blocks.
  std::vector<uint32_t> leaves;
  uint32_t count = 0;
  const std::vector<uint32_t> leaf_blocks = leaf_first_blocks(bvh, leaves, count);
  walk_.build(bvh, arity_of(kind), leaf_blocks);
  // The binary ids of the slots are made again when an observer asks.
  std::vector<uint32_t>().swap(walk_.slot_source);
  assign_huge(blocks_, count);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, leaves.size(), kLeafGrain),
                    [&](const tbb::blocked_range<size_t>& range) {
                      for (size_t l = range.begin(); l < range.end(); ++l) {
                        const BvhNode& n = bvh.nodes[leaves[l]];
                        const uint32_t first = leaf_blocks[n.index];
                        for (uint32_t j = 0; j < n.count; ++j) {
                          TriangleBlock& b = blocks_[first + j / kLanes];
                          const unsigned lane = j % kLanes;
                          if (lane == 0) b.first = n.index + j;
                          const PrimRecord& r = records[n.index + j];
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
    std::vector<uint32_t> leaves;
    uint32_t blocks = 0;
    WideBvh again;
    again.build(bvh, walk_.arity(), leaf_first_blocks(bvh, leaves, blocks));
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
