// No structure (AccelKind::None, and every scene of at most
// Aggregate::kBruteForceMax primitives): every record is tested against every
// ray and every range, O(n) per query. The yardstick the other structures are
// tested against, and the lecture's starting point.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "rayscope/accel/accel_structure.h"
#include "rayscope/accel/bvh_on_demand.h"

namespace rayscope {

class BruteForce {
 public:
  BruteForce() = default;
  /// `records`: how many there are. `hierarchy`: the binary BVH the aggregate
  /// built for the leaf order, which the tools show (a walk of nothing shows
  /// nothing; the BVH is what the other kinds are compared with).
  BruteForce(uint32_t records, std::shared_ptr<const BvhOnDemand> hierarchy)
      : records_(records), hierarchy_(std::move(hierarchy)) {}

  /// Tests every record, in order; no node is reported to the observer.
  template <bool AnyHit, class Observer, class PrimFn>
  [[gnu::always_inline]] bool traverse(const Ray& /*ray*/, float& tmax, PrimFn&& prim,
                                       Observer& /*obs*/) const {
    return test_records<AnyHit>(0, records_, tmax, prim);
  }
  /// Every record, in order.
  template <class Range, class Observer, class PrimFn>
  void walk_range(Range& /*range*/, PrimFn&& prim, Observer& /*obs*/) const {
    for (uint32_t i = 0; i < records_; ++i) prim(i);
  }

  AccelFigures figures() const;
  size_t memory_bytes() const { return 0; }
  /// The binary BVH (see the constructor).
  AccelView view() const;
  /// Shows `hierarchy` from now on (a copy of the aggregate's).
  void share_hierarchy(std::shared_ptr<const BvhOnDemand> hierarchy) {
    hierarchy_ = std::move(hierarchy);
  }
  std::string stats_line() const;
  std::string walk_legend() const;

 private:
  uint32_t records_ = 0;
  std::shared_ptr<const BvhOnDemand> hierarchy_;
};

}  // namespace rayscope
