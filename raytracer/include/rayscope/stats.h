// Ray and traversal statistics. Counters are kept per thread and merged after a
// render, so the hot paths never touch shared memory. Traversal counters (nodes,
// boxes, primitives) are only gathered by renders that ask for statistics: they
// come from a compile-time policy (StatsRecorder), never from a runtime flag
// checked per ray.
#pragma once

#include <array>
#include <cstdint>

#include "rayscope/accel/ray_packet.h"
#include "rayscope/ray.h"
#include "rayscope/traversal.h"

namespace rayscope {

struct RayCounters {
  std::array<uint64_t, kRayKindCount> rays{};  ///< Rays traced, by RayKind.
  uint64_t shadow_occluded = 0;                ///< Shadow rays that found an occluder.
  uint64_t primary_hits = 0;                   ///< Primary rays that hit something.
  uint64_t hits = 0;                           ///< Closest-hit rays (all kinds) that hit.
  uint64_t shadow_skipped_backfacing = 0;  ///< No shadow ray: light behind the surface (N.L <= 0).
  uint64_t depth_cutoffs = 0;              ///< Secondary rays not traced: maximum depth reached.
  uint64_t weight_cutoffs = 0;             ///< Secondary rays not traced: weight below the minimum.
  uint64_t total_internal_reflections = 0;
  // Traversal counters, gathered only with statistics on.
  uint64_t nodes_visited = 0;
  uint64_t boxes_tested = 0;
  uint64_t prims_tested = 0;
  uint64_t nodes_culled = 0;  ///< Skipped by early termination (beyond the closest hit).
  // Packets (render_block.h), gathered only with statistics on.
  uint64_t packets = 0;              ///< Packets traced (primary and shadow).
  uint64_t packet_node_visits = 0;   ///< Nodes they entered.
  uint64_t packet_active_lanes = 0;  ///< Their rays active in those nodes, summed.
  uint64_t packet_fallbacks = 0;     ///< Packets traced one ray at a time.

  uint64_t total_rays() const {
    uint64_t s = 0;
    for (uint64_t r : rays) s += r;
    return s;
  }
  RayCounters& operator+=(const RayCounters& o) {
    for (int i = 0; i < kRayKindCount; ++i) rays[i] += o.rays[i];
    shadow_occluded += o.shadow_occluded;
    primary_hits += o.primary_hits;
    hits += o.hits;
    shadow_skipped_backfacing += o.shadow_skipped_backfacing;
    depth_cutoffs += o.depth_cutoffs;
    weight_cutoffs += o.weight_cutoffs;
    total_internal_reflections += o.total_internal_reflections;
    nodes_visited += o.nodes_visited;
    boxes_tested += o.boxes_tested;
    prims_tested += o.prims_tested;
    nodes_culled += o.nodes_culled;
    packets += o.packets;
    packet_node_visits += o.packet_node_visits;
    packet_active_lanes += o.packet_active_lanes;
    packet_fallbacks += o.packet_fallbacks;
    return *this;
  }
};

/// Traversal cost of one pixel (all its samples and rays).
struct PixelCost {
  uint32_t rays = 0;
  uint32_t nodes = 0;
  uint32_t boxes = 0;
  uint32_t prims = 0;
  uint32_t culled = 0;
};

/// Integrator policy that counts traversal work per pixel (statistics and cost
/// AOVs). Same interface as NullRecorder; every hook is a counter increment.
struct StatsRecorder {
  static constexpr bool kActive = true;
  /// Primary and shadow rays traced in packets are counted from the
  /// packet's walk (add_packet_walk), not observed ray by ray.
  static constexpr bool kCountsPackets = true;
  PixelCost cost;

  /// The work a packet's walk did for the ray in `lane`.
  void add_packet_walk(const PacketWalkCost& c, unsigned lane) {
    cost.nodes += c.nodes[lane];
    cost.boxes += c.boxes[lane];
    cost.prims += c.prims[lane];
    cost.culled += c.culled[lane];
  }
  /// A packet's figures into the frame's counters.
  static void add_packet(const PacketWalkCost& c, RayCounters& counters) {
    counters.packets++;
    counters.packet_node_visits += c.node_visits;
    counters.packet_active_lanes += c.active_lanes;
    counters.packet_fallbacks += c.fell_back;
  }

  struct Observer : TraversalHooks {
    static constexpr bool kActive = true;
    static constexpr bool kNodeIds = false;
    PixelCost* c;
    explicit Observer(PixelCost* cost) : c(cost) {}
    void on_node(uint32_t) { c->nodes++; }
    void on_box_test(uint32_t, bool) { c->boxes++; }
    void on_cull(uint32_t) { c->culled++; }
    void on_prim_test(uint32_t) { c->prims++; }
  };
  void begin_sample(int) {}
  template <class RayT, class ColorT>
  int begin_ray(RayKind, const RayT&, int, const ColorT&, int) {
    cost.rays++;
    return 0;
  }
  Observer traversal(int) { return Observer{&cost}; }
  template <class... A>
  void on_hit(A&&...) {}
  template <class... A>
  void on_shadow(A&&...) {}
  template <class... A>
  void on_refraction(A&&...) {}
  template <class... A>
  void on_ambient(A&&...) {}
  template <class... A>
  void on_light_terms(A&&...) {}
  template <class... A>
  void skip_ray(A&&...) {}
  template <class... A>
  void end_ray(A&&...) {}

  void add_to(RayCounters& c) const {
    c.nodes_visited += cost.nodes;
    c.boxes_tested += cost.boxes;
    c.prims_tested += cost.prims;
    c.nodes_culled += cost.culled;
  }
};

}  // namespace rayscope
