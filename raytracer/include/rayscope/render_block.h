// A block of pixels rendered together, the frame loop's path for coherent
// rays (lecture: "in practice: coherence"): for each sample, the primary rays
// of a block of up to kBlockSide x kBlockSide neighbouring pixels are traced
// as one packet (Scene::intersect_packet), then the shadow rays of their hits
// toward each light as one packet per light (Scene::occluded_packet); the
// hits are then shaded one by one by the integrator, whose secondary rays
// (reflection, refraction, and their shadow rays) are incoherent and take the
// single-ray walk. The packet calls give the single-ray walk's answers bit
// for bit, so every pixel has render_pixel()'s color, bit for bit.
#pragma once

#include <algorithm>
#include <span>
#include <string>

#include "rayscope/accel/ray_packet.h"
#include "rayscope/render.h"
#include "rayscope/tiles.h"

namespace rayscope {

/// Side of the square blocks of pixels whose primary rays form one packet.
inline constexpr int kBlockSide = 4;
static_assert(kBlockSide * kBlockSide <= kPacketRays);

/// The block of kBlockSide x kBlockSide pixels from (bx, by) on in `tile`, cut
/// at the tile's edges: the frame loop's blocks start at each tile's corner.
inline TileRect pixel_block_at(const TileRect& tile, int bx, int by) {
  return {bx, by, std::min(bx + kBlockSide, tile.x1), std::min(by + kBlockSide, tile.y1)};
}

/// The block whose primary rays the frame loop traces in one packet with
/// those of pixel (x, y) (top-left origin).
inline TileRect pixel_block(const TileGrid& grid, int x, int y) {
  const TileRect tile = grid.rect(grid.tile_of(x, y));
  return pixel_block_at(tile, tile.x0 + (x - tile.x0) / kBlockSide * kBlockSide,
                        tile.y0 + (y - tile.y0) / kBlockSide * kBlockSide);
}

/// Most lights whose shadow rays render_block() traces as packets (one bit per
/// light); scenes with more lights render pixel by pixel.
inline constexpr size_t kMaxPacketLights = 64;

/// Why the frame loop renders `settings` pixel by pixel, every ray alone
/// (empty: it renders in blocks): packets are off, adaptive sampling (pixels
/// take different samples), or more than kMaxPacketLights lights.
inline std::string why_every_ray_alone(const Scene& scene, const RenderSettings& settings) {
  if (!settings.packets)
    return "packets are off (--single-rays; in VTK, renders that make Cost arrays, such as the "
           "viewer's cost heat map)";
  if (settings.max_samples != 0) return "adaptive sampling gives the pixels different samples";
  if (scene.lights.size() > kMaxPacketLights)
    return "the scene has more than " + std::to_string(kMaxPacketLights) + " lights";
  return {};
}

/// Whether the frame loop renders `settings` in blocks (why_every_ray_alone()
/// says nothing against it). Policies whose recorder observes each ray's walk
/// (recording ray trees, the structure views' visit counts) render pixel by
/// pixel; statistics count the packets' walks.
inline bool renders_in_blocks(const Scene& scene, const RenderSettings& settings) {
  return why_every_ray_alone(scene, settings).empty();
}

/// What render_block() gives for each pixel: render_pixel()'s color, its
/// sample 0's primary hit, whether that sample hit anything, and if so its
/// distance along the primary ray (primary_depth()).
struct BlockPixel {
  Color color;
  SurfaceHit first_hit;
  bool hit_anything = false;
  float depth = 0.0f;
};

/// Renders the pixels [x0, x1) x [y0, y1) (at most kBlockSide on a side) into
/// out, row by row, pixel i with recorder recs[i]: NullRecorder, or one that
/// counts_packets, which receives each packet's walk for its pixel's rays
/// (and the frame's packet counters go to `counters`).
/// renders_in_blocks(scene, settings) must hold.
template <class Recorder, bool kShadows, bool kSecondary>
void render_block(const Scene& scene, const RenderSettings& settings, int x0, int y0, int x1,
                  int y1, RayCounters& counters, Recorder* recs, BlockPixel* out) {
  constexpr bool kCount = Recorder::kActive;
  static_assert(!kCount || counts_packets<Recorder>);
  constexpr int kMax = kBlockSide * kBlockSide;
  const int n = settings.sample_grid(), w = x1 - x0, count = w * (y1 - y0);
  const Color weight(1.0f / float(n * n));
  Color sum[kMax];
  RayDifferential diffs[kMax];  // only with the texture filter
  Ray rays[kMax];
  PrimHit ph[kMax];
  SurfaceHit hits[kMax];
  uint64_t occluded[kMax];
  // A packet's walk, counted for the recorders: the frame's packet figures,
  // and the work for the ray in `lane` to the recorder of pixel[lane].
  PacketWalkCost cost;
  PacketWalkCost* const counted = kCount ? &cost : nullptr;
  auto take_cost = [&](const int* pixel, int lanes) {
    if constexpr (kCount) {
      Recorder::add_packet(cost, counters);
      for (int j = 0; j < lanes; ++j) recs[pixel[j]].add_packet_walk(cost, unsigned(j));
      cost = PacketWalkCost{};
    }
  };
  int identity[kMax];
  for (int i = 0; i < kMax; ++i) identity[i] = i;
  auto trace_sample = [&](int k) {
    for (int i = 0; i < count; ++i)
      rays[i] = primary_ray(scene, settings, x0 + i % w, y0 + i / w, k, &diffs[i]);
    const unsigned found =
        scene.intersect_packet(std::span<const Ray>(rays, size_t(count)), ph, counted);
    take_cost(identity, count);
    for (int i = 0; i < count; ++i) {
      occluded[i] = 0;
      if (found >> i & 1u) hits[i] = scene.surface_hit(rays[i], ph[i]);
    }
    if constexpr (kShadows) {
      // One packet per light: the shadow rays the integrator would trace from
      // these hits (light_view() Facing, casts_shadows), with their pixels.
      Ray shadows[kMax];
      int pixel[kMax];
      ShadingNormals sn[kMax];
      for (int i = 0; i < count; ++i)
        if (found >> i & 1u) sn[i] = shading_normals(rays[i], hits[i]);
      for (size_t li = 0; li < scene.lights.size(); ++li) {
        const Light& light = scene.lights[li];
        if (!light.casts_shadows) continue;
        int m = 0;
        for (int i = 0; i < count; ++i) {
          if (!(found >> i & 1u)) continue;
          const LightView lv = light_view(light, hits[i], sn[i].ng, sn[i].ns);
          if (lv.status != LightView::Status::Facing) continue;
          shadows[m] = shadow_ray(hits[i], sn[i].ng, light, lv.l);
          pixel[m++] = i;
        }
        if (m == 0) continue;
        const unsigned blocked =
            scene.occluded_packet(std::span<const Ray>(shadows, size_t(m)), counted);
        take_cost(pixel, m);
        for (int j = 0; j < m; ++j)
          if (blocked >> j & 1u) occluded[pixel[j]] |= uint64_t(1) << li;
      }
    }
    for (int i = 0; i < count; ++i) {
      const bool hit = found >> i & 1u;
      WhittedIntegrator<Recorder, kShadows, kSecondary> integrator(scene, settings, counters,
                                                                   recs[i]);
      const Color c =
          integrator.trace_from_packet(rays[i], hit ? &hits[i] : nullptr, weight, nullptr,
                                       settings.texture_filter ? &diffs[i] : nullptr, occluded[i]);
      if (settings.only_sample >= 0)
        sum[i] = c;
      else
        sum[i] += c;
      if (k == 0) {
        out[i].hit_anything = hit;
        if (hit) {
          out[i].first_hit = hits[i];
          out[i].depth = primary_depth(rays[i], hits[i]);
        }
      }
    }
  };
  if (settings.only_sample >= 0) {  // a progressive pass: one sample, unscaled
    trace_sample(settings.only_sample);
    for (int i = 0; i < count; ++i) out[i].color = sum[i];
    return;
  }
  for (int i = 0; i < count; ++i) sum[i] = Color(0.0f);
  for (int k = 0; k < n * n; ++k) trace_sample(k);
  for (int i = 0; i < count; ++i) out[i].color = sum[i] * weight;
}

}  // namespace rayscope
