// Uniform grid (lecture: "Spatial data structures"): the box around all
// primitives cut into nx x ny x nz equal cells, each primitive stored in every
// cell its bounds overlap (the lecture's "store it multiple times"), and the
// 3D-DDA walk (Amanatides & Woo) from cell to cell, front to back, with early
// termination and mailboxing.
//
// Like the other builders (bvh.h, kdtree.h), the builder knows nothing about
// geometry: it takes one bounding box per primitive and a GridBuildConfig.
// Primitives are named by their index in that span. The cells' reference lists
// are stored compactly (CSR): cell c holds refs[offsets[c] .. offsets[c+1]).
//
// Cells are named by their linear index c = x + nx * (y + ny * z), 0 <= c <
// cells(); the grid's own box (the only box a ray is tested against) is named
// by box_id() = cells(), one past the last cell.
//
// PrimStorage::SmallestCell ("overlapping regions", a loose grid): every cell
// is enlarged by loose_factor times its size on every side (at most
// kMaxLooseFactor = 0.5, so a loose cell reaches into its 26 neighbours and no
// further), and each primitive is stored once: in the cell holding its
// bounds' center if its bounds fit that cell's loose box, else in the grid's
// list of big primitives (big_refs), which every ray that enters the grid
// tests: the grid is the loose grid's only inner node. A primitive stored in
// cell c can then only be hit in c or a neighbour, so the walk, at each cell
// it enters, tests the lists of the cell and its neighbours whose loose boxes
// the ray hits, each list once per ray (mailboxed by cell).
#pragma once

#include <algorithm>
#include <array>
#include <cassert>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "rayscope/accel/accel_structure.h"
#include "rayscope/accel/mailbox.h"
#include "rayscope/accel/prim_storage.h"
#include "rayscope/intersect.h"
#include "rayscope/math.h"
#include "rayscope/ray.h"
#include "rayscope/traversal.h"

namespace rayscope {

/// Settings of the grid builder, with the defaults used by RayScope.
struct GridBuildConfig {
  /// Cells per primitive of the automatic resolution (the classic rule's
  /// lambda): about density * n cells in all for n primitives, cubic cells,
  /// so cells per axis = extent * cbrt(density * n / volume), rounded and
  /// clamped to [1, UniformGrid::kMaxResolution]. An axis whose extent would
  /// get less than one cell (a flat scene) gets one, and the others share the
  /// density (per area, per length).
  float density = 2.0f;
  /// Cells per axis (x, y, z) given explicitly; 0 on an axis: chosen by the
  /// automatic rule (from the density and the axes given).
  glm::uvec3 resolution{0u};
};

/// Quality figures of a built grid (see UniformGrid::quality()).
struct GridQuality {
  glm::uvec3 resolution{0u};
  size_t cells = 0, empty_cells = 0;
  size_t references = 0;  ///< Primitive references in all cells and the big list.
  /// SmallestCell: primitives in the grid's big list (fit no loose cell).
  size_t big_refs = 0;
  double refs_per_prim = 0.0;  ///< references / primitives: how often one is stored.
  uint32_t max_cell_refs = 0;
  double mean_cell_refs = 0.0;  ///< Over the non-empty cells.
  size_t memory_bytes = 0;      ///< Cell offsets, references and cell planes.
  double build_seconds = 0.0;
};

/// Why `resolution` (cells per axis, 0: automatic) cannot be built, in one
/// line; empty when it can (at most UniformGrid::kMaxResolution per axis and,
/// when all three are given, kMaxCells in all). The one check: the builder
/// throws std::length_error with it, the CLI's --grid-resolution and the VTK
/// image algorithm's GridResolution report it.
std::string grid_resolution_error(const glm::uvec3& resolution);

class UniformGrid {
 public:
  /// Most cells per axis (automatic resolutions are clamped to it; a larger
  /// explicit one is refused).
  static constexpr uint32_t kMaxResolution = 4096;
  /// Most cells in all: 64 MiB of cell offsets.
  static constexpr size_t kMaxCells = size_t(1) << 24;
  /// Most references in all (1 GiB): an explicit resolution that would store
  /// more is refused.
  static constexpr size_t kMaxReferences = size_t(1) << 28;
  /// The automatic resolution is coarsened until the grid holds at most this
  /// many references per primitive (objects that span many cells, such as
  /// long thin triangles, would otherwise multiply without bound).
  static constexpr size_t kMaxAutoReferencesPerPrim = 32;

  /// Builds the grid over bounds.size() primitives (finite bounds, lo <= hi;
  /// zero-size boxes are fine), stored the `storage` way: EveryCell or
  /// SmallestCell (the loose grid), whose cells are enlarged by `loose_factor`
  /// times their size on every side. An empty input gives an empty grid that
  /// every ray misses. Throws std::invalid_argument for non-finite or inverted
  /// bounds, std::length_error for an explicit resolution beyond
  /// kMaxResolution, kMaxCells or kMaxReferences.
  ///
  /// Precondition (asserted): storage is not Split and loose_factor_error()
  /// accepts loose_factor (at most kMaxLooseFactor, which the loose walk
  /// relies on). build_accel() (accel_build.h) checks both for AccelConfig
  /// and refuses a bad one with a message.
  void build(std::span<const Bounds3> bounds, const GridBuildConfig& config = {},
             PrimStorage storage = PrimStorage::EveryCell,
             float loose_factor = kDefaultLooseFactor);

  bool empty() const { return offsets.empty(); }
  /// The grid's box: the bounds of all primitives.
  Bounds3 bounds() const { return bounds_; }
  /// Cells per axis (0 when empty).
  glm::uvec3 resolution() const { return res_; }
  size_t cells() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  /// The id the grid's box is reported with (on_box_test): one past the last
  /// cell.
  uint32_t box_id() const { return uint32_t(cells()); }
  /// Cell (x, y, z)'s linear index, the id the observer sees.
  uint32_t cell_id(uint32_t x, uint32_t y, uint32_t z) const {
    return x + res_.x * (y + res_.y * z);
  }
  /// The box of cell (x, y, z): between its planes (closed).
  Bounds3 cell_box(uint32_t x, uint32_t y, uint32_t z) const {
    return Bounds3(Vec3(planes[0][x], planes[1][y], planes[2][z]),
                   Vec3(planes[0][x + 1], planes[1][y + 1], planes[2][z + 1]));
  }
  /// Whether the cells are loose (PrimStorage::SmallestCell).
  bool loose() const { return loose_; }
  /// How the grid stores straddlers: EveryCell or SmallestCell.
  PrimStorage storage() const {
    return loose_ ? PrimStorage::SmallestCell : PrimStorage::EveryCell;
  }
  /// The box the walks test for cell (x, y, z): cell_box(), enlarged by the
  /// loose factor for SmallestCell (loose_box()).
  Bounds3 node_box(uint32_t x, uint32_t y, uint32_t z) const {
    return loose_ ? loose_box(cell_box(x, y, z), loose_factor_) : cell_box(x, y, z);
  }
  /// The cells (first, last per axis) whose closed boxes overlap the closed
  /// box b, clipped to the grid; false if b misses the grid.
  bool cell_range(const Bounds3& b, glm::uvec3& first, glm::uvec3& last) const;
  /// The primitives stored in cell `id` (indices into the build's span).
  std::span<const uint32_t> cell_refs(uint32_t id) const {
    return {refs.data() + offsets[id], refs.data() + offsets[id + 1]};
  }
  GridQuality quality() const;
  /// The AccelStructure interface (accel_structure.h): figures, teaching
  /// view (refs: the indices build() was given), the --stats line and the
  /// ray-tree legend of the walk.
  AccelFigures figures() const;
  AccelView view() const;
  std::string stats_line() const;
  std::string walk_legend() const;
  size_t memory_bytes() const {
    return (offsets.size() + refs.size() + big_refs.size()) * sizeof(uint32_t) +
           (planes[0].size() + planes[1].size() + planes[2].size()) * sizeof(float);
  }

  /// Walks the cells the ray [origin, origin + tmax * dir] crosses, nearest
  /// first (3D-DDA). `prim(index, tmax)` tests primitive `index` and returns
  /// true on a hit, lowering tmax to the hit distance (closest hit) or ending
  /// the walk (AnyHit). Returns whether anything was hit.
  ///
  /// - Robustness: a cell's crossings are computed as box_interval() computes
  ///   a box's, and crossings within the margin kBoxFarScale of one another
  ///   count as simultaneous: the walk then enters every cell around the
  ///   corner or edge they meet at (as box_interval() would report each of
  ///   them hit), so rounding never skips a cell the ray touches. The first
  ///   cell is chosen the same way (by the crossings, not by the entry
  ///   point). Axes the ray does not move along (zero or denormal direction
  ///   component) keep the origin's cell. A primitive touching a plane is
  ///   stored on both sides, so a ray lying in a plane finds it on either.
  /// - Early termination: the next cell is entered only if its entry
  ///   distance is at most tmax (with the margin kBoxFarScale), that is, the
  ///   walk stops once the closest hit so far lies within the cells visited.
  ///   A primitive stored in several cells can be hit beyond the cell it was
  ///   tested in; that hit is kept (it may still be the closest) and the walk
  ///   goes on until the cell holding the hit point is passed.
  /// - Mailboxing (mailbox.h): each primitive is tested at most once per ray,
  ///   however many of the cells visited hold it.
  /// - SmallestCell: the big list first, then the same DDA; entering a cell
  ///   tests the lists of the cell and of each non-empty neighbour whose
  ///   loose box the ray hits (box_interval() up to tmax; a cell list is
  ///   looked at once per ray: the mailbox stamps cells, not primitives,
  ///   since each primitive is stored once). Early termination is unchanged:
  ///   a hit at a point in the cells entered so far is in the list of one of
  ///   them or their neighbours, so once the closest hit lies before the next
  ///   cell's entry, nothing after it can be closer.
  ///
  /// Observer hooks (traversal.h): on_box_test(box_id(), hit) for the grid's
  /// box; on_node(cell) for every cell entered, each at most once per ray;
  /// on_cull(cell) for the cell the walk would have entered next when a hit
  /// found meanwhile stops it (early termination; at most one per ray, none
  /// when the ray leaves the grid or ends). Cells have no child boxes: boxes
  /// tested = 1 per ray (SmallestCell: plus on_box_test(cell, hit) for every
  /// neighbour's loose box tested). Primitive tests are the caller's (`prim`), after
  /// the mailbox: a primitive is reported at most once per ray.
  ///
  template <bool AnyHit, class Observer, class PrimFn>
  bool traverse(const Ray& ray, float& tmax, PrimFn&& prim, Observer& obs) const;

  /// Visits the cells a range overlaps, for range queries (all objects in a
  /// box, within a sphere, nearest to a point). `Range` provides
  /// `Bounds3 bounds() const`, an axis-aligned box around the range (which may
  /// shrink between calls, as a k-nearest query's radius does), and
  /// `bool overlaps(const Bounds3& box) const`. The walk reports
  /// on_box_test(box_id(), overlaps) for the grid's box, then for every cell
  /// inside the range's current bounds (z, then y, then x order; cells the
  /// bounds have shrunk away from are skipped) on_box_test(cell, overlaps),
  /// and on_node(cell) for those it overlaps, whose primitives it passes to
  /// `prim(index)`, each once per query (mailboxed). `prim` tests the
  /// primitive itself: a cell holds every primitive whose bounds touch it.
  /// SmallestCell: the big list is reported first (when the range overlaps
  /// the grid's box), then the cells one further on every side than the
  /// range's bounds, tested (and reported) with their loose boxes.
  template <class Range, class Observer, class PrimFn>
  void walk_range(Range& range, PrimFn&& prim, Observer& obs) const;

  /// CSR storage: cell c's references are refs[offsets[c] .. offsets[c + 1]).
  std::vector<uint32_t> offsets;
  std::vector<uint32_t> refs;  ///< Primitive indices, ascending within a cell.
  /// SmallestCell: the primitives that fit no loose cell (the grid's own
  /// list, tested by every ray that enters the grid). Ascending.
  std::vector<uint32_t> big_refs;
  /// The cell planes per axis: res + 1 positions from bounds().lo to
  /// bounds().hi (equal spacing, rounded to float once); cell k along an axis
  /// lies between planes[axis][k] and planes[axis][k + 1].
  std::array<std::vector<float>, 3> planes;
  GridBuildConfig config;

 private:
  /// The cell along `axis` that holds coordinate x (clamped to the grid);
  /// on a plane, the cell above it.
  uint32_t cell_of(int axis, float x) const;

  Bounds3 bounds_;
  glm::uvec3 res_{0u};
  Vec3 inv_width_{0.0f};  ///< res / extent per axis (0 for a flat axis): first guesses only.
  uint32_t num_prims_ = 0;
  bool loose_ = false;
  float loose_factor_ = 0.0f;
  double build_seconds_ = 0.0;
};

// ---------------------------------------------------------------------------

inline uint32_t UniformGrid::cell_of(int axis, float x) const {
  const std::vector<float>& pl = planes[axis];
  const uint32_t n = res_[axis];
  const float f = (x - pl[0]) * inv_width_[axis];
  uint32_t k = f > 0.0f ? (f < float(n) ? std::min(uint32_t(f), n - 1) : n - 1) : 0u;
  while (k > 0 && x < pl[k]) --k;
  while (k + 1 < n && x >= pl[k + 1]) ++k;
  return k;
}

template <bool AnyHit, class Observer, class PrimFn>
bool UniformGrid::traverse(const Ray& ray, float& tmax, PrimFn&& prim, Observer& obs) const {
  if (offsets.empty()) return false;
  const Vec3 inv_dir = 1.0f / ray.dir;
  float t0, t1;
  box_interval(bounds_.lo, bounds_.hi, ray.origin, inv_dir, tmax, t0, t1);
  const bool box_hit = t0 <= t1;
  if constexpr (Observer::kActive) obs.on_box_test(box_id(), box_hit);
  if (!box_hit) return false;

  // Per axis: the current cell, the step (+1, -1, or 0 for an axis the ray
  // does not move along) and t_next, where the ray crosses the current
  // cell's exit plane (computed as box_interval() computes a slab).
  int idx[3], step[3];
  float t_next[3];
  for (int a = 0; a < 3; ++a) {
    const float* pl = planes[a].data();
    const int n = int(res_[a]);
    const float o = ray.origin[a], inv = inv_dir[a];
    auto cross = [&](float plane) { return (plane - o) * inv; };
    if (!(std::abs(inv) < kInfinity)) {
      idx[a] = int(cell_of(a, o));
      step[a] = 0;
      t_next[a] = kInfinity;
      continue;
    }
    int k = int(cell_of(a, o + t0 * ray.dir[a]));  // a first guess
    // The first cell along the ray whose exit plane the ray does not cross
    // clearly before t0 (within the margin, the earlier cell).
    if (inv > 0.0f) {
      while (k > 0 && cross(pl[k]) * kBoxFarScale >= t0) --k;
      while (k + 1 < n && cross(pl[k + 1]) * kBoxFarScale < t0) ++k;
      step[a] = 1;
      t_next[a] = cross(pl[k + 1]);
    } else {
      while (k + 1 < n && cross(pl[k + 1]) * kBoxFarScale >= t0) ++k;
      while (k > 0 && cross(pl[k]) * kBoxFarScale < t0) --k;
      step[a] = -1;
      t_next[a] = cross(pl[k]);
    }
    idx[a] = k;
  }

  bool hit = false;
  // The loose grid's big list: the grid is its only inner node.
  for (const uint32_t p : big_refs)
    if (prim(p, tmax)) {
      hit = true;
      if constexpr (AnyHit) return true;
    }
  // Stamps primitives (EveryCell) or cell lists (SmallestCell).
  MailboxQuery mailbox(loose_ ? uint32_t(cells()) : num_prims_);
  const int nx = int(res_.x), ny = int(res_.y), nz = int(res_.z);
  auto inside = [&](int a, int k) { return k >= 0 && k < int(res_[a]); };
  // Tests the list of cell c (SmallestCell, each list once per ray): true
  // when an any-hit query is done.
  auto test_list = [&](uint32_t c) {
    const uint32_t* r = refs.data() + offsets[c];
    for (const uint32_t* end = refs.data() + offsets[c + 1]; r != end; ++r)
      if (prim(*r, tmax)) {
        hit = true;
        if constexpr (AnyHit) return true;
      }
    return false;
  };
  // Enters cell c: true when an any-hit query is done.
  auto enter = [&](int x, int y, int z) {
    const uint32_t c = uint32_t(x + nx * (y + ny * z));
    if constexpr (Observer::kActive) obs.on_node(c);
    if (loose_) {
      // The cell's and its neighbours' lists, where their loose boxes are hit.
      for (int z1 = std::max(z - 1, 0); z1 <= std::min(z + 1, nz - 1); ++z1)
        for (int y1 = std::max(y - 1, 0); y1 <= std::min(y + 1, ny - 1); ++y1)
          for (int x1 = std::max(x - 1, 0); x1 <= std::min(x + 1, nx - 1); ++x1) {
            const uint32_t n = uint32_t(x1 + nx * (y1 + ny * z1));
            if (offsets[n] == offsets[n + 1] || !mailbox.first_visit(n)) continue;
            const Bounds3 b = node_box(uint32_t(x1), uint32_t(y1), uint32_t(z1));
            float b0, b1;
            box_interval(b.lo, b.hi, ray.origin, inv_dir, tmax, b0, b1);
            if constexpr (Observer::kActive) obs.on_box_test(n, b0 <= b1);
            if (b0 <= b1 && test_list(n)) return true;
          }
      return false;
    }
    const uint32_t* r = refs.data() + offsets[c];
    for (const uint32_t* end = refs.data() + offsets[c + 1]; r != end; ++r) {
      if (!mailbox.first_visit(*r)) continue;
      if (prim(*r, tmax)) {
        hit = true;
        if constexpr (AnyHit) return true;
      }
    }
    return false;
  };
  const float* pl[3] = {planes[0].data(), planes[1].data(), planes[2].data()};
  if (enter(idx[0], idx[1], idx[2])) return true;
  for (;;) {
    // The axes by next crossing; the crossings tied with the first (each
    // within the margin of the one before) are taken together.
    int o0 = 0, o1 = 1, o2 = 2;
    if (t_next[o1] < t_next[o0]) std::swap(o0, o1);
    if (t_next[o2] < t_next[o1]) std::swap(o1, o2);
    if (t_next[o1] < t_next[o0]) std::swap(o0, o1);
    const float tn = t_next[o0];
    if (!(tn < kInfinity)) return hit;  // the ray moves along no axis (or NaN)
    if (!(step[o1] != 0 && t_next[o1] <= tn * kBoxFarScale)) {
      // The common case, one plane crossed: the general steps below with
      // tied = {o0}, written out.
      const int a = o0;
      idx[a] += step[a];
      if (!inside(a, idx[a])) return hit;
      if (!(tn <= tmax * kBoxFarScale)) {
        if constexpr (Observer::kActive)
          if (hit && tn <= t1) obs.on_cull(uint32_t(idx[0] + nx * (idx[1] + ny * idx[2])));
        return hit;
      }
      t_next[a] = (pl[a][idx[a] + (step[a] > 0)] - ray.origin[a]) * inv_dir[a];
      if (enter(idx[0], idx[1], idx[2])) return true;
      continue;
    }
    unsigned tied = 1u << o0;
    {
      tied |= 1u << o1;
      if (step[o2] != 0 && t_next[o2] <= t_next[o1] * kBoxFarScale) tied |= 1u << o2;
    }
    // Whether the walk ends before a cell entered at tn: beyond the closest
    // hit (early termination: the cell is culled) or beyond the ray's end.
    auto stop = [&](const int* c) {
      if (tn <= tmax * kBoxFarScale) return false;
      if constexpr (Observer::kActive)
        if (hit && tn <= t1) obs.on_cull(uint32_t(c[0] + nx * (c[1] + ny * c[2])));
      return true;
    };
    // Around a corner or edge of tied crossings, every cell past some but not
    // all of the tied planes (those inside the grid)...
    if (tied & (tied - 1)) {
      for (unsigned sub = (tied - 1) & tied; sub != 0; sub = (sub - 1) & tied) {
        int c[3] = {idx[0], idx[1], idx[2]};
        bool in = true;
        for (int a = 0; a < 3; ++a)
          if (sub & (1u << a)) {
            c[a] += step[a];
            in = in && inside(a, c[a]);
          }
        if (!in) continue;
        if (stop(c)) return hit;
        if (enter(c[0], c[1], c[2])) return true;
      }
    }
    // ...then the cell past all of them, unless the ray leaves the grid there.
    for (int a = 0; a < 3; ++a)
      if (tied & (1u << a)) {
        idx[a] += step[a];
        if (!inside(a, idx[a])) return hit;
      }
    if (stop(idx)) return hit;
    for (int a = 0; a < 3; ++a)
      if (tied & (1u << a))
        t_next[a] = (pl[a][idx[a] + (step[a] > 0)] - ray.origin[a]) * inv_dir[a];
    if (enter(idx[0], idx[1], idx[2])) return true;
  }
}

template <class Range, class Observer, class PrimFn>
void UniformGrid::walk_range(Range& range, PrimFn&& prim, Observer& obs) const {
  if (offsets.empty()) return;
  const bool box_hit = range.overlaps(bounds_);
  if constexpr (Observer::kActive) obs.on_box_test(box_id(), box_hit);
  if (!box_hit) return;
  for (const uint32_t p : big_refs) prim(p);  // SmallestCell: the grid's own list
  // The cells whose (loose) boxes can overlap the range: one further on every
  // side for loose cells, which reach half a cell at most into a neighbour.
  auto cells_near = [&](glm::uvec3& first, glm::uvec3& last) {
    if (!cell_range(range.bounds(), first, last)) return false;
    if (loose_) {
      first = glm::max(first, glm::uvec3(1u)) - 1u;
      last = glm::min(last + 1u, res_ - 1u);
    }
    return true;
  };
  glm::uvec3 lo, hi;
  if (!cells_near(lo, hi)) return;
  MailboxQuery mailbox(loose_ ? 0u : num_prims_);
  for (uint32_t z = lo.z; z <= hi.z; ++z)
    for (uint32_t y = lo.y; y <= hi.y; ++y)
      for (uint32_t x = lo.x; x <= hi.x; ++x) {
        if (x < lo.x || y < lo.y || z < lo.z) continue;  // the range shrank away
        const uint32_t c = cell_id(x, y, z);
        const bool overlaps = range.overlaps(node_box(x, y, z));
        if constexpr (Observer::kActive) obs.on_box_test(c, overlaps);
        if (!overlaps) continue;
        if constexpr (Observer::kActive) obs.on_node(c);
        bool called = false;
        for (uint32_t r : cell_refs(c))
          if (loose_ || mailbox.first_visit(r)) {
            prim(r);
            called = true;
          }
        if (!called) continue;
        // The range may have shrunk: the remaining cells are those inside
        // both the old and the new bounds.
        glm::uvec3 nlo, nhi;
        if (!cells_near(nlo, nhi)) return;
        lo = glm::max(lo, nlo);
        hi = glm::min(hi, nhi);
        if (lo.x > hi.x || lo.y > hi.y || lo.z > hi.z) return;
      }
}

}  // namespace rayscope
