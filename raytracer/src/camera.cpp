#include "rayscope/camera.h"

#include <cmath>
#include <stdexcept>

namespace rayscope {

namespace {

// The view direction and the (unnormalised) right vector of a camera, in
// float as the rays use them: camera_error() checks them and prepare() keeps
// them, so what one accepts the other can use. Right is zero when up is zero
// or parallel to the view direction.
struct ViewBasis {
  Vec3 view, forward, right;
};
ViewBasis view_basis(const DVec3& eye, const DVec3& look_at, const DVec3& up) {
  ViewBasis b;
  b.view = Vec3(look_at - eye);
  b.forward = glm::normalize(b.view);
  const Vec3 u(up);
  b.right = glm::cross(b.forward, u == Vec3(0.0f) ? u : normalize_any_length(u));
  return b;
}

bool finite_d(const DVec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

std::string camera_error(const DVec3& eye, const DVec3& look_at, const DVec3& up,
                         double vfov_degrees, bool parallel, double parallel_scale,
                         const CameraNames& n) {
  using std::string;
  // up is used in float; eye and look_at only by their difference (a scene
  // far from the origin is rendered in local coordinates, Scene::origin).
  if (!finite_d(eye) || !finite_d(look_at) || !all_finite(Vec3(up)))
    return string(n.eye) + ", " + n.look_at + " and " + n.up + " must be finite";
  // Rays start at eye and aim at points up to |look_at - eye| away: beyond
  // ~1.8e19 their directions overflow float (found by fuzz_scene_parser: 6e38
  // gave NaN rays).
  const ViewBasis b = view_basis(eye, look_at, up);
  if (b.view == Vec3(0.0f)) return string(n.eye) + " and " + n.look_at + " coincide";
  if (!std::isfinite(glm::dot(b.view, b.view)))
    return string(n.eye) + " and " + n.look_at + " are too far apart";
  if (b.right == Vec3(0.0f)) return string(n.up) + " is zero or parallel to the view direction";
  // Both are used in float: checked as float, so that a double too small or
  // too large for float is refused here rather than rendered degenerate.
  if (parallel) {
    const float s = float(parallel_scale);
    if (!(std::isfinite(s) && s > 0.0f))
      return string(n.parallel_scale) + " must be finite and > 0";
  } else {
    const float f = float(vfov_degrees);
    if (!(f > float(kMinFovDegrees) && f < float(kMaxFovDegrees)))
      return string(n.fov) + " must be in (0, 180) degrees";
  }
  return {};
}

void Camera::prepare(int width, int height) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("image size must be positive");
  if (std::string e = camera_error(DVec3(eye), DVec3(look_at), DVec3(up), vfov_degrees, parallel,
                                   parallel_scale);
      !e.empty())
    throw std::invalid_argument(e);
  const ViewBasis b = view_basis(DVec3(eye), DVec3(look_at), DVec3(up));
  forward_ = b.forward;
  right_ = normalize_any_length(b.right);
  up_ortho_ = glm::cross(right_, forward_);
  float aspect = float(width) / float(height);
  half_height_ = parallel ? parallel_scale : std::tan(0.5f * glm::radians(vfov_degrees));
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

CameraFit fit_bounds(const DVec3& lo, const DVec3& hi, const DVec3& eye, const DVec3& look_at,
                     const DVec3& up, double vfov_degrees, double aspect) {
  CameraFit c;
  double radius = 1.0;
  c.look_at = DVec3(0.0);
  if (!(lo.x > hi.x || lo.y > hi.y || lo.z > hi.z)) {
    c.look_at = 0.5 * (lo + hi);
    radius = 0.5 * glm::length(hi - lo);
    if (radius == 0.0) radius = 0.5;
  }
  DVec3 dir = eye - look_at;
  const double len = glm::length(dir);
  dir = len > 0.0 ? dir / len : DVec3(0.0, 0.0, 1.0);
  c.up = up;
  if (!(glm::length(glm::cross(dir, up)) > kMinFitUpCross))
    c.up = std::abs(dir.y) > 0.999 ? DVec3(0.0, 0.0, -1.0) : DVec3(0.0, 1.0, 0.0);
  double half = 0.5 * glm::radians(vfov_degrees);
  c.parallel_scale = radius;
  if (aspect < 1.0) {
    // A tall image: its horizontal field of view is the narrower one.
    half = std::atan(std::tan(half) * aspect);
    c.parallel_scale = radius / aspect;
  }
  c.eye = c.look_at + radius / std::sin(half) * dir;
  return c;
}

Camera frame_bounds(const Bounds3& bounds, float aspect, const Camera& view) {
  const CameraFit f = fit_bounds(DVec3(bounds.lo), DVec3(bounds.hi), DVec3(view.eye),
                                 DVec3(view.look_at), DVec3(view.up), view.vfov_degrees, aspect);
  Camera c = view;
  c.eye = Vec3(f.eye);
  c.look_at = Vec3(f.look_at);
  c.up = Vec3(f.up);
  c.parallel_scale = float(f.parallel_scale);
  return c;
}

}  // namespace rayscope
