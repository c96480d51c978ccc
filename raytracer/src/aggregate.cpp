#include "rayscope/aggregate.h"

#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "rayscope/huge_pages.h"

namespace rayscope {
namespace {

// Primitives per task of the parallel record fill: large enough that a task's
// work dwarfs TBB's cost of handing it out.
constexpr size_t kParallelGrain = 16384;

}  // namespace

void Aggregate::build(std::span<const Bounds3> bounds, std::span<const Vec3> centroids,
                      const std::function<PrimRecord(size_t)>& record_of, uint32_t num_triangles,
                      std::vector<PlaneRecord> planes, const AccelConfig& config) {
  if (centroids.size() != bounds.size())
    throw std::invalid_argument("Aggregate::build: bounds and centroids differ in size");
  if (const std::string e = accel_config_error(config); !e.empty()) throw std::invalid_argument(e);
  config_ = config;
  num_triangles_ = num_triangles;
  planes_ = std::move(planes);
  structure_ = BruteForce{};  // frees the old structure before the new one is built
  hierarchy_ = std::make_shared<const BvhOnDemand>();
  records_.clear();
  const auto start = std::chrono::steady_clock::now();
  Bvh bvh;
  bvh.build(bounds, centroids, config.bvh);
  reserve_huge(records_, bounds.size());
  records_.resize(bounds.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, records_.size(), kParallelGrain),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t i = r.begin(); i < r.end(); ++i)
                        records_[i] = record_of(bvh.prim_indices[i]);
                    });
  use_walk_ = !accel_kind_name(config.kind).brute_force &&
              (!config.allow_brute_force || records_.size() > kBruteForceMax);
  hierarchy_ = std::make_shared<const BvhOnDemand>(bvh, records_, num_triangles);
  structure_ = build_accel(config, bvh, hierarchy_, records_, num_triangles, start);
}

Aggregate::Aggregate(const Aggregate& other)
    : config_(other.config_),
      structure_(other.structure_),
      records_(other.records_),
      planes_(other.planes_),
      num_triangles_(other.num_triangles_),
      use_walk_(other.use_walk_) {
  hierarchy_ = std::make_shared<const BvhOnDemand>(*other.hierarchy_, records_);
  std::visit(
      [&](auto& s) {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, BvhWalk> || std::is_same_v<S, BruteForce>)
          s.share_hierarchy(hierarchy_);
      },
      structure_);
}

Aggregate& Aggregate::operator=(const Aggregate& other) {
  if (this != &other) *this = Aggregate(other);
  return *this;
}

AccelFigures Aggregate::figures() const {
  AccelFigures f = std::visit([](const auto& s) { return s.figures(); }, structure_);
  f.memory_bytes += records_.size() * sizeof(PrimRecord) + planes_.size() * sizeof(PlaneRecord);
  return f;
}

size_t Aggregate::memory_bytes() const {
  return hierarchy_->memory_bytes() +
         std::visit([](const auto& s) { return s.memory_bytes(); }, structure_) +
         records_.size() * sizeof(PrimRecord) + planes_.size() * sizeof(PlaneRecord);
}

std::string Aggregate::stats_line() const {
  if (!use_walk_) return BruteForce{}.stats_line();
  return std::visit([](const auto& s) { return s.stats_line(); }, structure_);
}

std::string Aggregate::walk_legend() const {
  if (!use_walk_) return BruteForce{}.walk_legend();
  return std::visit([](const auto& s) { return s.walk_legend(); }, structure_);
}

}  // namespace rayscope
