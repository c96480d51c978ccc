// The lecture's cost of Whitted ray tracing, O(n * m * 2^r) for n pixels (and
// samples), m objects and recursion depth r, as a count: the most rays a
// render can trace, known before it starts. Front ends print it (rayscope
// render --explain) and warn before a render whose count exceeds kRayBudget.
#pragma once

#include <string>

namespace rayscope {

class Scene;
struct RenderSettings;

/// Worst-case rays above which a render is announced with a warning before it
/// starts: at the tens of millions of rays per second RayScope traces on a
/// few cores, 1e10 rays take minutes.
inline constexpr double kRayBudget = 1e10;

/// The most rays a render of a scene with given settings can trace, and what
/// drives the count.
///
/// Each primary sample starts a tree: a ray that hits a reflective material
/// spawns one reflection ray, a refractive one a reflection and a refraction
/// ray (branching b = 0, 1 or 2, the largest over the materials), up to
/// max_depth levels, and every ray that hits spawns one shadow ray per light.
/// A child's weight is its parent's times the material's reflection or
/// transmission factor, and a material's factors sum to at most s =
/// reflectivity + transparency (Fresnel splits the transparency), so the rays
/// of level k weigh at most s^k in all, none more than s^k: with the
/// contribution cutoff c > 0 (RenderSettings::min_contribution, a weight
/// within the sample) level k holds at most min(b^k, s^k / c) rays, and none
/// once s^k < c. The count is then samples x (1 + lights) x the sum over the
/// levels: every ray hitting, which real scenes never reach.
struct RayEstimate {
  double samples = 0;          ///< Primary rays: pixels x N x N (the adaptive grid's M x M).
  int lights = 0;              ///< Shadow rays per hit, at most.
  int branching = 0;           ///< b: secondary rays per hit, at most.
  double weight_sum = 0;       ///< s: the largest reflectivity + transparency.
  int levels = 0;              ///< Deepest level k that can hold a ray (<= max_depth).
  double rays_per_sample = 0;  ///< Rays of one sample's tree, shadow rays included.
  double rays = 0;             ///< samples x rays_per_sample.

  /// One line: the count, and the settings that drive it, e.g. "up to 3.7e+21
  /// rays: 307200 pixels x 4 samples x (1 + 2 shadow rays per hit) x 1.8e+19
  /// rays per sample (branching 2 to depth 64, min contribution 0)".
  std::string text(const RenderSettings& settings) const;
};

RayEstimate estimate_rays(const Scene& scene, const RenderSettings& settings);

}  // namespace rayscope
