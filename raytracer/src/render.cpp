#include "rayscope/render.h"

#include <atomic>
#include <mutex>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace rayscope {

void RenderSettings::validate() const {
  auto fail = [](const std::string& s) { throw std::invalid_argument(s); };
  if (width <= 0 || height <= 0) fail("image size must be positive");
  if (width > 32768 || height > 32768 || double(width) * height > 268435456.0)
    fail("image size " + std::to_string(width) + "x" + std::to_string(height) + " is too large");
  if (samples < 1 || samples > 64) fail("samples must be in 1..64 (N for N x N per pixel)");
  if (max_depth < 0 || max_depth > 64) fail("max_depth must be in 0..64");
  if (!std::isfinite(min_contribution) || min_contribution < 0.0f)
    fail("min_contribution must be finite and >= 0");
  if (threads < 0 || threads > 1024) fail("threads must be in 0..1024");
  if (tile_size < 1 || tile_size > 1024) fail("tile_size must be in 1..1024");
}

namespace {
// SplitMix64: a small, well-mixed hash for the deterministic jitter.
uint64_t mix(uint64_t z) {
  z += 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}
}  // namespace

Vec2 sample_position(int x, int y, int k, int n, uint32_t seed) {
  if (n == 1) return Vec2(float(x) + 0.5f, float(y) + 0.5f);
  uint64_t h =
      mix((uint64_t(seed) << 32) ^ mix((uint64_t(uint32_t(y)) << 32) | uint32_t(x)) ^ uint64_t(k));
  float u = float(h >> 40) * 0x1p-24f;
  float v = float((h >> 16) & 0xffffff) * 0x1p-24f;
  int sx = k % n, sy = k / n;
  return Vec2(float(x) + (float(sx) + u) / float(n), float(y) + (float(sy) + v) / float(n));
}

namespace {

template <bool kStats, bool kShadows, bool kSecondary>
void render_tiles(const Scene& scene, const RenderSettings& settings, Framebuffer& fb,
                  tbb::enumerable_thread_specific<RayCounters>& local, const ProgressFn& progress) {
  const int ts = settings.tile_size;
  const int tiles_x = (settings.width + ts - 1) / ts;
  const int tiles_y = (settings.height + ts - 1) / ts;
  const size_t total = size_t(tiles_x) * size_t(tiles_y);
  std::atomic<size_t> done{0};
  std::mutex progress_mutex;
  using Recorder = std::conditional_t<kStats, StatsRecorder, NullRecorder>;

  auto body = [&](const tbb::blocked_range<size_t>& r) {
    RayCounters& cnt = local.local();
    for (size_t tile = r.begin(); tile != r.end(); ++tile) {
      int x0 = int(tile % size_t(tiles_x)) * ts, y0 = int(tile / size_t(tiles_x)) * ts;
      int x1 = std::min(x0 + ts, settings.width), y1 = std::min(y0 + ts, settings.height);
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
          SurfaceHit hit;
          bool any = false;
          Recorder rec;
          Color c = render_pixel<Recorder, kShadows, kSecondary>(scene, settings, x, y, cnt, rec,
                                                                 &hit, &any);
          size_t i = fb.index(x, y);
          fb.color[i] = c;
          if constexpr (kStats) {
            fb.cost[i] = rec.cost;
            rec.add_to(cnt);
          }
          if (any) {
            Vec2 s = sample_position(x, y, 0, settings.samples, settings.seed);
            fb.depth[i] = hit.t * glm::length(scene.camera.generate_ray(s.x, s.y).dir);
            fb.normal[i] = hit.ns;
            fb.object_id[i] = float(hit.object);
          }
        }
      size_t d = ++done;
      if (progress) {
        std::lock_guard<std::mutex> lock(progress_mutex);
        progress(d, total);
      }
    }
  };
  tbb::parallel_for(tbb::blocked_range<size_t>(0, total, 1), body);
}

}  // namespace

Framebuffer render(Scene& scene, const RenderSettings& settings, RayCounters* counters,
                   const ProgressFn& progress) {
  settings.validate();
  scene.camera.prepare(settings.width, settings.height);
  Framebuffer fb;
  fb.resize(settings.width, settings.height);
  if (settings.statistics) fb.cost.assign(fb.color.size(), PixelCost{});
  tbb::enumerable_thread_specific<RayCounters> local;
  const Scene& cscene = scene;
  const int threads =
      settings.threads > 0 ? settings.threads : tbb::this_task_arena::max_concurrency();
  tbb::task_arena arena(threads);
  arena.execute([&] {
    with_scene_features(cscene, [&]<bool kShadows, bool kSecondary>() {
      if (settings.statistics)
        render_tiles<true, kShadows, kSecondary>(cscene, settings, fb, local, progress);
      else
        render_tiles<false, kShadows, kSecondary>(cscene, settings, fb, local, progress);
    });
  });
  if (counters) {
    RayCounters sum;
    for (const RayCounters& c : local) sum += c;
    *counters = sum;
  }
  return fb;
}

}  // namespace rayscope
