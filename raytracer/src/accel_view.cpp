#include "rayscope/accel_view.h"

#include <algorithm>

#include "rayscope/aggregate.h"

namespace rayscope {

namespace {

// Levels and depth from the parents (counted up to the root: the grid's box
// has the last id, so a parent may come after its children).
void finish_levels(AccelView& v) {
  for (AccelViewNode& n : v.nodes) {
    n.level = 0;
    for (int32_t p = n.parent; p >= 0; p = v.nodes[size_t(p)].parent) ++n.level;
    v.depth = std::max(v.depth, n.level + 1);
  }
}

// The nodes of a binary hierarchy whose inner nodes name their first child
// (`index`, the second follows it) and whose leaves a range of `count`
// records from `index` (the BVH's and the sphere tree's layout); `volume`
// sets each node's box (and sphere).
template <class Node, class Volume>
void binary_nodes(AccelView& v, const std::vector<Node>& nodes, Volume volume) {
  v.nodes.resize(nodes.size());
  for (size_t i = 0; i < nodes.size(); ++i) {
    const Node& n = nodes[i];
    AccelViewNode& o = v.nodes[i];
    volume(n, o);
    o.leaf = n.is_leaf();
    if (o.leaf) {
      o.first = n.index;
      o.count = n.count;
    } else {
      v.nodes[n.index].parent = v.nodes[n.index + 1].parent = int32_t(i);
    }
  }
}

AccelView bvh_view(const Aggregate& a) {
  AccelView v;
  const Bvh& bvh = a.bvh();
  v.structure = "bvh";
  v.traversal_cost = bvh.config.traversal_cost;
  v.intersection_cost = bvh.config.intersection_cost;
  binary_nodes(v, bvh.nodes, [](const BvhNode& n, AccelViewNode& o) { o.box = n.bounds(); });
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
  const std::vector<Bounds3> cells = kd.cells();
  for (size_t i = 0; i < kd.nodes.size(); ++i) {
    const KdNode& n = kd.nodes[i];
    AccelViewNode& o = v.nodes[i];
    o.box = kd.node_box(cells[i]);  // the loose box for smallest-cell storage
    o.leaf = n.is_leaf();
    // Inner nodes of a loose kD-tree hold primitives too.
    const std::span<const uint32_t> held = kd.node_refs(uint32_t(i));
    o.first = held.empty() ? 0u : uint32_t(held.data() - kd.refs.data());
    o.count = uint32_t(held.size());
    if (o.leaf) continue;
    // The cell below the plane is the next node, the one above at above().
    v.nodes[i + 1].parent = v.nodes[n.above()].parent = int32_t(i);
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

AccelView bsp_view(const Aggregate& a) {
  AccelView v;
  const BspTree& bsp = a.bsp();
  v.structure = "bsp";
  v.nodes.resize(bsp.nodes.size());
  for (size_t i = 0; i < bsp.nodes.size(); ++i) {
    const BspNode& n = bsp.nodes[i];
    AccelViewNode& o = v.nodes[i];
    o.box = bsp.cell_boxes[i];
    o.leaf = n.is_leaf();
    o.first = n.first;  // inner nodes hold primitives with smallest-cell storage
    o.count = n.count;
    o.polygon_first = bsp.plane_polygons[i].first;
    o.polygon_count = bsp.plane_polygons[i].count;
    if (!n.is_leaf()) v.nodes[i + 1].parent = v.nodes[n.front].parent = int32_t(i);
  }
  v.polygon_vertices = bsp.plane_vertices;
  v.refs.reserve(bsp.refs.size());
  for (uint32_t r : bsp.refs) v.refs.push_back(a.records()[r].id);
  finish_levels(v);
  return v;
}

AccelView sphere_tree_view(const Aggregate& a) {
  AccelView v;
  const SphereTree& tree = a.sphere_tree();
  v.structure = "spheres";
  v.traversal_cost = tree.config.traversal_cost;
  v.intersection_cost = tree.config.intersection_cost;
  binary_nodes(v, tree.nodes, [](const SphereNode& n, AccelViewNode& o) {
    o.sphere = n.sphere();
    o.box = n.sphere().box();
  });
  v.refs.reserve(tree.prim_indices.size());
  for (uint32_t r : tree.prim_indices) v.refs.push_back(a.records()[r].id);
  finish_levels(v);
  return v;
}

AccelView grid_view(const Aggregate& a) {
  AccelView v;
  const UniformGrid& grid = a.grid();
  v.structure = "grid";
  const uint32_t ncells = uint32_t(grid.cells());
  if (ncells == 0) return v;
  // Cells x + nx (y + ny z), then the grid's box (box_id() = ncells): the ids
  // the walk reports.
  v.nodes.resize(size_t(ncells) + 1);
  const glm::uvec3 res = grid.resolution();
  for (uint32_t z = 0; z < res.z; ++z)
    for (uint32_t y = 0; y < res.y; ++y)
      for (uint32_t x = 0; x < res.x; ++x) {
        const uint32_t id = grid.cell_id(x, y, z);
        AccelViewNode& o = v.nodes[id];
        o.box = grid.node_box(x, y, z);  // the loose box for smallest-cell storage
        o.parent = int32_t(grid.box_id());
        o.leaf = true;
        o.first = grid.offsets[id];
        o.count = grid.offsets[id + 1] - grid.offsets[id];
      }
  // The grid's box holds the loose grid's big list, after the cells' lists.
  AccelViewNode& box = v.nodes[grid.box_id()];
  box.box = grid.bounds();
  box.first = uint32_t(grid.refs.size());
  box.count = uint32_t(grid.big_refs.size());
  v.refs.reserve(grid.refs.size() + grid.big_refs.size());
  for (uint32_t r : grid.refs) v.refs.push_back(a.records()[r].id);
  for (uint32_t r : grid.big_refs) v.refs.push_back(a.records()[r].id);
  finish_levels(v);
  return v;
}

}  // namespace

AccelView make_accel_view(const Aggregate& accel) {
  switch (accel.kind()) {
    case AccelKind::KdTree:
      return kdtree_view(accel);
    case AccelKind::Grid:
      return grid_view(accel);
    case AccelKind::Octree:
      return octree_view(accel);
    case AccelKind::Bsp:
      return bsp_view(accel);
    case AccelKind::Spheres:
      return sphere_tree_view(accel);
    case AccelKind::Bvh:
    case AccelKind::BinaryBvh:
    case AccelKind::None:
      break;
  }
  return bvh_view(accel);
}

}  // namespace rayscope
