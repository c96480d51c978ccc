#include "rayscope/progressive.h"

#include <stdexcept>
#include <string>

namespace rayscope {

void ProgressiveImage::restart(const RenderSettings& settings) {
  const int n = settings.sample_grid();
  passes_ = 0;
  total_ = n * n;
  sum_.assign(size_t(settings.width) * size_t(settings.height), Color(0.0f));
  image_ = Framebuffer{};
  counters_ = RayCounters{};
}

RenderSettings ProgressiveImage::next_pass(const RenderSettings& settings) const {
  RenderSettings pass = settings;
  pass.only_sample = passes_;
  return pass;
}

void ProgressiveImage::add(const Framebuffer& pass, const RayCounters& counters) {
  if (complete()) throw std::logic_error("ProgressiveImage::add: all passes are in");
  if (pass.color.size() != sum_.size())
    throw std::invalid_argument("ProgressiveImage::add: a pass of " +
                                std::to_string(pass.color.size()) + " pixels, the image has " +
                                std::to_string(sum_.size()));
  if (passes_ == 0) {
    image_ = pass;
  } else if (!image_.cost.empty() && pass.cost.size() == image_.cost.size()) {
    for (size_t i = 0; i < pass.cost.size(); ++i) {
      PixelCost& c = image_.cost[i];
      const PixelCost& p = pass.cost[i];
      c.rays += p.rays;
      c.nodes += p.nodes;
      c.boxes += p.boxes;
      c.prims += p.prims;
      c.culled += p.culled;
    }
  }
  for (size_t i = 0; i < sum_.size(); ++i) sum_[i] += pass.color[i];
  counters_ += counters;
  ++passes_;
  // The weight render_pixel() gives the sum of all N^2 samples, computed as it
  // computes it; before that, the mean of the samples so far.
  const Color scale = complete() ? Color(1.0f / float(total_)) : Color(1.0f / float(passes_));
  for (size_t i = 0; i < sum_.size(); ++i) image_.color[i] = sum_[i] * scale;
}

}  // namespace rayscope
