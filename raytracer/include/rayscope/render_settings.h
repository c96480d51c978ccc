// The settings of a render and their limits. This header owns both: every
// front end (the JSON scene parser, the rayscope command, the VTK module)
// checks settings by calling RenderSettings::validate(), and quotes the named
// limits below instead of writing the numbers again.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace rayscope {

/// One of `count` shares of an image's tiles (tiles.h numbers them row by
/// row): the tiles whose owner() is index. Processes that render share 0, 1,
/// ..., count-1 of the same settings render every pixel once between them,
/// each pixel exactly as a render of the whole image does. Without `owners`
/// the tiles are interleaved (tile t to share t % count), which spreads
/// expensive regions of the image over all shares; with it (balance_shares()
/// in share_balance.h hands tiles out by their estimated cost, so that a share
/// of cheap tiles takes more of them) owners[t] renders tile t.
struct TileShare {
  int index = 0;
  int count = 1;
  /// The share of each tile (all in 0..count-1, one per tile of the image),
  /// or null for the interleaved shares.
  std::shared_ptr<const std::vector<int>> owners;
  /// The share (index) that renders `tile`.
  int owner(size_t tile) const { return owners ? (*owners)[tile] : int(tile % size_t(count)); }
  bool operator==(const TileShare&) const = default;
};

/// Settings of a render; every field has a sensible default.
struct RenderSettings {
  // --- Limits (inclusive) -------------------------------------------------
  /// Largest image width or height in pixels.
  static constexpr int kMaxImageSide = 32768;
  /// Most pixels in one image (2^28: 1 GiB of 32-bit floats per channel).
  static constexpr int64_t kMaxPixels = int64_t(1) << 28;
  /// Largest N of N x N samples per pixel.
  static constexpr int kMaxSamples = 64;
  /// Deepest recursion (primary rays have depth 0).
  static constexpr int kMaxDepth = 64;
  /// Largest contribution cutoff: a weight within a sample is at most 1.
  static constexpr float kMaxMinContribution = 1.0f;
  /// Most worker threads (0 means all hardware threads).
  static constexpr int kMaxThreads = 1024;
  /// Most shares an image's tiles can be split into (processes of one render).
  static constexpr int kMaxShares = 65536;
  /// Largest tile side in pixels.
  static constexpr int kMaxTileSize = 1024;
  /// Largest seed: 2^31 - 1, so that the seed fits every front end's integer.
  static constexpr uint32_t kMaxSeed = 2147483647u;
  /// Largest target error of adaptive sampling (a standard error of a pixel's
  /// linear RGB; colors of lit surfaces are of order 1).
  static constexpr float kMaxTargetError = 1.0f;
  /// Adaptive sampling estimates a pixel's error only once it has at least
  /// this many samples, and two batches (a variance of fewer says little).
  static constexpr int kMinAdaptiveSamples = 4;

  // --- Fields -------------------------------------------------------------
  int width = 640;
  int height = 480;
  int samples = 1;  ///< N: each pixel takes N x N stratified samples (1..kMaxSamples).
  /// -1: each pixel takes all its samples. k in 0..N*N-1: each pixel traces
  /// only sample k of its N x N grid and its color is that sample's (not
  /// divided by N^2; traced with the weight 1 / N^2, so that the contribution
  /// cutoff is the full render's): one pass of progressive rendering, which
  /// ProgressiveImage (progressive.h) adds up into the N x N render bit for
  /// bit. The AOVs (depth, normal, object id) come from sample 0, so only
  /// pass 0 has them. Not with adaptive sampling.
  int only_sample = -1;
  int max_depth = 5;  ///< Maximum recursion depth r (0..kMaxDepth).
  /// Secondary rays whose weight within their sample (the product of the
  /// reflection and transmission factors along their path, largest RGB
  /// component) is smaller are not traced (0..kMaxMinContribution). Per sample,
  /// so that the error it causes does not grow with the sample count (a ray's
  /// weight in the pixel is this times 1 / N^2).
  float min_contribution = 1e-3f;
  int threads = 0;    ///< 0: all hardware threads.
  uint32_t seed = 0;  ///< Seed of the stratified jitter (0..kMaxSeed).
  int tile_size = 16;
  /// The tiles this render computes (all by default); the others are left as
  /// Framebuffer::resize() clears them.
  TileShare share;
  /// Box-filter procedural textures (the checkerboard) over the footprint on
  /// the surface of each primary sample's cell of the pixel (render_pixel()),
  /// from ray differentials (camera.h, footprint() in ray.h,
  /// material_color_filtered()); secondary rays' hits stay point sampled.
  bool texture_filter = false;
  /// Adaptive sampling: 0 (off: every pixel takes samples x samples), or M, a
  /// multiple of `samples` up to kMaxSamples: a pixel then takes its samples
  /// from the M x M stratified grid in batches of samples x samples (each
  /// batch spread over the whole pixel), and stops once the standard error of
  /// its mean (from the variance of the batches' means) is below
  /// target_error, or when all
  /// M x M are taken. With target_error 0 it takes all: the M x M render.
  int max_samples = 0;
  /// Adaptive sampling's target standard error of a pixel (0..kMaxTargetError);
  /// needs max_samples > 0.
  float target_error = 0.0f;
  /// Gather traversal statistics and per-pixel cost AOVs (a separate compiled
  /// path; the plain path has no counting code at all).
  bool statistics = false;
  /// Trace the primary rays of blocks of neighbouring pixels, and their hits'
  /// shadow rays, as packets (render_block.h); false: every ray alone. The
  /// image is the same bit for bit either way.
  bool packets = true;

  /// N of the N x N grid a pixel's samples come from: max_samples with
  /// adaptive sampling, else samples.
  int sample_grid() const { return max_samples > 0 ? max_samples : samples; }
  bool operator==(const RenderSettings&) const = default;

  /// Throws std::invalid_argument naming the first bad field, its range and
  /// the value, e.g. "samples must be in 1..64 (N for N x N per pixel), got 65".
  void validate() const;
};

/// The shortest text that reads back as the same float ("0.001", not
/// "0.00100000005"): how settings are printed, in validate()'s messages and in
/// command lines that must reproduce them exactly.
std::string shortest_text(float v);

}  // namespace rayscope
