#include "rayscope/aggregate.h"

#include <stdexcept>
#include <string>

namespace rayscope {

const char* to_string(AccelKind kind) {
  switch (kind) {
    case AccelKind::Bvh:
      return "bvh";
    case AccelKind::BinaryBvh:
      return "bvh2";
    case AccelKind::None:
      return "none";
    case AccelKind::KdTree:
      return "kdtree";
    case AccelKind::Grid:
      return "grid";
  }
  return "?";
}

bool parse_accel_kind(std::string_view name, AccelKind& kind) {
  for (AccelKind k :
       {AccelKind::Bvh, AccelKind::BinaryBvh, AccelKind::None, AccelKind::KdTree, AccelKind::Grid})
    if (name == to_string(k)) {
      kind = k;
      return true;
    }
  return false;
}

void Aggregate::build(std::span<const Bounds3> bounds, std::span<const Vec3> centroids,
                      std::span<const PrimRecord> records, uint32_t num_triangles,
                      std::vector<PlaneRecord> planes, const AccelConfig& config) {
  if (bounds.size() != records.size() || centroids.size() != records.size())
    throw std::invalid_argument("Aggregate::build: bounds, centroids and records differ in size");
  config_ = config;
  num_triangles_ = num_triangles;
  planes_ = std::move(planes);
  bvh_.build(bounds, centroids, config.bvh);
  records_.resize(records.size());
  for (size_t i = 0; i < bvh_.prim_indices.size(); ++i) records_[i] = records[bvh_.prim_indices[i]];
  use_walk_ = config.kind != AccelKind::None &&
              (!config.allow_brute_force || records_.size() > kBruteForceMax);
  walk_ = WideBvh{};
  kdtree_ = KdTree{};
  grid_ = UniformGrid{};
  if (config.kind == AccelKind::KdTree || config.kind == AccelKind::Grid) {
    // Over the records (leaf order), so that its references are record
    // indices.
    std::vector<Bounds3> leaf_order_bounds(records_.size());
    for (size_t i = 0; i < leaf_order_bounds.size(); ++i)
      leaf_order_bounds[i] = bounds[bvh_.prim_indices[i]];
    if (config.kind == AccelKind::KdTree)
      kdtree_.build(leaf_order_bounds, config.kdtree);
    else
      grid_.build(leaf_order_bounds, config.grid);
  } else if (config.kind != AccelKind::None) {
    walk_.build(bvh_, config.kind == AccelKind::BinaryBvh ? 2 : WideBvh::kMaxArity);
  }
}

size_t Aggregate::memory_bytes() const {
  return bvh_.nodes.size() * sizeof(BvhNode) + bvh_.prim_indices.size() * sizeof(uint32_t) +
         walk_.memory_bytes() + kdtree_.memory_bytes() + grid_.memory_bytes() +
         records_.size() * sizeof(PrimRecord) + planes_.size() * sizeof(PlaneRecord);
}

}  // namespace rayscope
