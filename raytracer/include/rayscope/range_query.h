// Range queries (lecture: "Range Queries", "Range Query Algorithm"): which
// objects lie in a range. The lecture's one algorithm, for every hierarchy:
//
//   start at the root; if the range overlaps the node's bounding box, test the
//   node's primitives (report those within the range) and recurse into its
//   children; if it does not, end the recursion.
//
// Ray tracing is the special case where the ray is the range (sorted
// recursion, stop after the hit). This file holds the other ranges and their
// exact primitive tests; each structure writes the walk once, as
// `walk_range(range, prim, observer)` (Bvh, KdTree, SphereTree, ...), and the Aggregate
// (aggregate.h) runs the three queries through the chosen structure's walk:
//
// - box query: every object that intersects an axis-aligned box (closed; a
//   box of zero size is a point, a segment or a rectangle);
// - sphere query: every object within distance r of a point;
// - k nearest: the k objects nearest to a point, nearest first. It is the
//   sphere range whose radius shrinks to the k-th best distance found so far,
//   so the same walk serves it; visiting nearer children first makes it prune
//   early.
//
// Distances are exact point-object distances: 0 on or inside a sphere or a
// capsule (both solid here), the distance to the closest point of a
// triangle, the distance to a plane.
#pragma once

#include <algorithm>
#include <concepts>
#include <cstdint>
#include <vector>

#include "rayscope/math.h"

namespace rayscope {

// ---------------------------------------------------------------------------
// Exact tests. Computed in double from the float input, so that they are exact
// for every configuration that is exact in float (touching at a vertex, an
// edge or a face) up to the final rounding of a distance to float.
//
// What keeps every structure equal to brute force: a walk prunes a node by
// its box (the union of its primitives' bounds, or a cell that holds them), so
// a primitive's test must never accept what its own bounds reject. The box
// tests below therefore check the primitive's bounds first (exactly, as
// comparisons), and the distances are never below the distance to the
// primitive's bounds (the same mathematically; as rounded, the maximum of the
// two, since point_box_distance() is monotone in the box). The bounds are
// those Scene::commit() gives the builders: a triangle's vertices' minimum and
// maximum, a sphere's center -/+ radius, in float, a capsule's
// capsule_bounds() (intersect_capsule.h).

/// Distance from p to the closest point of the box (0 on or inside it). It
/// never grows when the box grows, also as rounded: for boxes a within b the
/// result for b is <= the result for a, bit for bit (every step is a monotone
/// rounding).
float point_box_distance(const Vec3& p, const Bounds3& box);

/// Distance from p to the closest point of triangle (a, b, c), never below
/// the distance to its bounds (see above).
float point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);
/// The distance itself: to the face if p projects inside the triangle, else
/// to the nearest edge. Degenerate triangles (a segment or a point) are their
/// edges.
float exact_point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

/// Distance from p to the solid ball: max(0, |p - center| - radius), never
/// below the distance to its bounds.
float point_sphere_distance(const Vec3& p, const Vec3& center, float radius);

/// Distance from p to the solid capsule around the segment p0 p1:
/// max(0, distance to the segment - radius), never below the distance to its
/// bounds. Exact up to double rounding (the segment's closest point).
float point_capsule_distance(const Vec3& p, const Vec3& p0, const Vec3& p1, float radius);

/// Distance from p to the plane through `point` with unit normal `normal`.
float point_plane_distance(const Vec3& p, const Vec3& point, const Vec3& normal);

/// Whether the triangle and the closed box share a point: the separating-axis
/// theorem (Akenine-Moeller) over the box's three axes, the triangle's normal
/// and the nine cross products of triangle edges and box axes; touching
/// counts. Degenerate triangles and boxes of zero size are exact too (the box
/// always contributes its three edge directions).
bool triangle_overlaps_box(const Vec3& a, const Vec3& b, const Vec3& c, const Bounds3& box);

/// Whether the solid ball and the closed box share a point: the box overlaps
/// the ball's bounds and the distance from the center to the box is at most
/// the radius.
bool sphere_overlaps_box(const Vec3& center, float radius, const Bounds3& box);

/// Whether the solid capsule around the segment p0 p1 and the closed box share
/// a point: the box overlaps the capsule's bounds (exact comparisons) and the
/// distance from the segment to the box is at most the radius. That distance
/// is the minimum of a convex piecewise quadratic along the segment (its
/// pieces end where a coordinate crosses a face's plane), found piece by
/// piece in double: exact up to double rounding, and exact where the nearest
/// point is an end of the segment (where it is the sphere's test).
bool capsule_overlaps_box(const Vec3& p0, const Vec3& p1, float radius, const Bounds3& box);

/// Whether the plane through `point` with unit normal `normal` crosses or
/// touches the closed box (the box's corners are not all strictly on one side).
bool plane_overlaps_box(const Vec3& point, const Vec3& normal, const Bounds3& box);

// Tests of a node's bounding sphere (sphere_tree.h), the one owner of how a
// range meets a ball. A walk prunes a node by them, so they must never reject
// what a primitive test inside the ball accepts. The primitives' own tests
// round to float (a sphere's distance to a box, a point-primitive distance),
// so these keep a margin of kBallSlack times the scale of the question
// (|p - center| + radius) on the accepting side: about 16 float roundings,
// far below anything a drawing or a count of visited nodes would show.

/// Relative margin of point_ball_distance() and ball_overlaps_box(): 2^-20.
inline constexpr double kBallSlack = 1.0 / 1048576.0;

/// Distance from p to the solid ball (0 on or inside it), lowered by the
/// margin and rounded down: never above the distance to anything inside it.
float point_ball_distance(const Vec3& p, const BoundingSphere& ball);

/// Whether the solid ball and the closed box share a point: the distance from
/// its center to the box (exact comparisons, squares in double) against the
/// radius raised by the margin.
bool ball_overlaps_box(const BoundingSphere& ball, const Bounds3& box);

// ---------------------------------------------------------------------------
// Ranges.

/// What every structure's walk_range takes. overlaps(box): whether the range
/// may hold something of the box (a walk enters a node exactly when this is
/// true for its box, and tests its primitives); distance(box): a lower bound
/// of the distance from the range's center to anything in the box, by which
/// a walk visits children nearer first; bounds(): an axis-aligned box that
/// contains the range (a structure may use it to find its cells). A range may
/// shrink while it is walked (KnnRange): overlaps() and bounds() then answer
/// for the current range, so a walk checks overlaps() again when it pops a node
/// it pushed earlier.
///
/// The same two questions for a ball (sphere_tree.h's nodes): overlaps(ball)
/// and distance(ball), through the ball tests above.
template <class R>
concept QueryRange = requires(const R& r, const Bounds3& box, const BoundingSphere& ball) {
  { r.overlaps(box) } -> std::same_as<bool>;
  { r.distance(box) } -> std::same_as<float>;
  { r.overlaps(ball) } -> std::same_as<bool>;
  { r.distance(ball) } -> std::same_as<float>;
  { r.bounds() } -> std::same_as<Bounds3>;
};

/// All objects that intersect a closed axis-aligned box.
class BoxRange {
 public:
  /// Throws std::invalid_argument unless the corners are finite and
  /// box.lo <= box.hi in every axis (lo == hi is fine: a box of zero size).
  explicit BoxRange(const Bounds3& box);
  static void check(const Bounds3& box);

  bool overlaps(const Bounds3& b) const {
    return b.lo.x <= box_.hi.x && b.hi.x >= box_.lo.x && b.lo.y <= box_.hi.y &&
           b.hi.y >= box_.lo.y && b.lo.z <= box_.hi.z && b.hi.z >= box_.lo.z;
  }
  float distance(const Bounds3& b) const { return point_box_distance(center_, b); }
  bool overlaps(const BoundingSphere& s) const { return ball_overlaps_box(s, box_); }
  float distance(const BoundingSphere& s) const { return point_ball_distance(center_, s); }
  Bounds3 bounds() const { return box_; }
  const Bounds3& box() const { return box_; }

 private:
  Bounds3 box_;
  Vec3 center_;
};

/// All objects within distance `radius` of `center` (closed: at exactly the
/// radius is within).
class SphereRange {
 public:
  /// Throws std::invalid_argument unless the center and the radius are finite
  /// and radius >= 0 (0: the objects that contain or touch the point).
  SphereRange(const Vec3& center, float radius);
  static void check(const Vec3& center, float radius);

  bool overlaps(const Bounds3& b) const { return point_box_distance(center_, b) <= radius_; }
  float distance(const Bounds3& b) const { return point_box_distance(center_, b); }
  bool overlaps(const BoundingSphere& s) const {
    return point_ball_distance(center_, s) <= radius_;
  }
  float distance(const BoundingSphere& s) const { return point_ball_distance(center_, s); }
  /// Rounded outward, so that it contains every point within the radius.
  Bounds3 bounds() const;
  const Vec3& center() const { return center_; }
  float radius() const { return radius_; }

 private:
  Vec3 center_;
  float radius_;
};

/// One object a range query found.
struct RangeHit {
  uint32_t prim = ~0u;    ///< Global primitive index; ~0u for a plane.
  int plane = -1;         ///< Index of the plane (Scene::planes), else -1.
  float distance = 0.0f;  ///< From the query point (sphere and k-nearest queries; 0 for boxes).
  bool operator==(const RangeHit&) const = default;
};

/// The order of sphere and k-nearest results: nearer first; at equal distance
/// primitives (by global index) before planes (by index). A strict total order
/// on distinct objects, so results never depend on the order of a walk.
inline bool nearer(const RangeHit& a, const RangeHit& b) {
  if (a.distance != b.distance) return a.distance < b.distance;
  if ((a.plane >= 0) != (b.plane >= 0)) return a.plane < 0;
  return a.plane >= 0 ? a.plane < b.plane : a.prim < b.prim;
}

/// The order of box results: primitives by global index, then planes.
inline bool before_in_box_order(const RangeHit& a, const RangeHit& b) {
  if ((a.plane >= 0) != (b.plane >= 0)) return a.plane < 0;
  return a.plane >= 0 ? a.plane < b.plane : a.prim < b.prim;
}

/// The k objects nearest to a point: a sphere range around it whose radius is
/// the distance of the k-th best object found so far (infinite until k are
/// found), so that it shrinks as the walk finds nearer objects. Ties at the
/// k-th distance are kept in the range (an object at that distance with a
/// lower index may still replace the k-th); the result is the first k objects
/// in the order nearer().
class KnnRange {
 public:
  /// Throws std::invalid_argument unless the point is finite and k >= 1. A k
  /// larger than the number of objects gives them all.
  KnnRange(const Vec3& center, uint32_t k);
  static void check(const Vec3& center, uint32_t k);

  bool overlaps(const Bounds3& b) const { return point_box_distance(center_, b) <= radius_; }
  float distance(const Bounds3& b) const { return point_box_distance(center_, b); }
  bool overlaps(const BoundingSphere& s) const {
    return point_ball_distance(center_, s) <= radius_;
  }
  float distance(const BoundingSphere& s) const { return point_ball_distance(center_, s); }
  Bounds3 bounds() const;
  const Vec3& center() const { return center_; }
  /// The current radius: the k-th best distance, or +inf while fewer than k
  /// objects were offered.
  float radius() const { return radius_; }

  /// Offers an object at its distance; returns whether it is now among the k
  /// best (it may be pushed out later).
  bool offer(const RangeHit& hit);
  /// The k best (fewer if fewer were offered), nearest first; ends the query.
  std::vector<RangeHit> take_sorted();

 private:
  Vec3 center_;
  uint32_t k_;
  float radius_ = kInfinity;
  std::vector<RangeHit> heap_;  ///< Max-heap by nearer(): the worst of the best at the front.
};

static_assert(QueryRange<BoxRange> && QueryRange<SphereRange> && QueryRange<KnnRange>);

}  // namespace rayscope
