// The hot loops of kernels.h for the instruction set this file is compiled for
// (isa.h's RAYSCOPE_ISA): the build compiles it once per level, each copy in
// its own inline namespace, and kernels_table.cpp picks one at run time.
#include "rayscope/kernels.h"

#include <algorithm>

#include "accel/bvh_builder.h"
#include "rayscope/frame.h"

namespace rayscope {
inline namespace RAYSCOPE_ISA {
namespace {

void render_prepared(Framebuffer& fb, const Scene& scene, const RenderSettings& settings,
                     RayCounters* counters, const ProgressFn& progress) {
  if (settings.statistics) {
    StatsPolicy stats;
    render_frame_into(fb, scene, settings, stats, counters, progress);
    return;
  }
  FramePolicy plain;
  render_frame_into(fb, scene, settings, plain, counters, progress);
}

void intersect_each(const Scene& scene, std::span<const Ray> rays, PrimHit* hits, uint8_t* found) {
  for (size_t i = 0; i < rays.size(); ++i) found[i] = scene.intersect(rays[i], hits[i]) ? 1 : 0;
}

void intersect_packets(const Scene& scene, std::span<const Ray> rays, PrimHit* hits,
                       uint8_t* found) {
  for (size_t first = 0; first < rays.size(); first += kPacketRays) {
    const size_t n = std::min(rays.size() - first, size_t(kPacketRays));
    const unsigned hit = scene.intersect_packet(rays.subspan(first, n), hits + first);
    for (size_t k = 0; k < n; ++k) found[first + k] = (hit >> k) & 1u;
  }
}

void occluded_each(const Scene& scene, std::span<const Ray> rays, uint8_t* occluded) {
  for (size_t i = 0; i < rays.size(); ++i) occluded[i] = scene.occluded(rays[i]) ? 1 : 0;
}

void occluded_packets(const Scene& scene, std::span<const Ray> rays, uint8_t* occluded) {
  for (size_t first = 0; first < rays.size(); first += kPacketRays) {
    const size_t n = std::min(rays.size() - first, size_t(kPacketRays));
    const unsigned hit = scene.occluded_packet(rays.subspan(first, n));
    for (size_t k = 0; k < n; ++k) occluded[first + k] = (hit >> k) & 1u;
  }
}

}  // namespace

/// This level's table (kernels_table.cpp declares one per level): the one
/// symbol the copies for higher levels keep global (raytracer/CMakeLists.txt).
const Kernels& isa_kernels() {
  static constexpr Kernels kTable{kCompiledIsa,      render_prepared, intersect_each,
                                  intersect_packets, occluded_each,   occluded_packets,
                                  build_bvh};
  return kTable;
}

}  // namespace RAYSCOPE_ISA
}  // namespace rayscope
