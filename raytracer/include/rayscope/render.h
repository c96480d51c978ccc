// Rendering an image: a pixel's samples through the integrator (render_pixel,
// the body of the frame loop in frame.h), and render(), the frame loop with
// the plain or the statistics policy. Each pixel depends only on its
// coordinates, the settings and the seed, so the image is bit-identical for any
// thread count.
#pragma once

#include <functional>

#include "rayscope/image.h"
#include "rayscope/integrator.h"
#include "rayscope/render_settings.h"
#include "rayscope/scene.h"
#include "rayscope/stats.h"

namespace rayscope {

/// Called after each finished tile with (tiles done, tiles in all); calls are
/// serialised.
using ProgressFn = std::function<void(size_t done, size_t total)>;

/// Image-plane position of sample k (0 <= k < N*N) of pixel (x, y): the center of
/// the pixel for N == 1, else a jittered point in stratum k of an N x N grid.
/// Pixel (0, 0) is the top-left pixel.
Vec2 sample_position(int x, int y, int k, int n, uint32_t seed);

/// What every frame needs first: validates the settings (the one
/// RenderSettings::validate()) and prepares scene.camera for the image size.
/// render(), render_and_record() and the replay of a pixel call it; a caller
/// that runs the frame loop itself (render_frame) calls it once before.
void prepare_frame(Scene& scene, const RenderSettings& settings);

/// Renders the committed scene: prepare_frame(), then the frame loop, with the
/// statistics policy (per-pixel cost AOVs and traversal counters) when
/// settings.statistics is set. Throws std::invalid_argument for bad settings.
Framebuffer render(Scene& scene, const RenderSettings& settings, RayCounters* counters = nullptr,
                   const ProgressFn& progress = {});

/// Calls f.template operator()<kShadows, kSecondary>() with the integrator
/// features the scene needs: no shadow code without lights, no secondary rays
/// without reflective or refractive materials.
template <class F>
decltype(auto) with_scene_features(const Scene& scene, F&& f) {
  const SceneSummary& s = scene.summary();
  const bool shadows = s.lights > 0, secondary = s.reflective || s.refractive;
  if (shadows && secondary) return f.template operator()<true, true>();
  if (shadows) return f.template operator()<true, false>();
  if (secondary) return f.template operator()<false, true>();
  return f.template operator()<false, false>();
}

/// One pixel, all its samples: what the frame loop does per pixel, so a pixel
/// rendered alone (replayed) has exactly the color it has in the frame.
/// `first_hit` receives the first sample's primary hit (for the AOVs).
template <class Recorder = NullRecorder, bool kShadows = true, bool kSecondary = true>
Color render_pixel(const Scene& scene, const RenderSettings& settings, int x, int y,
                   RayCounters& counters, Recorder& recorder, SurfaceHit* first_hit = nullptr,
                   bool* hit_anything = nullptr) {
  WhittedIntegrator<Recorder, kShadows, kSecondary> integrator(scene, settings, counters, recorder);
  const int n = settings.samples;
  const Color w(1.0f / float(n * n));
  Color sum(0.0f);
  for (int k = 0; k < n * n; ++k) {
    if constexpr (Recorder::kActive) recorder.begin_sample(k);
    Vec2 s = sample_position(x, y, k, n, settings.seed);
    Ray ray = scene.camera.generate_ray(s.x, s.y);
    SurfaceHit hit;
    hit.t = kInfinity;
    sum += integrator.trace(ray, RayKind::Primary, 0, w, -1, k == 0 ? &hit : nullptr);
    if (k == 0) {
      if (first_hit) *first_hit = hit;
      if (hit_anything) *hit_anything = hit.t != kInfinity;
    }
  }
  return sum * w;
}

}  // namespace rayscope
