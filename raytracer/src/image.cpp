#include "rayscope/image.h"

#include <atomic>
#include <memory>
#include <stdexcept>
#include <string>
#include <system_error>

#include <unistd.h>

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
}

float linear_to_srgb(float v) {
  if (!(v > 0.0f)) return 0.0f;
  if (v >= 1.0f) return 1.0f;
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

namespace {

std::string lower_ext(const std::filesystem::path& p) {
  std::string e = p.extension().string();
  for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

}  // namespace

void write_image(const std::filesystem::path& path, const Framebuffer& fb) {
  namespace fs = std::filesystem;
  if (fb.width <= 0 || fb.height <= 0) throw std::runtime_error(path.string() + ": empty image");
  const std::string ext = lower_ext(path);
  if (ext.empty())
    throw std::runtime_error(path.string() + ": no file extension to choose the image format");
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
    const int nc = 8;
    OIIO::ImageSpec spec(fb.width, fb.height, nc, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"R", "G", "B", "Z", "N.x", "N.y", "N.z", "objectId"};
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
