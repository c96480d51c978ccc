#include "rayscope/aggregate.h"

#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "rayscope/huge_pages.h"

namespace rayscope {
namespace {

// Primitives per task of the parallel record fill: large enough that a task's
// work dwarfs TBB's cost of handing it out.
constexpr size_t kParallelGrain = 16384;

}  // namespace

void Aggregate::build(std::span<const Bounds3> bounds, std::span<const Vec3> centroids,
                      const std::function<PrimRecord(size_t)>& record_of, uint32_t num_triangles,
                      std::vector<PlaneRecord> planes, const AccelConfig& config) {
  if (centroids.size() != bounds.size())
    throw std::invalid_argument("Aggregate::build: bounds and centroids differ in size");
  if (const std::string e = accel_config_error(config); !e.empty()) throw std::invalid_argument(e);
  config_ = config;
  num_triangles_ = num_triangles;
  planes_ = std::move(planes);
  structure_ = BruteForce{};  // frees the old structure before the new one is built
  hierarchy_ = std::make_shared<const BvhOnDemand>();
  records_.clear();
  const auto start = std::chrono::steady_clock::now();
  Bvh bvh;
  bvh.build(bounds, centroids, config.bvh);
  reserve_huge(records_, bounds.size());
  records_.resize(bounds.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, records_.size(), kParallelGrain),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t i = r.begin(); i < r.end(); ++i)
                        records_[i] = record_of(bvh.prim_indices[i]);
                    });
  use_walk_ = !accel_kind_name(config.kind).brute_force &&
              (!config.allow_brute_force || records_.size() > kBruteForceMax);
  hierarchy_ = std::make_shared<const BvhOnDemand>(bvh, records_, num_triangles);
  structure_ = build_accel(config, bvh, hierarchy_, records_, num_triangles, start);
}

Aggregate::Aggregate(const Aggregate& other)
    : config_(other.config_),
      structure_(other.structure_),
      records_(other.records_),
      planes_(other.planes_),
      num_triangles_(other.num_triangles_),
      use_walk_(other.use_walk_) {
  hierarchy_ = std::make_shared<const BvhOnDemand>(*other.hierarchy_, records_);
  std::visit(
      [&](auto& s) {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, BvhWalk> || std::is_same_v<S, BruteForce>)
          s.share_hierarchy(hierarchy_);
      },
      structure_);
}

Aggregate& Aggregate::operator=(const Aggregate& other) {
  if (this != &other) *this = Aggregate(other);
  return *this;
}

AccelFigures Aggregate::figures() const {
  AccelFigures f = std::visit([](const auto& s) { return s.figures(); }, structure_);
  f.memory_bytes += records_.size() * sizeof(PrimRecord) + planes_.size() * sizeof(PlaneRecord);
  return f;
}

size_t Aggregate::memory_bytes() const {
  return hierarchy_->memory_bytes() +
         std::visit([](const auto& s) { return s.memory_bytes(); }, structure_) +
         records_.size() * sizeof(PrimRecord) + planes_.size() * sizeof(PlaneRecord);
}

std::string Aggregate::stats_line() const {
  if (!use_walk_) return BruteForce{}.stats_line();
  return std::visit([](const auto& s) { return s.stats_line(); }, structure_);
}

std::string Aggregate::walk_legend() const {
  if (!use_walk_) return BruteForce{}.walk_legend();
  return std::visit([](const auto& s) { return s.walk_legend(); }, structure_);
}

const BvhWalk* Aggregate::packet_walk(std::span<const Ray> rays, RayPacket& packet) const {
  if (rays.size() > size_t(kPacketRays))
    throw std::invalid_argument("Aggregate: " + std::to_string(rays.size()) +
                                " rays for a packet of at most " + std::to_string(kPacketRays));
  const BvhWalk* w = use_walk_ ? std::get_if<BvhWalk>(&structure_) : nullptr;
  return w != nullptr && packet.load(rays) ? w : nullptr;
}

namespace {

// A packet's lane as a single-ray observer: the walk of a ray traced alone,
// counted in its lane of a PacketWalkCost.
struct LaneCost : TraversalHooks {
  static constexpr bool kActive = true;
  static constexpr bool kNodeIds = false;
  PacketWalkCost* c;
  unsigned lane;
  void on_node(uint32_t) { c->nodes[lane]++; }
  void on_box_test(uint32_t, bool) { c->boxes[lane]++; }
  void on_cull(uint32_t) { c->culled[lane]++; }
  void on_prim_test(uint32_t) { c->prims[lane]++; }
};

// The single-ray observer of lane k: a LaneCost, or none.
template <class Cost>
auto lane_observer(Cost& cost, size_t k) {
  if constexpr (Cost::kActive) {
    cost.fell_back = true;
    return LaneCost{{}, &cost, unsigned(k)};
  } else {
    return NullTraversalObserver{};
  }
}

// The packet calls' fallback: one(k, observer) traces rays[k] alone with its
// lane's observer and says whether it hit; returns the lanes that did.
template <class Cost, class One>
unsigned each_ray_alone(std::span<const Ray> rays, Cost& cost, One&& one) {
  unsigned found = 0;
  for (size_t k = 0; k < rays.size(); ++k) {
    auto lane = lane_observer(cost, k);
    if (one(k, lane)) found |= 1u << k;
  }
  return found;
}

}  // namespace

template <class Cost>
unsigned Aggregate::intersect_packet(std::span<const Ray> rays, PrimHit* hits, Cost& cost) const {
  NullTraversalObserver obs;
  RayPacket packet;
  const BvhWalk* w = packet_walk(rays, packet);
  if (w == nullptr)
    return each_ray_alone(rays, cost,
                          [&](size_t k, auto& lane) { return intersect(rays[k], hits[k], lane); });
  unsigned found = 0;
  TrianglePrecomp pre[kPacketRays];
  ClosestSoFar closest[kPacketRays];
  for (size_t k = 0; k < rays.size(); ++k) pre[k] = TrianglePrecomp(rays[k]);
  auto prim = [&](unsigned lane, uint32_t i, float& t, const TriangleHit* decided)
      __attribute__((always_inline)) {
    return offer_closest(i, rays[lane], pre[lane], t, decided, closest[lane], obs);
  };
  w->traverse_packet<false>(packet, pre, prim, cost);
  for (size_t k = 0; k < rays.size(); ++k)
    if (closest_with_planes(rays[k], packet.tmax[k], closest[k], hits[k], obs)) found |= 1u << k;
  return found;
}

template <class Cost>
unsigned Aggregate::occluded_packet(std::span<const Ray> rays, Cost& cost) const {
  RayPacket packet;
  const BvhWalk* w = packet_walk(rays, packet);
  if (w == nullptr)
    return each_ray_alone(rays, cost,
                          [&](size_t k, auto& lane) { return occluded(rays[k], lane); });
  unsigned found = 0;
  TrianglePrecomp pre[kPacketRays];
  for (size_t k = 0; k < rays.size(); ++k) {
    float tp;
    if (first_plane_hit(rays[k], tp) >= 0) found |= 1u << k;
    pre[k] = TrianglePrecomp(rays[k]);
  }
  packet.valid &= ~found;
  auto prim = [&](unsigned lane, uint32_t i, float& t, const TriangleHit* decided)
      __attribute__((always_inline)) {
    TriangleHit th;
    return decided != nullptr || test_prim(records_[i], rays[lane], pre[lane], t, false, th);
  };
  return found | w->traverse_packet<true>(packet, pre, prim, cost);
}

unsigned Aggregate::intersect_packet(std::span<const Ray> rays, PrimHit* hits,
                                     PacketWalkCost* cost) const {
  if (cost) return intersect_packet(rays, hits, *cost);
  NoPacketWalkCost none;
  return intersect_packet(rays, hits, none);
}

unsigned Aggregate::occluded_packet(std::span<const Ray> rays, PacketWalkCost* cost) const {
  if (cost) return occluded_packet(rays, *cost);
  NoPacketWalkCost none;
  return occluded_packet(rays, none);
}

}  // namespace rayscope
