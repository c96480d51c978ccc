// Octree builder: top down, depth first; a node's children are allocated
// together (consecutive, in octant order) before any of them is built.
//
// EveryCell: a primitive goes to every octant its bounds overlap, faces
// included (closed boxes), so whatever point of its bounds a ray reaches lies
// in a leaf that holds it. SmallestCell: a primitive goes to the octant whose
// loose box holds its bounds (the octant of its center when that one does,
// else the first that does), or stays in the node when none does.
#include "rayscope/accel/octree.h"

#include <cstdio>

#include <algorithm>
#include <cassert>
#include <chrono>
#include <stdexcept>
#include <string>

namespace rayscope {
namespace {

/// Whether a cell can be halved on every axis (false once floats cannot
/// resolve its midpoint, and for the point-like cell of point-like input).
bool can_cut(const Bounds3& cell) {
  const Vec3 mid = 0.5f * cell.lo + 0.5f * cell.hi;
  for (int a = 0; a < 3; ++a)
    if (!(mid[a] > cell.lo[a] && mid[a] < cell.hi[a])) return false;
  return true;
}

struct Builder {
  std::span<const Bounds3> bounds;
  const OctreeBuildConfig& cfg;
  const Octree& tree;  ///< For loose() and node_box() (the storage and loose factor in use).
  int max_depth;
  size_t max_refs;
  std::vector<OctNode>& nodes;
  std::vector<uint32_t>& refs;

  void hold(uint32_t node, const std::vector<uint32_t>& prims) {
    if (refs.size() + prims.size() > size_t(~0u))
      throw std::length_error("Octree::build: too many references");
    nodes[node].first = uint32_t(refs.size());
    nodes[node].count = uint32_t(prims.size());
    refs.insert(refs.end(), prims.begin(), prims.end());
  }

  /// Allocates the children of `node` for the non-empty lists and builds them.
  void build_children(uint32_t node, const Bounds3& cell, std::vector<uint32_t> (&lists)[8],
                      int depth) {
    uint8_t mask = 0;
    for (int o = 0; o < 8; ++o)
      if (!lists[o].empty()) mask |= uint8_t(1u << o);
    if (nodes.size() + 8 > size_t(~0u)) throw std::length_error("Octree::build: too many nodes");
    const uint32_t first = uint32_t(nodes.size());
    nodes[node].mask = mask;
    nodes[node].first_child = first;
    nodes.resize(nodes.size() + size_t(std::popcount(unsigned(mask))));
    uint32_t child = first;
    for (int o = 0; o < 8; ++o) {
      if (lists[o].empty()) continue;
      build(child++, Octree::octant_cell(cell, o), std::move(lists[o]), depth + 1);
    }
  }

  void build(uint32_t node, const Bounds3& cell, std::vector<uint32_t> prims, int depth) {
    const size_t n = prims.size();
    if (n <= cfg.max_leaf_size || depth >= max_depth || !can_cut(cell) ||
        refs.size() + n > max_refs)
      return hold(node, prims);
    const Vec3 mid = 0.5f * cell.lo + 0.5f * cell.hi;
    std::vector<uint32_t> lists[8];
    if (!tree.loose()) {
      // Every octant the (closed) bounds overlap. The bounds overlap this
      // cell, so per axis: the lower half if they reach down to the
      // midpoint, the upper one if they reach up to it.
      for (uint32_t p : prims) {
        const Bounds3& b = bounds[p];
        int lower = 0, upper = 0;  // bit a: the half on axis a is reached
        for (int a = 0; a < 3; ++a) {
          lower |= int(b.lo[a] <= mid[a]) << a;
          upper |= int(b.hi[a] >= mid[a]) << a;
        }
        for (int o = 0; o < 8; ++o)
          if ((upper & o) == o && (lower & ~o & 7) == (~o & 7)) lists[o].push_back(p);
      }
      // Cutting that separates nothing would only repeat this list (several
      // octants each holding all of it); one octant holding all is progress:
      // the cell shrinks around them.
      int full = 0, present = 0;
      for (const auto& l : lists) {
        present += !l.empty();
        full += l.size() == n;
      }
      if (present > 1 && full == present) return hold(node, prims);
      prims = {};
      hold(node, prims);
    } else {
      std::vector<uint32_t> stay;
      Bounds3 loose[8];
      for (int o = 0; o < 8; ++o) loose[o] = tree.node_box(Octree::octant_cell(cell, o));
      for (uint32_t p : prims) {
        const Bounds3& b = bounds[p];
        const Vec3 c = b.center();
        const int home = int(c.x >= mid.x) | int(c.y >= mid.y) << 1 | int(c.z >= mid.z) << 2;
        int fit = loose[home].contains(b) ? home : -1;
        for (int o = 0; o < 8 && fit < 0; ++o)
          if (loose[o].contains(b)) fit = o;
        (fit < 0 ? stay : lists[fit]).push_back(p);
      }
      hold(node, stay);
      if (stay.size() == n) return;  // nothing fits a child: a leaf
    }
    build_children(node, cell, lists, depth);
  }
};

}  // namespace

void Octree::build(std::span<const Bounds3> bounds, const OctreeBuildConfig& cfg,
                   PrimStorage storage, float loose_factor) {
  const auto start = std::chrono::steady_clock::now();
  // build_accel() refuses both with a message (accel_config_error()).
  assert(storage != PrimStorage::Split);
  assert(loose_factor_error(loose_factor).empty());
  config = cfg;
  nodes.clear();
  refs.clear();
  bounds_ = Bounds3();
  loose_ = storage == PrimStorage::SmallestCell;
  loose_factor_ = loose_ ? loose_factor : 0.0f;
  max_depth_ = std::clamp(cfg.max_depth, 0, kMaxDepth);
  const size_t n = bounds.size();
  if (n > size_t(~0u) - 1) throw std::length_error("Octree::build: too many primitives");
  num_prims_ = uint32_t(n);
  if (n > 0) {
    Bounds3 all;
    for (const Bounds3& b : bounds) all.extend(b);
    // The cube around them: their center, their largest extent as the side;
    // min/max keep every bound inside whatever the rounding.
    const Vec3 c = all.center(), e = all.extent();
    const float h = 0.5f * std::max({e.x, e.y, e.z});
    bounds_.lo = glm::min(c - h, all.lo);
    bounds_.hi = glm::max(c + h, all.hi);
    std::vector<uint32_t> ids(n);
    for (uint32_t i = 0; i < n; ++i) ids[i] = i;
    nodes.emplace_back();
    Builder b{bounds, cfg, *this, max_depth_, kMaxReferencesPerPrim * n, nodes, refs};
    b.build(0, bounds_, std::move(ids), 0);
    nodes.shrink_to_fit();
    refs.shrink_to_fit();
  }
  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::vector<Bounds3> Octree::cells() const {
  std::vector<Bounds3> c(nodes.size());
  if (nodes.empty()) return c;
  c[0] = bounds_;
  // Children come after their parent in the array.
  for (size_t i = 0; i < nodes.size(); ++i)
    for (int o = 0; o < 8; ++o)
      if (nodes[i].has_child(o)) c[nodes[i].child(o)] = octant_cell(c[i], o);
  return c;
}

std::vector<uint32_t> Octree::depths() const {
  std::vector<uint32_t> d(nodes.size(), 0u);
  for (size_t i = 0; i < nodes.size(); ++i)
    for (int o = 0; o < 8; ++o)
      if (nodes[i].has_child(o)) d[nodes[i].child(o)] = d[i] + 1;
  return d;
}

OctreeQuality Octree::quality() const {
  OctreeQuality q;
  q.build_seconds = build_seconds_;
  if (nodes.empty()) return q;
  q.nodes = uint32_t(nodes.size());
  q.references = refs.size();
  q.refs_per_prim = num_prims_ ? double(refs.size()) / num_prims_ : 0.0;
  q.memory_bytes = memory_bytes();
  const CellRefCounts c = count_cell_refs(nodes, depths());
  q.leaves = c.leaves;
  q.depth = c.depth;
  q.max_leaf_refs = c.max_leaf_refs;
  q.inner_refs = c.inner_refs;
  q.mean_leaf_refs = c.mean_leaf_refs;
  for (const OctNode& n : nodes)
    if (!n.is_leaf()) q.empty_leaves += 8u - uint32_t(std::popcount(unsigned(n.mask)));
  return q;
}

AccelFigures Octree::figures() const {
  const OctreeQuality q = quality();
  return figures_of(q, q.refs_per_prim);
}

AccelView Octree::view() const {
  AccelView v;
  v.structure = "octree";
  const std::vector<Bounds3> cell = cells();
  v.nodes.resize(nodes.size());
  for (size_t i = 0; i < nodes.size(); ++i) {
    const OctNode& n = nodes[i];
    AccelViewNode& o = v.nodes[i];
    o.box = node_box(cell[i]);  // the loose box for smallest-cell storage
    o.leaf = n.is_leaf();
    o.first = n.first;  // inner nodes of a loose octree hold primitives too
    o.count = n.count;
    for (int k = 0; k < 8; ++k)
      if (n.has_child(k)) v.nodes[n.child(k)].parent = int32_t(i);
  }
  v.refs = refs;
  finish_levels(v);
  return v;
}

std::string Octree::stats_line() const {
  const OctreeQuality q = quality();
  char line[512];
  std::snprintf(line, sizeof line,
                "octree, %s: %u nodes, %u leaves (%u empty octants not stored), depth %u (limit "
                "%d), %.2f references per primitive (%zu held by inner nodes), %.1f per leaf (max "
                "%u), %.2f MiB, built in %.3f s",
                storage_text(storage(), loose_factor_).c_str(), q.nodes, q.leaves, q.empty_leaves,
                q.depth, max_depth(), q.refs_per_prim, q.inner_refs, q.mean_leaf_refs,
                q.max_leaf_refs, double(q.memory_bytes) / (1024.0 * 1024.0), q.build_seconds);
  return line;
}

std::string Octree::walk_legend() const {
  return loose() ? "the loose octree (--accel octree --storage smallest-cell); nodes are named "
                   "by their octree ids, a node's child boxes are its octants' loose boxes "
                   "(overlapping, entered nearest first), and inner nodes hold primitives too "
                   "(those that fit no child): hit in leaf is the node that holds the hit"
                 : "the octree (--accel octree --storage every-cell); nodes are named by their "
                   "octree ids, a node's child boxes are its non-empty octants, and a primitive "
                   "stored in several cells is tested once";
}

}  // namespace rayscope
