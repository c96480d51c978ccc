// Uniform grid builder: the resolution from the object count (or given), the
// cell planes, then two passes over the primitives' cell ranges: count the
// references per cell, then fill them in (CSR). A primitive goes to every
// cell whose closed box its closed bounds overlap, so one touching a plane is
// stored on both sides (grid.h's walk relies on it for rays lying in a plane).
//
// SmallestCell (the loose grid): the same resolution (no reference budget:
// each primitive is stored once), then one pass: the cell of each primitive's
// center if its loose box holds the bounds, else the big list.
#include "rayscope/accel/grid.h"

#include <cstdio>

#include <cassert>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rayscope {
namespace {

/// The automatic resolution (see GridBuildConfig::density), with `scale`
/// times the rule's cells per unit length on the automatic axes.
glm::uvec3 auto_resolution(const Bounds3& box, size_t n, const GridBuildConfig& cfg, double scale) {
  glm::uvec3 res(1u);
  double target = std::max(1.0, double(cfg.density) * double(n));  // cells in all
  bool active[3];
  for (int a = 0; a < 3; ++a) {
    if (cfg.resolution[a] != 0) {
      res[a] = cfg.resolution[a];
      target /= double(cfg.resolution[a]);
      active[a] = false;
    } else {
      active[a] = double(box.hi[a]) > double(box.lo[a]);
    }
  }
  // Cells per unit length s over the k automatic non-flat axes: their
  // extents' product times s^k is the target. An axis that would get less
  // than one cell gets one, and s is found again without it.
  double s = 0.0;
  for (int round = 0; round < 3; ++round) {
    double product = 1.0;
    int k = 0;
    for (int a = 0; a < 3; ++a)
      if (active[a]) {
        product *= double(box.hi[a]) - double(box.lo[a]);
        ++k;
      }
    if (k == 0) break;
    s = std::pow(std::max(target, 1.0) / product, 1.0 / k);
    bool dropped = false;
    for (int a = 0; a < 3; ++a)
      if (active[a] && (double(box.hi[a]) - double(box.lo[a])) * s < 1.0) {
        active[a] = false;
        dropped = true;
      }
    if (!dropped) break;
  }
  for (int a = 0; a < 3; ++a)
    if (active[a]) {
      const double cells = std::round((double(box.hi[a]) - double(box.lo[a])) * s * scale);
      res[a] = uint32_t(std::clamp(cells, 1.0, double(UniformGrid::kMaxResolution)));
    }
  return res;
}

size_t cell_count(const glm::uvec3& r) {
  return size_t(r.x) * size_t(r.y) * size_t(r.z);
}

std::string text(const glm::uvec3& r) {
  return std::to_string(r.x) + " x " + std::to_string(r.y) + " x " + std::to_string(r.z);
}

}  // namespace

bool UniformGrid::cell_range(const Bounds3& b, glm::uvec3& first, glm::uvec3& last) const {
  if (offsets.empty()) return false;
  for (int a = 0; a < 3; ++a) {
    if (!(b.lo[a] <= bounds_.hi[a] && b.hi[a] >= bounds_.lo[a])) return false;
    const std::vector<float>& pl = planes[a];
    const uint32_t n = res_[a];
    // First cell whose upper plane reaches b.lo, last whose lower plane is at
    // or below b.hi (closed boxes: a plane touched counts on both sides).
    first[a] = uint32_t(std::lower_bound(pl.begin() + 1, pl.end(), b.lo[a]) - (pl.begin() + 1));
    last[a] = uint32_t(std::upper_bound(pl.begin(), pl.begin() + n, b.hi[a]) - pl.begin());
    first[a] = std::min(first[a], n - 1);
    last[a] = last[a] > 0 ? last[a] - 1 : 0;
  }
  return true;
}

std::string grid_resolution_error(const glm::uvec3& resolution) {
  for (int a = 0; a < 3; ++a)
    if (resolution[a] > UniformGrid::kMaxResolution)
      return "resolution " + text(resolution) + " exceeds " +
             std::to_string(UniformGrid::kMaxResolution) + " cells per axis";
  if (resolution.x > 0 && resolution.y > 0 && resolution.z > 0 &&
      cell_count(resolution) > UniformGrid::kMaxCells)
    return "resolution " + text(resolution) + " has more than " +
           std::to_string(UniformGrid::kMaxCells) + " cells";
  return {};
}

void UniformGrid::build(std::span<const Bounds3> bounds, const GridBuildConfig& cfg,
                        PrimStorage storage, float loose_factor) {
  const auto start = std::chrono::steady_clock::now();
  // build_accel() refuses both with a message (accel_config_error()).
  assert(storage != PrimStorage::Split);
  assert(loose_factor_error(loose_factor).empty());
  config = cfg;
  loose_ = storage == PrimStorage::SmallestCell;
  loose_factor_ = loose_ ? loose_factor : 0.0f;
  offsets.clear();
  refs.clear();
  big_refs.clear();
  for (std::vector<float>& pl : planes) pl.clear();
  bounds_ = Bounds3();
  res_ = glm::uvec3(0u);
  inv_width_ = Vec3(0.0f);
  num_prims_ = uint32_t(bounds.size());
  const size_t n = bounds.size();
  if (const std::string e = grid_resolution_error(cfg.resolution); !e.empty())
    throw std::length_error("UniformGrid::build: " + e);
  if (n == 0) {
    build_seconds_ =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return;
  }
  if (n > kMaxReferences) throw std::length_error("UniformGrid::build: too many primitives");
  for (size_t i = 0; i < n; ++i) {
    const Bounds3& b = bounds[i];
    if (!all_finite(b.lo) || !all_finite(b.hi) || b.empty())
      throw std::invalid_argument("UniformGrid::build: primitive " + std::to_string(i) +
                                  " has non-finite or inverted bounds");
    bounds_.extend(b);
  }

  // The resolution; planes and cell ranges for it; the references it stores.
  std::vector<glm::uvec3> first(n), last(n);
  auto layout = [&](const glm::uvec3& res) {
    res_ = res;
    for (int a = 0; a < 3; ++a) {
      const double lo = bounds_.lo[a], hi = bounds_.hi[a];
      std::vector<float>& pl = planes[a];
      pl.resize(res[a] + 1);
      for (uint32_t k = 0; k <= res[a]; ++k)
        pl[k] = std::min(float(lo + (hi - lo) * double(k) / double(res[a])), bounds_.hi[a]);
      pl[0] = bounds_.lo[a];
      pl[res[a]] = bounds_.hi[a];
      inv_width_[a] = hi > lo ? float(double(res[a]) / (hi - lo)) : 0.0f;
    }
    offsets.assign(1, 0u);  // non-empty: cell_range() works
    size_t total = 0;
    if (loose_) return n;  // stored once each
    for (size_t i = 0; i < n; ++i) {
      cell_range(bounds[i], first[i], last[i]);
      total += cell_count(last[i] - first[i] + 1u);
    }
    return total;
  };
  glm::uvec3 res = auto_resolution(bounds_, n, cfg, 1.0);
  const bool automatic = cfg.resolution.x == 0 || cfg.resolution.y == 0 || cfg.resolution.z == 0;
  // An automatic resolution is coarsened (cells per length times 0.8 at a
  // time) until the cells and references fit their budgets.
  const size_t auto_budget = std::min(kMaxReferences, kMaxAutoReferencesPerPrim * n);
  double scale = 1.0;
  while (automatic && cell_count(res) > kMaxCells)
    res = auto_resolution(bounds_, n, cfg, scale *= 0.8);
  size_t total = layout(res);
  while (automatic && total > auto_budget) {
    const glm::uvec3 coarser = auto_resolution(bounds_, n, cfg, scale *= 0.8);
    if (coarser == res) {
      if (coarser == glm::uvec3(1u) || scale < 1e-6) break;
      continue;
    }
    res = coarser;
    total = layout(res);
  }
  if (total > kMaxReferences) {
    offsets.clear();
    throw std::length_error("UniformGrid::build: " + text(res) + " cells would store " +
                            std::to_string(total) + " references, more than kMaxReferences (" +
                            std::to_string(kMaxReferences) + ")");
  }

  const size_t cells = cell_count(res_);
  if (loose_) {
    // The cell of each primitive's center, or the big list; then CSR.
    std::vector<uint32_t> home(n);
    for (size_t i = 0; i < n; ++i) {
      const Vec3 c = bounds[i].center();
      const uint32_t x = cell_of(0, c.x), y = cell_of(1, c.y), z = cell_of(2, c.z);
      home[i] = node_box(x, y, z).contains(bounds[i]) ? cell_id(x, y, z) : ~0u;
      if (home[i] == ~0u) big_refs.push_back(uint32_t(i));
    }
    offsets.assign(cells + 1, 0u);
    for (size_t i = 0; i < n; ++i)
      if (home[i] != ~0u) offsets[home[i] + 1]++;
    for (size_t c = 0; c < cells; ++c) offsets[c + 1] += offsets[c];
    refs.resize(n - big_refs.size());
    std::vector<uint32_t> fill(offsets.begin(), offsets.end() - 1);
    for (size_t i = 0; i < n; ++i)
      if (home[i] != ~0u) refs[fill[home[i]]++] = uint32_t(i);
    build_seconds_ =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return;
  }
  // Count per cell, prefix sums, fill (primitives in index order).
  offsets.assign(cells + 1, 0u);
  auto for_cells = [&](size_t i, auto&& f) {
    for (uint32_t z = first[i].z; z <= last[i].z; ++z)
      for (uint32_t y = first[i].y; y <= last[i].y; ++y) {
        const uint32_t row = res_.x * (y + res_.y * z);
        for (uint32_t x = first[i].x; x <= last[i].x; ++x) f(row + x);
      }
  };
  for (size_t i = 0; i < n; ++i) for_cells(i, [&](uint32_t c) { offsets[c + 1]++; });
  for (size_t c = 0; c < cells; ++c) offsets[c + 1] += offsets[c];
  refs.resize(total);
  std::vector<uint32_t> fill(offsets.begin(), offsets.end() - 1);
  for (size_t i = 0; i < n; ++i) for_cells(i, [&](uint32_t c) { refs[fill[c]++] = uint32_t(i); });
  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

GridQuality UniformGrid::quality() const {
  GridQuality q;
  q.build_seconds = build_seconds_;
  if (offsets.empty()) return q;
  q.resolution = res_;
  q.cells = cells();
  q.references = refs.size() + big_refs.size();
  q.big_refs = big_refs.size();
  q.refs_per_prim = num_prims_ ? double(q.references) / num_prims_ : 0.0;
  q.memory_bytes = memory_bytes();
  for (size_t c = 0; c < q.cells; ++c) {
    const uint32_t k = offsets[c + 1] - offsets[c];
    q.empty_cells += k == 0;
    q.max_cell_refs = std::max(q.max_cell_refs, k);
  }
  const size_t full = q.cells - q.empty_cells;
  q.mean_cell_refs = full ? double(refs.size()) / double(full) : 0.0;
  return q;
}

AccelFigures UniformGrid::figures() const {
  const GridQuality q = quality();
  AccelFigures f;
  f.build_seconds = q.build_seconds;
  f.memory_bytes = memory_bytes();
  f.nodes = q.cells;
  f.leaves = q.cells - q.empty_cells;
  f.depth = 1;
  f.refs_per_prim = q.refs_per_prim;
  return f;
}

AccelView UniformGrid::view() const {
  AccelView v;
  v.structure = "grid";
  const uint32_t ncells = uint32_t(cells());
  if (ncells == 0) return v;
  // Cells x + nx (y + ny z), then the grid's box (box_id() = ncells): the ids
  // the walk reports.
  v.nodes.resize(size_t(ncells) + 1);
  const glm::uvec3 res = resolution();
  for (uint32_t z = 0; z < res.z; ++z)
    for (uint32_t y = 0; y < res.y; ++y)
      for (uint32_t x = 0; x < res.x; ++x) {
        const uint32_t id = cell_id(x, y, z);
        AccelViewNode& o = v.nodes[id];
        o.box = node_box(x, y, z);  // the loose box for smallest-cell storage
        o.parent = int32_t(box_id());
        o.leaf = true;
        o.first = offsets[id];
        o.count = offsets[id + 1] - offsets[id];
      }
  // The grid's box holds the loose grid's big list, after the cells' lists.
  AccelViewNode& box = v.nodes[box_id()];
  box.box = bounds();
  box.first = uint32_t(refs.size());
  box.count = uint32_t(big_refs.size());
  v.refs.reserve(refs.size() + big_refs.size());
  v.refs.insert(v.refs.end(), refs.begin(), refs.end());
  v.refs.insert(v.refs.end(), big_refs.begin(), big_refs.end());
  finish_levels(v);
  return v;
}

std::string UniformGrid::stats_line() const {
  const GridQuality g = quality();
  char line[512];
  std::snprintf(line, sizeof line,
                "grid, %s: %u x %u x %u cells (%zu, %zu empty), %.2f references per primitive "
                "(%zu in the grid's own list), %.1f per non-empty cell (at most %u), %.2f MiB, "
                "built in %.3f s",
                storage_text(storage(), loose_factor_).c_str(), g.resolution.x, g.resolution.y,
                g.resolution.z, g.cells, g.empty_cells, g.refs_per_prim, g.big_refs,
                g.mean_cell_refs, g.max_cell_refs, double(g.memory_bytes) / (1024.0 * 1024.0),
                g.build_seconds);
  return line;
}

std::string UniformGrid::walk_legend() const {
  return "the uniform grid (--accel grid); nodes are cells, named by their index x + nx * (y + "
         "ny * z), entered front to back; the one box tested is the grid's (id = the number of "
         "cells), and a primitive stored in several cells is tested once";
}

}  // namespace rayscope
