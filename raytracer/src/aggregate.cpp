#include "rayscope/aggregate.h"

#include <algorithm>
#include <cassert>
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
                      const RecordSource& record_of, uint32_t num_triangles,
                      std::vector<PlaneRecord> planes, const AccelConfig& config) {
  if (centroids.size() != bounds.size())
    throw std::invalid_argument("Aggregate::build: bounds and centroids differ in size");
  if (const std::string e = accel_config_error(config); !e.empty()) throw std::invalid_argument(e);
  config_ = config;
  num_triangles_ = num_triangles;
  planes_ = std::move(planes);
  structure_ = BruteForce{};  // frees the old structure before the new one is built
  hierarchy_ = std::make_shared<const BvhOnDemand>();
  records_ = std::make_shared<const LeafRecords>();
  walk_records_ = nullptr;
  std::vector<PrimRecord>().swap(others_);
  const auto start = std::chrono::steady_clock::now();
  Bvh bvh;
  bvh.build(bounds, centroids, config.bvh);
  const size_t n = bounds.size();
  use_walk_ = !accel_kind_name(config.kind).brute_force &&
              (!config.allow_brute_force || n > kBruteForceMax);
  assign_huge(ids_, n);
  if (use_walk_ && (config.kind == AccelKind::Bvh || config.kind == AccelKind::BinaryBvh)) {
    // The walk's blocks hold the triangles (blocks_hold_records()): they are
    // filled straight from record_of, with each record's id and the other
    // primitives' records kept on the way, and no array of records is made
    // (on 1.1M triangles 53 MB to fill, first touches included); the records
    // are made again from the blocks when a tool asks. Ids increase with i,
    // so the last primitive's bounds the other primitives' ids.
    const uint32_t last = n > 0 ? record_of(n - 1).id : 0;
    others_.resize(n > 0 && last >= num_triangles ? last + 1 - num_triangles : 0);
    structure_ = build_accel(
        config, bvh, hierarchy_,
        [&](size_t i) {
          const PrimRecord r = record_of(bvh.prim_indices[i]);
          ids_[i] = r.id;
          if (r.id >= num_triangles) others_[r.id - num_triangles] = r;
          return r;
        },
        num_triangles, start);
    assert(blocks_hold_records());
    records_ = std::make_shared<const LeafRecords>(make_records());
    hierarchy_ = std::make_shared<const BvhOnDemand>(bvh, records_, num_triangles);
    share_hierarchy();
    return;
  }
  // Every other structure walks the records themselves, in leaf order.
  std::vector<PrimRecord> records;
  reserve_huge(records, n);
  records.resize(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, kParallelGrain),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t i = r.begin(); i < r.end(); ++i) {
                        records[i] = record_of(bvh.prim_indices[i]);
                        ids_[i] = records[i].id;
                      }
                    });
  records_ = std::make_shared<const LeafRecords>(std::move(records));
  walk_records_ = records_->get().data();
  hierarchy_ = std::make_shared<const BvhOnDemand>(bvh, records_, num_triangles);
  const std::vector<PrimRecord>& held = records_->get();
  structure_ = build_accel(
      config, bvh, hierarchy_, [&](size_t i) { return held[i]; }, num_triangles, start);
  assert(!blocks_hold_records());
}

LeafRecords::Make Aggregate::make_records() const {
  return [blocks = std::span(std::get<BvhWalk>(structure_).triangle_blocks()),
          ids = std::span(ids_), others = std::span(others_), num_triangles = num_triangles_] {
    return BvhWalk::records_from_blocks(blocks, ids, others, num_triangles);
  };
}

void Aggregate::share_hierarchy() {
  std::visit(
      [&](auto& s) {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, BvhWalk> || std::is_same_v<S, BruteForce>)
          s.share_hierarchy(hierarchy_);
      },
      structure_);
}

Aggregate::Aggregate(const Aggregate& other)
    : config_(other.config_),
      structure_(other.structure_),
      walk_records_(other.walk_records_),
      ids_(other.ids_),
      others_(other.others_),
      planes_(other.planes_),
      num_triangles_(other.num_triangles_),
      use_walk_(other.use_walk_) {
  // Held records are shared (they never change); records made from blocks
  // are made from the copy's own.
  records_ = blocks_hold_records()
                 ? std::make_shared<const LeafRecords>(*other.records_, make_records())
                 : other.records_;
  hierarchy_ = std::make_shared<const BvhOnDemand>(*other.hierarchy_, records_);
  share_hierarchy();
}

Aggregate& Aggregate::operator=(const Aggregate& other) {
  if (this != &other) *this = Aggregate(other);
  return *this;
}

AccelFigures Aggregate::figures() const {
  AccelFigures f = std::visit([](const auto& s) { return s.figures(); }, structure_);
  f.memory_bytes += records_bytes();
  return f;
}

size_t Aggregate::memory_bytes() const {
  return hierarchy_->memory_bytes() +
         std::visit([](const auto& s) { return s.memory_bytes(); }, structure_) + records_bytes();
}

size_t Aggregate::records_bytes() const {
  return records_->memory_bytes() + ids_.size() * sizeof(uint32_t) +
         others_.size() * sizeof(PrimRecord) + planes_.size() * sizeof(PlaneRecord);
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
