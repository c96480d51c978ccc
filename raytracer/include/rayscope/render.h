// Rendering an image: a pixel's samples through the integrator (render_pixel,
// the body of the frame loop in frame.h), and render(), the frame loop with
// the plain or the statistics policy. Each pixel depends only on its
// coordinates, the settings and the seed, so the image is bit-identical for any
// thread count.
#pragma once

#include <functional>
#include <vector>

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
/// settings.statistics is set, compiled for the widest instruction set the CPU
/// has (kernels.h; the same image on every one). Throws std::invalid_argument
/// for bad settings, std::runtime_error for a bad $RAYSCOPE_ISA (isa.h).
Framebuffer render(Scene& scene, const RenderSettings& settings, RayCounters* counters = nullptr,
                   const ProgressFn& progress = {});
/// render() into `fb`, which is resized and cleared first: a caller that
/// renders frame after frame keeps one framebuffer, so that its memory is not
/// allocated and page-faulted in again every frame (32 bytes a pixel without
/// cost AOVs: 30 MB at 1280x720).
void render_into(Framebuffer& fb, Scene& scene, const RenderSettings& settings,
                 RayCounters* counters = nullptr, const ProgressFn& progress = {});

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

/// Adaptive sampling's order of the batches along one axis: 0..count-1 in
/// bit-reversed order (0, count/2, count/4, 3count/4, ... for a power of two;
/// values >= count skipped otherwise), so that consecutive batches lie far
/// apart. Writes count values to order (count <= RenderSettings::kMaxSamples).
void spread_order(int count, int* order);

/// The strata (indices k into the M x M grid, M = settings.sample_grid()) of
/// batch j of adaptive sampling: with B = settings.samples and K = M / B, batch
/// j takes one stratum in each K x K block of the grid, at the same offset in
/// every block, so each batch is a B x B stratified pattern over the whole
/// pixel; the K x K batches together are the whole grid. `order` is
/// spread_order(K). Writes B * B indices to out, in row order.
void batch_strata(const RenderSettings& settings, const int* order, int j, int* out);

/// The primary ray of sample k of pixel (x, y). With settings.texture_filter
/// and diff not null, *diff receives the differentials of the sample's cell
/// of the pixel: the strata of the N x N grid, or with adaptive sampling the
/// B x B strata of a batch (a sample stands for that much of the pixel until
/// more batches come, and the samples of one cell then share their texture
/// footprint).
inline Ray primary_ray(const Scene& scene, const RenderSettings& settings, int x, int y, int k,
                       RayDifferential* diff) {
  const int n = settings.sample_grid();
  const Vec2 s = sample_position(x, y, k, n, settings.seed);
  if (settings.texture_filter && diff) {
    const int cells = settings.max_samples > 0 ? settings.samples : n, per_cell = n / cells;
    const float side = 1.0f / float(cells);
    const int cx = (k % n) / per_cell, cy = (k / n) / per_cell;
    *diff = scene.camera.generate_differential(float(x) + (float(cx) + 0.5f) * side,
                                               float(y) + (float(cy) + 0.5f) * side, side);
  }
  return scene.camera.generate_ray(s.x, s.y);
}

/// The framebuffer's depth of a pixel whose sample-0 primary ray `primary`
/// hit `hit`: the distance along the ray (its direction need not be unit).
inline float primary_depth(const Ray& primary, const SurfaceHit& hit) {
  return hit.t * glm::length(primary.dir);
}

/// One pixel, all its samples: what the frame loop does per pixel, so a pixel
/// rendered alone (replayed) has exactly the color it has in the frame.
/// `first_hit` receives the first sample's primary hit (for the AOVs): sample
/// 0, the top-left stratum, which every render takes first. `samples_taken`
/// receives the number of samples the pixel took (all, unless adaptive;
/// one with settings.only_sample, whose color is that sample's alone).
/// With settings.max_samples > 0 (adaptive sampling) the pixel takes batches
/// (batch_strata()) until the standard error of its mean, estimated from the
/// variance of the batches' means in each channel (the largest; at least two
/// batches and RenderSettings::kMinAdaptiveSamples samples), is below
/// settings.target_error (so a target of 0 takes every sample, even of a flat
/// pixel), or all M x M samples are taken; the samples' colors
/// are then summed in stratum order, so that a pixel that takes all of them
/// is bit-identical to the fixed M x M render (without the texture filter,
/// whose cells are then the batches' B x B strata, not the M x M ones).
/// Every sample is traced with the weight 1 / M^2 either way (the
/// contribution cutoff is per sample).
/// With settings.texture_filter, each sample's texture is box-filtered over
/// the footprint of its cell of the pixel (a stratum of the N x N grid, or of
/// a batch's B x B pattern), centred on the cell: the cells tile the pixel,
/// so their mean is the texture's mean over the pixel's footprint.
template <class Recorder = NullRecorder, bool kShadows = true, bool kSecondary = true>
Color render_pixel(const Scene& scene, const RenderSettings& settings, int x, int y,
                   RayCounters& counters, Recorder& recorder, SurfaceHit* first_hit = nullptr,
                   bool* hit_anything = nullptr, int* samples_taken = nullptr) {
  WhittedIntegrator<Recorder, kShadows, kSecondary> integrator(scene, settings, counters, recorder);
  const int n = settings.sample_grid();
  const Color w(1.0f / float(n * n));
  auto sample = [&](int k) {
    if constexpr (Recorder::kActive) recorder.begin_sample(k);
    RayDifferential diff;
    const Ray ray = primary_ray(scene, settings, x, y, k, &diff);
    SurfaceHit hit;
    hit.t = kInfinity;
    SurfaceHit* h = k == 0 ? &hit : nullptr;
    const Color c = integrator.trace(ray, RayKind::Primary, 0, w, -1, h,
                                     settings.texture_filter ? &diff : nullptr);
    if (k == 0) {
      if (first_hit) *first_hit = hit;
      if (hit_anything) *hit_anything = hit.t != kInfinity;
    }
    return c;
  };
  if (settings.only_sample >= 0) {  // a progressive pass: one sample, unscaled
    if (samples_taken) *samples_taken = 1;
    return sample(settings.only_sample);
  }
  if (settings.max_samples == 0) {
    Color sum(0.0f);
    for (int k = 0; k < n * n; ++k) sum += sample(k);
    if (samples_taken) *samples_taken = n * n;
    return sum * w;
  }
  // Adaptive sampling.
  constexpr int kMax = RenderSettings::kMaxSamples;
  const int b = settings.samples, kb = n / b, per_batch = b * b;
  int order[kMax], strata[kMax * kMax];
  spread_order(kb, order);
  thread_local std::vector<Color> colors;  // by stratum
  thread_local std::vector<uint8_t> taken;
  colors.resize(size_t(n) * size_t(n));
  taken.assign(size_t(n) * size_t(n), 0);
  // Each batch is a stratified estimate of the pixel of its own; the
  // variance of the batch means over the number of batches estimates the
  // variance of their mean (the variance between the strata of a batch,
  // which stratification removes, does not count).
  double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
  int count = 0, batches = 0;
  for (int j = 0; j < kb * kb; ++j) {
    batch_strata(settings, order, j, strata);
    Color batch(0.0f);
    for (int i = 0; i < per_batch; ++i) {
      const int k = strata[i];
      const Color c = sample(k);
      colors[size_t(k)] = c;
      taken[size_t(k)] = 1;
      batch += c;
    }
    for (int ch = 0; ch < 3; ++ch) {
      const double m = double(batch[ch]) / per_batch;
      sum[ch] += m;
      sum2[ch] += m * m;
    }
    count += per_batch;
    ++batches;
    if (count < RenderSettings::kMinAdaptiveSamples || batches < 2 || count == n * n) continue;
    double var = 0.0;  // the largest channel's variance of the batch means
    for (int ch = 0; ch < 3; ++ch) {
      const double mean = sum[ch] / batches;
      var = std::max(var, (sum2[ch] - batches * mean * mean) / (batches - 1));
    }
    if (std::sqrt(std::max(var, 0.0) / batches) < double(settings.target_error)) break;
  }
  Color total(0.0f);
  for (int k = 0; k < n * n; ++k)
    if (taken[size_t(k)]) total += colors[size_t(k)];
  if (samples_taken) *samples_taken = count;
  return count == n * n ? total * w : total * Color(1.0f / float(count));
}

}  // namespace rayscope
