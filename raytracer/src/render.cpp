#include "rayscope/render.h"

#include "rayscope/frame.h"

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

void prepare_frame(Scene& scene, const RenderSettings& settings) {
  settings.validate();
  scene.camera.prepare(settings.width, settings.height);
}

Framebuffer render(Scene& scene, const RenderSettings& settings, RayCounters* counters,
                   const ProgressFn& progress) {
  prepare_frame(scene, settings);
  if (settings.statistics) {
    StatsPolicy stats;
    return render_frame(scene, settings, stats, counters, progress);
  }
  FramePolicy plain;
  return render_frame(scene, settings, plain, counters, progress);
}

}  // namespace rayscope
