// The binary BVH (bvh.h) when only the teaching tools need it. The aggregate
// builds it for every scene: its leaf order is the records' order, and the
// wide BVH renders walk is collapsed from it. After that a plain render needs
// neither its nodes nor its leaf order, so they are dropped and built again,
// from the records, the first time something asks for them: a tool that
// shows the tree, a walk that reports node ids to an observer, a range query
// or the tree's figures. The second build sees the same bounds and centroids
// in the same order, so it makes the same tree, node for node (checked).
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>

#include "rayscope/accel/bvh.h"
#include "rayscope/accel/leaf_records.h"
#include "rayscope/accel/prim_record.h"

namespace rayscope {

/// What the BVH builder sees of one primitive.
struct PrimBox {
  Bounds3 bounds;
  Vec3 centroid;
};

/// What the builder is given for a triangle: its box and the box's center.
inline PrimBox triangle_box(const Vec3& a, const Vec3& b, const Vec3& c) {
  PrimBox p;
  p.bounds = Bounds3(a);
  p.bounds.extend(b);
  p.bounds.extend(c);
  p.centroid = p.bounds.center();
  return p;
}
/// For a capsule (a tube segment; a point is one from p to p): its box
/// rounded outward (capsule_bounds) and the box's center.
PrimBox capsule_box(const Vec3& a, const Vec3& b, float radius);
/// For a sphere: its box and its center.
inline PrimBox sphere_box(const Vec3& center, float radius) {
  return PrimBox{Bounds3(center - Vec3(radius), center + Vec3(radius)), center};
}
/// What the builder is given for record `r` (triangles are the records with
/// id < num_triangles), by the rules above: the scene's commit and the
/// hierarchy built again see the same boxes.
PrimBox prim_box(const PrimRecord& r, uint32_t num_triangles);

class BvhOnDemand {
 public:
  /// An empty hierarchy.
  BvhOnDemand() = default;
  /// `built`: the hierarchy built over prim_box() of the primitives in the
  /// scene's order (increasing ids), not kept; `records`: those primitives in
  /// its leaf order.
  BvhOnDemand(const Bvh& built, std::shared_ptr<const LeafRecords> records, uint32_t num_triangles);
  /// `other`'s hierarchy over a copy of its records (the same hierarchy,
  /// shared while held).
  BvhOnDemand(const BvhOnDemand& other, std::shared_ptr<const LeafRecords> records);
  BvhOnDemand(const BvhOnDemand&) = delete;
  BvhOnDemand& operator=(const BvhOnDemand&) = delete;

  /// The hierarchy: the one built, or built again from the records on the
  /// first call after it was dropped (once, whichever thread asks first).
  /// Throws std::logic_error if the second build's leaf order were not the
  /// records' order.
  const Bvh& get() const;
  /// Whether the hierarchy is held now (memory_bytes() counts it).
  bool held() const { return held_.load(std::memory_order_acquire); }
  /// The root's box, kept when the nodes are dropped.
  Bounds3 bounds() const { return bounds_; }
  /// Bytes of the nodes and leaf order held now.
  size_t memory_bytes() const;

 private:
  mutable std::once_flag once_;
  mutable std::shared_ptr<const Bvh> bvh_;
  mutable std::atomic<bool> held_{false};
  std::shared_ptr<const LeafRecords> records_ = std::make_shared<const LeafRecords>();
  uint32_t num_triangles_ = 0;
  BvhBuildConfig config_;
  Bounds3 bounds_;
};

}  // namespace rayscope
