#include "rayscope/ray_estimate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "rayscope/render_settings.h"
#include "rayscope/scene.h"

namespace rayscope {

RayEstimate estimate_rays(const Scene& scene, const RenderSettings& settings) {
  RayEstimate e;
  const double grid = double(settings.sample_grid());
  e.samples = double(settings.width) * double(settings.height) * grid * grid;
  e.lights = int(scene.lights.size());
  for (const Material& m : scene.materials) {
    e.branching = std::max(e.branching, m.refractive() ? 2 : m.reflective() ? 1 : 0);
    e.weight_sum = std::max(e.weight_sum, double(m.reflectivity) + double(m.transparency));
  }
  const double cutoff = double(settings.min_contribution);
  double level_rays = 1.0;    // b^k
  double level_weight = 1.0;  // s^k
  double tree = 1.0;          // the primary ray
  for (int k = 1; k <= settings.max_depth && e.branching > 0; ++k) {
    level_rays *= double(e.branching);
    level_weight *= e.weight_sum;
    if (cutoff > 0.0 && level_weight < cutoff) break;
    tree += cutoff > 0.0 ? std::min(level_rays, std::floor(level_weight / cutoff)) : level_rays;
    e.levels = k;
  }
  e.rays_per_sample = tree * double(1 + e.lights);
  e.rays = e.samples * e.rays_per_sample;
  return e;
}

std::string RayEstimate::text(const RenderSettings& s) const {
  char buf[384];
  std::snprintf(buf, sizeof buf,
                "up to %.3g rays: %dx%d pixels x %d samples x (1 + %d shadow rays per hit) x "
                "%.3g rays per sample (branching %d, %d of --max-depth %d levels above "
                "--min-contribution %g)",
                rays, s.width, s.height, s.sample_grid() * s.sample_grid(), lights,
                rays_per_sample / double(1 + lights), branching, levels, s.max_depth,
                double(s.min_contribution));
  return buf;
}

}  // namespace rayscope
