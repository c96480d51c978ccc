// Color conventions of RayScope's VTK side.
//
// VTK colors are display values: vtkProperty colors, background colors, lookup
// table entries and the unsigned char colors a mapper produces are sRGB-encoded
// (the framebuffer shows them as they are). The core works in linear RGB. Every
// color entering the core is decoded with the sRGB transfer function, every
// color leaving it (the "Color" image array) is encoded back and rounded as
// RayScope's PNG writer rounds: lround(255 * linear_to_srgb(c)). An unlit color
// (ambient 1, diffuse 0, white ambient light) therefore comes out as the very
// byte VTK shows, up to one rounding step.
#pragma once

#include <array>
#include <cmath>

namespace rayscope_vtk {

/// sRGB-encoded value in [0, 1] -> linear.
inline float srgb_to_linear(double v) {
  float s = float(v);
  if (!(s > 0.0f)) return 0.0f;
  if (s >= 1.0f) return 1.0f;
  return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
}

/// The linear values of the 256 sRGB bytes.
inline const std::array<float, 256>& srgb_byte_table() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[size_t(i)] = srgb_to_linear(double(i) / 255.0);
    return t;
  }();
  return table;
}

}  // namespace rayscope_vtk
