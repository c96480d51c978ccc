#include "rayscope/accel_view.h"

#include <algorithm>

#include "rayscope/aggregate.h"

namespace rayscope {

namespace {

// Levels and depth from the parents (a parent's id is always below its
// children's in every structure's flattened order).
void finish_levels(AccelView& v) {
  for (AccelViewNode& n : v.nodes) {
    n.level = n.parent < 0 ? 0 : v.nodes[size_t(n.parent)].level + 1;
    v.depth = std::max(v.depth, n.level + 1);
  }
}

AccelView bvh_view(const Aggregate& a) {
  AccelView v;
  const Bvh& bvh = a.bvh();
  v.structure = "bvh";
  v.traversal_cost = bvh.config.traversal_cost;
  v.intersection_cost = bvh.config.intersection_cost;
  v.nodes.resize(bvh.nodes.size());
  for (size_t i = 0; i < bvh.nodes.size(); ++i) {
    const BvhNode& n = bvh.nodes[i];
    AccelViewNode& o = v.nodes[i];
    o.box = n.bounds();
    o.leaf = n.is_leaf();
    if (o.leaf) {
      o.first = n.index;
      o.count = n.count;
    } else {
      v.nodes[n.index].parent = v.nodes[n.index + 1].parent = int32_t(i);
    }
  }
  v.refs.reserve(a.records().size());
  for (const PrimRecord& r : a.records()) v.refs.push_back(r.id);
  finish_levels(v);
  return v;
}

AccelView kdtree_view(const Aggregate& a) {
  AccelView v;
  const KdTree& kd = a.kdtree();
  v.structure = "kdtree";
  v.traversal_cost = kd.config.traversal_cost;
  v.intersection_cost = kd.config.intersection_cost;
  v.nodes.resize(kd.nodes.size());
  if (!kd.nodes.empty()) v.nodes[0].box = kd.bounds();
  for (size_t i = 0; i < kd.nodes.size(); ++i) {
    const KdNode& n = kd.nodes[i];
    AccelViewNode& o = v.nodes[i];
    if (n.is_leaf()) {
      o.leaf = true;
      o.first = n.first();
      o.count = n.count();
      continue;
    }
    // The cell below the plane is the next node, the one above at above().
    AccelViewNode& below = v.nodes[i + 1];
    AccelViewNode& above = v.nodes[n.above()];
    below.box = above.box = o.box;
    below.box.hi[n.axis()] = above.box.lo[n.axis()] = n.split();
    below.parent = above.parent = int32_t(i);
  }
  v.refs.reserve(kd.refs.size());
  for (uint32_t r : kd.refs) v.refs.push_back(a.records()[r].id);
  finish_levels(v);
  return v;
}

AccelView octree_view(const Aggregate& a) {
  AccelView v;
  const Octree& oct = a.octree();
  v.structure = "octree";
  const std::vector<Bounds3> cells = oct.cells();
  v.nodes.resize(oct.nodes.size());
  for (size_t i = 0; i < oct.nodes.size(); ++i) {
    const OctNode& n = oct.nodes[i];
    AccelViewNode& o = v.nodes[i];
    o.box = oct.node_box(cells[i]);  // the loose box for smallest-cell storage
    o.leaf = n.is_leaf();
    o.first = n.first;  // inner nodes of a loose octree hold primitives too
    o.count = n.count;
    for (int k = 0; k < 8; ++k)
      if (n.has_child(k)) v.nodes[n.child(k)].parent = int32_t(i);
  }
  v.refs.reserve(oct.refs.size());
  for (uint32_t r : oct.refs) v.refs.push_back(a.records()[r].id);
  finish_levels(v);
  return v;
}

}  // namespace

AccelView make_accel_view(const Aggregate& accel) {
  switch (accel.kind()) {
    case AccelKind::KdTree:
      return kdtree_view(accel);
    case AccelKind::Octree:
      return octree_view(accel);
    case AccelKind::Bvh:
    case AccelKind::BinaryBvh:
    case AccelKind::None:
      break;
  }
  return bvh_view(accel);
}

}  // namespace rayscope
