// Progressive rendering: an N x N render in N^2 passes of one sample per
// pixel (RenderSettings::only_sample 0, 1, ..., N^2 - 1), shown after each,
// as a view refines its image while the camera rests. After the last pass the
// image is the N x N render bit for bit: render_pixel() sums a pixel's samples
// one by one in stratum order and scales the sum by 1 / N^2, and so does this
// image, pass after pass.
#pragma once

#include <vector>

#include "rayscope/image.h"
#include "rayscope/render_settings.h"
#include "rayscope/stats.h"

namespace rayscope {

class ProgressiveImage {
 public:
  /// Starts again, for passes of `settings` (its size and sample grid; any
  /// only_sample).
  void restart(const RenderSettings& settings);
  /// The settings of the next pass: `settings` with only_sample = passes().
  RenderSettings next_pass(const RenderSettings& settings) const;
  /// Adds a pass rendered with next_pass()'s settings. Pass 0 gives the AOVs
  /// (depth, normal and object id come from sample 0 in every render); cost
  /// counters, when the passes have them, are summed, as one render of all
  /// samples counts them.
  void add(const Framebuffer& pass, const RayCounters& counters = {});
  int passes() const { return passes_; }
  /// Passes in the whole render: N^2.
  int total() const { return total_; }
  bool complete() const { return passes_ > 0 && passes_ == total_; }
  /// The image so far: the mean of the passes' colors (the N x N render's
  /// colors once complete()), with pass 0's AOVs.
  const Framebuffer& image() const { return image_; }
  /// The counters of all passes so far.
  const RayCounters& counters() const { return counters_; }

 private:
  int passes_ = 0, total_ = 1;
  std::vector<Color> sum_;
  Framebuffer image_;
  RayCounters counters_;
};

}  // namespace rayscope
