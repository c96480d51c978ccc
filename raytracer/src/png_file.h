// PNG files of 8-bit RGB pixels through libpng, in the core itself. A PNG is
// what `rayscope render` writes by default, and loading OpenImageIO's module
// for it (image_file_module.h) cost a bunny render at 800x600 0.33 s of its
// 0.63 s wall time on the project's two-core machine (docs/performance.md):
// libpng is one small library the core loads at start-up. Every PNG RayScope
// writes goes through here; OpenImageIO writes the other formats and draws
// the heat maps' text.
#pragma once

#include <string>

namespace rayscope {

/// Writes `rgb` (width x height pixels, 3 bytes each, rows from the top) to
/// `file` as an 8-bit RGB PNG. `srgb` tags it as sRGB (the sRGB chunk with its
/// gAMA and cHRM fallbacks). Returns "" on success, else the problem.
std::string write_png_rgb8(const std::string& file, int width, int height, const unsigned char* rgb,
                           bool srgb);

}  // namespace rayscope
