// The binned SAH builder of Bvh::build() (Wald 2007): for each node, the primitive centroids are
// sorted into equal-width bins along each axis and the split between bins with
// the lowest surface area heuristic cost is taken.
//
// One pass over a node's primitives bins them on all three axes at once; a box is extended by one
// 8-float min (AVX, two SSE halves, or a plain loop, chosen by cfg.simd; all round the same); each
// bin keeps the box of its primitives, so that the two children's boxes are unions of bins (exact:
// min and max do not round), and the partition bounds each side's centroids as it moves them, so
// that no node walks its primitives again to bound them. Only bins that hold a primitive are swept.
// The primitives are copied into one array of references (box, centroid, index) that the partitions
// reorder in place, so that a node reads its primitives in order instead of through an index.
// Subtrees of at least cfg.parallel_min_prims primitives are built in parallel (TBB), each task's
// subtree kept at its used size, then placed where the serial recursion puts it: the tree is the
// same, node for node, whatever the number of threads.
//
// Private to raytracer/src: included by kernels.cpp, which is compiled once per
// instruction set (kernels.h), so the builder bins with the widest instructions
// the CPU has. Everything here has internal linkage (an unnamed namespace):
// each copy keeps its own.
#pragma once

#include "rayscope/accel/bvh.h"

#include "rayscope/accel/bvh.h"
#include "rayscope/huge_pages.h"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cassert>
#include <cstddef>
#include <memory>
#include <vector>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace rayscope {
namespace {

/// Most bins per axis (BvhBuildConfig::bins is clamped to [2, kMaxBins]).
constexpr int kMaxBins = 256;

/// The instructions that bin and bound boxes (BvhBuildConfig::simd): each
/// builds the same tree, bit for bit; kBest is the widest this file is
/// compiled for.
enum BoxOps { kScalar, kSse, kAvx };
#if defined(__AVX__)
constexpr BoxOps kBest = kAvx;
#elif defined(__SSE2__)
constexpr BoxOps kBest = kSse;
#else
constexpr BoxOps kBest = kScalar;
#endif

/// x, y, z and a fourth lane that nothing reads.
struct alignas(16) Lanes {
  float f[4];
};

/// A box as its lower corner and its negated upper corner, so that extending
/// it is one min over eight floats (one AVX instruction, two SSE ones, a loop
/// without SSE): min(-a, -b) = -max(a, b) exactly, and _mm_min_ps(v, acc) is
/// v < acc ? v : acc, which is how glm::min(acc, v) and, negated,
/// glm::max(acc, v) round (Bounds3::extend), signed zeros included. The empty
/// box is +inf everywhere.
struct alignas(32) Box {
  Lanes lo{{kInfinity, kInfinity, kInfinity, kInfinity}};
  Lanes neg_hi{{kInfinity, kInfinity, kInfinity, kInfinity}};

  /// Extends this box by the box (b_lo, b_neg_hi); b_neg_hi must follow
  /// b_lo in memory (one 32-byte load with AVX).
  template <BoxOps I>
  void extend(const Lanes& b_lo, const Lanes& b_neg_hi) {
#if defined(__AVX__)
    if constexpr (I == kAvx) {
      assert(&b_neg_hi == &b_lo + 1);
      _mm256_store_ps(lo.f, _mm256_min_ps(_mm256_loadu_ps(b_lo.f), _mm256_load_ps(lo.f)));
      return;
    }
#endif
#if defined(__SSE2__)
    if constexpr (I != kScalar) {
      _mm_store_ps(lo.f, _mm_min_ps(_mm_load_ps(b_lo.f), _mm_load_ps(lo.f)));
      _mm_store_ps(neg_hi.f, _mm_min_ps(_mm_load_ps(b_neg_hi.f), _mm_load_ps(neg_hi.f)));
      return;
    }
#endif
    for (int i = 0; i < 4; ++i) {
      lo.f[i] = b_lo.f[i] < lo.f[i] ? b_lo.f[i] : lo.f[i];
      neg_hi.f[i] = b_neg_hi.f[i] < neg_hi.f[i] ? b_neg_hi.f[i] : neg_hi.f[i];
    }
  }
  template <BoxOps I>
  void extend(const Box& b) {
    extend<I>(b.lo, b.neg_hi);
  }
  template <BoxOps I>
  void extend(const Lanes& p) {
    Box point;
    for (int i = 0; i < 4; ++i) {
      point.lo.f[i] = p.f[i];
      point.neg_hi.f[i] = -p.f[i];
    }
    extend<I>(point);
  }
  Bounds3 bounds() const {
    Bounds3 b;
    b.lo = Vec3(lo.f[0], lo.f[1], lo.f[2]);
    b.hi = -Vec3(neg_hi.f[0], neg_hi.f[1], neg_hi.f[2]);
    return b;
  }
  /// Bounds3::half_area() of a box that is not empty, rounded the same way.
  float half_area() const {
    const float x = -neg_hi.f[0] - lo.f[0], y = -neg_hi.f[1] - lo.f[1], z = -neg_hi.f[2] - lo.f[2];
    return x * y + y * z + z * x;
  }
};

/// One primitive: its box and centroid. The box's fourth lo lane holds the
/// primitive's index (its bits; never read as a number, only carried along
/// by min into lanes nobody reads); the other fourth lanes are 0. 48 bytes:
/// the box is read unaligned (every other one is not 32-byte aligned).
struct PrimRef {
  Lanes lo, neg_hi;  ///< The box, as Box holds it.
  Lanes c;           ///< Centroid.
  uint32_t id() const { return std::bit_cast<uint32_t>(lo.f[3]); }
};
static_assert(sizeof(PrimRef) == 48 && offsetof(PrimRef, neg_hi) == 16);

/// A node's primitives refs[begin, end), their box and their centroids' box.
struct Range {
  uint32_t begin = 0, end = 0;
  Box box, cbox;
  uint32_t count() const { return end - begin; }
};

/// A task's scratch space: per axis, the bins' boxes and counts (empty
/// between nodes); the bins that hold a primitive, in order; and the SAH cost
/// of the right side of the plane before each of them.
struct Scratch {
  std::array<std::array<Box, kMaxBins>, 3> box;
  std::array<std::array<uint32_t, kMaxBins>, 3> count{};
  /// Per axis, a bit per bin that holds a primitive (set while binning).
  std::array<std::array<uint64_t, kMaxBins / 64>, 3> occupied{};
  std::array<std::array<int, kMaxBins>, 3> used;
  std::array<int, 3> num_used;
  std::array<float, kMaxBins> right_cost;
};

template <BoxOps I>
struct Builder {
  std::span<PrimRef> refs;
  const BvhBuildConfig& cfg;
  int nb;  ///< Bins per axis.

  void bound(Range& r) const {
    r.box = Box();
    r.cbox = Box();
    for (uint32_t i = r.begin; i < r.end; ++i) {
      r.box.extend<I>(refs[i].lo, refs[i].neg_hi);
      r.cbox.extend<I>(refs[i].c);
    }
  }

  // Splits at the object median on the centroids' widest axis.
  void median_split(const Range& r, Range& left, Range& right) const {
    const uint32_t mid = r.begin + r.count() / 2;
    const int axis = max_dimension(r.cbox.bounds().extent());
    std::nth_element(
        refs.begin() + r.begin, refs.begin() + mid, refs.begin() + r.end,
        [axis](const PrimRef& a, const PrimRef& b) { return a.c.f[axis] < b.c.f[axis]; });
    left.begin = r.begin;
    left.end = right.begin = mid;
    right.end = r.end;
    bound(left);
    bound(right);
  }

  // Splits r in two (false: r becomes a leaf).
  bool split(const Range& r, int depth, Scratch& s, Range& left, Range& right) const {
    const uint32_t count = r.count();
    // One primitive is always a leaf (the node count bound of build_parallel
    // relies on it).
    if (count <= std::max(cfg.min_leaf_size, 1u)) return false;

    // Bvh::traverse keeps a 64-entry stack, one entry per level at most, so no
    // leaf may lie deeper than 64 levels below the root. Median splits need
    // ceil(log2(count / max_leaf_size)) more levels; switch to them while that
    // still fits (SAH alone can peel a few primitives per level, e.g. for
    // geometrically spaced objects, and go arbitrarily deep).
    int median_levels = 0;
    while ((uint64_t(std::max(cfg.max_leaf_size, 1u)) << median_levels) < count) ++median_levels;
    if (depth >= cfg.max_depth || depth + median_levels >= 63) {
      if (count <= cfg.max_leaf_size) return false;
      median_split(r, left, right);
      return true;
    }

    // The bin of a centroid on each axis: its offset from the centroids' box,
    // scaled to [0, nb), clamped to [0, nb - 1] before converting. Centroids
    // spanning more than the float range (e.g. spheres at -3e38 and 3e38)
    // give ext = inf, scale = 0 and inf * 0 = NaN, which goes to bin 0
    // (converting NaN to int is undefined; tests/fuzz regression
    // bvh_centroids_span_beyond_float_range.json).
    const Vec3 ext = r.cbox.bounds().extent();
    Lanes scale{{0.0f, 0.0f, 0.0f, 0.0f}};
    for (int axis = 0; axis < 3; ++axis) {
      scale.f[axis] = ext[axis] > 0.0f ? float(nb) / ext[axis] : 0.0f;
    }
    const Lanes& clo = r.cbox.lo;
    auto bins_of = [&, last = float(nb - 1)](const Lanes& c, int out[4]) {
#if defined(__SSE2__)
      if constexpr (I != kScalar) {
        __m128 x =
            _mm_mul_ps(_mm_sub_ps(_mm_load_ps(c.f), _mm_load_ps(clo.f)), _mm_load_ps(scale.f));
        x = _mm_min_ps(_mm_max_ps(x, _mm_setzero_ps()), _mm_set1_ps(last));  // NaN -> 0
        _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm_cvttps_epi32(x));
        return;
      }
#endif
      for (int axis = 0; axis < 3; ++axis) {
        const float x = (c.f[axis] - clo.f[axis]) * scale.f[axis];
        out[axis] = !(x > 0.0f) ? 0 : x < last ? int(x) : nb - 1;  // also NaN
      }
    };
    // Each primitive's box goes into its bin on each axis; mark(axis, bin)
    // records which bins hold something (in registers for up to 64 bins).
    auto bin_refs = [&](auto&& mark) {
      for (uint32_t i = r.begin; i < r.end; ++i) {
        const PrimRef& p = refs[i];
        int b[4];
        bins_of(p.c, b);
        for (int axis = 0; axis < 3; ++axis) {
          s.box[axis][size_t(b[axis])].extend<I>(p.lo, p.neg_hi);
          s.count[axis][size_t(b[axis])]++;
          mark(axis, b[axis]);
        }
      }
    };
    if (nb <= 64) {
      uint64_t occupied[3] = {0, 0, 0};
      bin_refs([&](int axis, int b) { occupied[axis] |= uint64_t(1) << b; });
      for (int axis = 0; axis < 3; ++axis) s.occupied[axis][0] = occupied[axis];
    } else {
      bin_refs(
          [&](int axis, int b) { s.occupied[axis][size_t(b) / 64] |= uint64_t(1) << (b % 64); });
    }

    // The candidate planes lie between bins; a plane with empty bins on
    // either side costs what the plane just after the last non-empty bin
    // before it costs, so only those are swept (the first plane of equal
    // cost wins, as in a sweep over every bin).
    for (int axis = 0; axis < 3; ++axis) {
      int m = 0;
      for (size_t w = 0; w < s.occupied[axis].size(); ++w) {
        for (uint64_t bits = s.occupied[axis][w]; bits; bits &= bits - 1)
          s.used[axis][size_t(m++)] = int(w * 64) + std::countr_zero(bits);
        s.occupied[axis][w] = 0;
      }
      s.num_used[axis] = m;
    }
    float best_cost = kInfinity;
    int best_axis = -1, best_bin = 0;
    for (int axis = 0; axis < 3; ++axis) {
      if (!(ext[axis] > 0.0f)) continue;
      const std::array<int, kMaxBins>& used = s.used[axis];
      const size_t m = size_t(s.num_used[axis]);
      if (m < 2) continue;
      // Sweep from the right, then from the left.
      Box acc;
      uint32_t n = 0;
      for (size_t k = m - 1; k > 0; --k) {
        acc.extend<I>(s.box[axis][size_t(used[k])]);
        n += s.count[axis][size_t(used[k])];
        s.right_cost[k] = acc.half_area() * float(n);
      }
      acc = Box();
      n = 0;
      for (size_t k = 0; k + 1 < m; ++k) {
        acc.extend<I>(s.box[axis][size_t(used[k])]);
        n += s.count[axis][size_t(used[k])];
        const float cost = acc.half_area() * float(n) + s.right_cost[k + 1];
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = axis;
          best_bin = used[k];
        }
      }
    }

    // The children's boxes, if r is split at the best plane; then the bins
    // are left empty for the next node (only those that were used).
    left = Range{r.begin, r.begin, {}, {}};
    right = Range{r.end, r.end, {}, {}};
    for (int axis = 0; axis < 3; ++axis) {
      for (int k = 0; k < s.num_used[axis]; ++k) {
        const int b = s.used[axis][size_t(k)];
        if (axis == best_axis) (b <= best_bin ? left : right).box.extend<I>(s.box[axis][size_t(b)]);
        s.box[axis][size_t(b)] = Box();
        s.count[axis][size_t(b)] = 0;
      }
    }

    const float parent_area = r.box.bounds().half_area();
    const float leaf_cost = cfg.intersection_cost * float(count);
    if (best_axis < 0) {
      // All centroids coincide: no plane separates them.
      if (count <= cfg.max_leaf_size) return false;
      median_split(r, left, right);
      return true;
    }
    float split_cost = cfg.traversal_cost;
    if (parent_area > 0.0f) split_cost += cfg.intersection_cost * best_cost / parent_area;
    if (split_cost >= leaf_cost && count <= cfg.max_leaf_size) return false;

    // Partition in place (the order std::partition gives), bounding each
    // side's centroids on the way.
    auto goes_left = [&](const PrimRef& p) {
      int b[4];
      bins_of(p.c, b);
      return b[best_axis] <= best_bin;
    };
    uint32_t i = r.begin, j = r.end;
    for (;;) {
      while (i < j && goes_left(refs[i])) left.cbox.extend<I>(refs[i++].c);
      while (i < j && !goes_left(refs[j - 1])) right.cbox.extend<I>(refs[--j].c);
      if (i == j) break;
      std::swap(refs[i], refs[j - 1]);
      left.cbox.extend<I>(refs[i++].c);
      right.cbox.extend<I>(refs[--j].c);
    }
    if (i == r.begin || i == r.end) {
      median_split(r, left, right);
      return true;
    }
    left.end = right.begin = i;
    return true;
  }

  // Builds the subtree of r whose root is nodes[node], writing its other
  // nodes from nodes[cursor] on, depth first: a node's two children next to
  // each other, then the left child's subtree, then the right child's.
  // Returns one past the last node written.
  uint32_t build_serial(std::span<BvhNode> nodes, uint32_t node, uint32_t cursor, const Range& r,
                        int depth, Scratch& s) const {
    const Bounds3 box = r.box.bounds();
    nodes[node].lo = box.lo;
    nodes[node].hi = box.hi;
    Range left, right;
    if (!split(r, depth, s, left, right)) {
      nodes[node].index = r.begin;
      nodes[node].count = r.count();
      return cursor;
    }
    const uint32_t first = cursor;
    nodes[node].index = first;
    nodes[node].count = 0;
    cursor = build_serial(nodes, first, first + 2, left, depth + 1, s);
    return build_serial(nodes, first + 1, cursor, right, depth + 1, s);
  }

  // Where the tasks' subtrees are kept until they are placed: one array with
  // huge pages, each task taking the nodes its subtree used (in whatever
  // order the tasks finish; place() puts them in build_serial's order).
  struct Pool {
    BvhNode* nodes;
    std::atomic<uint32_t> next{0};
  };

  // A subtree built by the parallel recursion. Below cfg.parallel_min_prims
  // primitives, one task builds it with build_serial (the root first, child
  // indices local) and keeps it at pool.nodes[first]. Above, the split node
  // alone is kept (`root`) with its two subtrees, built as two parallel tasks.
  struct Subtree {
    bool in_pool = false;
    uint32_t first = 0;  ///< In the pool.
    BvhNode root{};
    std::unique_ptr<Subtree> left, right;
    uint32_t size = 0;  ///< Nodes in the subtree.
  };

  Subtree build_parallel(const Range& r, int depth, Pool& pool) const {
    Subtree t;
    const auto scratch = std::make_unique<Scratch>();
    if (r.count() < cfg.parallel_min_prims) {
      // Built in this thread's own array, at most 2n - 1 nodes (every leaf
      // holds one primitive at least) and reused by its next task, then
      // copied into the pool at its used size.
      thread_local std::vector<BvhNode> local;
      if (local.size() < 2 * size_t(r.count()) - 1) local.resize(2 * size_t(r.count()) - 1);
      t.size = build_serial(local, 0, 1, r, depth, *scratch);
      t.in_pool = true;
      t.first = pool.next.fetch_add(t.size);
      std::copy(local.begin(), local.begin() + t.size, pool.nodes + t.first);
      return t;
    }
    const Bounds3 box = r.box.bounds();
    t.root.lo = box.lo;
    t.root.hi = box.hi;
    Range left, right;
    if (!split(r, depth, *scratch, left, right)) {
      t.root.index = r.begin;
      t.root.count = r.count();
      t.size = 1;
      return t;
    }
    t.root.count = 0;
    t.left = std::make_unique<Subtree>();
    t.right = std::make_unique<Subtree>();
    tbb::parallel_invoke([&] { *t.left = build_parallel(left, depth + 1, pool); },
                         [&] { *t.right = build_parallel(right, depth + 1, pool); });
    t.size = 1 + t.left->size + t.right->size;
    return t;
  }

  // Writes subtree t as build_serial would have: its root at out[node], its
  // other nodes from out[cursor] on (the root's two children, then the left
  // child's descendants, then the right child's).
  static void place(const Subtree& t, const Pool& pool, std::span<BvhNode> out, uint32_t node,
                    uint32_t cursor) {
    if (t.in_pool) {
      // Local index k >= 1 is out[cursor + k - 1].
      const BvhNode* in = pool.nodes + t.first;
      auto moved = [&](BvhNode n) {
        if (!n.is_leaf()) n.index = cursor + n.index - 1;
        return n;
      };
      out[node] = moved(in[0]);
      for (uint32_t k = 1; k < t.size; ++k) out[cursor + k - 1] = moved(in[k]);
      return;
    }
    out[node] = t.root;
    if (!t.left) return;  // a leaf
    out[node].index = cursor;
    const uint32_t right_cursor = cursor + 2 + (t.left->size - 1);
    tbb::parallel_invoke([&] { place(*t.left, pool, out, cursor, cursor + 2); },
                         [&] { place(*t.right, pool, out, cursor + 1, right_cursor); });
  }

  // The tree of refs (bounded by all) into nodes: build_serial's array, node
  // for node, whatever the tasks and threads. Memory is touched where nodes
  // are written: the pool and the final array hold the used nodes only, not
  // the worst case's 2n - 1 (three times what a tree of 2.8 primitives per
  // leaf uses; on 1.1M triangles 71 MB, which the kernel zeroed first).
  void build(const Range& all, std::vector<BvhNode>& nodes) const {
    if (all.count() < cfg.parallel_min_prims) {  // one task: straight into nodes
      reserve_huge(nodes, 2 * size_t(all.count()) - 1);
      nodes.resize(2 * size_t(all.count()) - 1);
      Scratch scratch;
      nodes.resize(build_serial(nodes, 0, 1, all, 0, scratch));
      shrink_huge(nodes);
      return;
    }
    // The pool's address space covers the worst case; pages are backed only
    // where tasks write.
    const size_t worst = 2 * size_t(all.count()) - 1;
    const std::unique_ptr<BvhNode[]> storage(new BvhNode[worst]);
    advise_huge_pages(storage.get(), worst * sizeof(BvhNode));
    Pool pool{storage.get()};
    const Subtree tree = build_parallel(all, 0, pool);
    reserve_huge(nodes, tree.size);
    nodes.resize(tree.size);
    place(tree, pool, nodes, 0, 1);
  }
};

/// Bvh::build() with this translation unit's instructions (the hot loops,
/// kernels.h, call it with their level's).
inline void build_bvh(Bvh& bvh, std::span<const Bounds3> bounds, std::span<const Vec3> centroids,
                      const BvhBuildConfig& cfg) {
  assert(bounds.size() == centroids.size());
  bvh.config = cfg;
  bvh.nodes.clear();
  bvh.prim_indices.clear();
  const size_t n = bounds.size();
  if (n == 0) return;
  std::vector<PrimRef> refs;
  assign_huge(refs, n);
  Range all{0, uint32_t(n), {}, {}};
  for (size_t i = 0; i < n; ++i) {
    const Vec3 &lo = bounds[i].lo, &hi = bounds[i].hi, &c = centroids[i];
    PrimRef& r = refs[i];
    r.lo = Lanes{{lo.x, lo.y, lo.z, std::bit_cast<float>(uint32_t(i))}};
    r.neg_hi = Lanes{{-hi.x, -hi.y, -hi.z, 0.0f}};
    r.c = Lanes{{c.x, c.y, c.z, 0.0f}};
    all.box.extend<kScalar>(r.lo, r.neg_hi);
    all.cbox.extend<kScalar>(r.c);
  }
  const int bins = std::clamp(cfg.bins, 2, kMaxBins);
  switch (cfg.simd) {
    case BvhBuildConfig::Simd::Best:
      Builder<kBest>{refs, cfg, bins}.build(all, bvh.nodes);
      break;
    case BvhBuildConfig::Simd::Sse:
      Builder<kBest == kAvx ? kSse : kBest>{refs, cfg, bins}.build(all, bvh.nodes);
      break;
    case BvhBuildConfig::Simd::Scalar:
      Builder<kScalar>{refs, cfg, bins}.build(all, bvh.nodes);
      break;
  }
  assign_huge(bvh.prim_indices, n);
  for (size_t i = 0; i < n; ++i) bvh.prim_indices[i] = refs[i].id();
}

}  // namespace
}  // namespace rayscope
