// Rays, the kinds of rays the lecture names, and robust spawning of secondary rays.
#pragma once

#include <cstdint>

#include "rayscope/math.h"

namespace rayscope {

/// The kinds of rays a Whitted tracer shoots (see the lecture: primary, shadow,
/// reflection and refraction rays).
enum class RayKind : uint8_t { Primary = 0, Shadow = 1, Reflection = 2, Refraction = 3 };
inline constexpr int kRayKindCount = 4;
const char* to_string(RayKind kind);

/// A ray P(t) = origin + t * dir for t in (0, tmax]. dir need not be unit length.
struct Ray {
  Vec3 origin{0.0f};
  Vec3 dir{0.0f, 0.0f, 1.0f};
  float tmax = kInfinity;
};

/// The footprint of a primary sample for texture filtering (after Igehy 1999,
/// "Tracing ray differentials"), as rays: the ray through the centre of the
/// image-plane cell the sample stands for, and the rays one cell to the right
/// (dx) and below (dy) of it. Where they meet the tangent plane of the
/// sample's hit bounds the cell's footprint on the surface.
struct RayDifferential {
  Ray center, dx, dy;
};

/// The axis-aligned world box bounding a sample's footprint on a surface.
struct Footprint {
  Vec3 center{0.0f};      ///< Where the cell's centre ray meets the tangent plane.
  Vec3 half_width{0.0f};  ///< Half the box's sides; 0: no filtering.
};

/// The footprint of a cell on the tangent plane (point p, unit normal n) of a
/// hit: the parallelogram c + a * (px - c) + b * (py - c), a, b in [-1/2,
/// 1/2], where c, px and py are the three rays' hits on the plane, and its
/// bounding box. The offsets are projected onto the plane, so that a plane's
/// own axis (y on a floor) gets exactly 0 rather than rounding noise. When a
/// ray misses the plane (grazing angles, at the horizon) the footprint is the
/// point p itself (no filtering).
inline Footprint footprint(const RayDifferential& d, const Vec3& p, const Vec3& n) {
  auto on_plane = [&](const Ray& r, Vec3& out) {
    const float t = glm::dot(n, p - r.origin) / glm::dot(n, r.dir);
    if (!(t > 0.0f) || !std::isfinite(t)) return false;
    out = r.origin + t * r.dir - p;
    out -= glm::dot(out, n) * n;  // onto the plane
    return all_finite(out);
  };
  Vec3 c, ox, oy;
  if (!on_plane(d.center, c) || !on_plane(d.dx, ox) || !on_plane(d.dy, oy))
    return Footprint{p, Vec3(0.0f)};
  return Footprint{p + c, 0.5f * (glm::abs(ox - c) + glm::abs(oy - c))};
}

/// Moves a surface point p, whose computed position lies within +-p_error of the
/// exact one, along the geometric normal n just far enough that a ray leaving in
/// direction w cannot re-intersect the surface it starts on. Then rounds the
/// result one ulp further away. No global epsilon: the offset scales with the
/// error bound of the hit point (the approach of pbrt-v3/v4, written for RayScope).
inline Vec3 offset_ray_origin(const Vec3& p, const Vec3& p_error, const Vec3& n, const Vec3& w) {
  float d = glm::dot(glm::abs(n), p_error);
  Vec3 offset = d * n;
  if (glm::dot(w, n) < 0.0f) offset = -offset;
  Vec3 po = p + offset;
  for (int i = 0; i < 3; ++i) {
    if (offset[i] > 0.0f)
      po[i] = next_float_up(po[i]);
    else if (offset[i] < 0.0f)
      po[i] = next_float_down(po[i]);
  }
  return po;
}

/// A ray leaving a surface point in direction w.
inline Ray spawn_ray(const Vec3& p, const Vec3& p_error, const Vec3& n, const Vec3& w) {
  return Ray{offset_ray_origin(p, p_error, n, w), w, kInfinity};
}

/// A ray leaving a surface point toward `target` (e.g. a point light), stopping
/// at t = 1 exactly at the target.
inline Ray spawn_ray_to(const Vec3& p, const Vec3& p_error, const Vec3& n, const Vec3& target) {
  Vec3 o = offset_ray_origin(p, p_error, n, target - p);
  return Ray{o, target - o, 1.0f};
}

}  // namespace rayscope
