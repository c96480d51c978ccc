#include "rayscope/render_settings.h"

#include <charconv>
#include <cmath>
#include <string>

namespace rayscope {

namespace {
[[noreturn]] void fail(const std::string& s) {
  throw std::invalid_argument(s);
}
std::string range(long long lo, long long hi) {
  return std::to_string(lo) + ".." + std::to_string(hi);
}
}  // namespace

std::string shortest_text(float v) {
  char buf[32];
  return std::string(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
}

void RenderSettings::validate() const {
  const std::string size = std::to_string(width) + "x" + std::to_string(height);
  if (width < 1 || height < 1)
    fail("image size " + size + " is invalid: width and height must be at least 1");
  if (width > kMaxImageSide || height > kMaxImageSide ||
      int64_t(width) * int64_t(height) > kMaxPixels)
    fail("image size " + size + " is too large: at most " + std::to_string(kMaxImageSide) +
         " pixels per side and " + std::to_string(kMaxPixels) + " pixels in all");
  if (samples < 1 || samples > kMaxSamples)
    fail("samples must be in " + range(1, kMaxSamples) + " (N for N x N per pixel), got " +
         std::to_string(samples));
  if (max_depth < 0 || max_depth > kMaxDepth)
    fail("max_depth must be in " + range(0, kMaxDepth) + ", got " + std::to_string(max_depth));
  if (!(min_contribution >= 0.0f && min_contribution <= kMaxMinContribution))
    fail("min_contribution must be in 0.." + shortest_text(kMaxMinContribution) + ", got " +
         shortest_text(min_contribution));
  if (threads < 0 || threads > kMaxThreads)
    fail("threads must be in " + range(0, kMaxThreads) + " (0: all), got " +
         std::to_string(threads));
  if (seed > kMaxSeed)
    fail("seed must be in " + range(0, kMaxSeed) + ", got " + std::to_string(seed));
  if (max_samples != 0 &&
      (max_samples < samples || max_samples > kMaxSamples || max_samples % samples != 0))
    fail("max_samples must be 0 (no adaptive sampling) or a multiple of samples (" +
         std::to_string(samples) + ") in " + range(samples, kMaxSamples) + ", got " +
         std::to_string(max_samples));
  if (!(target_error >= 0.0f && target_error <= kMaxTargetError))
    fail("target_error must be in 0.." + shortest_text(kMaxTargetError) + ", got " +
         shortest_text(target_error));
  if (target_error > 0.0f && max_samples == 0)
    fail("target_error " + shortest_text(target_error) +
         " needs adaptive sampling: max_samples must be set (a multiple of samples)");
  if (tile_size < 1 || tile_size > kMaxTileSize)
    fail("tile_size must be in " + range(1, kMaxTileSize) + ", got " + std::to_string(tile_size));
  if (share.count < 1 || share.count > kMaxShares)
    fail("share.count must be in " + range(1, kMaxShares) + ", got " + std::to_string(share.count));
  if (share.index < 0 || share.index >= share.count)
    fail("share.index must be in " + range(0, share.count - 1) + ", got " +
         std::to_string(share.index));
  if (share.owners) {
    const int64_t tiles = int64_t((width + tile_size - 1) / tile_size) *
                          int64_t((height + tile_size - 1) / tile_size);
    if (int64_t(share.owners->size()) != tiles)
      fail("share.owners must name the share of each of the " + std::to_string(tiles) +
           " tiles, got " + std::to_string(share.owners->size()));
    for (int o : *share.owners)
      if (o < 0 || o >= share.count)
        fail("share.owners must be shares in " + range(0, share.count - 1) + ", got " +
             std::to_string(o));
  }
  const int grid = sample_grid();
  if (only_sample < -1 || only_sample >= grid * grid)
    fail("only_sample must be -1 (all samples) or a sample in " + range(0, grid * grid - 1) +
         " of the " + std::to_string(grid) + " x " + std::to_string(grid) + " grid, got " +
         std::to_string(only_sample));
  if (only_sample >= 0 && max_samples != 0)
    fail(
        "only_sample (one sample per pixel, a progressive pass) does not go with adaptive "
        "sampling (max_samples " +
        std::to_string(max_samples) + ")");
}

}  // namespace rayscope
