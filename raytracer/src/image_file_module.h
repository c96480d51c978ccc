// What the core (image.cpp) hands the image-file module
// (image_file_module.cpp, built as librayscope_image_files.so). The module is
// the only code that links OpenImageIO. Debian's OpenImageIO pulls in about 260
// shared libraries (codecs, GDAL, OpenCV, DICOM...). Loading and relocating
// them took 0.35 s before main() on this project's machine, in every process
// that linked the core: more than the bunny scene's render. The core loads the
// module (dlopen) when an image is first read or written, or in the background
// from preload_image_files(). Front ends that never touch an image file (the
// VTK module, the ParaView plugin, `rayscope inspect`) never load it, and
// neither does a PNG file: the core writes those itself (png_file.h).
#pragma once

#include <string>
#include <vector>

namespace rayscope::image_files {

/// Pixels to write: interleaved channels, rows from the top.
struct Pixels {
  int width = 0, height = 0;
  std::vector<std::string> channel_names;  ///< One per channel.
  const void* data = nullptr;
  bool float_data = false;  ///< `data` holds floats, else 8-bit values.
  bool float_file = false;  ///< Stored as 32-bit floats, else 8-bit.
  int z_channel = -1;       ///< The depth channel, or -1.
  bool zip = false;         ///< Zip compression (OpenEXR).
  bool srgb = false;        ///< Tagged as sRGB.
};

/// Text drawn in black over the pixels before they are written.
struct Label {
  int x = 0, y = 0;  ///< The baseline's left end.
  std::string text;
  int size = 11;  ///< Font size in pixels.
};

/// The module's functions. Each returns "" on success, else the problem
/// (OpenImageIO's message); exceptions stay inside the module.
struct Functions {
  int version;
  /// Writes `px` to `file`, in the format its extension names. (PNG files
  /// are the core's own: png_file.h.)
  std::string (*write)(const std::string& file, const Pixels& px);
  /// Draws `labels` in black, in `font` (a TrueType file), over `rgb`:
  /// width x height pixels of 3 floats, rows from the top.
  std::string (*draw_text)(int width, int height, float* rgb, const std::vector<Label>& labels,
                           const std::string& font);
  /// Reads every channel of `file` as floats.
  std::string (*read)(const std::string& file, int& width, int& height, int& channels,
                      std::vector<float>& values);
  /// Writes `frames` (8-bit, all of one size) as the frames of one animated
  /// file (GIF) that loops, shown `fps_num / fps_den` frames per second.
  std::string (*write_frames)(const std::string& file, const std::vector<Pixels>& frames,
                              int fps_num, int fps_den);
};

/// Bumped whenever Pixels, Label or Functions change: a module of another
/// build is refused by name, not called.
inline constexpr int kVersion = 3;
/// The module's one exported symbol, extern "C": `const Functions* ()`.
inline constexpr const char* kEntrySymbol = "rayscope_image_files";
using EntryFn = const Functions* (*)();

}  // namespace rayscope::image_files
