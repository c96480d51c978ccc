#include "rayscope/camera.h"

#include <cmath>
#include <stdexcept>

namespace rayscope {

void Camera::prepare(int width, int height) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("image size must be positive");
  if (!all_finite(eye) || !all_finite(look_at) || !all_finite(up))
    throw std::invalid_argument("camera vectors must be finite");
  Vec3 f = look_at - eye;
  if (f == Vec3(0.0f)) throw std::invalid_argument("eye and look_at coincide");
  // Rays start at eye and aim at points up to |f| away: beyond ~1.8e19 their
  // directions overflow (found by fuzz_scene_parser: 6e38 gave NaN rays).
  if (!std::isfinite(glm::dot(f, f)))
    throw std::invalid_argument("eye and look_at are too far apart");
  forward_ = glm::normalize(f);
  Vec3 r = glm::cross(forward_, up == Vec3(0.0f) ? up : normalize_any_length(up));
  if (r == Vec3(0.0f)) throw std::invalid_argument("up is zero or parallel to the view direction");
  right_ = normalize_any_length(r);
  up_ortho_ = glm::cross(right_, forward_);
  float aspect = float(width) / float(height);
  if (parallel) {
    if (!(parallel_scale > 0.0f)) throw std::invalid_argument("parallel_scale must be positive");
    half_height_ = parallel_scale;
  } else {
    if (!(vfov_degrees > 0.0f && vfov_degrees < 180.0f))
      throw std::invalid_argument("field of view must be in (0, 180) degrees");
    half_height_ = std::tan(0.5f * glm::radians(vfov_degrees));
  }
  half_width_ = half_height_ * aspect;
  inv_width_ = 1.0f / float(width);
  inv_height_ = 1.0f / float(height);
}

bool Camera::project(const Vec3& p, float& px, float& py) const {
  const Vec3 q = p - eye;
  float sx = glm::dot(q, right_), sy = glm::dot(q, up_ortho_);
  if (!parallel) {
    const float depth = glm::dot(q, forward_);  // the image plane is at distance 1
    if (!(depth > 0.0f)) return false;
    sx /= depth;
    sy /= depth;
  }
  px = 0.5f * (sx / half_width_ + 1.0f) / inv_width_;
  py = 0.5f * (1.0f - sy / half_height_) / inv_height_;
  return std::isfinite(px) && std::isfinite(py);
}

Camera frame_bounds(const Bounds3& bounds, float aspect, const Camera& view) {
  Vec3 center(0.0f);
  float radius = 1.0f;
  if (!bounds.empty()) {
    center = bounds.center();
    radius = 0.5f * glm::length(bounds.extent());
    if (radius == 0.0f) radius = 1.0f;
  }
  Vec3 dir = view.eye - view.look_at;
  dir = dir == Vec3(0.0f) ? Vec3(0.0f, 0.0f, 1.0f) : normalize_any_length(dir);
  Camera c = view;
  c.look_at = center;
  if (view.parallel) {
    // Half the image height; a tall image is narrower than it is high.
    c.parallel_scale = aspect < 1.0f ? radius / aspect : radius;
    c.eye = center + 2.0f * radius * dir;  // outside the sphere: nothing lies behind the eye
  } else {
    float half = 0.5f * glm::radians(view.vfov_degrees);
    if (aspect < 1.0f) half = std::atan(std::tan(half) * aspect);  // the horizontal half-angle
    c.eye = center + radius / std::sin(half) * dir;
  }
  return c;
}

}  // namespace rayscope
