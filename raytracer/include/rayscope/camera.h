// Central projection (lecture: "Central projection", "Primary rays"): a pinhole
// camera whose rays start at the eye and pass through the pixels of an image
// plane at distance 1. A parallel projection is available for VTK cameras.
#pragma once

#include "rayscope/math.h"
#include "rayscope/ray.h"

namespace rayscope {

struct Camera {
  Vec3 eye{0.0f, 0.0f, 5.0f};
  Vec3 look_at{0.0f};
  Vec3 up{0.0f, 1.0f, 0.0f};
  float vfov_degrees = 40.0f;   ///< Vertical field of view of the central projection.
  bool parallel = false;        ///< Parallel (orthographic) projection instead.
  float parallel_scale = 1.0f;  ///< Half the image height in world units when parallel.

  /// Precomputes the image-plane basis for an image of width x height pixels.
  /// Throws std::invalid_argument for a degenerate camera.
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

/// A camera that shows all of `bounds`, as VTK's vtkRenderer::ResetCamera does:
/// it looks at the center of the box from along `view`'s direction (eye - look_at,
/// +z if they coincide), keeps `view`'s up vector, field of view and projection,
/// and stands just far enough away (central projection) or zooms out just enough
/// (parallel projection) for the box's bounding sphere to fit the smaller of the
/// vertical and horizontal field of view of an image of width / height = aspect.
/// An empty box frames the unit sphere at the origin; a single point, the unit
/// sphere around it.
Camera frame_bounds(const Bounds3& bounds, float aspect, const Camera& view = Camera{});

}  // namespace rayscope
