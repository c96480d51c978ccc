// The lecture's range-query algorithm on a binary hierarchy of bounding
// volumes, written once for the BVH (boxes) and the sphere tree (spheres):
// start at the root; if the range overlaps a node's volume, enter it (a
// leaf's primitives are reported, an inner node's two children tested);
// children that overlap are visited nearer first, the farther pushed; a
// pushed node is entered only if the range still overlaps it when popped (a
// k-nearest range shrinks while it is walked), else culled.
#pragma once

#include <cassert>
#include <cstdint>
#include <vector>

namespace rayscope {

/// Walks `nodes` (nodes[0] the root; an inner node's children at `index` and
/// `index + 1`, a leaf's primitives the leaf-order positions `index` ..
/// `index + count - 1`), passing each leaf position `i` of an entered leaf to
/// `prim(i)`, each exactly once. `volume(node)` is the node's bounding volume,
/// which `range.overlaps()` and `range.distance()` take (Bounds3 or
/// BoundingSphere; range_query.h). `kStack` entries bound the depth.
/// Observer hooks (traversal.h): on_box_test for the root and both children
/// of every inner node entered, on_node for each node entered, on_cull for a
/// popped node the range no longer overlaps; ids are the node indices.
template <int kStack, class Node, class VolumeOf, class Range, class PrimFn, class Observer>
void walk_binary_range(const std::vector<Node>& nodes, VolumeOf&& volume, Range& range,
                       PrimFn&& prim, Observer& obs) {
  if (nodes.empty()) return;
  const bool root_overlaps = range.overlaps(volume(nodes[0]));
  if constexpr (Observer::kActive) obs.on_box_test(0, root_overlaps);
  if (!root_overlaps) return;
  uint32_t stack[kStack];
  int sp = 0;
  uint32_t node = 0;
  for (;;) {
    if constexpr (Observer::kActive) obs.on_node(node);
    const Node& n = nodes[node];
    if (n.is_leaf()) {
      for (uint32_t i = n.index; i < n.index + n.count; ++i) prim(i);
    } else {
      const uint32_t c0 = n.index, c1 = n.index + 1;
      const auto v0 = volume(nodes[c0]), v1 = volume(nodes[c1]);
      const bool o0 = range.overlaps(v0), o1 = range.overlaps(v1);
      if constexpr (Observer::kActive) {
        obs.on_box_test(c0, o0);
        obs.on_box_test(c1, o1);
      }
      if (o0 && o1) {
        const bool second_first = range.distance(v1) < range.distance(v0);
        assert(sp < kStack);
        stack[sp++] = second_first ? c0 : c1;
        node = second_first ? c1 : c0;
        continue;
      }
      if (o0 || o1) {
        node = o0 ? c0 : c1;
        continue;
      }
    }
    // Pop the next node the range still overlaps.
    for (;;) {
      if (sp == 0) return;
      const uint32_t next = stack[--sp];
      if (range.overlaps(volume(nodes[next]))) {
        node = next;
        break;
      }
      if constexpr (Observer::kActive) obs.on_cull(next);
    }
  }
}

}  // namespace rayscope
