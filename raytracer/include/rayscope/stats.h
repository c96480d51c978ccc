// Ray statistics. Counters are kept per thread and merged after a render, so the
// hot paths never touch shared memory.
#pragma once

#include <array>
#include <cstdint>

#include "rayscope/ray.h"

namespace rayscope {

struct RayCounters {
  std::array<uint64_t, kRayKindCount> rays{};  ///< Rays traced, by RayKind.
  uint64_t shadow_occluded = 0;                ///< Shadow rays that found an occluder.
  uint64_t primary_hits = 0;                   ///< Primary rays that hit something.
  uint64_t depth_cutoffs = 0;   ///< Secondary rays not traced: maximum depth reached.
  uint64_t weight_cutoffs = 0;  ///< Secondary rays not traced: weight below the minimum.
  uint64_t total_internal_reflections = 0;

  uint64_t total_rays() const {
    uint64_t s = 0;
    for (uint64_t r : rays) s += r;
    return s;
  }
  RayCounters& operator+=(const RayCounters& o) {
    for (int i = 0; i < kRayKindCount; ++i) rays[i] += o.rays[i];
    shadow_occluded += o.shadow_occluded;
    primary_hits += o.primary_hits;
    depth_cutoffs += o.depth_cutoffs;
    weight_cutoffs += o.weight_cutoffs;
    total_internal_reflections += o.total_internal_reflections;
    return *this;
  }
};

}  // namespace rayscope
