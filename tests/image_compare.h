// Image comparisons shared by the tests that render: PSNR and the count of
// differing pixels, both on display values (linear color clamped to [0, 1]
// and sRGB-encoded, what write_image() stores in a PNG).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "rayscope/image.h"

namespace rstest {

/// PSNR of two renders in dB (peak 1).
inline double psnr(const rayscope::Framebuffer& a, const rayscope::Framebuffer& b) {
  using rayscope::linear_to_srgb;
  double se = 0.0;
  for (size_t i = 0; i < a.color.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      double d = double(linear_to_srgb(std::clamp(a.color[i][c], 0.0f, 1.0f))) -
                 double(linear_to_srgb(std::clamp(b.color[i][c], 0.0f, 1.0f)));
      se += d * d;
    }
  double mse = se / double(3 * a.color.size());
  return mse == 0.0 ? std::numeric_limits<double>::infinity() : 10.0 * std::log10(1.0 / mse);
}

/// Pixels whose display value differs by more than 1/255 in some channel.
inline size_t pixels_differing(const rayscope::Framebuffer& a, const rayscope::Framebuffer& b) {
  using rayscope::linear_to_srgb;
  size_t n = 0;
  for (size_t i = 0; i < a.color.size(); ++i)
    for (int c = 0; c < 3; ++c)
      if (std::abs(linear_to_srgb(std::clamp(a.color[i][c], 0.0f, 1.0f)) -
                   linear_to_srgb(std::clamp(b.color[i][c], 0.0f, 1.0f))) > 1.0f / 255.0f) {
        ++n;
        break;
      }
  return n;
}

}  // namespace rstest
