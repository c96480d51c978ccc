// Central projection (lecture: "Central projection", "Primary rays"): a pinhole
// camera whose rays start at the eye and pass through the pixels of an image
// plane at distance 1. A parallel projection is available for VTK cameras.
#pragma once

#include <string>

#include "rayscope/math.h"
#include "rayscope/ray.h"

namespace rayscope {

/// The field of view of a central projection, in degrees, lies strictly
/// between these.
inline constexpr double kMinFovDegrees = 0.0;
inline constexpr double kMaxFovDegrees = 180.0;

/// How camera_error() names the camera's values: the core's names by default;
/// the VTK module passes its property names (Position, FocalPoint, ...).
struct CameraNames {
  const char* eye = "eye";
  const char* look_at = "look_at";
  const char* up = "up";
  const char* fov = "field of view";
  const char* parallel_scale = "parallel_scale";
};

/// What is wrong with a camera, in words, or "" for a camera Camera::prepare()
/// accepts: finite vectors, eye and look_at apart (and close enough that the
/// rays' directions stay finite in float), an up vector not parallel to the
/// view direction, a field of view in (kMinFovDegrees, kMaxFovDegrees) for a
/// central projection and a finite parallel_scale > 0 for a parallel one.
/// The values are double so that cameras far from the origin (VTK's, or a
/// scene file's before it is made scene-local) are checked without rounding;
/// the view direction and up vector are checked as float, as the rays use them.
std::string camera_error(const DVec3& eye, const DVec3& look_at, const DVec3& up,
                         double vfov_degrees, bool parallel, double parallel_scale,
                         const CameraNames& names = {});

struct Camera {
  Vec3 eye{0.0f, 0.0f, 5.0f};
  Vec3 look_at{0.0f};
  Vec3 up{0.0f, 1.0f, 0.0f};
  float vfov_degrees = 40.0f;   ///< Vertical field of view of the central projection.
  bool parallel = false;        ///< Parallel (orthographic) projection instead.
  float parallel_scale = 1.0f;  ///< Half the image height in world units when parallel.

  /// Precomputes the image-plane basis for an image of width x height pixels.
  /// Throws std::invalid_argument for an image size < 1 or a camera that
  /// camera_error() refuses, with its message.
  void prepare(int width, int height);

  /// The primary ray through the image-plane point (px, py), in pixel units with
  /// (0, 0) at the top-left corner of the image and (w, h) at the bottom-right.
  Ray generate_ray(float px, float py) const {
    float sx = (2.0f * px * inv_width_ - 1.0f) * half_width_;
    float sy = (1.0f - 2.0f * py * inv_height_) * half_height_;
    if (parallel) return Ray{eye + sx * right_ + sy * up_ortho_, forward_, kInfinity};
    return Ray{eye, forward_ + sx * right_ + sy * up_ortho_, kInfinity};
  }

  /// The rays bounding the footprint of the image-plane cell of side `side`
  /// (in pixels) centred on (cx, cy): through the centre, and one side to the
  /// right and below.
  RayDifferential generate_differential(float cx, float cy, float side) const {
    return RayDifferential{generate_ray(cx, cy), generate_ray(cx + side, cy),
                           generate_ray(cx, cy + side)};
  }

  /// The inverse of generate_ray(): the image-plane point (px, py), in pixel
  /// units, whose primary ray passes through p. False for a point not in
  /// front of the camera (central projection: at or behind the eye's plane).
  bool project(const Vec3& p, float& px, float& py) const;

  const Vec3& forward() const { return forward_; }
  const Vec3& right() const { return right_; }
  const Vec3& up_vector() const { return up_ortho_; }

 private:
  Vec3 forward_{0.0f, 0.0f, -1.0f}, right_{1.0f, 0.0f, 0.0f}, up_ortho_{0.0f, 1.0f, 0.0f};
  float half_width_ = 1.0f, half_height_ = 1.0f;
  float inv_width_ = 1.0f, inv_height_ = 1.0f;
};

/// A view fitted to a box, in double so that data far from the origin keeps
/// its precision (fit_bounds()).
struct CameraFit {
  DVec3 eye, look_at, up;
  double parallel_scale;
};

/// fit_bounds() replaces the up vector when |cross(view direction, up)| is at
/// most this (the view direction a unit vector, up as given): the camera would
/// have no usable right vector.
inline constexpr double kMinFitUpCross = 1e-6;

/// The view that shows all of the box [lo, hi], as VTK's vtkRenderer::ResetCamera
/// places it: it looks at the center of the box from along the view direction
/// eye - look_at (+z if they coincide), at the distance r / sin(a / 2) where r
/// is the radius of the box's bounding sphere and a the vertical field of view
/// (narrowed to the horizontal one for an image of width / height = aspect < 1;
/// pass aspect 1 to fit the vertical field of view alone), and parallel_scale
/// is r (r / aspect when aspect < 1), which fits the sphere to a parallel
/// projection. The up vector is kept unless it is (nearly) parallel to the view
/// direction (kMinFitUpCross); it is then +y, or -z when the view is along y.
/// A box of one point is framed with r = 0.5, as ResetCamera does; an empty box
/// (lo > hi on some axis), the unit sphere at the origin. The one fit of the
/// core (frame_bounds) and of the VTK module (ResetCamera, AutoCamera).
CameraFit fit_bounds(const DVec3& lo, const DVec3& hi, const DVec3& eye, const DVec3& look_at,
                     const DVec3& up, double vfov_degrees, double aspect);

/// fit_bounds() for a float box and camera: `view` with the fitted eye,
/// look_at, up and parallel_scale.
Camera frame_bounds(const Bounds3& bounds, float aspect, const Camera& view = Camera{});

}  // namespace rayscope
