// Rays traced together (a packet): up to kPacketRays coherent rays, such as the
// primary rays of a 4x4 block of pixels or the shadow rays of their hits
// toward one light, one ray per lane of a vector of floats. The vectors are
// GCC's vector extensions, which the compiler lowers to the widest
// instructions it targets: one AVX-512 register, two AVX ones, four SSE ones,
// or scalar code. Each lane does exactly the float operations the single-ray
// code does for its ray, so that its answers are the single ray's, bit for bit.
//
// A packet walks the BVH as one (wide_bvh_packet.h) only while its rays agree
// on the sign of each direction component: then every lane of a box test reads
// the same near and far planes, as one ray does. A packet whose rays disagree
// is traced one ray at a time (RayPacket::load() says so).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "rayscope/isa.h"
#include "rayscope/math.h"
#include "rayscope/ray.h"

namespace rayscope {

/// Most rays in one packet: the lanes of one AVX-512 register of floats.
inline constexpr int kPacketRays = 16;

namespace packet_detail {

inline namespace RAYSCOPE_ISA {  // isa.h

/// One float per ray of a packet.
using Lanes = float __attribute__((vector_size(kPacketRays * sizeof(float))));
/// One comparison result per ray (all bits set where true).
using LaneBits = int32_t __attribute__((vector_size(kPacketRays * sizeof(int32_t))));

/// Bit k set where lane k of `c` is true. (Taken by reference: a 64-byte
/// vector passed by value changes the calling convention between instruction
/// sets, which GCC warns about.)
[[gnu::always_inline]] inline unsigned lane_mask(const LaneBits& c) {
#if defined(__AVX512F__)
  return _mm512_cmplt_epi32_mask(reinterpret_cast<const __m512i&>(c), _mm512_setzero_si512());
#elif defined(__AVX__)
  const __m256* h = reinterpret_cast<const __m256*>(&c);
  return unsigned(_mm256_movemask_ps(h[0])) | unsigned(_mm256_movemask_ps(h[1])) << 8;
#elif defined(__SSE2__)
  const __m128* q = reinterpret_cast<const __m128*>(&c);
  return unsigned(_mm_movemask_ps(q[0])) | unsigned(_mm_movemask_ps(q[1])) << 4 |
         unsigned(_mm_movemask_ps(q[2])) << 8 | unsigned(_mm_movemask_ps(q[3])) << 12;
#else
  unsigned m = 0;
  for (int k = 0; k < kPacketRays; ++k) m |= unsigned(c[k] != 0) << k;
  return m;
#endif
}

/// lane_mask(a <= b), with one instruction where AVX-512 has it (the compare
/// straight into a mask register).
[[gnu::always_inline]] inline unsigned lanes_le(const Lanes& a, const Lanes& b) {
#if defined(__AVX512F__)
  return _mm512_cmp_ps_mask(reinterpret_cast<const __m512&>(a), reinterpret_cast<const __m512&>(b),
                            _CMP_LE_OQ);
#else
  return lane_mask(a <= b);
#endif
}

/// The rays of a packet by lane, with what the box test needs of each.
struct alignas(64) RayPacket {
  Lanes ox, oy, oz;    ///< Origins.
  Lanes ix, iy, iz;    ///< 1 / direction, per component (as the single-ray walk's).
  Lanes tmax;          ///< Each ray's tmax; the walk lowers it at each closest hit.
  unsigned valid = 0;  ///< Lanes holding a ray.
  /// Whether the rays' direction components are negative (sign bits of ix,
  /// iy, iz), the same for every ray: bit a for axis a.
  unsigned negative = 0;

  /// Puts rays[k] in lane k (at most kPacketRays rays); the other lanes repeat
  /// the last ray and are not valid. Returns false, and loads nothing, when
  /// the rays disagree on the sign of a direction component (or there are no
  /// rays or too many): such rays are traced one at a time.
  bool load(std::span<const Ray> rays) {
    if (rays.empty() || rays.size() > size_t(kPacketRays)) return false;
    unsigned neg = ~0u;
    for (int k = 0; k < kPacketRays; ++k) {
      const Ray& r = rays[std::min(size_t(k), rays.size() - 1)];
      const Vec3 inv = 1.0f / r.dir;
      const unsigned s = unsigned(std::signbit(inv.x)) | unsigned(std::signbit(inv.y)) << 1 |
                         unsigned(std::signbit(inv.z)) << 2;
      if (neg == ~0u)
        neg = s;
      else if (s != neg)
        return false;
      ox[k] = r.origin.x;
      oy[k] = r.origin.y;
      oz[k] = r.origin.z;
      ix[k] = inv.x;
      iy[k] = inv.y;
      iz[k] = inv.z;
      tmax[k] = r.tmax;
    }
    valid = rays.size() == size_t(kPacketRays) ? (1u << kPacketRays) - 1
                                               : (1u << unsigned(rays.size())) - 1;
    negative = neg;
    return true;
  }
};

}  // namespace RAYSCOPE_ISA
}  // namespace packet_detail

using packet_detail::RayPacket;

/// One node a packet entered, as PacketWalkCost::steps logs it: the wide
/// BVH's child reference (WideBvhNode: an inner node's index, or kLeaf with
/// the leaf's first lane), a leaf's record count (0 for an inner node) and
/// the rays active in it, bit k for lane k.
struct PacketStep {
  uint32_t child = 0, count = 0;
  unsigned lanes = 0;
};

/// The work a packet's walk did for each of its rays (statistics and cost
/// AOVs), in the single-ray observer's units, per lane: the nodes the packet
/// entered while the lane's ray was active in them, the boxes tested for it
/// (the root's, then every child slot of those inner nodes), the primitives
/// tested for it (every record of the leaves it was active in) and the nodes
/// it took from the stack but skipped (beyond its closest hit). For a packet
/// of one ray and a closest hit these are the single-ray walk's counts. A
/// packet traced one ray at a time (fell_back) counts the single-ray walks.
struct PacketWalkCost {
  static constexpr bool kActive = true;
  uint32_t nodes[kPacketRays] = {}, boxes[kPacketRays] = {}, prims[kPacketRays] = {},
           culled[kPacketRays] = {};
  uint32_t node_visits = 0;   ///< Nodes the packet entered.
  uint32_t active_lanes = 0;  ///< The rays active in them, summed over the visits.
  bool fell_back = false;     ///< Its rays were traced one at a time.
  /// When set, each node entered is appended here in walk order (the
  /// packet view of record_packet(); renders leave it null).
  std::vector<PacketStep>* steps = nullptr;

  /// Adds n to field[k] for each lane k in `lanes`.
  static void add(uint32_t* field, unsigned lanes, uint32_t n) {
    for (; lanes != 0; lanes &= lanes - 1) field[__builtin_ctz(lanes)] += n;
  }
  /// The packet enters node `child` (a leaf of `count` records, or an inner
  /// node with count 0) with the rays in `lanes` active.
  void enter(uint32_t child, uint32_t count, unsigned lanes) {
    if (steps) steps->push_back({child, count, lanes});
    ++node_visits;
    active_lanes += unsigned(__builtin_popcount(lanes));
    add(nodes, lanes, 1);
  }
};

/// The plain walk's stand-in for PacketWalkCost: counts nothing.
struct NoPacketWalkCost {
  static constexpr bool kActive = false;
};

}  // namespace rayscope
