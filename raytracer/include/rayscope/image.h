// The framebuffer (color plus AOVs) and image files: PNG through libpng, in
// the core (src/png_file.h), the other formats through OpenImageIO. OpenImageIO
// lives in a module the core loads on first use (src/image_file_module.h), not
// in every program that links the core: its libraries took longer to load
// than the bunny scene takes to render.
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "rayscope/math.h"
#include "rayscope/stats.h"

namespace rayscope {

/// Linear RGB color plus arbitrary output variables (AOVs) of the first sample
/// of each pixel: distance along the primary ray to the first hit (inf on a
/// miss), unit shading normal (0 on a miss), object id (-1 on a miss).
struct Framebuffer {
  int width = 0, height = 0;
  std::vector<Color> color;
  std::vector<float> depth;
  std::vector<Vec3> normal;
  std::vector<float> object_id;
  std::vector<PixelCost> cost;  ///< Per-pixel traversal cost; empty unless statistics were on.
  /// Samples each pixel took; empty unless adaptive sampling was on.
  std::vector<float> samples;

  /// A w x h image cleared to the background (no hit): color 0, depth
  /// infinity, normal 0, object id -1; no cost or sample counts. Storage is
  /// kept for a framebuffer reused frame after frame.
  void resize(int w, int h);
  size_t index(int x, int y) const { return size_t(y) * size_t(width) + size_t(x); }
};

/// Linear to sRGB transfer function on [0, 1].
float linear_to_srgb(float v);

/// sRGB to linear transfer function on [0, 1] (linear_to_srgb's inverse;
/// values outside [0, 1] are clamped, NaN gives 0): display colors such as
/// VTK's (vtkProperty colors, lookup tables) are sRGB-encoded.
float srgb_to_linear(float v);

/// The linear values of the 256 8-bit sRGB values: srgb_to_linear(i / 255).
const std::array<float, 256>& srgb_byte_table();

/// The 8-bit sRGB value of a linear color component, exactly
/// std::lround(255 * linear_to_srgb(v)) (0 for NaN), from a table made once
/// from that function: the byte grows with v, so each byte has a smallest
/// linear value, and v's float bits (top 16) find the byte to start from.
/// About ten times faster than the power function it replaces.
unsigned char srgb_byte(float linear);

/// srgb_byte() of `n` values: out[k] = srgb_byte(linear[k]), with the table
/// looked up once (a whole image's colors).
void srgb_bytes(const float* linear, size_t n, unsigned char* out);

/// Writes the framebuffer. The format follows the extension: .png (8-bit sRGB,
/// color only; written by the core through libpng, without the module), .exr (32-bit float, linear
/// color plus Z, N.x/N.y/N.z and objectId channels, plus cost.rays/cost.nodes/cost.boxes/cost.prims
/// when the framebuffer has cost AOVs and `samples` when it has sample counts), .jpg or .jpeg
/// (8-bit sRGB color, through OpenImageIO). The file is written under a temporary name in the same
/// folder and renamed, so an interrupted run never leaves a half-written file. Throws
/// std::runtime_error. check_image_path() runs first.
void write_image(const std::filesystem::path& path, const Framebuffer& fb);

/// The image formats write_image() writes, by extension (lower case), and
/// the same as text for messages and help.
inline constexpr const char* kImageExtensions[] = {".png", ".jpg", ".jpeg", ".exr"};
inline constexpr const char* kImageFormatsText = ".png, .jpg (.jpeg) or .exr";

/// The one check of an output image path, before anything is loaded,
/// rendered or written: not an existing directory or other non-regular file
/// (a device such as /dev/full), an extension of kImageExtensions, an
/// existing folder in which this process may create a file (a read-only file
/// system fails here whoever runs it; permissions for all but root). Throws
/// std::runtime_error
/// "PATH: problem".
void check_image_path(const std::filesystem::path& path);

/// An 8-bit RGB picture, rows from the top (a frame of an animation).
struct Rgb8Image {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;  ///< width * height * 3 values.
};

/// The animation format write_animation() writes.
inline constexpr const char* kAnimationExtension = ".gif";
/// Frames per second an animation may show (write_animation()).
inline constexpr double kMinAnimationFps = 0.1, kMaxAnimationFps = 50.0;

/// The one check of an animation's output: check_image_path()'s checks of
/// the path, with the extension kAnimationExtension, and a rate of `fps`
/// frames per second in kMinAnimationFps..kMaxAnimationFps. Throws
/// std::runtime_error "PATH: problem".
void check_animation(const std::filesystem::path& path, double fps);

/// Writes `frames` (at least one, all of one size) as an animated GIF that
/// loops, `fps` frames per second (GIF keeps a frame's time in hundredths of
/// a second), through OpenImageIO, after check_animation(). Atomic like
/// write_image(). Throws std::runtime_error "PATH: problem".
void write_animation(const std::filesystem::path& path, const std::vector<Rgb8Image>& frames,
                     double fps);

/// Writes a color-mapped heat map of one value per pixel (e.g. BVH nodes visited)
/// with a legend strip below it: a color bar from 0 to the maximum, its scale and
/// `title`. Atomic like write_image(). Legend text needs the DejaVu Sans font
/// (Debian's fonts-dejavu-core); without it the bar is drawn without labels.
void write_heatmap(const std::filesystem::path& path, const std::vector<float>& values, int width,
                   int height, const std::string& title);

/// The heat map's color for t in [0, 1] (a perceptually ordered map, dark blue
/// through green to yellow).
Color heat_color(float t);

/// Whether writing `path` loads the image-file module (OpenImageIO): every
/// format but PNG, which the core writes itself. A heat map's legend text
/// loads it too.
bool image_needs_module(const std::filesystem::path& path);

/// Starts loading the image-file module (OpenImageIO) on a thread of its own
/// and returns at once, so that a program that will write an image can load
/// the module while it reads its scene and builds the BVH. Optional: the
/// first read or write loads it otherwise. A module that cannot be loaded is
/// reported by that read or write (set RAYSCOPE_IMAGE_MODULE to load another
/// copy of the module than the build tree's or the installed one).
void preload_image_files();

/// Reads an image's first three channels as floats (as stored: sRGB values for
/// 8-bit formats). Throws std::runtime_error.
std::vector<float> read_image_rgb(const std::filesystem::path& path, int& width, int& height);

}  // namespace rayscope
