// The teaching view of an acceleration structure: its nodes or cells as boxes,
// named by the ids its walk reports to observers (traversal.h), with levels,
// parents and the primitives each one holds. What the tools draw (the VTK
// structure source, the viewer) is built from this, whatever the structure,
// so that a recorded walk (its node ids) can be laid over it.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "rayscope/math.h"

namespace rayscope {

class Aggregate;

/// One node or cell.
struct AccelViewNode {
  /// Its box: a BVH node's bounds, a kD-tree cell, an octree node's (loose)
  /// box, the bounding box of a BSP node's cell, the box around a sphere tree
  /// node's sphere.
  Bounds3 box;
  /// The node's bounding sphere, for the sphere tree (drawn as a sphere);
  /// none for the structures of boxes.
  std::optional<BoundingSphere> sphere;
  int32_t parent = -1;  ///< Id of the parent, -1 for a root.
  int level = 0;        ///< Root = 0.
  bool leaf = false;
  /// The primitives the node itself holds: refs[first .. first + count) (a
  /// leaf's list; inner nodes hold none, except in a loose octree).
  uint32_t first = 0, count = 0;
  /// A BSP inner node's split plane clipped to its cell, a convex polygon:
  /// AccelView::polygon_vertices[polygon_first .. + polygon_count) (0 for
  /// every other node and structure).
  uint32_t polygon_first = 0, polygon_count = 0;
};

struct AccelView {
  /// The structure shown: "bvh" (the binary BVH, also for bvh2 and for none,
  /// whose rays walk nothing), "kdtree", "grid" (the cells, then the grid's
  /// box as the root with the last id), "octree", "bsp" or "spheres" (nodes
  /// with a sphere).
  const char* structure = "bvh";
  /// nodes[id]: ids are the ones the walk reports (dense, 0 .. size - 1).
  std::vector<AccelViewNode> nodes;
  /// Global primitive ids (Scene: triangles, tube segments, points, spheres) of the nodes'
  /// lists (record indices in a structure's own view()); a primitive stored in
  /// several cells appears in each.
  std::vector<uint32_t> refs;
  /// Vertices of the nodes' polygons (BSP split planes).
  std::vector<Vec3> polygon_vertices;
  /// Cost constants of the structure's build, for each node's SAH term:
  /// area / root area x (traversal_cost for an inner node + intersection_cost
  /// x count); 1 and 1 for the octree, whose build uses none. (For the
  /// sphere tree the area is the box's, as for every structure; its build
  /// weighs spheres by their own areas.)
  float traversal_cost = 1.0f, intersection_cost = 1.0f;
  /// Levels on the longest path (the deepest level + 1; 0 when empty).
  int depth = 0;
};

/// The view of the structure the aggregate's rays walk, refs naming global
/// primitive ids (each structure's own view() names records; this maps them).
AccelView make_accel_view(const Aggregate& accel);

/// Sets every node's level and the view's depth from the parents (counted up
/// to the root: the grid's box has the last id, so a parent may come after
/// its children). The last step of every structure's view().
void finish_levels(AccelView& v);

/// The nodes of a binary hierarchy whose inner nodes name their first child
/// (`index`, the second follows it) and whose leaves a range of `count`
/// records from `index` (the BVH's and the sphere tree's layout); `volume`
/// sets each node's box (and sphere).
template <class Node, class Volume>
void add_binary_nodes(AccelView& v, const std::vector<Node>& nodes, Volume volume) {
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

}  // namespace rayscope
