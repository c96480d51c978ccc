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
  /// Global primitive ids (triangles mesh by mesh, then spheres) of the nodes'
  /// lists; a primitive stored in several cells appears in each.
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

/// The view of the structure the aggregate's rays walk.
AccelView make_accel_view(const Aggregate& accel);

}  // namespace rayscope
