#include "rayscope/replay.h"

#include <stdexcept>
#include <string>

#include "rayscope/frame.h"

namespace rayscope {

void check_replay(const RenderSettings& settings, int x, int y, int sample) {
  if (x < 0 || y < 0 || x >= settings.width || y >= settings.height)
    throw std::out_of_range("pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                            ") is outside the " + std::to_string(settings.width) + "x" +
                            std::to_string(settings.height) + " image");
  const int n2 = settings.sample_grid() * settings.sample_grid();
  if (sample < -1 || sample >= n2)
    throw std::out_of_range("sample " + std::to_string(sample) + " is outside 0.." +
                            std::to_string(n2 - 1) + " (" + std::to_string(settings.sample_grid()) +
                            "x" + std::to_string(settings.sample_grid()) + " samples per pixel)");
}

namespace {

// Frame policy: plain pixels, except the selected ones, whose full ray trees
// are recorded (in the same pass, so recording costs nothing in other tiles).
struct RecordSelected : FramePolicy {
  static constexpr bool kSelects = true;
  int width;
  std::vector<int32_t> slot;  // per pixel: index into records, or -1
  std::vector<PixelRecord>* records;
  std::vector<uint8_t> tiles;  // per tile: holds a selected pixel
  bool tile_selected(size_t tile) const { return tiles[tile] != 0; }

  template <bool kShadows, bool kSecondary>
  bool select(int x, int y, const Scene& scene, const RenderSettings& settings, RayCounters& cnt,
              Color& c, SurfaceHit& hit, bool& any, int& taken) {
    const int32_t k = slot[size_t(y) * size_t(width) + size_t(x)];
    if (k < 0) return false;
    RayTreeRecorder rec;
    c = render_pixel<RayTreeRecorder, kShadows, kSecondary>(scene, settings, x, y, cnt, rec, &hit,
                                                            &any, &taken);
    PixelRecord& r = (*records)[size_t(k)];
    r.x = x;
    r.y = y;
    r.sample = -1;
    r.samples = settings.sample_grid();
    r.samples_taken = taken;
    r.color = c;
    r.rays = std::move(rec.rays);
    return true;
  }
};

}  // namespace

PixelRecord record_pixel(const Scene& scene, const RenderSettings& settings, int x, int y,
                         int sample) {
  check_replay(settings, x, y, sample);
  RayTreeRecorder rec(sample);
  RayCounters counters;
  PixelRecord out;
  out.x = x;
  out.y = y;
  out.sample = sample;
  out.samples = settings.sample_grid();
  out.color = with_scene_features(scene, [&]<bool kShadows, bool kSecondary>() {
    return render_pixel<RayTreeRecorder, kShadows, kSecondary>(
        scene, settings, x, y, counters, rec, nullptr, nullptr, &out.samples_taken);
  });
  out.rays = std::move(rec.rays);
  return out;
}

Framebuffer render_and_record(Scene& scene, const RenderSettings& settings,
                              const std::vector<glm::ivec2>& pixels,
                              std::vector<PixelRecord>& records, RayCounters* counters) {
  if (settings.statistics)
    throw std::invalid_argument("render_and_record: statistics and recording are exclusive");
  prepare_frame(scene, settings);
  const TileGrid grid(settings);
  RecordSelected sel;
  sel.width = settings.width;
  sel.slot.assign(size_t(settings.width) * size_t(settings.height), -1);
  sel.records = &records;
  sel.tiles.assign(grid.count(), 0);
  records.assign(pixels.size(), PixelRecord{});
  for (size_t k = 0; k < pixels.size(); ++k) {
    const glm::ivec2& p = pixels[k];
    check_replay(settings, p.x, p.y);
    sel.slot[size_t(p.y) * size_t(settings.width) + size_t(p.x)] = int32_t(k);
    sel.tiles[grid.tile_of(p.x, p.y)] = 1;
  }
  Framebuffer fb = render_frame(scene, settings, sel, counters);
  // A pixel listed twice shares one slot; fill the duplicates' records.
  for (size_t k = 0; k < pixels.size(); ++k) {
    const int32_t s = sel.slot[size_t(pixels[k].y) * size_t(settings.width) + size_t(pixels[k].x)];
    if (size_t(s) != k) records[k] = records[size_t(s)];
  }
  return fb;
}

}  // namespace rayscope
