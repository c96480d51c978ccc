// BSP tree builder: top down, depth first (the back child of node i is node
// i + 1), in double precision: signed distances, clipped fragments and cells.
//
// Each node carries its cell as a convex polyhedron (its faces: polygons with
// their outward planes), starting from the root box. Cutting a cell by a plane
// clips every face to each side and adds the cap, the plane's polygon inside
// the cell: the cap is the split polygon drawn for the node, the faces'
// vertices give each child's cell box.
#include "rayscope/accel/bsp.h"

#include <cstdio>

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>

namespace rayscope {
namespace {

using DVec3 = glm::dvec3;
using Polygon = std::vector<DVec3>;

/// A plane {x : dot(n, x) = d}.
struct Plane {
  DVec3 n;
  double d;
  double distance(const DVec3& p) const { return glm::dot(n, p) - d; }
};

/// The part of `poly` where sign x plane.distance() <= 0 (Sutherland-Hodgman;
/// convex in, convex out; empty when nothing is left).
Polygon clip(const Polygon& poly, const Plane& plane, double sign) {
  Polygon out;
  const size_t m = poly.size();
  for (size_t i = 0; i < m; ++i) {
    const DVec3& p = poly[i];
    const DVec3& q = poly[(i + 1) % m];
    const double sp = sign * plane.distance(p), sq = sign * plane.distance(q);
    if (sp <= 0.0) out.push_back(p);
    if ((sp < 0.0 && sq > 0.0) || (sp > 0.0 && sq < 0.0))
      out.push_back(p + (sp / (sp - sq)) * (q - p));
  }
  if (out.size() < 3) out.clear();
  return out;
}

/// A face of a convex cell: its polygon and its plane, the cell on the side
/// where distance <= 0.
struct Face {
  Plane plane;
  Polygon poly;
};
using Cell = std::vector<Face>;

Cell box_cell(const DVec3& lo, const DVec3& hi) {
  Cell c;
  for (int a = 0; a < 3; ++a) {
    const int u = (a + 1) % 3, v = (a + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      Face f;
      f.plane.n = DVec3(0.0);
      f.plane.n[a] = side ? 1.0 : -1.0;
      f.plane.d = side ? hi[a] : -lo[a];
      const double x = side ? hi[a] : lo[a];
      const double us[4] = {lo[u], hi[u], hi[u], lo[u]}, vs[4] = {lo[v], lo[v], hi[v], hi[v]};
      for (int k = 0; k < 4; ++k) {
        DVec3 p;
        p[a] = x;
        p[u] = us[k];
        p[v] = vs[k];
        f.poly.push_back(p);
      }
      c.push_back(std::move(f));
    }
  }
  return c;
}

/// The plane's polygon inside the cell: a square on the plane bigger than the
/// cell, clipped by every face's half-space.
Polygon cap(const Cell& cell, const Plane& plane) {
  Bounds3 b;
  for (const Face& f : cell)
    for (const DVec3& p : f.poly) b.extend(Vec3(p));
  if (b.empty()) return {};
  const DVec3 n = plane.n / glm::length(plane.n);
  const DVec3 center = DVec3(b.center());
  const DVec3 o = center - (plane.distance(center) / glm::length(plane.n)) * n;
  const DVec3 helper = std::abs(n.x) < 0.6 ? DVec3(1, 0, 0) : DVec3(0, 1, 0);
  const DVec3 u = glm::normalize(glm::cross(n, helper)), v = glm::cross(n, u);
  const double r = 2.0 * double(glm::length(b.extent())) + 1.0;
  Polygon poly = {o - r * u - r * v, o + r * u - r * v, o + r * u + r * v, o - r * u + r * v};
  for (const Face& f : cell) {
    if (poly.empty()) break;
    poly = clip(poly, f.plane, 1.0);
  }
  return poly;
}

/// The child cell on side `sign` (-1: back, +1: front) of the plane.
Cell cut_cell(const Cell& cell, const Plane& plane, double sign, const Polygon& lid) {
  Cell c;
  for (const Face& f : cell) {
    Polygon p = clip(f.poly, plane, -sign);  // back (-1): distance <= 0; front: >= 0
    if (!p.empty()) c.push_back({f.plane, std::move(p)});
  }
  if (!lid.empty()) c.push_back({Plane{sign * -plane.n, sign * -plane.d}, lid});
  return c;
}

Bounds3 cell_box(const Cell& cell, double tolerance, const Bounds3& fallback) {
  Bounds3 b;
  for (const Face& f : cell)
    for (const DVec3& p : f.poly) b.extend(Vec3(p));
  if (b.empty()) return fallback;
  const float t = float(tolerance);
  b.lo -= Vec3(t) * 2.0f;
  b.hi += Vec3(t) * 2.0f;
  return b;
}

/// One piece of work: a primitive, and for triangles its polygon (the whole
/// triangle, or with Split the fragment left after the cuts above).
struct Item {
  uint32_t prim;
  Polygon poly;  ///< Empty for spheres and capsules.
};

struct Builder {
  std::span<const BspPrim> prims;
  const BspBuildConfig& cfg;
  BspTree& tree;
  double tol;
  int max_depth;
  size_t max_refs;
  std::vector<char> cut;  ///< Split: triangles cut at least once.

  /// Lowest and highest signed distance of the item from the plane.
  void extent(const Item& it, const Plane& p, double& lo, double& hi) const {
    if (it.poly.empty()) {
      const BspPrim& s = prims[it.prim];
      const double ca = p.distance(DVec3(s.a)), cb = p.distance(DVec3(s.b));
      const double r = double(s.radius) * glm::length(p.n);
      lo = std::min(ca, cb) - r;
      hi = std::max(ca, cb) + r;
      return;
    }
    lo = kInfinity;
    hi = -kInfinity;
    for (const DVec3& v : it.poly) {
      const double s = p.distance(v);
      lo = std::min(lo, s);
      hi = std::max(hi, s);
    }
  }

  /// The plane of primitive `i` (a triangle with a non-zero area), false
  /// for spheres and degenerate triangles. Normal rounded to float, offset
  /// through vertex a in double: BspNode holds exactly this plane.
  bool triangle_plane(uint32_t i, Plane& p) const {
    const BspPrim& t = prims[i];
    if (t.round) return false;
    const DVec3 a(t.a), b(t.b), c(t.c);
    const DVec3 n = glm::cross(b - a, c - a);
    const double len = glm::length(n);
    if (!(len > 0.0) || !std::isfinite(len)) return false;
    const Vec3 nf = Vec3(n / len);
    if (!(glm::length(nf) > 0.5f)) return false;
    p.n = DVec3(nf);
    p.d = glm::dot(p.n, a);
    return true;
  }

  /// Sides of every item: counts behind, in front, on both.
  void count(const std::vector<Item>& items, const Plane& p, size_t& back, size_t& front,
             size_t& both) const {
    back = front = both = 0;
    for (const Item& it : items) {
      double lo, hi;
      extent(it, p, lo, hi);
      const bool b = lo <= tol, f = hi >= -tol;
      back += b;
      front += f;
      both += b && f;
    }
  }

  /// Whether the plane cuts the cell (its vertices lie beyond the tolerance
  /// on both sides). With EveryCell, a node's primitives reach out of its
  /// cell, and a plane outside the cell could separate them there: a cut
  /// that divides nothing of the space the node stands for.
  bool cuts(const Cell& cell, const Plane& p) const {
    double lo = kInfinity, hi = -kInfinity;
    for (const Face& f : cell)
      for (const DVec3& v : f.poly) {
        const double s = p.distance(v);
        lo = std::min(lo, s);
        hi = std::max(hi, s);
      }
    return lo < -tol && hi > tol;
  }

  /// The cheapest plane for `items` (see bsp.h) that cuts `cell`; false if
  /// none makes progress.
  bool choose(const std::vector<Item>& items, const Cell& cell, Plane& best) const {
    const size_t n = items.size();
    std::vector<uint32_t> tris;
    for (uint32_t k = 0; k < n; ++k)
      if (!items[k].poly.empty()) tris.push_back(k);
    double best_cost = kInfinity;
    const size_t stride = std::max<size_t>(1, tris.size() / cfg.candidates);
    for (size_t k = 0, tried = 0; k < tris.size() && tried < cfg.candidates; k += stride, ++tried) {
      Plane p;
      if (!triangle_plane(items[tris[k]].prim, p) || !cuts(cell, p)) continue;
      size_t back, front, both;
      count(items, p, back, front, both);
      if (back == n || front == n) continue;  // no progress
      const double cost =
          double(cfg.split_weight) * double(both) + std::abs(double(front) - double(back));
      if (cost < best_cost) {
        best_cost = cost;
        best = p;
      }
    }
    if (best_cost < kInfinity) return true;
    // No triangle plane: the median of the centers on their widest axis.
    Bounds3 b;
    std::vector<float> centers[3];
    for (const Item& it : items) {
      const BspPrim& q = prims[it.prim];
      const Vec3 c =
          !q.round ? (q.a + q.b + q.c) / 3.0f : (q.a == q.b ? q.a : 0.5f * q.a + 0.5f * q.b);
      b.extend(c);
      for (int a = 0; a < 3; ++a) centers[a].push_back(c[a]);
    }
    const Vec3 e = b.extent();
    const int axis = e.x >= e.y && e.x >= e.z ? 0 : (e.y >= e.z ? 1 : 2);
    std::vector<float>& cs = centers[axis];
    std::nth_element(cs.begin(), cs.begin() + cs.size() / 2, cs.end());
    Plane p;
    p.n = DVec3(0.0);
    p.n[axis] = 1.0;
    p.d = cs[cs.size() / 2];
    size_t back, front, both;
    count(items, p, back, front, both);
    if (back == n || front == n || !cuts(cell, p)) return false;
    best = p;
    return true;
  }

  void hold(uint32_t node, const std::vector<Item>& items, bool keep_fragments) {
    if (tree.refs.size() + items.size() > size_t(~0u) - 1)
      throw std::length_error("BspTree::build: too many references");
    tree.nodes[node].first = uint32_t(tree.refs.size());
    tree.nodes[node].count = uint32_t(items.size());
    for (const Item& it : items) {
      tree.refs.push_back(it.prim);
      if (!keep_fragments) continue;
      BspFragment f;
      f.prim = it.prim;
      f.first = uint32_t(tree.fragment_vertices.size());
      f.count = uint32_t(it.poly.size());
      for (const DVec3& v : it.poly) tree.fragment_vertices.push_back(Vec3(v));
      tree.fragments.push_back(f);
    }
  }

  uint32_t new_node(const Bounds3& box) {
    if (tree.nodes.size() >= size_t(~0u) - 1)
      throw std::length_error("BspTree::build: too many nodes");
    tree.nodes.emplace_back();
    tree.cell_boxes.push_back(box);
    tree.plane_polygons.emplace_back();
    return uint32_t(tree.nodes.size() - 1);
  }

  void build(uint32_t node, std::vector<Item> items, const Cell& cell, int depth) {
    const bool split = tree.storage() == PrimStorage::Split;
    const size_t n = items.size();
    Plane p;
    if (n <= cfg.max_leaf_size || depth >= max_depth || tree.refs.size() + n > max_refs ||
        !choose(items, cell, p))
      return hold(node, items, split);
    std::vector<Item> back, front, stay;
    for (Item& it : items) {
      double lo, hi;
      extent(it, p, lo, hi);
      const bool b = lo <= tol, f = hi >= -tol;
      if (b && !f) {
        back.push_back(std::move(it));
      } else if (f && !b) {
        front.push_back(std::move(it));
      } else if (tree.storage() == PrimStorage::SmallestCell ||
                 (split && !it.poly.empty() && lo >= -tol && hi <= tol)) {
        // The node's list: every straddler (SmallestCell), or a triangle
        // lying in the plane (Split: the classic BSP's coincident polygons).
        stay.push_back(std::move(it));
      } else if (split && !it.poly.empty()) {
        // Clipped into its convex fragments on either side. A side the
        // polygon only touches (no vertex strictly beyond the plane) gets
        // nothing; a degenerate polygon whose piece clips to nothing goes
        // whole.
        Polygon bp = clip(it.poly, p, 1.0), fp = clip(it.poly, p, -1.0);
        cut[it.prim] |= !bp.empty() && !fp.empty();
        if (!bp.empty())
          back.push_back({it.prim, std::move(bp)});
        else if (lo < 0.0)
          back.push_back(it);
        if (!fp.empty())
          front.push_back({it.prim, std::move(fp)});
        else if (hi > 0.0)
          front.push_back(it);
      } else {  // EveryCell, or a sphere or capsule with Split: whole to both sides
        front.push_back(it);
        back.push_back(std::move(it));
      }
    }
    items = {};
    hold(node, stay, split);
    const Polygon lid = cap(cell, p);
    {
      BspTree::Range32 r{uint32_t(tree.plane_vertices.size()), uint32_t(lid.size())};
      for (const DVec3& v : lid) tree.plane_vertices.push_back(Vec3(v));
      tree.plane_polygons[node] = r;
    }
    tree.nodes[node].normal = Vec3(p.n);
    tree.nodes[node].offset = p.d;
    const Bounds3 parent_box = tree.cell_boxes[node];
    {
      const Cell c = cut_cell(cell, p, -1.0, lid);
      const uint32_t b = new_node(cell_box(c, tol, parent_box));
      assert(b == node + 1);
      (void)b;
      build(node + 1, std::move(back), c, depth + 1);
    }
    const Cell c = cut_cell(cell, p, 1.0, lid);
    const uint32_t f = new_node(cell_box(c, tol, parent_box));
    tree.nodes[node].front = f;
    build(f, std::move(front), c, depth + 1);
  }
};

}  // namespace

void BspTree::build(std::span<const BspPrim> prims, const BspBuildConfig& cfg,
                    PrimStorage storage) {
  const auto start = std::chrono::steady_clock::now();
  if (cfg.candidates == 0) throw std::invalid_argument("BSP candidates must be >= 1, got 0");
  if (!(cfg.split_weight >= 0.0f) || !std::isfinite(cfg.split_weight))
    throw std::invalid_argument("BSP split weight must be finite and >= 0, got " +
                                std::to_string(cfg.split_weight));
  const size_t n = prims.size();
  if (n > size_t(~0u) - 1) throw std::length_error("BspTree::build: too many primitives");
  Bounds3 all;
  for (size_t i = 0; i < n; ++i) {
    const BspPrim& q = prims[i];
    if (!all_finite(q.a) || !all_finite(q.b) || !all_finite(q.c) || !std::isfinite(q.radius) ||
        q.radius < 0.0f)
      throw std::invalid_argument("BspTree::build: primitive " + std::to_string(i) +
                                  " has a non-finite coordinate or an invalid radius");
    if (q.round) {
      all.extend(q.a - Vec3(q.radius));
      all.extend(q.a + Vec3(q.radius));
      all.extend(q.b - Vec3(q.radius));
      all.extend(q.b + Vec3(q.radius));
    } else {
      all.extend(q.a);
      all.extend(q.b);
      all.extend(q.c);
    }
  }
  config = cfg;
  storage_ = storage;
  nodes.clear();
  refs.clear();
  cell_boxes.clear();
  plane_polygons.clear();
  plane_vertices.clear();
  fragments.clear();
  fragment_vertices.clear();
  bounds_ = Bounds3();
  num_prims_ = uint32_t(n);
  split_prims_ = 0;
  tolerance_ = 0.0;
  if (n > 0) {
    bounds_ = all;
    const Vec3 mag = glm::max(glm::abs(all.lo), glm::abs(all.hi));
    tolerance_ = kClassifyEpsilon *
                 (double(std::max({mag.x, mag.y, mag.z})) + double(glm::length(all.extent())));
    std::vector<Item> items(n);
    for (uint32_t i = 0; i < n; ++i) {
      items[i].prim = i;
      if (!prims[i].round)
        items[i].poly = {DVec3(prims[i].a), DVec3(prims[i].b), DVec3(prims[i].c)};
    }
    Builder b{prims,
              cfg,
              *this,
              tolerance_,
              std::clamp(cfg.max_depth, 0, kMaxDepth),
              kMaxReferencesPerPrim * n,
              std::vector<char>(n, 0)};
    const Cell root = box_cell(DVec3(bounds_.lo), DVec3(bounds_.hi));
    b.new_node(cell_box(root, tolerance_, bounds_));
    b.build(0, std::move(items), root, 0);
    for (char c : b.cut) split_prims_ += size_t(c);
  }
  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::vector<DVec3> plane_in_box(const DVec3& point, const DVec3& normal, const DVec3& lo,
                                const DVec3& hi) {
  if (!(glm::length(normal) > 0.0)) return {};
  return cap(box_cell(lo, hi), Plane{normal, glm::dot(normal, point)});
}

std::vector<uint32_t> BspTree::depths() const {
  std::vector<uint32_t> d(nodes.size(), 0u);
  for (size_t i = 0; i < nodes.size(); ++i)
    if (!nodes[i].is_leaf()) d[i + 1] = d[nodes[i].front] = d[i] + 1;
  return d;
}

BspQuality BspTree::quality() const {
  BspQuality q;
  q.build_seconds = build_seconds_;
  if (nodes.empty()) return q;
  q.nodes = uint32_t(nodes.size());
  q.references = refs.size();
  q.refs_per_prim = num_prims_ ? double(refs.size()) / num_prims_ : 0.0;
  q.fragments = storage_ == PrimStorage::Split ? refs.size() : 0;
  q.split_prims = split_prims_;
  q.memory_bytes = memory_bytes();
  const CellRefCounts c = count_cell_refs(nodes, depths());
  q.leaves = c.leaves;
  q.depth = c.depth;
  q.max_leaf_refs = c.max_leaf_refs;
  q.inner_refs = c.inner_refs;
  q.mean_leaf_refs = c.mean_leaf_refs;
  return q;
}

AccelFigures BspTree::figures() const {
  const BspQuality q = quality();
  AccelFigures f = figures_of(q, q.refs_per_prim);
  f.fragments = q.fragments;
  return f;
}

AccelView BspTree::view() const {
  AccelView v;
  v.structure = "bsp";
  v.nodes.resize(nodes.size());
  for (size_t i = 0; i < nodes.size(); ++i) {
    const BspNode& n = nodes[i];
    AccelViewNode& o = v.nodes[i];
    o.box = cell_boxes[i];
    o.leaf = n.is_leaf();
    o.first = n.first;  // inner nodes hold primitives with smallest-cell storage
    o.count = n.count;
    o.polygon_first = plane_polygons[i].first;
    o.polygon_count = plane_polygons[i].count;
    if (!n.is_leaf()) v.nodes[i + 1].parent = v.nodes[n.front].parent = int32_t(i);
  }
  v.polygon_vertices = plane_vertices;
  v.refs = refs;
  finish_levels(v);
  return v;
}

std::string BspTree::stats_line() const {
  const BspQuality q = quality();
  char line[512];
  std::snprintf(line, sizeof line,
                "bsp, %s: %u nodes, %u leaves, depth %u (limit %d), %.2f references per "
                "primitive (%zu held by inner nodes), %zu fragments (%zu triangles cut), %.1f per "
                "leaf (max %u), %.2f MiB, built in %.3f s",
                to_string(storage_), q.nodes, q.leaves, q.depth, config.max_depth, q.refs_per_prim,
                q.inner_refs, q.fragments, q.split_prims, q.mean_leaf_refs, q.max_leaf_refs,
                double(q.memory_bytes) / (1024.0 * 1024.0), q.build_seconds);
  return line;
}

std::string BspTree::walk_legend() const {
  switch (storage_) {
    case PrimStorage::SmallestCell:
      return "the BSP tree (--accel bsp --storage smallest-cell); nodes are named by their BSP "
             "ids, a node's two child boxes are the half-spaces of its split plane the ray "
             "reaches, and a primitive that straddles a plane is held (and tested) by that "
             "plane's node";
    case PrimStorage::Split:
      return "the BSP tree (--accel bsp --storage split); nodes are named by their BSP ids, a "
             "node's two child boxes are the half-spaces of its split plane the ray reaches, and "
             "a triangle cut into fragments is tested once per fragment reached (no mailbox)";
    case PrimStorage::EveryCell:
      break;
  }
  return "the BSP tree (--accel bsp --storage every-cell); nodes are named by their BSP ids, a "
         "node's two child boxes are the half-spaces of its split plane the ray reaches, and a "
         "primitive stored in several cells is tested once";
}

}  // namespace rayscope
