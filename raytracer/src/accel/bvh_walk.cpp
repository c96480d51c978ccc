#include "rayscope/accel/bvh_walk.h"

#include <cstdio>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "rayscope/huge_pages.h"

namespace rayscope {
namespace {

// Leaves per task of the parallel block fill: large enough that a task's work
// dwarfs TBB's cost of handing it out.
constexpr size_t kLeafGrain = 4096;

}  // namespace

void BvhWalk::build(AccelKind kind, std::shared_ptr<const Bvh> hierarchy,
                    std::span<const PrimRecord> records, uint32_t num_triangles) {
  constexpr int kLanes = TriangleBlock::kLanes;
  kind_ = kind;
  hierarchy_ = std::move(hierarchy);
  const Bvh& bvh = *hierarchy_;
  // Each leaf's first block (leaves in node order), the walk labelled with
  // them, then the blocks filled leaf by leaf on every core: each leaf writes
  // only its own blocks.
  std::vector<uint32_t> leaves;
  std::vector<uint32_t> leaf_blocks;  // [first record of a leaf]: its first block
  assign_huge(leaf_blocks, records.size(), ~0u);
  uint32_t count = 0;
  for (uint32_t i = 0; i < bvh.nodes.size(); ++i) {
    const BvhNode& n = bvh.nodes[i];
    if (!n.is_leaf()) continue;
    leaves.push_back(i);
    leaf_blocks[n.index] = count;
    count += (n.count + kLanes - 1) / kLanes;
  }
  walk_.build(bvh, kind == AccelKind::BinaryBvh ? 2 : WideBvh::kRenderArity, leaf_blocks);
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

AccelFigures BvhWalk::figures() const {
  AccelFigures f;
  const BvhQuality q = hierarchy_->quality();
  f.build_seconds = build_seconds_;
  f.memory_bytes = memory_bytes();
  f.nodes = walk_.nodes.size() + q.leaves;  // inner wide nodes and the leaves they hold
  f.leaves = q.leaves;
  f.depth = walk_.depth();
  f.refs_per_prim = hierarchy_->prim_indices.empty() ? 0.0 : 1.0;
  return f;
}

AccelView BvhWalk::view() const {
  return hierarchy_->view();
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
