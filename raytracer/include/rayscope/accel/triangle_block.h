// A BVH leaf's triangles four at a time: their vertices stored by coordinate
// (structure of arrays), so that one SSE instruction does one step of
// intersect_triangle() for all four lanes.
//
// The block test decides nothing differently from intersect_triangle(): it
// repeats the float test lane by lane with the same operations in the same
// order (translation, shear, edge functions, the miss path's error bound, det,
// the scaled distance, t against tmax, t against its error bound). A lane is
// a miss only where intersect_triangle() returns false at one of those steps,
// and a hit only where it returns true, with the same t and barycentrics, bit
// for bit. Every other lane is left undecided, for the scalar test of the whole
// primitive: an edge function exactly 0 (recomputed in double), a miss within
// the rounding error or a t within its error bound of 0 (the exact test), and
// the lanes of other primitives. So the hits, and their order, are the same
// with or without blocks and with any instruction set. Most lanes are decided
// here (every lane of rays in general position, test_triangle_block).
#pragma once

#include <cmath>
#include <cstdint>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "rayscope/intersect.h"

namespace rayscope {

/// Up to kLanes triangles of one leaf or of neighbouring small leaves (a leaf
/// tests only its own lanes), by coordinate: v[vertex][axis][lane].
struct alignas(16) TriangleBlock {
  static constexpr int kLanes = 4;
  float v[3][3][kLanes];
  /// Lanes holding a triangle the cull may drop.
  uint8_t triangles = 0;
  /// Lanes holding another primitive (a sphere or capsule): always left to
  /// the scalar test.
  uint8_t others = 0;
  /// The record in lane 0; lane k holds record first + k. A leaf's blocks
  /// follow one another, so a leaf labelled by its first lane s (block s /
  /// kLanes, lane s % kLanes) has its record j in lane s + j. (Kept here, in
  /// the block's padding, so that a walk reaching a leaf by its first block
  /// needs no other load to find the records.)
  uint32_t first = 0;

  /// Vertex i (0, 1, 2) of the triangle in `lane`: the record's, bit for bit.
  Vec3 vertex(int i, unsigned lane) const { return {v[i][0][lane], v[i][1][lane], v[i][2][lane]}; }
  /// intersect_triangle() for the triangle in `lane`: the whole test, which
  /// decides what the block test leaves undecided.
  bool test_lane(unsigned lane, const TrianglePrecomp& pre, float tmax, TriangleHit& th) const {
    return intersect_triangle(pre, tmax, vertex(0, lane), vertex(1, lane), vertex(2, lane), th);
  }
};
static_assert(sizeof(TriangleBlock) == 160, "the record index lives in the padding");

/// Per-ray constants of the cull, from the triangle test's TrianglePrecomp.
struct TriangleBlockRay {
  const TrianglePrecomp& pre;
  float abs_sx, abs_sy;
#if defined(__SSE2__)
  __m128 ox, oy, oz, sx, sy, sz, abs_sx4, abs_sy4;
#endif

  explicit TriangleBlockRay(const TrianglePrecomp& p)
      : pre(p), abs_sx(std::abs(p.sx)), abs_sy(std::abs(p.sy)) {
#if defined(__SSE2__)
    ox = _mm_set1_ps(p.origin_k.x);
    oy = _mm_set1_ps(p.origin_k.y);
    oz = _mm_set1_ps(p.origin_k.z);
    sx = _mm_set1_ps(p.sx);
    sy = _mm_set1_ps(p.sy);
    sz = _mm_set1_ps(p.sz);
    abs_sx4 = _mm_set1_ps(abs_sx);
    abs_sy4 = _mm_set1_ps(abs_sy);
#endif
  }
};

/// What the block test decided for each lane: `hits` (t and barycentrics
/// exactly as intersect_triangle() gives them), or `undecided` (the scalar
/// test of the whole primitive decides: an edge function exactly 0, a miss
/// within the rounding error, a hit whose t is within its error bound of 0, and
/// the lanes of other primitives). The lanes in neither are misses.
struct TriangleBlockResult {
  unsigned hits = 0, undecided = 0;
  alignas(16) float t[TriangleBlock::kLanes];
  alignas(16) float b0[TriangleBlock::kLanes];
  alignas(16) float b1[TriangleBlock::kLanes];
  alignas(16) float b2[TriangleBlock::kLanes];
  TriangleHit hit(unsigned lane) const { return {t[lane], b0[lane], b1[lane], b2[lane]}; }
};

/// intersect_triangle() with this tmax for the triangles of `b`, one lane at a
/// time, up to where it would call the double or exact test: the portable
/// fallback of test_triangle_block() and its reference in the tests.
inline void test_triangle_block_scalar(const TriangleBlock& b, const TriangleBlockRay& r,
                                       float tmax, TriangleBlockResult& out) {
  const TrianglePrecomp& pre = r.pre;
  out.hits = 0;
  out.undecided = b.others;
  for (int k = 0; k < TriangleBlock::kLanes; ++k) {
    if (!((b.triangles >> k) & 1u)) continue;
    Vec3 p[3];
    for (int i = 0; i < 3; ++i) {
      p[i] = Vec3(b.v[i][pre.kx][k] - pre.origin_k.x, b.v[i][pre.ky][k] - pre.origin_k.y,
                  b.v[i][pre.kz][k] - pre.origin_k.z);
      p[i].x += pre.sx * p[i].z;
      p[i].y += pre.sy * p[i].z;
    }
    const float e0 = p[1].x * p[2].y - p[1].y * p[2].x;
    const float e1 = p[2].x * p[0].y - p[2].y * p[0].x;
    const float e2 = p[0].x * p[1].y - p[0].y * p[1].x;
    const unsigned lane = 1u << k;
    if (e0 == 0.0f || e1 == 0.0f || e2 == 0.0f) {
      out.undecided |= lane;  // recomputed in double
      continue;
    }
    const Vec3 m = glm::max(glm::abs(p[0]), glm::max(glm::abs(p[1]), glm::abs(p[2])));
    const float de = edge_error_bound(pre, m.x, m.y, m.z);
    if ((e0 < 0.0f || e1 < 0.0f || e2 < 0.0f) && (e0 > 0.0f || e1 > 0.0f || e2 > 0.0f)) {
      if (!((e0 < -de || e1 < -de || e2 < -de) && (e0 > de || e1 > de || e2 > de)))
        out.undecided |= lane;  // decided exactly
      continue;
    }
    const float det = e0 + e1 + e2;
    const float z0 = p[0].z * pre.sz, z1 = p[1].z * pre.sz, z2 = p[2].z * pre.sz;
    const float t_scaled = e0 * z0 + e1 * z1 + e2 * z2;
    if (det == 0.0f || (det < 0.0f && t_scaled >= 0.0f) || (det > 0.0f && t_scaled <= 0.0f))
      continue;
    const float inv_det = 1.0f / det;
    const float t = t_scaled * inv_det;
    if (!(t <= tmax)) continue;
    const float max_zt = max_component(glm::abs(Vec3(z0, z1, z2)));
    const float max_e = max_component(glm::abs(Vec3(e0, e1, e2)));
    const float delta_t = 3.0f *
                          (gamma(3) * max_e * max_zt + de * max_zt + gamma(3) * max_zt * max_e) *
                          std::abs(inv_det);
    if (!(t > delta_t)) {
      out.undecided |= lane;  // t may still be positive: decided exactly
      continue;
    }
    out.hits |= lane;
    out.t[k] = t;
    out.b0[k] = e0 * inv_det;
    out.b1[k] = e1 * inv_det;
    out.b2[k] = e2 * inv_det;
  }
}

#if defined(__SSE2__)
/// test_triangle_block_scalar() for the four lanes at once, with SSE. With
/// EarlyMiss, a block where every lane is a miss decided by the edge functions
/// returns before the hit path (the division and t's error bound): same
/// result, one branch more (see test_triangle_block()).
template <bool EarlyMiss = false>
[[gnu::always_inline]] inline void test_triangle_block_sse(const TriangleBlock& b,
                                                           const TriangleBlockRay& r, float tmax,
                                                           TriangleBlockResult& out) {
  const TrianglePrecomp& pre = r.pre;
  __m128 x[3], y[3], z[3];
  for (int i = 0; i < 3; ++i) {
    z[i] = _mm_sub_ps(_mm_load_ps(b.v[i][pre.kz]), r.oz);
    x[i] = _mm_add_ps(_mm_sub_ps(_mm_load_ps(b.v[i][pre.kx]), r.ox), _mm_mul_ps(r.sx, z[i]));
    y[i] = _mm_add_ps(_mm_sub_ps(_mm_load_ps(b.v[i][pre.ky]), r.oy), _mm_mul_ps(r.sy, z[i]));
  }
  auto edge = [&](int i, int j) {
    return _mm_sub_ps(_mm_mul_ps(x[i], y[j]), _mm_mul_ps(y[i], x[j]));
  };
  const __m128 e0 = edge(1, 2), e1 = edge(2, 0), e2 = edge(0, 1);
  const __m128 zero = _mm_setzero_ps();
  auto any = [](__m128 a, __m128 b, __m128 c) { return _mm_or_ps(_mm_or_ps(a, b), c); };
  auto max3 = [](__m128 a, __m128 b, __m128 c) { return _mm_max_ps(a, _mm_max_ps(b, c)); };
  const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
  auto abs = [&](__m128 a) { return _mm_and_ps(a, abs_mask); };

  const __m128 some_zero =
      any(_mm_cmpeq_ps(e0, zero), _mm_cmpeq_ps(e1, zero), _mm_cmpeq_ps(e2, zero));
  const __m128 disagree =
      _mm_and_ps(any(_mm_cmplt_ps(e0, zero), _mm_cmplt_ps(e1, zero), _mm_cmplt_ps(e2, zero)),
                 any(_mm_cmpgt_ps(e0, zero), _mm_cmpgt_ps(e1, zero), _mm_cmpgt_ps(e2, zero)));

  // edge_error_bound() of the largest |x'|, |y'|, |z|.
  const __m128 mx = max3(abs(x[0]), abs(x[1]), abs(x[2]));
  const __m128 my = max3(abs(y[0]), abs(y[1]), abs(y[2]));
  const __m128 mz = max3(abs(z[0]), abs(z[1]), abs(z[2]));
  const __m128 g7 = _mm_set1_ps(gamma(7));
  const __m128 dx = _mm_mul_ps(g7, _mm_add_ps(mx, _mm_mul_ps(r.abs_sx4, mz)));
  const __m128 dy = _mm_mul_ps(g7, _mm_add_ps(my, _mm_mul_ps(r.abs_sy4, mz)));
  const __m128 de = _mm_mul_ps(
      _mm_set1_ps(2.0f),
      _mm_add_ps(
          _mm_add_ps(_mm_mul_ps(_mm_mul_ps(_mm_set1_ps(gamma(2)), mx), my), _mm_mul_ps(dy, mx)),
          _mm_mul_ps(dx, my)));
  const __m128 nde = _mm_xor_ps(de, _mm_set1_ps(-0.0f));
  const __m128 clear_miss =
      _mm_and_ps(any(_mm_cmplt_ps(e0, nde), _mm_cmplt_ps(e1, nde), _mm_cmplt_ps(e2, nde)),
                 any(_mm_cmpgt_ps(e0, de), _mm_cmpgt_ps(e1, de), _mm_cmpgt_ps(e2, de)));
  const __m128 near_miss = _mm_andnot_ps(clear_miss, disagree);

  const unsigned tris = b.triangles;
  const unsigned zero_lanes = unsigned(_mm_movemask_ps(some_zero));
  if (EarlyMiss && (tris & ~(unsigned(_mm_movemask_ps(clear_miss)) & ~zero_lanes)) == 0) {
    out.hits = 0;
    out.undecided = b.others;
    return;
  }

  // The hit path: the sign of the scaled distance, t against tmax, then t
  // against its error bound.
  const __m128 det = _mm_add_ps(_mm_add_ps(e0, e1), e2);
  const __m128 z0 = _mm_mul_ps(z[0], r.sz), z1 = _mm_mul_ps(z[1], r.sz),
               z2 = _mm_mul_ps(z[2], r.sz);
  const __m128 t_scaled =
      _mm_add_ps(_mm_add_ps(_mm_mul_ps(e0, z0), _mm_mul_ps(e1, z1)), _mm_mul_ps(e2, z2));
  const __m128 inv_det = _mm_div_ps(_mm_set1_ps(1.0f), det);
  const __m128 t = _mm_mul_ps(t_scaled, inv_det);
  const __m128 in_range = _mm_andnot_ps(
      any(_mm_cmpeq_ps(det, zero),
          _mm_or_ps(_mm_and_ps(_mm_cmplt_ps(det, zero), _mm_cmpge_ps(t_scaled, zero)),
                    _mm_and_ps(_mm_cmpgt_ps(det, zero), _mm_cmple_ps(t_scaled, zero))),
          _mm_cmpnle_ps(t, _mm_set1_ps(tmax))),
      _mm_castsi128_ps(_mm_set1_epi32(-1)));
  const __m128 max_zt = max3(abs(z0), abs(z1), abs(z2));
  const __m128 max_e = max3(abs(e0), abs(e1), abs(e2));
  const __m128 g3 = _mm_set1_ps(gamma(3));
  const __m128 delta_t = _mm_mul_ps(
      _mm_mul_ps(_mm_set1_ps(3.0f), _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_mul_ps(g3, max_e), max_zt),
                                                          _mm_mul_ps(de, max_zt)),
                                               _mm_mul_ps(_mm_mul_ps(g3, max_zt), max_e))),
      abs(inv_det));
  const __m128 sure = _mm_cmpgt_ps(t, delta_t);
  const __m128 maybe_hit = _mm_andnot_ps(_mm_or_ps(some_zero, disagree), in_range);

  const unsigned near_lanes = unsigned(_mm_movemask_ps(near_miss)) & ~zero_lanes;
  const unsigned maybe_lanes = unsigned(_mm_movemask_ps(maybe_hit));
  const unsigned sure_lanes = unsigned(_mm_movemask_ps(sure));
  out.hits = tris & maybe_lanes & sure_lanes;
  out.undecided = (tris & (zero_lanes | near_lanes | (maybe_lanes & ~sure_lanes))) | b.others;
  _mm_store_ps(out.t, t);
  _mm_store_ps(out.b0, _mm_mul_ps(e0, inv_det));
  _mm_store_ps(out.b1, _mm_mul_ps(e1, inv_det));
  _mm_store_ps(out.b2, _mm_mul_ps(e2, inv_det));
}
#endif

/// intersect_triangle() with this tmax for the triangles of `b`, as far as
/// the float test goes (TriangleBlockResult): SSE where the compiler targets
/// it, else test_triangle_block_scalar(). Same result.
///
/// EarlyMiss: see test_triangle_block_sse(). Closest-hit walks use it: most
/// blocks a primary ray reaches miss in every lane, and skipping the hit path
/// there made bench_trace's primary rays 8-12% faster on the bunny. Shadow rays
/// do not: the branch made them 10% slower (probably because they start on a
/// surface, so the first blocks they test hold the triangle they leave, a
/// lane left undecided; not verified).
template <bool EarlyMiss = false>
[[gnu::always_inline]] inline void test_triangle_block(const TriangleBlock& b,
                                                       const TriangleBlockRay& r, float tmax,
                                                       TriangleBlockResult& out) {
#if defined(__SSE2__)
  test_triangle_block_sse<EarlyMiss>(b, r, tmax, out);
#else
  test_triangle_block_scalar(b, r, tmax, out);
#endif
}

}  // namespace rayscope
