#include "rayscope/image.h"

#include <atomic>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <system_error>

#include <unistd.h>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

namespace rayscope {

void Framebuffer::resize(int w, int h) {
  width = w;
  height = h;
  size_t n = size_t(w) * size_t(h);
  color.assign(n, Color(0.0f));
  depth.assign(n, kInfinity);
  normal.assign(n, Vec3(0.0f));
  object_id.assign(n, -1.0f);
  samples.clear();
}

float linear_to_srgb(float v) {
  if (!(v > 0.0f)) return 0.0f;
  if (v >= 1.0f) return 1.0f;
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

namespace {

// Writes `buf` (any format OIIO knows by extension) to a temporary file, then
// renames it over `path`.
void write_buf_atomic(const std::filesystem::path& path, OIIO::ImageBuf& buf) {
  namespace fs = std::filesystem;
  static std::atomic<unsigned> counter{0};
  fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  std::string tmp_name(".");
  tmp_name += path.stem().string();
  tmp_name += ".tmp" + std::to_string(::getpid()) + "_h" + std::to_string(counter++) +
              path.extension().string();
  fs::path tmp = dir / tmp_name;
  std::error_code ec;
  if (!buf.write(tmp.string())) {
    fs::remove(tmp, ec);
    throw std::runtime_error(path.string() + ": cannot write image: " + buf.geterror());
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw std::runtime_error(path.string() + ": cannot rename temporary file: " + ec.message());
  }
}

std::string lower_ext(const std::filesystem::path& p) {
  std::string e = p.extension().string();
  for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

}  // namespace

void check_image_path(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec))
    throw std::runtime_error(path.string() + ": is a directory, not an image file");
  const fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  if (!fs::is_directory(dir, ec))
    throw std::runtime_error(path.string() + ": folder '" + dir.string() + "' does not exist");
  if (lower_ext(path).empty())
    throw std::runtime_error(path.string() + ": no file extension (use .png, .jpg or .exr)");
}

void write_image(const std::filesystem::path& path, const Framebuffer& fb) {
  namespace fs = std::filesystem;
  if (fb.width <= 0 || fb.height <= 0) throw std::runtime_error(path.string() + ": empty image");
  check_image_path(path);
  const std::string ext = lower_ext(path);
  static std::atomic<unsigned> counter{0};
  fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  std::string tmp_name(".");
  tmp_name += path.stem().string();
  tmp_name += ".tmp" + std::to_string(::getpid()) + "_" + std::to_string(counter++) + ext;
  fs::path tmp = dir / tmp_name;
  auto out = OIIO::ImageOutput::create(tmp.string());
  if (!out)
    throw std::runtime_error(path.string() + ": cannot write this image format (" +
                             OIIO::geterror() + ")");
  const size_t n = size_t(fb.width) * size_t(fb.height);
  bool ok;
  if (ext == ".exr") {
    const bool cost = fb.cost.size() == n;
    const bool samples = fb.samples.size() == n;
    const int nc = 8 + (cost ? 4 : 0) + (samples ? 1 : 0);
    OIIO::ImageSpec spec(fb.width, fb.height, nc, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"R", "G", "B", "Z", "N.x", "N.y", "N.z", "objectId"};
    if (cost)
      for (const char* c : {"cost.rays", "cost.nodes", "cost.boxes", "cost.prims"})
        spec.channelnames.push_back(c);
    if (samples) spec.channelnames.push_back("samples");
    spec.z_channel = 3;
    spec.attribute("compression", "zip");
    std::vector<float> px(n * nc);
    for (size_t i = 0; i < n; ++i) {
      float* p = &px[i * nc];
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
    ok = out->open(tmp.string(), spec) && out->write_image(OIIO::TypeDesc::FLOAT, px.data());
  } else {
    OIIO::ImageSpec spec(fb.width, fb.height, 3, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:ColorSpace", "sRGB");
    std::vector<unsigned char> px(n * 3);
    for (size_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c)
        px[i * 3 + c] = (unsigned char)std::lround(255.0f * linear_to_srgb(fb.color[i][c]));
    ok = out->open(tmp.string(), spec) && out->write_image(OIIO::TypeDesc::UINT8, px.data());
  }
  std::string err = ok ? std::string() : out->geterror();
  ok = out->close() && ok;
  if (!ok) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw std::runtime_error(path.string() +
                             ": cannot write image: " + (err.empty() ? out->geterror() : err));
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw std::runtime_error(path.string() + ": cannot rename temporary file: " + ec.message());
  }
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
  OIIO::ImageBuf buf(OIIO::ImageSpec(width, height + legend, 3, OIIO::TypeDesc::UINT8));
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
  buf.set_pixels(OIIO::ROI(0, width, 0, height + legend), OIIO::TypeDesc::FLOAT, px.data());
  const char* font = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
  std::error_code ec;
  if (std::filesystem::exists(font, ec)) {
    const float black[3] = {0.0f, 0.0f, 0.0f};
    const int size = 11, ty = height + 32;
    char hi[64];
    std::snprintf(hi, sizeof hi, "%.6g", double(vmax));
    OIIO::ImageBufAlgo::render_text(buf, x0, ty, "0", size, font, black);
    OIIO::ImageBufAlgo::render_text(buf, x1 - 8 * int(std::strlen(hi)), ty, hi, size, font, black);
    OIIO::ImageBufAlgo::render_text(buf, width / 2 - 3 * int(title.size()), ty + 10, title, size,
                                    font, black, OIIO::ImageBufAlgo::TextAlignX::Left);
  }
  write_buf_atomic(path, buf);
}

std::vector<float> read_image_rgb(const std::filesystem::path& path, int& width, int& height) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in)
    throw std::runtime_error(path.string() + ": cannot read image (" + OIIO::geterror() + ")");
  const OIIO::ImageSpec& spec = in->spec();
  width = spec.width;
  height = spec.height;
  if (spec.nchannels < 3) throw std::runtime_error(path.string() + ": fewer than 3 channels");
  std::vector<float> all(size_t(width) * height * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, all.data()))
    throw std::runtime_error(path.string() + ": " + in->geterror());
  std::vector<float> rgb(size_t(width) * height * 3);
  for (size_t i = 0; i < size_t(width) * height; ++i)
    for (int c = 0; c < 3; ++c) rgb[i * 3 + c] = all[i * spec.nchannels + c];
  return rgb;
}

}  // namespace rayscope
