#include "rayscope/image.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <future>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <system_error>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/tbb_allocator.h>

#include <dlfcn.h>
#include <fcntl.h>
#include <unistd.h>

#include "image_file_module.h"
#include "png_file.h"
#include "rayscope/input_file.h"

namespace rayscope {

void Framebuffer::resize(int w, int h) {
  width = w;
  height = h;
  size_t n = size_t(w) * size_t(h);
  color.assign(n, Color(0.0f));
  depth.assign(n, kInfinity);
  normal.assign(n, Vec3(0.0f));
  object_id.assign(n, -1.0f);
  cost.clear();
  samples.clear();
}

float linear_to_srgb(float v) {
  if (!(v > 0.0f)) return 0.0f;
  if (v >= 1.0f) return 1.0f;
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

float srgb_to_linear(float s) {
  if (!(s > 0.0f)) return 0.0f;
  if (s >= 1.0f) return 1.0f;
  return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
}

const std::array<float, 256>& srgb_byte_table() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[size_t(i)] = srgb_to_linear(float(double(i) / 255.0));
    return t;
  }();
  return table;
}

namespace {

unsigned char srgb_byte_exact(float v) {
  return (unsigned char)std::lround(255.0f * linear_to_srgb(v));
}

float float_of(uint32_t bits) {
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

// srgb_byte()'s table. srgb_byte_exact() never decreases as v grows (checked
// once on all 1,065,353,217 floats of [0, 1]), so byte b is the one of every
// v in [threshold[b], threshold[b + 1]). Srgb.BytesOfEveryFloat
// compares srgb_byte() with srgb_byte_exact() on every float of [2^-16, 1].
struct SrgbTable {
  static constexpr uint32_t kOne = 0x3f800000u;  // the bits of 1.0f
  float threshold[257];
  std::vector<unsigned char> start;  // the byte of the first float of each 2^16 bits
  SrgbTable() {
    threshold[0] = 0.0f;
    for (int b = 1; b < 256; ++b) {  // the smallest float of (0, 1] whose byte is b or more
      uint32_t lo = 0, hi = kOne;
      while (lo < hi) {
        const uint32_t mid = lo + (hi - lo) / 2;
        if (srgb_byte_exact(float_of(mid)) >= b)
          hi = mid;
        else
          lo = mid + 1;
      }
      threshold[b] = float_of(lo);
    }
    threshold[256] = std::numeric_limits<float>::infinity();
    start.resize((kOne >> 16) + 1);
    for (uint32_t k = 0; k < start.size(); ++k) start[k] = srgb_byte_exact(float_of(k << 16));
  }

  unsigned char byte(float v) const {
    if (!(v > 0.0f)) return 0;  // NaN too
    if (v >= 1.0f) return 255;
    uint32_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    unsigned b = start[bits >> 16];
    while (v >= threshold[b + 1]) ++b;
    return (unsigned char)b;
  }
};

const SrgbTable& srgb_table() {
  static const SrgbTable table;
  return table;
}

}  // namespace

unsigned char srgb_byte(float v) {
  return srgb_table().byte(v);
}

void srgb_bytes(const float* linear, size_t n, unsigned char* out) {
  const SrgbTable& table = srgb_table();
  for (size_t k = 0; k < n; ++k) out[k] = table.byte(linear[k]);
}

namespace {

namespace fs = std::filesystem;
using image_files::Functions;

// Loads the image-file module (image_file_module.h): RAYSCOPE_IMAGE_MODULE
// when it is set, else the build tree's copy, else the installed one. Throws
// std::runtime_error naming the module and the problem.
const Functions* load_image_module() {
  std::vector<std::string> paths;
  if (const char* env = std::getenv("RAYSCOPE_IMAGE_MODULE"); env && *env)
    paths = {env};
  else
    paths = {RAYSCOPE_IMAGE_MODULE_BUILD_PATH, RAYSCOPE_IMAGE_MODULE_INSTALL_PATH};
  std::error_code ec;
  const auto found = std::find_if(paths.begin(), paths.end(),
                                  [&](const std::string& p) { return fs::exists(p, ec); });
  if (found == paths.end())
    throw std::runtime_error("the image module " + paths.front() + " is missing");
  void* handle = dlopen(found->c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* why = dlerror();
    throw std::runtime_error("cannot load the image module " + *found + " (" +
                             (why ? why : "unknown error") + ")");
  }
  const auto entry =
      reinterpret_cast<image_files::EntryFn>(dlsym(handle, image_files::kEntrySymbol));
  const Functions* f = entry ? entry() : nullptr;
  if (!f || f->version != image_files::kVersion)
    throw std::runtime_error(*found + " is not this build's image module");
  return f;
}

// The module, loading on a thread of its own from the first call on.
const std::shared_future<const Functions*>& image_module_loading() {
  static const std::shared_future<const Functions*> loading =
      std::async(std::launch::async, load_image_module).share();
  return loading;
}

// The loaded module; a failure to load it names `file`, the image at hand.
const Functions& image_module(const fs::path& file) {
  try {
    return *image_module_loading().get();
  } catch (const std::exception& e) {
    throw std::runtime_error(file.string() + ": " + e.what());
  }
}

// Runs `write_to(temporary)` (returning "" or the problem) on a temporary
// file in the folder of `path`, with its extension, then renames it over
// `path`: an interrupted or failed write never leaves a half-written file.
void write_atomically(const fs::path& path,
                      const std::function<std::string(const std::string&)>& write_to) {
  static std::atomic<unsigned> counter{0};
  const fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  std::string name(".");  // built by appending: GCC 12 warns (-Wrestrict) on "." + string
  name += path.stem().string();
  name += ".tmp" + std::to_string(::getpid()) + "_" + std::to_string(counter++);
  name += path.extension().string();
  const fs::path tmp = dir / name;
  std::error_code ec;
  if (const std::string problem = write_to(tmp.string()); !problem.empty()) {
    fs::remove(tmp, ec);
    throw std::runtime_error(path.string() + ": " + problem);
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw std::runtime_error(path.string() + ": cannot rename temporary file: " + ec.message());
  }
}

// Writes `px`, 8-bit RGB or floats, atomically: a PNG by the core itself
// (png_file.h), any other format through the module.
void write_pixels(const fs::path& path, const image_files::Pixels& px) {
  if (!image_needs_module(path)) {
    write_atomically(path, [&](const std::string& tmp) {
      return write_png_rgb8(tmp, px.width, px.height, static_cast<const unsigned char*>(px.data),
                            px.srgb);
    });
    return;
  }
  const Functions& m = image_module(path);
  write_atomically(path, [&](const std::string& tmp) { return m.write(tmp, px); });
}

// 8-bit codes of values in [0, 1], rounded to nearest as OpenImageIO converts.
std::vector<unsigned char> to_codes(const std::vector<float>& values) {
  std::vector<unsigned char> codes(values.size());
  for (size_t i = 0; i < values.size(); ++i)
    codes[i] = (unsigned char)std::lround(255.0f * std::clamp(values[i], 0.0f, 1.0f));
  return codes;
}

}  // namespace

void preload_image_files() {
  // dlopen() holds the dynamic loader's lock for the whole load, so a dlopen()
  // on this thread would wait for the module. TBB makes two on first use (its
  // memory allocator, through tbb_allocator, and its thread server), which
  // VTK's readers and the BVH build reach: made here, before the load starts.
  tbb::tbb_allocator<char> allocator;
  allocator.deallocate(allocator.allocate(1), 1);
  tbb::parallel_for(0, 2, [](int) {});
  image_module_loading();
}

bool image_needs_module(const std::filesystem::path& path) {
  return lower_extension(path) != ".png";
}

namespace {

// The one check of an output file's path (check_image_path(),
// check_animation_path()): `extensions` are the ones allowed, `formats` says
// them in a message.
void check_output_path(const std::filesystem::path& path, std::span<const char* const> extensions,
                       const char* formats) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const std::string p = path.string();
  const fs::file_status st = fs::status(path, ec);
  if (fs::is_directory(st)) throw std::runtime_error(p + ": is a directory, not an image file");
  // An existing device, pipe or socket (/dev/full, /dev/stdout) would be
  // replaced by the atomic rename, or fail only once the render is done.
  if (fs::exists(st) && !fs::is_regular_file(st))
    throw std::runtime_error(p + ": exists and is not a regular file");
  const std::string ext = lower_extension(path);
  if (std::find(extensions.begin(), extensions.end(), ext) == extensions.end())
    throw std::runtime_error(p + ": " +
                             (ext.empty() ? std::string("no file extension")
                                          : "unsupported image format '" + ext + "'") +
                             " (use " + formats + ")");
  const fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  if (!fs::is_directory(dir, ec))
    throw std::runtime_error(p + ": folder '" + dir.string() + "' does not exist");
  // Whether this process may create files in the folder, asked of the
  // kernel with the effective ids (as the write will run): a read-only file
  // system fails for everyone (EROFS), permissions for all but root. No file
  // is made: a probe file would show up beside concurrent writers' outputs.
  if (::faccessat(AT_FDCWD, dir.c_str(), W_OK | X_OK, AT_EACCESS) != 0)
    throw std::runtime_error(p + ": cannot create a file in '" + dir.string() +
                             "': " + std::strerror(errno));
}

}  // namespace

void check_image_path(const std::filesystem::path& path) {
  check_output_path(path, kImageExtensions, kImageFormatsText);
}

void check_animation(const std::filesystem::path& path, double fps) {
  const char* const extensions[] = {kAnimationExtension};
  check_output_path(path, extensions, kAnimationExtension);
  if (!(fps >= kMinAnimationFps && fps <= kMaxAnimationFps)) {
    char range[96];
    std::snprintf(range, sizeof range, "%g frames per second is outside %g..%g", fps,
                  kMinAnimationFps, kMaxAnimationFps);
    throw std::runtime_error(path.string() + ": " + range);
  }
}

void write_animation(const std::filesystem::path& path, const std::vector<Rgb8Image>& frames,
                     double fps) {
  check_animation(path, fps);
  if (frames.empty()) throw std::runtime_error(path.string() + ": no frames");
  std::vector<image_files::Pixels> px(frames.size());
  for (size_t i = 0; i < frames.size(); ++i) {
    const Rgb8Image& f = frames[i];
    if (f.width != frames[0].width || f.height != frames[0].height ||
        f.rgb.size() != size_t(f.width) * size_t(f.height) * 3 || f.width <= 0 || f.height <= 0)
      throw std::runtime_error(path.string() + ": frame " + std::to_string(i) +
                               " is not a picture of the first frame's size");
    px[i].width = f.width;
    px[i].height = f.height;
    px[i].channel_names = {"R", "G", "B"};
    px[i].data = f.rgb.data();
  }
  const Functions& m = image_module(path);
  write_atomically(path, [&](const std::string& tmp) {
    return m.write_frames(tmp, px, int(std::lround(fps * 100.0)), 100);
  });
}

void write_image(const std::filesystem::path& path, const Framebuffer& fb) {
  if (fb.width <= 0 || fb.height <= 0) throw std::runtime_error(path.string() + ": empty image");
  check_image_path(path);
  const size_t n = size_t(fb.width) * size_t(fb.height);
  image_files::Pixels px;
  px.width = fb.width;
  px.height = fb.height;
  std::vector<float> values;
  std::vector<unsigned char> codes;
  if (lower_extension(path) == ".exr") {
    const bool cost = fb.cost.size() == n;
    const bool samples = fb.samples.size() == n;
    px.channel_names = {"R", "G", "B", "Z", "N.x", "N.y", "N.z", "objectId"};
    if (cost)
      for (const char* c : {"cost.rays", "cost.nodes", "cost.boxes", "cost.prims"})
        px.channel_names.push_back(c);
    if (samples) px.channel_names.push_back("samples");
    const size_t nc = px.channel_names.size();
    values.resize(n * nc);
    for (size_t i = 0; i < n; ++i) {
      float* p = &values[i * nc];
      p[0] = fb.color[i].r;
      p[1] = fb.color[i].g;
      p[2] = fb.color[i].b;
      p[3] = fb.depth[i];
      p[4] = fb.normal[i].x;
      p[5] = fb.normal[i].y;
      p[6] = fb.normal[i].z;
      p[7] = fb.object_id[i];
      if (cost) {
        p[8] = float(fb.cost[i].rays);
        p[9] = float(fb.cost[i].nodes);
        p[10] = float(fb.cost[i].boxes);
        p[11] = float(fb.cost[i].prims);
      }
      if (samples) p[nc - 1] = fb.samples[i];
    }
    px.data = values.data();
    px.float_data = px.float_file = true;
    px.z_channel = 3;
    px.zip = true;
  } else {
    px.channel_names = {"R", "G", "B"};
    codes.resize(n * 3);
    // On every core: one powf per channel took 19 ms of an 800x600 render's
    // 0.29 s command on one.
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096),
                      [&](const tbb::blocked_range<size_t>& r) {
                        for (size_t i = r.begin(); i < r.end(); ++i)
                          for (int c = 0; c < 3; ++c)
                            codes[i * 3 + c] =
                                (unsigned char)std::lround(255.0f * linear_to_srgb(fb.color[i][c]));
                      });
    px.data = codes.data();
    px.srgb = true;
  }
  write_pixels(path, px);
}

Color heat_color(float t) {
  // Control points of a viridis-like map (sRGB values, converted below).
  static const Color pts[] = {{0.267f, 0.005f, 0.329f},
                              {0.230f, 0.322f, 0.546f},
                              {0.128f, 0.567f, 0.551f},
                              {0.369f, 0.789f, 0.383f},
                              {0.993f, 0.906f, 0.144f}};
  t = std::clamp(std::isfinite(t) ? t : 0.0f, 0.0f, 1.0f) * 4.0f;
  int i = std::min(3, int(t));
  return glm::mix(pts[i], pts[i + 1], t - float(i));
}

void write_heatmap(const std::filesystem::path& path, const std::vector<float>& values, int width,
                   int height, const std::string& title) {
  if (width <= 0 || height <= 0 || values.size() != size_t(width) * size_t(height))
    throw std::runtime_error(path.string() + ": heat map size does not match the image");
  check_image_path(path);
  float vmax = 0.0f;
  for (float v : values)
    if (std::isfinite(v)) vmax = std::max(vmax, v);
  const int legend = 44;
  std::vector<float> px(size_t(width) * size_t(height + legend) * 3, 1.0f);
  auto put = [&](int x, int y, const Color& c) {
    float* p = &px[(size_t(y) * size_t(width) + size_t(x)) * 3];
    p[0] = c.r;
    p[1] = c.g;
    p[2] = c.b;
  };
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      put(x, y,
          heat_color(vmax > 0.0f ? values[size_t(y) * size_t(width) + size_t(x)] / vmax : 0.0f));
  // Legend: a color bar across the middle 80% of the width, with its scale.
  const int x0 = width / 10, x1 = width - width / 10, by0 = height + 6, by1 = height + 18;
  for (int x = x0; x < x1; ++x)
    for (int y = by0; y < by1; ++y)
      put(x, y, heat_color(float(x - x0) / float(std::max(1, x1 - x0 - 1))));
  const std::string font = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
  std::error_code ec;
  const bool have_font = fs::exists(font, ec);
  char hi[64];
  std::snprintf(hi, sizeof hi, "%.6g", double(vmax));
  const int ty = height + 32;
  const std::vector<image_files::Label> labels = {
      {x0, ty, "0"},
      {x1 - 8 * int(std::strlen(hi)), ty, hi},
      {width / 2 - 3 * int(title.size()), ty + 10, title}};
  if (have_font)
    if (const std::string problem =
            image_module(path).draw_text(width, height + legend, px.data(), labels, font);
        !problem.empty())
      throw std::runtime_error(path.string() + ": " + problem);
  const std::vector<unsigned char> codes = to_codes(px);
  image_files::Pixels image;
  image.width = width;
  image.height = height + legend;
  image.channel_names = {"R", "G", "B"};
  image.data = codes.data();
  write_pixels(path, image);
}

std::vector<float> read_image_rgb(const std::filesystem::path& path, int& width, int& height) {
  int channels = 0;
  std::vector<float> all;
  if (const std::string problem =
          image_module(path).read(path.string(), width, height, channels, all);
      !problem.empty())
    throw std::runtime_error(path.string() + ": " + problem);
  if (channels < 3) throw std::runtime_error(path.string() + ": fewer than 3 channels");
  std::vector<float> rgb(size_t(width) * height * 3);
  for (size_t i = 0; i < size_t(width) * height; ++i)
    for (int c = 0; c < 3; ++c) rgb[i * 3 + c] = all[i * size_t(channels) + c];
  return rgb;
}

}  // namespace rayscope
