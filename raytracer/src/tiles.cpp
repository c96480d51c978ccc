#include "rayscope/tiles.h"

#include <algorithm>
#include <bit>
#include <stdexcept>
#include <string>

namespace rayscope {

TileGrid::TileGrid(const RenderSettings& settings)
    : width_(settings.width),
      height_(settings.height),
      size_(settings.tile_size),
      tiles_x_((settings.width + settings.tile_size - 1) / settings.tile_size),
      tiles_y_((settings.height + settings.tile_size - 1) / settings.tile_size) {}

TileRect TileGrid::rect(size_t tile) const {
  const int x0 = int(tile % size_t(tiles_x_)) * size_, y0 = int(tile / size_t(tiles_x_)) * size_;
  return {x0, y0, std::min(x0 + size_, width_), std::min(y0 + size_, height_)};
}

std::vector<size_t> TileGrid::share_tiles(const TileShare& share) const {
  std::vector<size_t> tiles;
  for (size_t t = 0, n = count(); t < n; ++t)
    if (share.owner(t) == share.index) tiles.push_back(t);
  return tiles;
}

namespace {

// The floats per pixel of a packed share, and one pass over the share's
// pixels in packing order: f(pixel index, floats at that pixel).
size_t floats_per_pixel(const Framebuffer& fb) {
  return 8 + (fb.samples.empty() ? 0 : 1) + (fb.cost.empty() ? 0 : 5);
}

template <class F>
void for_each_share_pixel(const RenderSettings& settings, F&& f) {
  const TileGrid grid(settings);
  for (size_t tile : grid.share_tiles(settings.share)) {
    const TileRect r = grid.rect(tile);
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x) f(size_t(y) * size_t(settings.width) + size_t(x));
  }
}

size_t share_pixels(const RenderSettings& settings) {
  size_t n = 0;
  for_each_share_pixel(settings, [&](size_t) { ++n; });
  return n;
}

}  // namespace

std::vector<float> pack_share(const Framebuffer& fb, const RenderSettings& settings) {
  std::vector<float> out;
  out.reserve(share_pixels(settings) * floats_per_pixel(fb));
  for_each_share_pixel(settings, [&](size_t i) {
    out.insert(out.end(), {fb.color[i].r, fb.color[i].g, fb.color[i].b, fb.depth[i], fb.normal[i].x,
                           fb.normal[i].y, fb.normal[i].z, fb.object_id[i]});
    if (!fb.samples.empty()) out.push_back(fb.samples[i]);
    if (!fb.cost.empty()) {
      const PixelCost& c = fb.cost[i];
      for (uint32_t v : {c.rays, c.nodes, c.boxes, c.prims, c.culled})
        out.push_back(std::bit_cast<float>(v));
    }
  });
  return out;
}

void unpack_share(Framebuffer& fb, const RenderSettings& settings, std::span<const float> packed) {
  const size_t per = floats_per_pixel(fb), expected = share_pixels(settings) * per;
  if (packed.size() != expected)
    throw std::invalid_argument("unpack_share: share " + std::to_string(settings.share.index) +
                                " of " + std::to_string(settings.share.count) + " has " +
                                std::to_string(packed.size()) + " values, expected " +
                                std::to_string(expected));
  const float* p = packed.data();
  for_each_share_pixel(settings, [&](size_t i) {
    fb.color[i] = Color(p[0], p[1], p[2]);
    fb.depth[i] = p[3];
    fb.normal[i] = Vec3(p[4], p[5], p[6]);
    fb.object_id[i] = p[7];
    p += 8;
    if (!fb.samples.empty()) fb.samples[i] = *p++;
    if (!fb.cost.empty()) {
      PixelCost& c = fb.cost[i];
      for (uint32_t* v : {&c.rays, &c.nodes, &c.boxes, &c.prims, &c.culled})
        *v = std::bit_cast<uint32_t>(*p++);
    }
  });
}

}  // namespace rayscope
