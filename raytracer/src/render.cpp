#include "rayscope/render.h"

#include "rayscope/recorder.h"

#include <atomic>
#include <mutex>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace rayscope {

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

// No pixel is recorded: the selection check compiles away.
struct NoSelection {
  static constexpr bool kActive = false;
  bool tile_selected(size_t) const { return false; }
  template <bool, bool>
  bool record(int, int, const Scene&, const RenderSettings&, RayCounters&, Color&, SurfaceHit&,
              bool&) {
    return false;
  }
};

template <bool kStats, bool kShadows, bool kSecondary, class Selection = NoSelection>
void render_tiles(const Scene& scene, const RenderSettings& settings, Framebuffer& fb,
                  tbb::enumerable_thread_specific<RayCounters>& local, const ProgressFn& progress,
                  [[maybe_unused]] Selection& selection) {
  const int ts = settings.tile_size;
  const int tiles_x = (settings.width + ts - 1) / ts;
  const int tiles_y = (settings.height + ts - 1) / ts;
  const size_t total = size_t(tiles_x) * size_t(tiles_y);
  std::atomic<size_t> done{0};
  std::mutex progress_mutex;
  using Recorder = std::conditional_t<kStats, StatsRecorder, NullRecorder>;

  // One tile's pixels. With kCheck, each pixel first asks the selection whether
  // to record it; tiles without a selected pixel run the kCheck == false loop,
  // the very code of a plain render.
  auto tile_pixels = [&]<bool kCheck>(int x0, int y0, int x1, int y1, RayCounters& cnt) {
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        SurfaceHit hit;
        bool any = false;
        Color c;
        size_t i = fb.index(x, y);
        bool recorded = false;
        if constexpr (kCheck)
          recorded = selection.template record<kShadows, kSecondary>(x, y, scene, settings, cnt, c,
                                                                     hit, any);
        if (!recorded) {
          Recorder rec;
          c = render_pixel<Recorder, kShadows, kSecondary>(scene, settings, x, y, cnt, rec, &hit,
                                                           &any);
          if constexpr (kStats) {
            fb.cost[i] = rec.cost;
            rec.add_to(cnt);
          }
        }
        fb.color[i] = c;
        if (any) {
          Vec2 s = sample_position(x, y, 0, settings.samples, settings.seed);
          fb.depth[i] = hit.t * glm::length(scene.camera.generate_ray(s.x, s.y).dir);
          fb.normal[i] = hit.ns;
          fb.object_id[i] = float(hit.object);
        }
      }
  };

  auto body = [&](const tbb::blocked_range<size_t>& r) {
    RayCounters& cnt = local.local();
    for (size_t tile = r.begin(); tile != r.end(); ++tile) {
      int x0 = int(tile % size_t(tiles_x)) * ts, y0 = int(tile / size_t(tiles_x)) * ts;
      int x1 = std::min(x0 + ts, settings.width), y1 = std::min(y0 + ts, settings.height);
      bool check = false;
      if constexpr (Selection::kActive) check = selection.tile_selected(tile);
      if (check)
        tile_pixels.template operator()<true>(x0, y0, x1, y1, cnt);
      else
        tile_pixels.template operator()<false>(x0, y0, x1, y1, cnt);
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
  NoSelection none;
  arena.execute([&] {
    with_scene_features(cscene, [&]<bool kShadows, bool kSecondary>() {
      if (settings.statistics)
        render_tiles<true, kShadows, kSecondary>(cscene, settings, fb, local, progress, none);
      else
        render_tiles<false, kShadows, kSecondary>(cscene, settings, fb, local, progress, none);
    });
  });
  if (counters) {
    RayCounters sum;
    for (const RayCounters& c : local) sum += c;
    *counters = sum;
  }
  return fb;
}

namespace {

// Pixels whose ray trees are recorded during a full render.
struct PixelSelection {
  static constexpr bool kActive = true;
  int width;
  std::vector<int32_t> slot;  // per pixel: index into records, or -1
  std::vector<PixelRecord>* records;
  std::vector<uint8_t> tiles;  // per tile: holds a selected pixel
  bool tile_selected(size_t tile) const { return tiles[tile] != 0; }

  template <bool kShadows, bool kSecondary>
  bool record(int x, int y, const Scene& scene, const RenderSettings& settings, RayCounters& cnt,
              Color& c, SurfaceHit& hit, bool& any) {
    int32_t k = slot[size_t(y) * size_t(width) + size_t(x)];
    if (k < 0) return false;
    RayTreeRecorder rec;
    c = render_pixel<RayTreeRecorder, kShadows, kSecondary>(scene, settings, x, y, cnt, rec, &hit,
                                                            &any);
    PixelRecord& r = (*records)[size_t(k)];
    r.x = x;
    r.y = y;
    r.sample = -1;
    r.samples = settings.samples;
    r.color = c;
    r.rays = std::move(rec.rays);
    return true;
  }
};

}  // namespace

Framebuffer render_and_record(Scene& scene, const RenderSettings& settings,
                              const std::vector<glm::ivec2>& pixels,
                              std::vector<PixelRecord>& records, RayCounters* counters) {
  settings.validate();
  if (settings.statistics)
    throw std::invalid_argument("render_and_record: statistics and recording are exclusive");
  scene.camera.prepare(settings.width, settings.height);
  Framebuffer fb;
  fb.resize(settings.width, settings.height);
  const int ts = settings.tile_size, tiles_x = (settings.width + ts - 1) / ts;
  const int tiles_y = (settings.height + ts - 1) / ts;
  PixelSelection sel{settings.width, std::vector<int32_t>(fb.color.size(), -1), &records,
                     std::vector<uint8_t>(size_t(tiles_x) * size_t(tiles_y), 0)};
  records.assign(pixels.size(), PixelRecord{});
  for (size_t k = 0; k < pixels.size(); ++k) {
    const glm::ivec2& p = pixels[k];
    if (p.x < 0 || p.y < 0 || p.x >= settings.width || p.y >= settings.height)
      throw std::out_of_range("pixel (" + std::to_string(p.x) + ", " + std::to_string(p.y) +
                              ") is outside the image");
    sel.slot[size_t(p.y) * size_t(settings.width) + size_t(p.x)] = int32_t(k);
    sel.tiles[size_t(p.y / ts) * size_t(tiles_x) + size_t(p.x / ts)] = 1;
  }
  tbb::enumerable_thread_specific<RayCounters> local;
  const Scene& cscene = scene;
  const int threads =
      settings.threads > 0 ? settings.threads : tbb::this_task_arena::max_concurrency();
  tbb::task_arena arena(threads);
  arena.execute([&] {
    with_scene_features(cscene, [&]<bool kShadows, bool kSecondary>() {
      render_tiles<false, kShadows, kSecondary>(cscene, settings, fb, local, {}, sel);
    });
  });
  // A pixel listed twice shares one slot; fill the duplicates' records.
  for (size_t k = 0; k < pixels.size(); ++k) {
    int32_t s = sel.slot[size_t(pixels[k].y) * size_t(settings.width) + size_t(pixels[k].x)];
    if (size_t(s) != k) records[k] = records[size_t(s)];
  }
  if (counters) {
    RayCounters sum;
    for (const RayCounters& c : local) sum += c;
    *counters = sum;
  }
  return fb;
}

}  // namespace rayscope
