// Small numeric helpers shared by the tracing core: vector types, axis-aligned
// bounds and the floating-point error bounds used for robust intersection.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include <glm/glm.hpp>

namespace rayscope {

using Vec2 = glm::vec2;
using Vec3 = glm::vec3;
using DVec3 = glm::dvec3;
using Color = glm::vec3;  // linear RGB

inline constexpr float kInfinity = std::numeric_limits<float>::infinity();
inline constexpr float kPi = 3.14159265358979323846f;
/// Half a unit in the last place: the relative rounding error of one operation.
inline constexpr float kMachineEpsilon = std::numeric_limits<float>::epsilon() * 0.5f;

/// Bound on the relative error of n chained floating-point operations (Higham's gamma_n).
constexpr float gamma(int n) {
  return (float(n) * kMachineEpsilon) / (1.0f - float(n) * kMachineEpsilon);
}

/// The next representable float above v (v itself for +inf).
inline float next_float_up(float v) {
  if (std::isinf(v) && v > 0.0f) return v;
  if (v == -0.0f) v = 0.0f;
  uint32_t bits = std::bit_cast<uint32_t>(v);
  bits = v >= 0.0f ? bits + 1 : bits - 1;
  return std::bit_cast<float>(bits);
}

/// The next representable float below v (v itself for -inf).
inline float next_float_down(float v) {
  if (std::isinf(v) && v < 0.0f) return v;
  if (v == 0.0f) v = -0.0f;
  uint32_t bits = std::bit_cast<uint32_t>(v);
  bits = v > 0.0f ? bits - 1 : bits + 1;
  return std::bit_cast<float>(bits);
}

inline float max_component(const Vec3& v) {
  return std::max(v.x, std::max(v.y, v.z));
}
inline int max_dimension(const Vec3& v) {
  return (v.x > v.y) ? (v.x > v.z ? 0 : 2) : (v.y > v.z ? 1 : 2);
}
inline bool all_finite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
/// Unit vector along a finite, non-zero v of any magnitude. glm::normalize
/// alone returns zero (or loses precision) when v.v overflows or is subnormal
/// (components above ~1.8e19 or below ~1e-19): v is then first scaled to a
/// largest component of magnitude 1 (found by fuzz_scene_parser).
inline Vec3 normalize_any_length(Vec3 v) {
  if (!std::isnormal(glm::dot(v, v))) v /= std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  return glm::normalize(v);
}
inline float luminance(const Color& c) {
  return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
}

/// Axis-aligned bounding box. An empty box has lo > hi.
struct Bounds3 {
  Vec3 lo{kInfinity};
  Vec3 hi{-kInfinity};

  Bounds3() = default;
  Bounds3(const Vec3& a, const Vec3& b) : lo(glm::min(a, b)), hi(glm::max(a, b)) {}
  explicit Bounds3(const Vec3& p) : lo(p), hi(p) {}

  bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
  void extend(const Vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  void extend(const Bounds3& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  Vec3 extent() const { return hi - lo; }
  Vec3 center() const { return 0.5f * (lo + hi); }
  float half_area() const {
    if (empty()) return 0.0f;
    Vec3 e = extent();
    return e.x * e.y + e.y * e.z + e.z * e.x;
  }
  bool contains(const Vec3& p) const {
    return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z;
  }
  bool contains(const Bounds3& b) const { return contains(b.lo) && contains(b.hi); }
};

inline Bounds3 merge(Bounds3 a, const Bounds3& b) {
  a.extend(b);
  return a;
}

/// A ball (lecture: "Bounding sphere: store radius, center, such that all
/// geometry is contained"): the bounding volume of the sphere hierarchy
/// (sphere_tree.h), also what range queries test such nodes against.
struct BoundingSphere {
  Vec3 center{0.0f};
  float radius = 0.0f;

  /// The axis-aligned box around the ball (rounded outward).
  Bounds3 box() const {
    Bounds3 b;
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = next_float_down(center[a] - radius);
      b.hi[a] = next_float_up(center[a] + radius);
    }
    return b;
  }
};

/// Builds an orthonormal basis (t, b) around a unit vector n (Duff et al. 2017).
inline void orthonormal_basis(const Vec3& n, Vec3& t, Vec3& b) {
  float sign = std::copysign(1.0f, n.z);
  float a = -1.0f / (sign + n.z);
  float c = n.x * n.y * a;
  t = Vec3(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
  b = Vec3(c, sign + n.y * n.y * a, -n.y);
}

}  // namespace rayscope
