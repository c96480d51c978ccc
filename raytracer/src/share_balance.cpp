#include "rayscope/share_balance.h"

#include <algorithm>
#include <numeric>
#include <queue>
#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>

#include "rayscope/render.h"
#include "rayscope/thread_arena.h"
#include "rayscope/tiles.h"

namespace rayscope {

std::vector<uint64_t> estimate_tile_costs(Scene& scene, const RenderSettings& settings) {
  RenderSettings probe = settings;
  probe.samples = 1;
  probe.max_samples = 0;
  probe.target_error = 0.0f;
  probe.only_sample = -1;
  prepare_frame(scene, probe);
  const TileGrid grid(probe);
  std::vector<uint64_t> costs(grid.count(), 0);
  auto estimate = [&]<bool kShadows, bool kSecondary>() {
    tbb::parallel_for(size_t(0), grid.count(), [&](size_t tile) {
      if (settings.share.owner(tile) != settings.share.index) return;
      const TileRect r = grid.rect(tile);
      uint64_t work = 0;
      for (int j = 0; j < kBalanceProbes; ++j)
        for (int i = 0; i < kBalanceProbes; ++i) {
          const int x = r.x0 + ((2 * i + 1) * (r.x1 - r.x0)) / (2 * kBalanceProbes);
          const int y = r.y0 + ((2 * j + 1) * (r.y1 - r.y0)) / (2 * kBalanceProbes);
          RayCounters counters;
          StatsRecorder rec;
          render_pixel<StatsRecorder, kShadows, kSecondary>(scene, probe, x, y, counters, rec);
          work += uint64_t(rec.cost.rays) + rec.cost.nodes + rec.cost.prims;
        }
      costs[tile] = work;
    });
  };
  tbb::task_arena arena = thread_arena(settings.threads);
  arena.execute([&] { with_scene_features(scene, estimate); });
  return costs;
}

std::vector<int> balance_shares(const std::vector<uint64_t>& costs, int count) {
  if (count < 1 || count > RenderSettings::kMaxShares)
    throw std::invalid_argument("balance_shares: count must be in 1.." +
                                std::to_string(RenderSettings::kMaxShares) + ", got " +
                                std::to_string(count));
  std::vector<size_t> order(costs.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return costs[a] > costs[b]; });
  // The share with the least work so far (the lower index on ties) on top.
  using Load = std::pair<uint64_t, int>;
  std::priority_queue<Load, std::vector<Load>, std::greater<Load>> loads;
  for (int s = 0; s < count; ++s) loads.push({0, s});
  std::vector<int> owners(costs.size(), 0);
  for (size_t tile : order) {
    auto [load, share] = loads.top();
    loads.pop();
    owners[tile] = share;
    // Every tile weighs at least 1, so that tiles of no estimated work (the
    // probes missed what they hold) are spread too.
    loads.push({load + std::max<uint64_t>(costs[tile], 1), share});
  }
  return owners;
}

}  // namespace rayscope
