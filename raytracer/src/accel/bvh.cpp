// The binary BVH: its build (the binned SAH builder, accel/bvh_builder.h, run
// with the instructions of the hot loops, kernels.h), figures and view.
#include "rayscope/accel/bvh.h"

#include <algorithm>
#include <cassert>

#include "rayscope/kernels.h"

namespace rayscope {

void Bvh::build(std::span<const Bounds3> bounds, std::span<const Vec3> centroids,
                const BvhBuildConfig& cfg) {
  kernels().build_bvh(*this, bounds, centroids, cfg);
}

BvhQuality Bvh::quality() const {
  BvhQuality q;
  if (nodes.empty()) return q;
  q.nodes = uint32_t(nodes.size());
  q.min_leaf_prims = ~0u;
  q.memory_bytes = nodes.size() * sizeof(BvhNode) + prim_indices.size() * sizeof(uint32_t);
  const double root_area = std::max(1e-30, double(nodes[0].bounds().half_area()));
  uint64_t leaf_prims = 0;
  std::vector<std::pair<uint32_t, uint32_t>> stack{{0u, 1u}};
  while (!stack.empty()) {
    auto [i, d] = stack.back();
    stack.pop_back();
    const BvhNode& n = nodes[i];
    q.depth = std::max(q.depth, d);
    double rel = double(n.bounds().half_area()) / root_area;
    if (n.is_leaf()) {
      q.leaves++;
      leaf_prims += n.count;
      q.min_leaf_prims = std::min(q.min_leaf_prims, n.count);
      q.max_leaf_prims = std::max(q.max_leaf_prims, n.count);
      q.sah_cost += rel * config.intersection_cost * n.count;
      q.sah_cost_1to1 += rel * n.count;
    } else {
      q.sah_cost += rel * config.traversal_cost;
      q.sah_cost_1to1 += rel;
      stack.push_back({n.index, d + 1});
      stack.push_back({n.index + 1, d + 1});
    }
  }
  q.mean_leaf_prims = q.leaves ? double(leaf_prims) / q.leaves : 0.0;
  return q;
}

AccelView Bvh::view() const {
  AccelView v;
  v.structure = "bvh";
  v.traversal_cost = config.traversal_cost;
  v.intersection_cost = config.intersection_cost;
  add_binary_nodes(v, nodes, [](const BvhNode& n, AccelViewNode& o) { o.box = n.bounds(); });
  v.refs.resize(prim_indices.size());
  for (size_t i = 0; i < v.refs.size(); ++i) v.refs[i] = uint32_t(i);
  finish_levels(v);
  return v;
}

}  // namespace rayscope
