// The one front-to-back walk of a tree of cells in which any node may hold
// primitives and children's boxes may overlap: the octree (tight or loose,
// octree.h) and the loose kD-tree (PrimStorage::SmallestCell, kdtree.h). The
// lecture's "overlapping regions": a primitive that straddles a cut stays in
// the inner node, whose list the walk tests when it enters the node; the
// children's (loose) boxes overlap, so the walk cannot rely on a plane to
// order them and sorts those the ray hits by entry distance instead.
//
// A tree describes itself to the walk with three callables:
// - box(cell) -> Bounds3: the box tested for a node of that cell (its loose
//   box for SmallestCell);
// - refs(node) -> std::span<const uint32_t>: the primitives the node holds;
// - children(node, cell, emit): calls emit(child, child_cell) for each child,
//   in the order ties in entry distance keep (and the order a tight tree is
//   walked in when `sort` is false).
#pragma once

#include <cassert>
#include <cstdint>
#include <span>
#include <utility>

#include "rayscope/accel/mailbox.h"
#include "rayscope/intersect.h"
#include "rayscope/math.h"
#include "rayscope/ray.h"
#include "rayscope/traversal.h"

namespace rayscope {

/// Walks the nodes whose box the ray [origin, origin + tmax * dir] crosses,
/// the contract of KdTree::traverse (prim(index, tmax) tests a primitive,
/// lowers tmax on a hit or ends an AnyHit walk; returns whether anything was
/// hit). A node entered tests its own references first, then its children's
/// boxes; those hit are pushed so that the first emitted (sort false) or the
/// nearest entry (sort true, ties in emit order) is entered next. A popped
/// node whose entry lies beyond the closest hit (with the margin kBoxFarScale,
/// so that rounding never skips a node the ray touches) is culled. `mailbox`
/// (null: every primitive is stored once) filters repeated references.
///
/// Observer hooks: on_box_test(0, hit) for the root's box, on_node(id) for
/// every node entered, on_box_test(child, hit) for every child box tested,
/// on_cull(id) for a pushed node skipped by early termination.
template <bool AnyHit, int MaxChildren, int StackSize, class Cell, class BoxFn, class RefsFn,
          class ChildrenFn, class Observer, class PrimFn>
bool walk_cells(const Ray& ray, float& tmax, const Cell& root, bool sort, MailboxQuery* mailbox,
                BoxFn&& box, RefsFn&& refs, ChildrenFn&& children, PrimFn&& prim, Observer& obs) {
  const Vec3 inv_dir = 1.0f / ray.dir;
  struct Entry {
    uint32_t node;
    float t;  ///< Entry distance of the node's box.
    Cell cell;
  };
  float t0, t1;
  const Bounds3 root_box = box(root);
  box_interval(root_box.lo, root_box.hi, ray.origin, inv_dir, tmax, t0, t1);
  const bool root_hit = t0 <= t1;
  if constexpr (Observer::kActive) obs.on_box_test(0, root_hit);
  if (!root_hit) return false;
  Entry stack[StackSize];
  int sp = 0;
  stack[sp++] = {0u, t0, root};
  bool hit = false;
  while (sp > 0) {
    const Entry e = stack[--sp];
    if (e.t > tmax * kBoxFarScale) {
      if constexpr (Observer::kActive) obs.on_cull(e.node);
      continue;
    }
    if constexpr (Observer::kActive) obs.on_node(e.node);
    for (const uint32_t p : refs(e.node)) {
      if (mailbox && !mailbox->first_visit(p)) continue;
      if (prim(p, tmax)) {
        hit = true;
        if constexpr (AnyHit) return true;
      }
    }
    Entry kids[MaxChildren];
    int k = 0;
    children(e.node, e.cell, [&](uint32_t child, const Cell& cell) {
      const Bounds3 b = box(cell);
      float c0, c1;
      box_interval(b.lo, b.hi, ray.origin, inv_dir, tmax, c0, c1);
      const bool reached = c0 <= c1;
      if constexpr (Observer::kActive) obs.on_box_test(child, reached);
      if (reached) kids[k++] = {child, c0, cell};
    });
    if (sort)  // nearest entry first; ties keep the emit order
      for (int i = 1; i < k; ++i)
        for (int j = i; j > 0 && kids[j].t < kids[j - 1].t; --j) std::swap(kids[j], kids[j - 1]);
    assert(sp + k <= StackSize);
    while (k > 0) stack[sp++] = kids[--k];
  }
  return hit;
}

/// The lecture's range walk on the same trees (range_query.h): from the root,
/// wherever `range` overlaps a node's box, report the node's primitives with
/// `prim(index)` (after `mailbox`, when there is one) and go on into its
/// children, nearer ones first by range.distance() (ties in emit order). The
/// range may shrink between calls (k nearest): a pushed node is checked again
/// when popped and culled if the range no longer overlaps it. Observer:
/// on_box_test for the root's and every child's box tested, on_node for every
/// node entered, on_cull.
template <int MaxChildren, int StackSize, class Cell, class Range, class BoxFn, class RefsFn,
          class ChildrenFn, class Observer, class PrimFn>
void walk_cells_range(Range& range, const Cell& root, MailboxQuery* mailbox, BoxFn&& box,
                      RefsFn&& refs, ChildrenFn&& children, PrimFn&& prim, Observer& obs) {
  const bool root_hit = range.overlaps(box(root));
  if constexpr (Observer::kActive) obs.on_box_test(0, root_hit);
  if (!root_hit) return;
  struct Entry {
    uint32_t node;
    float distance;
    Cell cell;
  };
  Entry stack[StackSize];
  int sp = 0;
  stack[sp++] = {0u, 0.0f, root};
  while (sp > 0) {
    const Entry e = stack[--sp];
    // The range may have shrunk since the node was pushed.
    if (e.node != 0 && !range.overlaps(box(e.cell))) {
      if constexpr (Observer::kActive) obs.on_cull(e.node);
      continue;
    }
    if constexpr (Observer::kActive) obs.on_node(e.node);
    for (const uint32_t p : refs(e.node))
      if (!mailbox || mailbox->first_visit(p)) prim(p);
    Entry kids[MaxChildren];
    int k = 0;
    children(e.node, e.cell, [&](uint32_t child, const Cell& cell) {
      const Bounds3 b = box(cell);
      const bool reached = range.overlaps(b);
      if constexpr (Observer::kActive) obs.on_box_test(child, reached);
      if (reached) kids[k++] = {child, range.distance(b), cell};
    });
    for (int i = 1; i < k; ++i)  // nearest first; ties keep the emit order
      for (int j = i; j > 0 && kids[j].distance < kids[j - 1].distance; --j)
        std::swap(kids[j], kids[j - 1]);
    assert(sp + k <= StackSize);
    while (k > 0) stack[sp++] = kids[--k];
  }
}

}  // namespace rayscope
