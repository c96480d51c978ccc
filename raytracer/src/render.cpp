#include "rayscope/render.h"

#include "rayscope/kernels.h"

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

void spread_order(int count, int* order) {
  int bits = 0;
  while ((1 << bits) < count) ++bits;
  int m = 0;
  for (int r = 0; r < (1 << bits); ++r) {
    int v = 0;
    for (int i = 0; i < bits; ++i)
      if (r & (1 << i)) v |= 1 << (bits - 1 - i);
    if (v < count) order[m++] = v;
  }
}

void batch_strata(const RenderSettings& settings, const int* order, int j, int* out) {
  const int n = settings.sample_grid(), b = settings.samples, kb = n / b;
  // Batch j's offset within each K x K block: the first K batches lie on the
  // diagonal of the spread order (distinct rows and columns), the next K on
  // the next diagonal, and so on.
  const int ox = order[j % kb], oy = order[(j % kb + j / kb) % kb];
  for (int by = 0; by < b; ++by)
    for (int bx = 0; bx < b; ++bx) *out++ = (by * kb + oy) * n + bx * kb + ox;
}

void prepare_frame(Scene& scene, const RenderSettings& settings) {
  settings.validate();
  scene.camera.prepare(settings.width, settings.height);
}

Framebuffer render(Scene& scene, const RenderSettings& settings, RayCounters* counters,
                   const ProgressFn& progress) {
  Framebuffer fb;
  render_into(fb, scene, settings, counters, progress);
  return fb;
}

void render_into(Framebuffer& fb, Scene& scene, const RenderSettings& settings,
                 RayCounters* counters, const ProgressFn& progress) {
  prepare_frame(scene, settings);
  kernels().render(fb, scene, settings, counters, progress);
}

}  // namespace rayscope
