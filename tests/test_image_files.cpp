// Image files (image.h): a PNG is written by the core (libpng) without
// OpenImageIO; the other formats and reading go through the image-file
// module, which is not in a process that links the core until it is needed
// (its ~260 libraries once cost every RayScope program 0.35 s before main()).
// What is written reads back as written: 8-bit sRGB codes in PNG, every float
// channel in OpenEXR, a heat map's colors and legend.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <unistd.h>

#include "../raytracer/src/png_file.h"
#include "rayscope/image.h"

namespace {

using namespace rayscope;
namespace fs = std::filesystem;

// Whether a shared library whose file name contains `name` is mapped into
// this process.
bool library_loaded(const std::string& name) {
  std::ifstream maps("/proc/self/maps");
  std::string line;
  while (std::getline(maps, line))
    if (line.find(name) != std::string::npos) return true;
  return false;
}

fs::path scratch(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("rayscope_image_files_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / name;
}

Framebuffer gradient(int w, int h) {
  Framebuffer fb;
  fb.resize(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = fb.index(x, y);
      fb.color[i] = Color(float(x) / float(w - 1), float(y) / float(h - 1), 0.25f);
      fb.depth[i] = 1.0f + float(x + y);
      fb.normal[i] = Vec3(0.0f, 1.0f, 0.0f);
      fb.object_id[i] = float(x % 3);
    }
  return fb;
}

TEST(ImageFiles, APngIsWrittenWithoutOpenImageIO) {
  // This test program links the core and not OpenImageIO. A PNG is the
  // core's own (libpng); reading it back is OpenImageIO's, through the module.
  ASSERT_FALSE(library_loaded("libOpenImageIO")) << "loaded before any image was used";
  const fs::path png = scratch("gradient.png");
  const Framebuffer fb = gradient(16, 8);
  write_image(png, fb);
  EXPECT_FALSE(library_loaded("libOpenImageIO")) << "writing a PNG loaded OpenImageIO";
  EXPECT_FALSE(library_loaded("rayscope_image_files"));
  EXPECT_FALSE(image_needs_module(png));
  EXPECT_FALSE(image_needs_module("A.PNG"));
  EXPECT_TRUE(image_needs_module("a.exr"));
  EXPECT_TRUE(image_needs_module("a.jpg"));
  // Read back: the 8-bit sRGB code of each linear value, as write_image()
  // documents.
  int w = 0, h = 0;
  const std::vector<float> rgb = read_image_rgb(png, w, h);
  ASSERT_EQ(w, 16);
  ASSERT_EQ(h, 8);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) {
        const float code = std::round(255.0f * linear_to_srgb(fb.color[fb.index(x, y)][c]));
        EXPECT_EQ(std::round(255.0f * rgb[(size_t(y) * w + x) * 3 + c]), code)
            << x << "," << y << "," << c;
      }
  EXPECT_TRUE(library_loaded("libOpenImageIO"));
  EXPECT_TRUE(library_loaded("rayscope_image_files"));
  fs::remove_all(png.parent_path());
}

// The PNG's chunks: 8-bit RGB, tagged sRGB (with the gAMA and cHRM fallbacks
// that OpenImageIO's writer also wrote).
TEST(ImageFiles, APngIsEightBitRgbTaggedSrgb) {
  const fs::path png = scratch("tags.png");
  write_image(png, gradient(5, 3));
  std::ifstream f(png, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  ASSERT_GT(bytes.size(), 33u);
  EXPECT_EQ(bytes.substr(1, 3), "PNG");
  EXPECT_EQ(bytes.substr(12, 4), "IHDR");
  auto be32 = [&](size_t at) {
    return (uint32_t(uint8_t(bytes[at])) << 24) | (uint32_t(uint8_t(bytes[at + 1])) << 16) |
           (uint32_t(uint8_t(bytes[at + 2])) << 8) | uint32_t(uint8_t(bytes[at + 3]));
  };
  EXPECT_EQ(be32(16), 5u);
  EXPECT_EQ(be32(20), 3u);
  EXPECT_EQ(int(bytes[24]), 8);  // bit depth
  EXPECT_EQ(int(bytes[25]), 2);  // color type RGB
  for (const char* chunk : {"sRGB", "gAMA", "cHRM", "IDAT", "IEND"})
    EXPECT_NE(bytes.find(chunk), std::string::npos) << chunk;
  fs::remove_all(png.parent_path());
}

TEST(ImageFiles, ExrKeepsEveryFloatAndPreloadingChangesNothing) {
  preload_image_files();
  preload_image_files();  // a second call waits for nothing and loads nothing twice
  const fs::path exr = scratch("gradient.exr");
  const Framebuffer fb = gradient(9, 7);
  write_image(exr, fb);
  int w = 0, h = 0;
  const std::vector<float> rgb = read_image_rgb(exr, w, h);
  ASSERT_EQ(w, 9);
  ASSERT_EQ(h, 7);
  for (size_t i = 0; i < fb.color.size(); ++i)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(rgb[i * 3 + c], fb.color[i][c]) << i;
  fs::remove_all(exr.parent_path());
}

TEST(ImageFiles, HeatMapHasTheMapsColorsAndALegendBelow) {
  const fs::path png = scratch("heat.png");
  const int w = 40, h = 10;
  std::vector<float> values(size_t(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) values[size_t(y) * w + x] = float(x);
  write_heatmap(png, values, w, h, "test");
  int rw = 0, rh = 0;
  const std::vector<float> rgb = read_image_rgb(png, rw, rh);
  ASSERT_EQ(rw, w);
  ASSERT_GT(rh, h);  // the legend strip
  // The first and last columns: the map's ends (8-bit quantised).
  for (int x : {0, w - 1}) {
    const Color want = heat_color(float(x) / float(w - 1));
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(rgb[(size_t(h / 2) * w + x) * 3 + c], want[c], 0.5f / 255.0f + 1e-6f) << x;
  }
  fs::remove_all(png.parent_path());
}

TEST(ImageFiles, AFailedWriteNamesTheFileAndLeavesNothing) {
  const fs::path bad = scratch("gradient.notaformat");
  try {
    write_image(bad, gradient(4, 4));
    FAIL() << "an unknown format was written";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(bad.string() + ": ", 0), 0u) << e.what();
  }
  EXPECT_TRUE(fs::is_empty(bad.parent_path())) << "a temporary file was left";
  fs::remove_all(bad.parent_path());
}

TEST(ImageFiles, AFailedPngWriteNamesTheFileAndLeavesNothing) {
  if (::geteuid() == 0) GTEST_SKIP() << "root writes into read-only folders";
  const fs::path dir = scratch("readonly");
  fs::create_directories(dir);
  fs::permissions(dir, fs::perms::owner_read | fs::perms::owner_exec);
  const fs::path png = dir / "x.png";
  try {
    write_image(png, gradient(4, 4));
    FAIL() << "written into a read-only folder";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(png.string() + ": ", 0), 0u) << e.what();
  }
  fs::permissions(dir, fs::perms::owner_all);
  EXPECT_TRUE(fs::is_empty(dir));
  fs::remove_all(dir.parent_path());
}

// A PNG that cannot be completed (the disk is full: /dev/full takes the
// open and fails every write) is an error, not a short file called done.
TEST(ImageFiles, APngOnAFullDiskIsAnError) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const std::vector<unsigned char> rgb(64 * 64 * 3, 128);
  const std::string problem = write_png_rgb8("/dev/full", 64, 64, rgb.data(), true);
  EXPECT_NE(problem, "");
  EXPECT_EQ(write_png_rgb8(scratch("ok.png").string(), 64, 64, rgb.data(), true), "");
  fs::remove_all(scratch("ok.png").parent_path());
}

// srgb_byte() and srgb_bytes() (a table; the 8-bit colors of the VTK
// module's images) are std::lround(255 * linear_to_srgb(v)) for every float of
// [2^-16, 1] (2^27 of them), every 64th below, and outside [0, 1].
TEST(Srgb, BytesOfEveryFloat) {
  auto exact = [](float v) { return (unsigned char)std::lround(255.0f * linear_to_srgb(v)); };
  auto bits_of = [](float v) {
    uint32_t b;
    std::memcpy(&b, &v, sizeof b);
    return b;
  };
  const uint32_t low = bits_of(1.0f / 65536.0f), one = bits_of(1.0f);
  std::vector<float> values;  // converted a batch at a time by srgb_bytes()
  std::vector<unsigned char> bytes;
  uint64_t wrong = 0, wrong_in_batches = 0;
  auto convert_batch = [&] {
    bytes.assign(values.size(), 0);
    srgb_bytes(values.data(), values.size(), bytes.data());
    for (size_t k = 0; k < values.size(); ++k) wrong_in_batches += bytes[k] != exact(values[k]);
    values.clear();
  };
  for (uint32_t b = 0; b <= one; b += b < low ? 64 : 1) {
    float v;
    std::memcpy(&v, &b, sizeof v);
    wrong += srgb_byte(v) != exact(v);
    values.push_back(v);
    if (values.size() == 4099) convert_batch();  // not a multiple of any vector width
  }
  for (float v : {-0.0f, -1e-30f, -1.0f, 1.0f, 1.0000001f, 7.5f, INFINITY, -INFINITY, NAN}) {
    EXPECT_EQ(srgb_byte(v), exact(v)) << v;
    values.push_back(v);
  }
  convert_batch();
  EXPECT_EQ(wrong, 0u);
  EXPECT_EQ(wrong_in_batches, 0u);
}

// The table of the 256 sRGB bytes' linear values decodes each byte back to
// itself, and srgb_to_linear() inverts linear_to_srgb().
TEST(Srgb, ByteTableAndDecodingInvertTheEncoding) {
  const std::array<float, 256>& table = srgb_byte_table();
  for (int i = 0; i < 256; ++i) {
    EXPECT_EQ(table[size_t(i)], srgb_to_linear(float(double(i) / 255.0))) << i;
    EXPECT_EQ(srgb_byte(table[size_t(i)]), i) << i;
  }
  for (float v : {0.001f, 0.0031308f, 0.01f, 0.2f, 0.5f, 0.99f})
    EXPECT_NEAR(srgb_to_linear(linear_to_srgb(v)), v, 1e-6f * (1.0f + v)) << v;
  EXPECT_EQ(srgb_to_linear(-0.5f), 0.0f);
  EXPECT_EQ(srgb_to_linear(NAN), 0.0f);
  EXPECT_EQ(srgb_to_linear(1.5f), 1.0f);
}

}  // namespace
