#include "rayscope/range_query.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "rayscope/intersect_capsule.h"
#include "rayscope/render_settings.h"

namespace rayscope {

namespace {

std::string text(const Vec3& v) {
  return "(" + shortest_text(v.x) + ", " + shortest_text(v.y) + ", " + shortest_text(v.z) + ")";
}

double segment_distance(const DVec3& p, const DVec3& a, const DVec3& b) {
  const DVec3 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  const DVec3 d = p - (a + t * ab);
  return std::sqrt(glm::dot(d, d));
}

// A sphere's bounds as Scene::commit() gives them to the builders (so every
// node that holds the sphere contains them, bit for bit).
Bounds3 sphere_bounds(const Vec3& center, float radius) {
  return Bounds3(center - Vec3(radius), center + Vec3(radius));
}

Bounds3 triangle_bounds(const Vec3& a, const Vec3& b, const Vec3& c) {
  Bounds3 box(a);
  box.extend(b);
  box.extend(c);
  return box;
}

}  // namespace

float point_box_distance(const Vec3& p, const Bounds3& box) {
  // Per axis the gap to the box (exact comparisons), then squares summed in a
  // fixed order: each step rounds monotonically, so a box that contains
  // another is never farther, also as rounded.
  double d2 = 0.0;
  for (int i = 0; i < 3; ++i) {
    double gap = 0.0;
    if (p[i] < box.lo[i])
      gap = double(box.lo[i]) - double(p[i]);
    else if (p[i] > box.hi[i])
      gap = double(p[i]) - double(box.hi[i]);
    d2 += gap * gap;
  }
  return float(std::sqrt(d2));
}

float point_triangle_distance(const Vec3& pf, const Vec3& af, const Vec3& bf, const Vec3& cf) {
  return std::max(exact_point_triangle_distance(pf, af, bf, cf),
                  point_box_distance(pf, triangle_bounds(af, bf, cf)));
}

float exact_point_triangle_distance(const Vec3& pf, const Vec3& af, const Vec3& bf,
                                    const Vec3& cf) {
  // A vertex is on the triangle: exactly 0, which the formulas below may miss
  // by a rounding.
  if (pf == af || pf == bf || pf == cf) return 0.0f;
  const DVec3 p(pf), a(af), b(bf), c(cf);
  const DVec3 n = glm::cross(b - a, c - a);
  const double nn = glm::dot(n, n);
  if (nn > 0.0) {
    // Face region: p projects onto the triangle (on the inner side of every
    // edge, seen along the normal); else the nearest point lies on an edge.
    auto inside = [&](const DVec3& u, const DVec3& v) {
      return glm::dot(glm::cross(v - u, p - u), n) >= 0.0;
    };
    if (inside(a, b) && inside(b, c) && inside(c, a))
      return float(std::abs(glm::dot(p - a, n)) / std::sqrt(nn));
  }
  return float(
      std::min({segment_distance(p, a, b), segment_distance(p, b, c), segment_distance(p, c, a)}));
}

float point_sphere_distance(const Vec3& p, const Vec3& center, float radius) {
  const DVec3 d = DVec3(p) - DVec3(center);
  const float exact = float(std::max(0.0, std::sqrt(glm::dot(d, d)) - double(radius)));
  return std::max(exact, point_box_distance(p, sphere_bounds(center, radius)));
}

float point_capsule_distance(const Vec3& p, const Vec3& p0, const Vec3& p1, float radius) {
  const double exact =
      std::max(0.0, segment_distance(DVec3(p), DVec3(p0), DVec3(p1)) - double(radius));
  return std::max(float(exact), point_box_distance(p, capsule_bounds(p0, p1, radius)));
}

float point_plane_distance(const Vec3& p, const Vec3& point, const Vec3& normal) {
  return float(std::abs(glm::dot(DVec3(p) - DVec3(point), DVec3(normal))));
}

bool triangle_overlaps_box(const Vec3& af, const Vec3& bf, const Vec3& cf, const Bounds3& box) {
  // The box's own axes: the triangle's bounds against the box, exact.
  for (int i = 0; i < 3; ++i) {
    if (std::max({af[i], bf[i], cf[i]}) < box.lo[i]) return false;
    if (std::min({af[i], bf[i], cf[i]}) > box.hi[i]) return false;
  }
  // The other axes, about the box's center: the triangle's projection against
  // the box's projection radius.
  const DVec3 center = 0.5 * (DVec3(box.lo) + DVec3(box.hi));
  const DVec3 half = 0.5 * (DVec3(box.hi) - DVec3(box.lo));
  const DVec3 v[3] = {DVec3(af) - center, DVec3(bf) - center, DVec3(cf) - center};
  auto separates = [&](const DVec3& axis) {
    const double p0 = glm::dot(v[0], axis), p1 = glm::dot(v[1], axis), p2 = glm::dot(v[2], axis);
    const double r =
        half.x * std::abs(axis.x) + half.y * std::abs(axis.y) + half.z * std::abs(axis.z);
    return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
  };
  const DVec3 edges[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  for (const DVec3& e : edges)
    for (int i = 0; i < 3; ++i) {
      DVec3 u(0.0);
      u[i] = 1.0;
      if (separates(glm::cross(e, u))) return false;
    }
  return !separates(glm::cross(edges[0], edges[1]));
}

float point_ball_distance(const Vec3& p, const BoundingSphere& ball) {
  const DVec3 d = DVec3(p) - DVec3(ball.center);
  const double len = std::sqrt(glm::dot(d, d));
  const double r = double(ball.radius);
  const double lower = len - r - kBallSlack * (len + r);
  if (!(lower > 0.0)) return 0.0f;
  float f = float(lower);
  if (double(f) > lower) f = next_float_down(f);
  return f;
}

bool ball_overlaps_box(const BoundingSphere& ball, const Bounds3& box) {
  const double gap = double(point_box_distance(ball.center, box));
  const double r = double(ball.radius);
  // point_box_distance rounds to float: at most one half ulp of gap, which
  // the margin (relative to gap + radius) covers.
  return gap <= r + kBallSlack * (gap + r);
}

bool sphere_overlaps_box(const Vec3& center, float radius, const Bounds3& box) {
  const Bounds3 b = sphere_bounds(center, radius);
  for (int i = 0; i < 3; ++i)
    if (b.hi[i] < box.lo[i] || b.lo[i] > box.hi[i]) return false;
  double d2 = 0.0;
  for (int i = 0; i < 3; ++i) {
    double gap = 0.0;
    if (center[i] < box.lo[i])
      gap = double(box.lo[i]) - double(center[i]);
    else if (center[i] > box.hi[i])
      gap = double(center[i]) - double(box.hi[i]);
    d2 += gap * gap;
  }
  return d2 <= double(radius) * double(radius);
}

bool capsule_overlaps_box(const Vec3& p0f, const Vec3& p1f, float radius, const Bounds3& box) {
  const Bounds3 b = capsule_bounds(p0f, p1f, radius);
  for (int i = 0; i < 3; ++i)
    if (b.hi[i] < box.lo[i] || b.lo[i] > box.hi[i]) return false;
  // The squared distance from x(s) = p0 + s e to the box, s in [0, 1], is a
  // sum of squared gaps, each 0 inside the box's slab and linear outside it:
  // a convex quadratic between the s where a coordinate crosses a slab plane.
  const DVec3 p0(p0f), e = DVec3(p1f) - p0;
  const double r2 = double(radius) * double(radius);
  double cuts[8] = {0.0, 1.0};
  int n = 2;
  for (int i = 0; i < 3; ++i) {
    if (e[i] == 0.0) continue;
    for (const float plane : {box.lo[i], box.hi[i]}) {
      const double s = (double(plane) - p0[i]) / e[i];
      if (s > 0.0 && s < 1.0) cuts[n++] = s;
    }
  }
  std::sort(cuts, cuts + n);
  auto gap = [&](int i, double x) {
    return x < box.lo[i] ? double(box.lo[i]) - x : (x > box.hi[i] ? x - double(box.hi[i]) : 0.0);
  };
  auto dist2 = [&](double s) {
    double d2 = 0.0;
    for (int i = 0; i < 3; ++i) {
      // The ends exactly (x = p0 or p1 in float), the rest through e.
      const double x = s == 0.0 ? p0[i] : (s == 1.0 ? double(p1f[i]) : p0[i] + s * e[i]);
      const double g = gap(i, x);
      d2 += g * g;
    }
    return d2;
  };
  for (int k = 0; k + 1 < n; ++k) {
    const double s0 = cuts[k], s1 = cuts[k + 1];
    // Which side of each slab the piece lies on (from its middle), then the
    // quadratic's minimum sum (g_i + s h_i)^2 over the piece.
    const double mid = 0.5 * (s0 + s1);
    double num = 0.0, den = 0.0;
    for (int i = 0; i < 3; ++i) {
      const double x = p0[i] + mid * e[i];
      if (x < box.lo[i]) {
        num += (double(box.lo[i]) - p0[i]) * -e[i];
        den += e[i] * e[i];
      } else if (x > box.hi[i]) {
        num += (p0[i] - double(box.hi[i])) * e[i];
        den += e[i] * e[i];
      }
    }
    const double s = den > 0.0 ? std::clamp(-num / den, s0, s1) : s0;
    if (dist2(s) <= r2 || dist2(s0) <= r2 || dist2(s1) <= r2) return true;
  }
  return false;
}

bool plane_overlaps_box(const Vec3& point, const Vec3& normal, const Bounds3& box) {
  const DVec3 n(normal);
  const DVec3 center = 0.5 * (DVec3(box.lo) + DVec3(box.hi));
  const DVec3 half = 0.5 * (DVec3(box.hi) - DVec3(box.lo));
  const double s = glm::dot(center - DVec3(point), n);
  const double e = half.x * std::abs(n.x) + half.y * std::abs(n.y) + half.z * std::abs(n.z);
  return std::abs(s) <= e;
}

// ---------------------------------------------------------------------------

void BoxRange::check(const Bounds3& box) {
  if (!all_finite(box.lo) || !all_finite(box.hi))
    throw std::invalid_argument("the box's corners must be finite, got " + text(box.lo) + " and " +
                                text(box.hi));
  for (int i = 0; i < 3; ++i)
    if (box.lo[i] > box.hi[i])
      throw std::invalid_argument("the minimum corner " + text(box.lo) +
                                  " exceeds the maximum corner " + text(box.hi) + " in " +
                                  std::string(1, "xyz"[i]));
}

BoxRange::BoxRange(const Bounds3& box) : box_(box), center_(box.center()) {
  check(box);
}

void SphereRange::check(const Vec3& center, float radius) {
  if (!all_finite(center))
    throw std::invalid_argument("the center must be finite, got " + text(center));
  if (!std::isfinite(radius) || !(radius >= 0.0f))
    throw std::invalid_argument("the radius must be finite and >= 0, got " + shortest_text(radius));
}

SphereRange::SphereRange(const Vec3& center, float radius) : center_(center), radius_(radius) {
  check(center, radius);
}

namespace {
// The box around a ball, rounded outward.
Bounds3 ball_bounds(const Vec3& c, float r) {
  Bounds3 b;
  for (int i = 0; i < 3; ++i) {
    b.lo[i] = next_float_down(c[i] - r);
    b.hi[i] = next_float_up(c[i] + r);
  }
  return b;
}
}  // namespace

Bounds3 SphereRange::bounds() const {
  return ball_bounds(center_, radius_);
}

void KnnRange::check(const Vec3& center, uint32_t k) {
  if (!all_finite(center))
    throw std::invalid_argument("the point must be finite, got " + text(center));
  if (k < 1) throw std::invalid_argument("K must be at least 1");
}

KnnRange::KnnRange(const Vec3& center, uint32_t k) : center_(center), k_(k) {
  check(center, k);
}

Bounds3 KnnRange::bounds() const {
  return ball_bounds(center_, radius_);
}

bool KnnRange::offer(const RangeHit& hit) {
  if (heap_.size() < k_) {
    heap_.push_back(hit);
    std::push_heap(heap_.begin(), heap_.end(), nearer);
    if (heap_.size() == k_) radius_ = heap_.front().distance;
    return true;
  }
  if (!nearer(hit, heap_.front())) return false;
  std::pop_heap(heap_.begin(), heap_.end(), nearer);
  heap_.back() = hit;
  std::push_heap(heap_.begin(), heap_.end(), nearer);
  radius_ = heap_.front().distance;
  return true;
}

std::vector<RangeHit> KnnRange::take_sorted() {
  std::sort_heap(heap_.begin(), heap_.end(), nearer);
  return std::move(heap_);
}

}  // namespace rayscope
