// kD-tree builder: top-down, one split plane per cell, chosen by the surface
// area heuristic over the primitives' bound edges (sorted once per cell and
// axis: O(n log n) per level), at the cell's spatial median, or by the
// lecture's rule (axes in turn, the median of the primitives' centers). A primitive goes
// to every child cell its bounds overlap; one that only touches the plane goes
// to its own side, and one lying in the plane goes below (see goes_below). The
// walk reaches both sides wherever the ray meets the plane (kdtree.h), so a
// ray reaching any point of a primitive's bounds reaches a leaf that holds it.
//
// SmallestCell (the loose kD-tree): the same top-down recursion, the plane
// chosen with the loose children's cost (KdTreeBuildConfig), each
// primitive sent to the child whose loose box holds it (its center's side
// first) or kept in the node. A node is a leaf when it holds few enough, the
// cost says so, or nothing fits a child.
#include "rayscope/accel/kdtree.h"

#include <cstdio>

#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rayscope {
namespace {

/// Half the surface area of `cell` with its extent along `axis` replaced by
/// `length` (the area of a child cell).
float child_half_area(const Bounds3& cell, int axis, float length) {
  const Vec3 e = cell.extent();
  const float a = e[(axis + 1) % 3], b = e[(axis + 2) % 3];
  return length * (a + b) + a * b;
}

/// Which children of a cell split at `s` on `axis` a primitive goes to: below
/// if it reaches below the plane or lies in it, above if it reaches above it.
bool goes_below(const Bounds3& b, int axis, float s) {
  return b.lo[axis] < s || b.hi[axis] == s;
}
bool goes_above(const Bounds3& b, int axis, float s) {
  return b.hi[axis] > s;
}

struct Split {
  int axis = -1;
  float position = 0.0f;
  float cost = kInfinity;
};

struct Builder {
  std::span<const Bounds3> bounds;
  const KdTreeBuildConfig& cfg;
  int max_depth;
  size_t max_refs;
  std::vector<KdNode>& nodes;
  std::vector<uint32_t>& refs;
  std::vector<uint32_t>& offsets;  // SmallestCell: CSR of the nodes' lists
  float loose = 0.0f;              // SmallestCell's loose factor
  std::vector<float> fit_below = {}, fit_above = {}, candidates = {};  // reused per cell
  std::vector<float> lo_edges = {}, hi_edges = {}, flat_edges = {};    // reused per cell

  void make_leaf(uint32_t node, const std::vector<uint32_t>& prims) {
    if (refs.size() > KdNode::kMaxIndex || prims.size() > KdNode::kMaxIndex)
      throw std::length_error("KdTree::build: too many references for KdNode");
    nodes[node].payload = uint32_t(refs.size());
    nodes[node].bits = uint32_t(prims.size()) << 2 | KdNode::kLeafAxis;
    refs.insert(refs.end(), prims.begin(), prims.end());
  }

  /// The SAH's best plane over the edges of the cell's primitives on every
  /// axis, each candidate s counted as goes_below() and goes_above() send
  /// them. Planes on the cell's faces are skipped: they would cut off nothing.
  Split best_sah_split(const Bounds3& cell, const std::vector<uint32_t>& prims) {
    Split best;
    const float cell_area = cell.half_area();
    if (!(cell_area > 0.0f)) return best;
    const size_t n = prims.size();
    for (int axis = 0; axis < 3; ++axis) {
      if (!(cell.hi[axis] > cell.lo[axis])) continue;
      lo_edges.clear();
      hi_edges.clear();
      flat_edges.clear();
      for (uint32_t p : prims) {
        lo_edges.push_back(bounds[p].lo[axis]);
        hi_edges.push_back(bounds[p].hi[axis]);
        if (bounds[p].lo[axis] == bounds[p].hi[axis]) flat_edges.push_back(bounds[p].lo[axis]);
      }
      std::sort(lo_edges.begin(), lo_edges.end());
      std::sort(hi_edges.begin(), hi_edges.end());
      std::sort(flat_edges.begin(), flat_edges.end());
      // Sweep the distinct edge positions in order, counting lo < s (a),
      // hi <= s (b) and lo == hi == s (f: flat in the plane, sent below).
      const size_t nf = flat_edges.size();
      size_t a = 0, b = 0, c = 0;
      while (a < n || b < n) {
        const float s = std::min(a < n ? lo_edges[a] : kInfinity, b < n ? hi_edges[b] : kInfinity);
        const size_t below_lo = a;
        while (a < n && lo_edges[a] == s) ++a;
        while (b < n && hi_edges[b] == s) ++b;
        size_t f = 0;
        while (c < nf && flat_edges[c] < s) ++c;
        while (c < nf && flat_edges[c] == s) ++c, ++f;
        const size_t below = below_lo + f, above = n - b;
        if (!(s > cell.lo[axis] && s < cell.hi[axis])) continue;
        const float p_below = child_half_area(cell, axis, s - cell.lo[axis]) / cell_area;
        const float p_above = child_half_area(cell, axis, cell.hi[axis] - s) / cell_area;
        const float bonus = below == 0 || above == 0 ? 1.0f - cfg.empty_bonus : 1.0f;
        const float cost =
            cfg.traversal_cost +
            cfg.intersection_cost * bonus * (p_below * float(below) + p_above * float(above));
        if (cost < best.cost) best = Split{axis, s, cost};
      }
    }
    return best;
  }

  /// The SAH's best plane for SmallestCell (see KdTreeBuildConfig).
  /// On the split axis a primitive of extent [l, h] in a cell [L, H] fits the
  /// loose box of the child below the plane s, [L - f (s - L), s + f (s - L)],
  /// for every s >= max((h + f L) / (1 + f), (L (1 + f) - l) / f), and the
  /// child above for every s <= min((l + f H) / (1 + f), (H (1 + f) - h) / f):
  /// two sorted lists of thresholds give both counts for any plane. The
  /// candidate planes are the thresholds inside the cell. (An estimate: the
  /// distribution afterwards tests the real loose boxes.)
  Split best_loose_split(const Bounds3& cell, const std::vector<uint32_t>& prims) {
    Split best;
    const float f = loose;
    const float node_area = loose_box(cell, f).half_area();
    if (!(node_area > 0.0f)) return best;
    const float n = float(prims.size());
    for (int axis = 0; axis < 3; ++axis) {
      const float L = cell.lo[axis], H = cell.hi[axis];
      if (!(H > L)) continue;
      fit_below.clear();
      fit_above.clear();
      for (uint32_t p : prims) {
        const float l = bounds[p].lo[axis], h = bounds[p].hi[axis];
        float b = (h + f * L) / (1.0f + f), a = (l + f * H) / (1.0f + f);
        if (f > 0.0f) {
          b = std::max(b, (L * (1.0f + f) - l) / f);
          a = std::min(a, (H * (1.0f + f) - h) / f);
        } else {
          if (l < L) b = kInfinity;
          if (h > H) a = -kInfinity;
        }
        fit_below.push_back(b);
        fit_above.push_back(a);
      }
      std::sort(fit_below.begin(), fit_below.end());
      std::sort(fit_above.begin(), fit_above.end());
      candidates.clear();
      for (float s : fit_below)
        if (s > L && s < H) candidates.push_back(s);
      for (float s : fit_above)
        if (s > L && s < H) candidates.push_back(s);
      std::sort(candidates.begin(), candidates.end());
      candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
      for (float s : candidates) {
        const float below =
            float(std::upper_bound(fit_below.begin(), fit_below.end(), s) - fit_below.begin());
        const float above =
            float(fit_above.end() - std::lower_bound(fit_above.begin(), fit_above.end(), s));
        const float straddle = std::max(0.0f, n - below - above);
        Bounds3 bc = cell, ac = cell;
        bc.hi[axis] = ac.lo[axis] = s;
        const float p_below = loose_box(bc, f).half_area() / node_area;
        const float p_above = loose_box(ac, f).half_area() / node_area;
        // No empty-side bonus: a plane where every primitive fits one loose
        // child cuts off hardly any space (that child's loose box reaches
        // into the other), and the bonus made chains of such planes use up
        // the depth limit (measured on the bunny: 5,477 nodes at depth 29
        // with 147 primitives tested per ray).
        const float cost = cfg.traversal_cost +
                           cfg.intersection_cost * (straddle + p_below * below + p_above * above);
        if (cost < best.cost) best = Split{axis, s, cost};
      }
    }
    return best;
  }

  /// SmallestCell's recursion (see the file comment). Nodes are numbered in
  /// the order this visits them, so the lists written here are in node order
  /// (offsets).
  void build_loose(uint32_t node, const Bounds3& cell, std::vector<uint32_t> prims, int depth,
                   int bad_refines) {
    assert(offsets.size() == node);
    offsets.push_back(uint32_t(refs.size()));
    const size_t n = prims.size();
    if (n == 0 || depth >= max_depth || n <= (cfg.rule != KdSplitRule::Sah ? cfg.max_leaf_size : 0))
      return make_leaf(node, prims);
    Split split;
    if (cfg.rule == KdSplitRule::Sah) {
      split = best_loose_split(cell, prims);
      const float leaf_cost = cfg.intersection_cost * float(n);
      if (split.axis >= 0 && !(split.cost < leaf_cost)) {
        if (n <= cfg.max_leaf_size || bad_refines >= KdTree::kMaxBadRefines) split.axis = -1;
        ++bad_refines;
      }
    } else {
      split = rule_split(cell, prims, depth);
    }
    if (split.axis < 0) return make_leaf(node, prims);

    Bounds3 below_cell = cell, above_cell = cell;
    below_cell.hi[split.axis] = split.position;
    above_cell.lo[split.axis] = split.position;
    const Bounds3 below_box = loose_box(below_cell, loose),
                  above_box = loose_box(above_cell, loose);
    std::vector<uint32_t> stay, below, above;
    for (uint32_t p : prims) {
      const Bounds3& b = bounds[p];
      const bool fb = below_box.contains(b), fa = above_box.contains(b);
      if (fb && fa)
        (b.center()[split.axis] < split.position ? below : above).push_back(p);
      else
        (fb ? below : fa ? above : stay).push_back(p);
    }
    if (stay.size() == n) return make_leaf(node, prims);  // nothing fits a child
    prims = {};
    if (refs.size() + stay.size() > size_t(~0u))
      throw std::length_error("KdTree::build: too many references");
    refs.insert(refs.end(), stay.begin(), stay.end());
    nodes.emplace_back();  // node + 1: the child below
    build_loose(node + 1, below_cell, std::move(below), depth + 1, bad_refines);
    const size_t above_index = nodes.size();
    if (above_index > KdNode::kMaxIndex)
      throw std::length_error("KdTree::build: too many nodes for KdNode");
    nodes.emplace_back();
    nodes[node].payload = std::bit_cast<uint32_t>(split.position);
    nodes[node].bits = uint32_t(above_index) << 2 | uint32_t(split.axis);
    build_loose(uint32_t(above_index), above_cell, std::move(above), depth + 1, bad_refines);
  }

  /// The plane of a rule other than the SAH for a cell at `depth`.
  Split rule_split(const Bounds3& cell, const std::vector<uint32_t>& prims, int depth) {
    return cfg.rule == KdSplitRule::Median ? median_split(cell)
                                           : alternating_median_split(cell, prims, depth);
  }

  /// Axis depth % 3 (then the next ones in turn), at the median of the
  /// primitives' centers along it: the upper median, so that a plane between
  /// two centers sends each to its side. No split when no axis has its
  /// median strictly inside the cell.
  Split alternating_median_split(const Bounds3& cell, const std::vector<uint32_t>& prims,
                                 int depth) {
    std::vector<float>& c = candidates;  // reused per cell
    for (int turn = 0; turn < 3; ++turn) {
      const int axis = (depth + turn) % 3;
      c.clear();
      for (uint32_t p : prims) c.push_back(bounds[p].center()[axis]);
      auto mid = c.begin() + std::ptrdiff_t(c.size() / 2);
      std::nth_element(c.begin(), mid, c.end());
      const float m = *mid;
      if (m > cell.lo[axis] && m < cell.hi[axis]) return Split{axis, m, 0.0f};
    }
    return Split{};
  }

  /// The middle of the cell's longest axis (no split for a point-like cell).
  static Split median_split(const Bounds3& cell) {
    Split s;
    const Vec3 e = cell.extent();
    const int axis = max_dimension(e);
    const float mid = cell.lo[axis] + 0.5f * e[axis];
    if (mid > cell.lo[axis] && mid < cell.hi[axis]) s = Split{axis, mid, 0.0f};
    return s;
  }

  void build(uint32_t node, const Bounds3& cell, std::vector<uint32_t> prims, int depth,
             int bad_refines) {
    const size_t n = prims.size();
    if (n == 0 || depth >= max_depth || refs.size() + n > max_refs ||
        (cfg.rule != KdSplitRule::Sah && n <= cfg.max_leaf_size))
      return make_leaf(node, prims);
    Split split;
    if (cfg.rule == KdSplitRule::Sah) {
      split = best_sah_split(cell, prims);
      const float leaf_cost = cfg.intersection_cost * float(n);
      if (split.axis >= 0 && !(split.cost < leaf_cost)) {
        if (n <= cfg.max_leaf_size || bad_refines >= KdTree::kMaxBadRefines) split.axis = -1;
        ++bad_refines;
      }
    } else {
      split = rule_split(cell, prims, depth);
    }
    if (split.axis < 0) return make_leaf(node, prims);

    std::vector<uint32_t> below, above;
    for (uint32_t p : prims) {
      if (goes_below(bounds[p], split.axis, split.position)) below.push_back(p);
      if (goes_above(bounds[p], split.axis, split.position)) above.push_back(p);
    }
    // A plane that separates nothing would only repeat this cell's list twice.
    if (below.size() == n && above.size() == n) return make_leaf(node, prims);
    prims = {};

    Bounds3 below_cell = cell, above_cell = cell;
    below_cell.hi[split.axis] = split.position;
    above_cell.lo[split.axis] = split.position;
    nodes.emplace_back();  // node + 1: the child below
    build(node + 1, below_cell, std::move(below), depth + 1, bad_refines);
    const size_t above_index = nodes.size();
    if (above_index > KdNode::kMaxIndex)
      throw std::length_error("KdTree::build: too many nodes for KdNode");
    nodes.emplace_back();
    nodes[node].payload = std::bit_cast<uint32_t>(split.position);
    nodes[node].bits = uint32_t(above_index) << 2 | uint32_t(split.axis);
    build(uint32_t(above_index), above_cell, std::move(above), depth + 1, bad_refines);
  }
};

}  // namespace

const char* to_string(KdSplitRule rule) {
  switch (rule) {
    case KdSplitRule::Sah:
      return "sah";
    case KdSplitRule::Median:
      return "median";
    case KdSplitRule::AlternatingMedian:
      return "alternating-median";
  }
  return "?";
}

bool parse_kd_split_rule(std::string_view name, KdSplitRule& rule) {
  for (KdSplitRule r : {KdSplitRule::Sah, KdSplitRule::Median, KdSplitRule::AlternatingMedian})
    if (name == to_string(r)) {
      rule = r;
      return true;
    }
  return false;
}

void KdTree::build(std::span<const Bounds3> bounds, const KdTreeBuildConfig& cfg,
                   PrimStorage storage, float loose_factor) {
  const auto start = std::chrono::steady_clock::now();
  // build_accel() refuses both with a message (accel_config_error()).
  assert(storage != PrimStorage::Split);
  assert(loose_factor_error(loose_factor).empty());
  config = cfg;
  nodes.clear();
  refs.clear();
  offsets.clear();
  loose_ = storage == PrimStorage::SmallestCell;
  loose_factor_ = loose_ ? loose_factor : 0.0f;
  bounds_ = Bounds3();
  num_prims_ = uint32_t(bounds.size());
  const size_t n = bounds.size();
  max_depth_ = cfg.max_depth > 0
                   ? cfg.max_depth
                   : int(std::lround(8.0 + 1.3 * std::log2(double(std::max<size_t>(n, 1)))));
  max_depth_ = std::clamp(max_depth_, 0, kMaxDepth);
  if (n > 0) {
    if (n > KdNode::kMaxIndex) throw std::length_error("KdTree::build: too many primitives");
    for (const Bounds3& b : bounds) bounds_.extend(b);
    std::vector<uint32_t> all(n);
    for (uint32_t i = 0; i < n; ++i) all[i] = i;
    nodes.emplace_back();
    Builder b{bounds, cfg,  max_depth_, kMaxReferencesPerPrim * n,
              nodes,  refs, offsets,    loose_factor_};
    if (loose_) {
      b.build_loose(0, bounds_, std::move(all), 0, 0);
      offsets.push_back(uint32_t(refs.size()));
    } else {
      b.build(0, bounds_, std::move(all), 0, 0);
    }
    nodes.shrink_to_fit();
    refs.shrink_to_fit();
    offsets.shrink_to_fit();
  }
  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

KdTreeQuality KdTree::quality() const {
  KdTreeQuality q;
  q.build_seconds = build_seconds_;
  if (nodes.empty()) return q;
  q.nodes = uint32_t(nodes.size());
  q.references = refs.size();
  q.refs_per_prim = num_prims_ ? double(refs.size()) / num_prims_ : 0.0;
  q.memory_bytes = memory_bytes();
  const double root_area = std::max(1e-30, double(node_box(bounds_).half_area()));
  struct Item {
    uint32_t node, depth;
    Bounds3 cell;
  };
  std::vector<Item> stack{{0u, 0u, bounds_}};
  while (!stack.empty()) {
    const Item it = stack.back();
    stack.pop_back();
    const KdNode& n = nodes[it.node];
    q.depth = std::max(q.depth, it.depth);
    const double rel = double(node_box(it.cell).half_area()) / root_area;
    const uint32_t count = uint32_t(node_refs(it.node).size());
    q.sah_cost += rel * config.intersection_cost * count;
    if (n.is_leaf()) {
      q.leaves++;
      q.empty_leaves += count == 0;
      q.max_leaf_refs = std::max(q.max_leaf_refs, count);
      continue;
    }
    q.inner_refs += count;
    q.sah_cost += rel * config.traversal_cost;
    Bounds3 below = it.cell, above = it.cell;
    below.hi[n.axis()] = above.lo[n.axis()] = n.split();
    stack.push_back({it.node + 1, it.depth + 1, below});
    stack.push_back({n.above(), it.depth + 1, above});
  }
  const uint32_t full = q.leaves - q.empty_leaves;
  q.mean_leaf_refs = full ? double(refs.size() - q.inner_refs) / full : 0.0;
  return q;
}

std::vector<Bounds3> KdTree::cells() const {
  std::vector<Bounds3> c(nodes.size());
  if (nodes.empty()) return c;
  c[0] = bounds_;
  // Children come after their parent in the array.
  for (uint32_t i = 0; i < nodes.size(); ++i)
    for_children(i, c[i], [&](uint32_t child, const Bounds3& cell) { c[child] = cell; });
  return c;
}

AccelFigures KdTree::figures() const {
  const KdTreeQuality q = quality();
  AccelFigures f = figures_of(q, q.refs_per_prim);
  f.leaves = q.leaves - q.empty_leaves;
  return f;
}

AccelView KdTree::view() const {
  AccelView v;
  v.structure = "kdtree";
  v.traversal_cost = config.traversal_cost;
  v.intersection_cost = config.intersection_cost;
  v.nodes.resize(nodes.size());
  const std::vector<Bounds3> cell = cells();
  for (size_t i = 0; i < nodes.size(); ++i) {
    const KdNode& n = nodes[i];
    AccelViewNode& o = v.nodes[i];
    o.box = node_box(cell[i]);  // the loose box for smallest-cell storage
    o.leaf = n.is_leaf();
    // Inner nodes of a loose kD-tree hold primitives too.
    const std::span<const uint32_t> held = node_refs(uint32_t(i));
    o.first = held.empty() ? 0u : uint32_t(held.data() - refs.data());
    o.count = uint32_t(held.size());
    if (o.leaf) continue;
    // The cell below the plane is the next node, the one above at above().
    v.nodes[i + 1].parent = v.nodes[n.above()].parent = int32_t(i);
  }
  v.refs = refs;
  finish_levels(v);
  return v;
}

std::string KdTree::stats_line() const {
  const KdTreeQuality q = quality();
  char line[512];
  std::snprintf(line, sizeof line,
                "kdtree, %s split, %s: %u nodes, %u leaves (%u empty), depth %u (limit %d), %.2f "
                "references per primitive (%zu held by inner nodes), %.1f per non-empty leaf, SAH "
                "cost %.2f, %.2f MiB, built in %.3f s",
                to_string(config.rule), storage_text(storage(), loose_factor_).c_str(), q.nodes,
                q.leaves, q.empty_leaves, q.depth, max_depth(), q.refs_per_prim, q.inner_refs,
                q.mean_leaf_refs, q.sah_cost, double(q.memory_bytes) / (1024.0 * 1024.0),
                q.build_seconds);
  return line;
}

std::string KdTree::walk_legend() const {
  return "the kD-tree (--accel kdtree); nodes are named by their kD-tree ids, a node's two "
         "child boxes are the cells its split plane lets the ray reach, and a primitive "
         "stored in several cells is tested once";
}

}  // namespace rayscope
