// The frame loop: every pixel of an image (or of settings.share of its tiles:
// tiles.h), in tiles, in parallel with TBB
// inside an arena of settings.threads, each pixel through render_pixel() with
// the recorder its policy gives it. It is the only loop over an image's pixels
// in RayScope: plain renders, statistics, renders that record selected pixels'
// ray trees, and the VTK BVH source's visit counts are policies of it.
// Pixels of a policy without a recorder (Recorder = NullRecorder), or with
// one that counts packets (statistics), are rendered in blocks whose primary
// and shadow rays are traced as packets (render_block.h, when
// renders_in_blocks()); the others one by one.
//
// A policy derives from FramePolicy and overrides what it needs:
//   using Recorder = ...;                  the integrator's recorder for a pixel
//   Recorder recorder();                   a fresh one (called once per pixel)
//   void begin(Framebuffer&);              before the first pixel (e.g. allocate AOVs)
//   void finish(size_t index, Recorder&, RayCounters&, Framebuffer&);
//                                          after pixel `index` (fb.index(x, y))
//   void tile_done(int x0, int y0, int x1, int y1, const Framebuffer&);
//                                          after the pixels [x0, x1) x [y0, y1)
//                                          of a tile are in the framebuffer
//                                          (e.g. to show them while the frame
//                                          renders; other tiles are being
//                                          written meanwhile)
//   static constexpr bool kSelects;        some pixels are rendered by select():
//   bool tile_selected(size_t tile) const;   tiles holding such a pixel ask
//   template <bool kShadows, bool kSecondary>
//   bool select(int x, int y, const Scene&, const RenderSettings&, RayCounters&,
//               Color&, SurfaceHit&, bool& hit_anything, int& samples_taken);
//                                          renders (x, y) itself and returns
//                                          true, or returns false for the plain
//                                          path; tiles without a selected pixel
//                                          run the very code of a plain render.
// recorder(), finish(), tile_done() and select() run concurrently on several
// threads for different pixels.
#pragma once

#include <algorithm>
#include <atomic>
#include <mutex>
#include <type_traits>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "rayscope/render.h"
#include "rayscope/render_block.h"
#include "rayscope/thread_arena.h"
#include "rayscope/tiles.h"

namespace rayscope {

/// The plain policy, and the defaults every policy inherits.
struct FramePolicy {
  using Recorder = NullRecorder;
  static constexpr bool kSelects = false;
  NullRecorder recorder() { return {}; }
  void begin(Framebuffer&) {}
  template <class Recorder>
  void finish(size_t, Recorder&, RayCounters&, Framebuffer&) {}
  void tile_done(int, int, int, int, const Framebuffer&) {}
  bool tile_selected(size_t) const { return false; }
  template <bool kShadows, bool kSecondary>
  bool select(int, int, const Scene&, const RenderSettings&, RayCounters&, Color&, SurfaceHit&,
              bool&, int&) {
    return false;
  }
};

/// Statistics: traversal counters and the per-pixel cost AOVs (fb.cost).
struct StatsPolicy : FramePolicy {
  using Recorder = StatsRecorder;
  StatsRecorder recorder() { return {}; }
  void begin(Framebuffer& fb) { fb.cost.assign(fb.color.size(), PixelCost{}); }
  void finish(size_t i, StatsRecorder& rec, RayCounters& cnt, Framebuffer& fb) {
    fb.cost[i] = rec.cost;
    rec.add_to(cnt);
  }
};

/// Renders the scene with `policy` into `fb`, which is resized and cleared
/// first; a caller that renders frame after frame keeps one framebuffer, so
/// that its memory is not allocated (and page-faulted in) again every frame.
/// The scene must be committed and prepare_frame()d for these settings.
/// Counters of all threads are summed into *counters when not null.
template <class Policy>
void render_frame_into(Framebuffer& fb, const Scene& scene, const RenderSettings& settings,
                       Policy& policy, RayCounters* counters = nullptr,
                       const ProgressFn& progress = {}) {
  using Recorder = typename Policy::Recorder;
  fb.resize(settings.width, settings.height);
  const bool adaptive = settings.max_samples > 0;
  if (adaptive) fb.samples.assign(fb.color.size(), 0.0f);
  policy.begin(fb);
  const TileGrid grid(settings);
  const std::vector<size_t> tiles = grid.share_tiles(settings.share);
  const size_t total = tiles.size();
  std::atomic<size_t> done{0};
  std::mutex progress_mutex;
  tbb::enumerable_thread_specific<RayCounters> local;
  constexpr bool kRecorderInBlocks =
      std::is_same_v<Recorder, NullRecorder> || counts_packets<Recorder>;
  const bool blocks = kRecorderInBlocks && renders_in_blocks(scene, settings);

  auto frame = [&]<bool kShadows, bool kSecondary>() {
    // A pixel's results into the framebuffer.
    // `depth`: primary_depth() of the hit, when `any`.
    auto store = [&](size_t i, const Color& c, const SurfaceHit& hit, bool any, float depth,
                     int taken) {
      fb.color[i] = c;
      if (adaptive) fb.samples[i] = float(taken);
      if (any) {
        fb.depth[i] = depth;
        fb.normal[i] = hit.ns;
        fb.object_id[i] = float(hit.object);
      }
    };
    // One tile's pixels. With kCheck, each pixel first asks the policy whether
    // it renders the pixel itself.
    auto tile_pixels = [&]<bool kCheck>(int x0, int y0, int x1, int y1, RayCounters& cnt) {
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
          SurfaceHit hit;
          bool any = false;
          int taken = 0;
          Color c;
          const size_t i = fb.index(x, y);
          bool selected = false;
          if constexpr (kCheck)
            selected = policy.template select<kShadows, kSecondary>(x, y, scene, settings, cnt, c,
                                                                    hit, any, taken);
          if (!selected) {
            Recorder rec = policy.recorder();
            c = render_pixel<Recorder, kShadows, kSecondary>(scene, settings, x, y, cnt, rec, &hit,
                                                             &any, &taken);
            policy.finish(i, rec, cnt, fb);
          }
          const float depth =
              any ? primary_depth(primary_ray(scene, settings, x, y, 0, nullptr), hit) : 0.0f;
          store(i, c, hit, any, depth, taken);
        }
    };
    // One tile's pixels in blocks (render_block.h), for recorders that
    // follow packets (a template, instantiated only for them).
    auto tile_blocks = [&]<class R = Recorder>(int x0, int y0, int x1, int y1, RayCounters& cnt) {
      BlockPixel px[kBlockSide * kBlockSide];
      R recs[kBlockSide * kBlockSide];
      for (int by = y0; by < y1; by += kBlockSide)
        for (int bx = x0; bx < x1; bx += kBlockSide) {
          const TileRect b = pixel_block_at({x0, y0, x1, y1}, bx, by);
          const int ex = b.x1, ey = b.y1, count = (ex - bx) * (ey - by);
          for (int k = 0; k < count; ++k) recs[k] = policy.recorder();
          render_block<R, kShadows, kSecondary>(scene, settings, bx, by, ex, ey, cnt, recs, px);
          int k = 0;
          for (int y = by; y < ey; ++y)
            for (int x = bx; x < ex; ++x, ++k) {
              const size_t i = fb.index(x, y);
              policy.finish(i, recs[k], cnt, fb);
              store(i, px[k].color, px[k].first_hit, px[k].hit_anything, px[k].depth,
                    settings.sample_grid());
            }
        }
    };
    tbb::parallel_for(tbb::blocked_range<size_t>(0, total, 1), [&](const auto& r) {
      RayCounters& cnt = local.local();
      for (size_t k = r.begin(); k != r.end(); ++k) {
        const size_t tile = tiles[k];
        const auto [x0, y0, x1, y1] = grid.rect(tile);
        bool check = false;
        if constexpr (Policy::kSelects) check = policy.tile_selected(tile);
        if (check)
          tile_pixels.template operator()<true>(x0, y0, x1, y1, cnt);
        else if constexpr (kRecorderInBlocks) {
          if (blocks)
            tile_blocks(x0, y0, x1, y1, cnt);
          else
            tile_pixels.template operator()<false>(x0, y0, x1, y1, cnt);
        } else {
          tile_pixels.template operator()<false>(x0, y0, x1, y1, cnt);
        }
        policy.tile_done(x0, y0, x1, y1, fb);
        const size_t d = ++done;
        if (progress) {
          std::lock_guard<std::mutex> lock(progress_mutex);
          progress(d, total);
        }
      }
    });
  };
  tbb::task_arena arena = thread_arena(settings.threads);
  arena.execute([&] { with_scene_features(scene, frame); });
  if (counters) {
    RayCounters sum;
    for (const RayCounters& c : local) sum += c;
    *counters = sum;
  }
}

/// render_frame_into() a new framebuffer.
template <class Policy>
Framebuffer render_frame(const Scene& scene, const RenderSettings& settings, Policy& policy,
                         RayCounters* counters = nullptr, const ProgressFn& progress = {}) {
  Framebuffer fb;
  render_frame_into(fb, scene, settings, policy, counters, progress);
  return fb;
}

}  // namespace rayscope
