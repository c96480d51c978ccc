// One triangle against every ray of a packet (ray_packet.h): the block test
// (triangle_block.h) turned around, one lane per ray instead of one lane per
// triangle.
//
// Each lane repeats test_triangle_block_sse()'s operations for its ray, in the
// same order, so it decides exactly what that test decides: a hit with the
// same t and barycentrics as intersect_triangle(), a miss, or undecided (an
// edge function exactly 0, a miss within the rounding error, a t within its
// error bound of 0: the scalar test of the whole primitive decides). The
// rays must share the triangle test's axis permutation (kx, ky, kz: the
// dominant axis of their directions), so that a vertex's permuted coordinates
// are one value for every lane; TrianglePacketRays::load() says whether they
// do.
#pragma once

#include <cstdint>

#include "rayscope/accel/ray_packet.h"
#include "rayscope/accel/triangle_block.h"
#include "rayscope/intersect.h"
#include "rayscope/isa.h"

namespace rayscope {
namespace packet_detail {

inline namespace RAYSCOPE_ISA {  // isa.h

/// The packet's rays as the triangle test sees them (TrianglePrecomp, per lane).
struct alignas(64) TrianglePacketRays {
  Lanes ox, oy, oz;  ///< Origins, permuted to (kx, ky, kz).
  Lanes sx, sy, sz;  ///< The shear constants.
  Lanes abs_sx, abs_sy;
  int kx = 0, ky = 1, kz = 2;

  /// The constants of the valid lanes' rays (pre[k] for lane k). Returns
  /// false when their axis permutations differ.
  bool load(const TrianglePrecomp* pre, unsigned valid) {
    if (valid == 0) return false;
    const TrianglePrecomp& first = pre[__builtin_ctz(valid)];
    kx = first.kx;
    ky = first.ky;
    kz = first.kz;
    for (int k = 0; k < kPacketRays; ++k) {
      const TrianglePrecomp& p = ((valid >> k) & 1u) ? pre[k] : first;
      if (p.kz != kz) return false;
      ox[k] = p.origin_k.x;
      oy[k] = p.origin_k.y;
      oz[k] = p.origin_k.z;
      sx[k] = p.sx;
      sy[k] = p.sy;
      sz[k] = p.sz;
      abs_sx[k] = std::abs(p.sx);
      abs_sy[k] = std::abs(p.sy);
    }
    return true;
  }
};

/// What the test decided for each ray (TriangleBlockResult, by ray).
struct alignas(64) TrianglePacketResult {
  unsigned hits = 0, undecided = 0;
  Lanes t, b0, b1, b2;
  TriangleHit hit(unsigned lane) const { return {t[lane], b0[lane], b1[lane], b2[lane]}; }
};

/// test_triangle_block() for the triangle in `lane` of block `b` and the rays
/// `rays` of the packet, each with its own tmax. A lane holding another
/// primitive (a sphere, a capsule) leaves every ray undecided.
[[gnu::always_inline]] inline void test_triangle_packet(const TriangleBlock& b, unsigned lane,
                                                        const TrianglePacketRays& r,
                                                        const Lanes& tmax, unsigned rays,
                                                        TrianglePacketResult& out) {
  if (!((b.triangles >> lane) & 1u)) {
    out.hits = 0;
    out.undecided = rays;
    return;
  }
  Lanes x[3], y[3], z[3];
  for (int i = 0; i < 3; ++i) {
    z[i] = b.v[i][r.kz][lane] - r.oz;
    x[i] = (b.v[i][r.kx][lane] - r.ox) + r.sx * z[i];
    y[i] = (b.v[i][r.ky][lane] - r.oy) + r.sy * z[i];
  }
  const Lanes e0 = x[1] * y[2] - y[1] * x[2];
  const Lanes e1 = x[2] * y[0] - y[2] * x[0];
  const Lanes e2 = x[0] * y[1] - y[0] * x[1];
  const Lanes zero = {};
  const unsigned some_zero = lane_mask((e0 == zero) | (e1 == zero) | (e2 == zero));
  const unsigned disagree = lane_mask(((e0 < zero) | (e1 < zero) | (e2 < zero)) &
                                      ((e0 > zero) | (e1 > zero) | (e2 > zero)));
  auto abs = [](const Lanes& a, Lanes& out_abs) __attribute__((always_inline)) {
    out_abs = Lanes(LaneBits(a) & 0x7fffffff);  // the sign bit cleared, as with SSE
  };
  Lanes ax[3], ay[3], az[3];
  for (int i = 0; i < 3; ++i) {
    abs(x[i], ax[i]);
    abs(y[i], ay[i]);
    abs(z[i], az[i]);
  }
  // max(a, b) as _mm_max_ps computes it: a > b ? a : b.
  const Lanes mxr = ax[1] > ax[2] ? ax[1] : ax[2], mx = ax[0] > mxr ? ax[0] : mxr;
  const Lanes myr = ay[1] > ay[2] ? ay[1] : ay[2], my = ay[0] > myr ? ay[0] : myr;
  const Lanes mzr = az[1] > az[2] ? az[1] : az[2], mz = az[0] > mzr ? az[0] : mzr;
  const float g7 = gamma(7), g2 = gamma(2), g3 = gamma(3);
  const Lanes dx = g7 * (mx + r.abs_sx * mz);
  const Lanes dy = g7 * (my + r.abs_sy * mz);
  const Lanes de = 2.0f * (((g2 * mx) * my + dy * mx) + dx * my);
  const Lanes nde = -de;
  const unsigned clear_miss =
      lane_mask(((e0 < nde) | (e1 < nde) | (e2 < nde)) & ((e0 > de) | (e1 > de) | (e2 > de)));
  const unsigned near_miss = disagree & ~clear_miss & ~some_zero;
  const unsigned maybe_lanes = rays & ~(some_zero | disagree);
  if (maybe_lanes == 0) {  // every ray decided by the edge functions
    out.hits = 0;
    out.undecided = rays & (some_zero | near_miss);
    return;
  }
  const Lanes det = (e0 + e1) + e2;
  const Lanes z0 = z[0] * r.sz, z1 = z[1] * r.sz, z2 = z[2] * r.sz;
  const Lanes t_scaled = (e0 * z0 + e1 * z1) + e2 * z2;
  const Lanes inv_det = 1.0f / det;
  const Lanes t = t_scaled * inv_det;
  const unsigned out_of_range = lane_mask((det == zero) | ((det < zero) & (t_scaled >= zero)) |
                                          ((det > zero) & (t_scaled <= zero)) | ~(t <= tmax));
  Lanes az0, az1, az2, ae0, ae1, ae2, a_inv;
  abs(z0, az0);
  abs(z1, az1);
  abs(z2, az2);
  abs(e0, ae0);
  abs(e1, ae1);
  abs(e2, ae2);
  abs(inv_det, a_inv);
  const Lanes mztr = az1 > az2 ? az1 : az2, max_zt = az0 > mztr ? az0 : mztr;
  const Lanes mer = ae1 > ae2 ? ae1 : ae2, max_e = ae0 > mer ? ae0 : mer;
  const Lanes delta_t =
      (3.0f * (((g3 * max_e) * max_zt + de * max_zt) + (g3 * max_zt) * max_e)) * a_inv;
  const unsigned sure = lane_mask(t > delta_t);
  const unsigned maybe = maybe_lanes & ~out_of_range;
  out.hits = maybe & sure;
  out.undecided = rays & (some_zero | near_miss | (maybe & ~sure));
  out.t = t;
  out.b0 = e0 * inv_det;
  out.b1 = e1 * inv_det;
  out.b2 = e2 * inv_det;
}

}  // namespace RAYSCOPE_ISA
}  // namespace packet_detail

using packet_detail::TrianglePacketRays;
using packet_detail::TrianglePacketResult;

}  // namespace rayscope
