// Collapse of the binary hierarchy into the wide one (wide_bvh.h): each wide
// node takes a binary inner node's two children and, while it has fewer than
// the arity, replaces its inner child of largest surface area by that child's
// two children (the choice Embree's BVH4 and BVH8 builders make), so that the boxes a
// ray is most likely to enter are tested together. With arity 2 nothing is
// replaced: each wide node is one binary node.
#include "rayscope/accel/wide_bvh.h"

#include "rayscope/huge_pages.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace rayscope {

namespace {

uint32_t leaf_child(std::span<const uint32_t> leaf_label, const BvhNode& leaf) {
  const uint32_t label = leaf_label.empty() ? leaf.index : leaf_label[leaf.index];
  if (label & WideBvhNode::kLeaf) throw std::length_error("WideBvh: a leaf label is too large");
  return WideBvhNode::kLeaf | label;
}

}  // namespace

void WideBvh::build(const Bvh& bvh, int arity, std::span<const uint32_t> leaf_label) {
  if (arity < 2 || arity > kMaxArity)
    throw std::invalid_argument("WideBvh: arity " + std::to_string(arity) + " is outside 2.." +
                                std::to_string(kMaxArity));
  if (!leaf_label.empty() && leaf_label.size() != bvh.prim_indices.size())
    throw std::invalid_argument("WideBvh: " + std::to_string(leaf_label.size()) +
                                " leaf labels for " + std::to_string(bvh.prim_indices.size()) +
                                " primitives");
  arity_ = arity;
  nodes.clear();
  slot_source.clear();
  root_child_ = kNone;
  root_count_ = 0;
  depth_ = 0;
  root_lo_ = Vec3(kInfinity);
  root_hi_ = Vec3(-kInfinity);
  if (bvh.empty()) return;
  const BvhNode& root = bvh.nodes[0];
  root_lo_ = root.lo;
  root_hi_ = root.hi;
  if (root.is_leaf()) {
    root_child_ = leaf_child(leaf_label, root);
    root_count_ = root.count;
  } else {
    reserve_huge(nodes, bvh.nodes.size() / 2 + 1);
    reserve_huge(slot_source, nodes.capacity() * WideBvhNode::kWidth);
    root_child_ = collapse(bvh, leaf_label, 0, 1);
    root_count_ = 0;
  }
  // Not shrunk: the reserve above is address space, backed only where nodes
  // were written (under a third of it with 8-wide nodes), and a copy into
  // new memory cost more than the collapse on the 1.1M-triangle mesh.
  if (uint32_t(kMaxArity - 1) * depth_ > uint32_t(kStackSize))
    throw std::length_error("WideBvh: " + std::to_string(depth_) +
                            " levels exceed the traversal stack");
}

uint32_t WideBvh::collapse(const Bvh& bvh, std::span<const uint32_t> leaf_label,
                           uint32_t binary_node, uint32_t level) {
  depth_ = std::max(depth_, level);
  const BvhNode& bn = bvh.nodes[binary_node];
  uint32_t kids[kMaxArity] = {bn.index, bn.index + 1};
  int n = 2;
  while (n < arity_) {
    int open = -1;
    float area = -1.0f;
    for (int k = 0; k < n; ++k) {
      const BvhNode& c = bvh.nodes[kids[k]];
      if (c.is_leaf()) continue;
      const float a = c.bounds().half_area();
      if (a > area) {
        area = a;
        open = k;
      }
    }
    if (open < 0) break;
    const uint32_t first = bvh.nodes[kids[open]].index;
    kids[open] = first;  // keep the children in their spatial order
    for (int k = n; k > open + 1; --k) kids[k] = kids[k - 1];
    kids[open + 1] = first + 1;
    ++n;
  }

  const uint32_t me = uint32_t(nodes.size());
  nodes.emplace_back();
  slot_source.insert(slot_source.end(), WideBvhNode::kWidth, ~0u);
  {
    WideBvhNode& w = nodes[me];
    for (int k = 0; k < WideBvhNode::kWidth; ++k) {
      w.lo_x[k] = w.lo_y[k] = w.lo_z[k] = kInfinity;
      w.hi_x[k] = w.hi_y[k] = w.hi_z[k] = -kInfinity;
      w.child[k] = WideBvhNode::kLeaf;
      w.count[k] = 0;
    }
  }
  for (int k = 0; k < n; ++k) {
    const BvhNode& c = bvh.nodes[kids[k]];
    uint32_t child, count;
    if (c.is_leaf()) {
      child = leaf_child(leaf_label, c);
      count = c.count;
    } else {
      child = collapse(bvh, leaf_label, kids[k], level + 1);  // may reallocate `nodes`
      count = 0;
    }
    WideBvhNode& w = nodes[me];
    w.lo_x[k] = c.lo.x;
    w.lo_y[k] = c.lo.y;
    w.lo_z[k] = c.lo.z;
    w.hi_x[k] = c.hi.x;
    w.hi_y[k] = c.hi.y;
    w.hi_z[k] = c.hi.z;
    w.child[k] = child;
    w.count[k] = count;
    slot_source[WideBvhNode::kWidth * size_t(me) + size_t(k)] = kids[k];
  }
  return me;
}

}  // namespace rayscope
