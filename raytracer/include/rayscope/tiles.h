// An image's tiles: the squares of RenderSettings::tile_size pixels the frame
// loop hands to its threads, numbered row by row (the last column and row
// may be narrower), and a share of them (RenderSettings::share) as one of
// several processes renders it: which tiles, and their pixels packed into one
// buffer to send to the process that assembles the image.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "rayscope/image.h"
#include "rayscope/render_settings.h"

namespace rayscope {

struct TileRect {
  int x0, y0, x1, y1;  ///< Pixels [x0, x1) x [y0, y1).
};

class TileGrid {
 public:
  explicit TileGrid(const RenderSettings& settings);
  /// Tiles in the image.
  size_t count() const { return size_t(tiles_x_) * size_t(tiles_y_); }
  /// The tile holding pixel (x, y).
  size_t tile_of(int x, int y) const {
    return size_t(y / size_) * size_t(tiles_x_) + size_t(x / size_);
  }
  TileRect rect(size_t tile) const;
  /// The tiles of `share` in order: those whose TileShare::owner() is
  /// share.index.
  std::vector<size_t> share_tiles(const TileShare& share) const;

 private:
  int width_, height_, size_, tiles_x_, tiles_y_;
};

/// The pixels of settings.share in `fb` (rendered with `settings`), tile by
/// tile in share order and row by row within a tile: color, depth, normal and
/// object id, then the sample count when fb has them and the five cost counters
/// (their bits, exactly) when it has them. Every process of a render packs the same
/// channels, so the one that assembles the image unpacks each share with
/// unpack_share() and the same settings with that share.
std::vector<float> pack_share(const Framebuffer& fb, const RenderSettings& settings);

/// Writes a pack_share() buffer of settings.share into fb, which has the
/// image's size and the same channels (resize() it and allocate samples and
/// cost first). Throws std::invalid_argument when the buffer's length is not
/// the share's.
void unpack_share(Framebuffer& fb, const RenderSettings& settings, std::span<const float> packed);

}  // namespace rayscope
