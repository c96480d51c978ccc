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
