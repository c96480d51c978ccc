#include "rayscope/accel/bvh_on_demand.h"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "rayscope/intersect_capsule.h"

namespace rayscope {

PrimBox capsule_box(const Vec3& a, const Vec3& b, float radius) {
  PrimBox p;
  p.bounds = capsule_bounds(a, b, radius);
  p.centroid = p.bounds.center();
  return p;
}

PrimBox prim_box(const PrimRecord& r, uint32_t num_triangles) {
  if (r.id < num_triangles) return triangle_box(r.a, r.b, r.c);
  switch (r.shape) {
    case PrimShape::Capsule:
      return capsule_box(r.a, r.b, r.c.x);
    case PrimShape::Point:
      return capsule_box(r.a, r.a, r.b.x);
    default:
      return sphere_box(r.a, r.b.x);
  }
}

BvhOnDemand::BvhOnDemand(const Bvh& built, std::shared_ptr<const LeafRecords> records,
                         uint32_t num_triangles)
    : records_(std::move(records)),
      num_triangles_(num_triangles),
      config_(built.config),
      bounds_(built.bounds()) {}

BvhOnDemand::BvhOnDemand(const BvhOnDemand& other, std::shared_ptr<const LeafRecords> records)
    : records_(std::move(records)),
      num_triangles_(other.num_triangles_),
      config_(other.config_),
      bounds_(other.bounds_) {
  if (other.held())
    std::call_once(once_, [&] {
      bvh_ = other.bvh_;
      held_ = true;
    });
}

const Bvh& BvhOnDemand::get() const {
  std::call_once(once_, [this] {
    // The primitives in the scene's order are the records by increasing id.
    const std::vector<PrimRecord>& records = records_->get();
    const size_t n = records.size();
    std::vector<uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(),
              [&](uint32_t a, uint32_t b) { return records[a].id < records[b].id; });
    std::vector<Bounds3> bounds(n);
    std::vector<Vec3> centroids(n);
    for (size_t i = 0; i < n; ++i) {
      const PrimBox p = prim_box(records[order[i]], num_triangles_);
      bounds[i] = p.bounds;
      centroids[i] = p.centroid;
    }
    auto bvh = std::make_shared<Bvh>();
    bvh->build(bounds, centroids, config_);
    for (size_t i = 0; i < n; ++i)
      if (order[bvh->prim_indices[i]] != i)
        throw std::logic_error("BvhOnDemand: the binary BVH built again has another leaf order");
    bvh_ = std::move(bvh);
    held_ = true;
  });
  return *bvh_;
}

size_t BvhOnDemand::memory_bytes() const {
  if (!held()) return 0;
  return bvh_->nodes.size() * sizeof(BvhNode) + bvh_->prim_indices.size() * sizeof(uint32_t);
}

}  // namespace rayscope
