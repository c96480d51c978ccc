// The hot loops, compiled once for every instruction set (isa.h) and chosen at
// run time: the frame loop of render() with its plain and statistics policies
// (and with it the integrator, the BVH walk, its box tests, triangle blocks
// and packets), loops that trace a batch of rays one at a time or as packets
// (what bench_trace measures), and the BVH builder (every commit). The rest of
// RayScope is compiled for every x86-64 (SSE2), so one binary runs on any
// x86-64 CPU and takes the widest path the CPU has.
//
// src/kernels.cpp holds them; the build compiles it once more per level above
// the baseline and keeps each copy's inline functions private to it (see
// raytracer/CMakeLists.txt), so code compiled for AVX-512 is never called from
// code that runs on a CPU without it.
#pragma once

#include <cstdint>
#include <span>

#include "rayscope/isa.h"
#include "rayscope/render.h"

namespace rayscope {

/// One instruction set's hot loops.
struct Kernels {
  Isa isa;
  /// The frame loop of a prepared scene (prepare_frame) into `fb`:
  /// render_into()'s body, with the statistics policy when
  /// settings.statistics is set.
  void (*render)(Framebuffer& fb, const Scene& scene, const RenderSettings& settings,
                 RayCounters* counters, const ProgressFn& progress);
  /// Closest hits of rays one at a time (Scene::intersect): found[i] = 1
  /// and hits[i] set when rays[i] hits, else found[i] = 0.
  void (*intersect)(const Scene& scene, std::span<const Ray> rays, PrimHit* hits, uint8_t* found);
  /// The same as packets of kPacketRays consecutive rays (Scene::intersect_packet).
  void (*intersect_packets)(const Scene& scene, std::span<const Ray> rays, PrimHit* hits,
                            uint8_t* found);
  /// Any hits of rays one at a time (Scene::occluded): occluded[i] = 1 when
  /// rays[i] is occluded.
  void (*occluded)(const Scene& scene, std::span<const Ray> rays, uint8_t* occluded);
  /// The same as packets of kPacketRays consecutive rays (Scene::occluded_packet).
  void (*occluded_packets)(const Scene& scene, std::span<const Ray> rays, uint8_t* occluded);
  /// Bvh::build(): the binned SAH builder, binning with this level's widest
  /// instructions (the same tree on every level).
  void (*build_bvh)(Bvh& bvh, std::span<const Bounds3> bounds, std::span<const Vec3> centroids,
                    const BvhBuildConfig& cfg);
};

/// Whether this build has `isa`'s hot loops (every level on x86-64, only
/// kCompiledIsa elsewhere or in a -march=native build).
bool has_kernels(Isa isa);

/// The hot loops for `isa`. Throws std::runtime_error when this build does not
/// have them (has_kernels) or the CPU cannot run them (cpu_runs).
const Kernels& kernels(Isa isa);

/// The hot loops of chosen_isa(), or of the highest level below it that this
/// build has: what render() runs. Throws as chosen_isa() does.
const Kernels& kernels();

}  // namespace rayscope
