// The image-file module (image_file_module.h): reads and writes image files
// through OpenImageIO. Loaded by the core on first use; nothing else in
// RayScope links OpenImageIO.
#include "image_file_module.h"

#include <exception>
#include <memory>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

namespace {

using rayscope::image_files::Label;
using rayscope::image_files::Pixels;

std::string write(const std::string& file, const Pixels& px) {
  const int nc = int(px.channel_names.size());
  OIIO::ImageSpec spec(px.width, px.height, nc,
                       px.float_file ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  spec.channelnames = px.channel_names;
  spec.z_channel = px.z_channel;
  if (px.zip) spec.attribute("compression", "zip");
  if (px.srgb) spec.attribute("oiio:ColorSpace", "sRGB");
  OIIO::ImageBuf buf(spec);
  const OIIO::TypeDesc type = px.float_data ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8;
  if (!buf.set_pixels(OIIO::ROI(0, px.width, 0, px.height, 0, 1, 0, nc), type, px.data))
    return "cannot write image: " + buf.geterror();
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(file);
  if (!out) return "cannot write this image format (" + OIIO::geterror() + ")";
  bool ok = out->open(file, spec) && buf.write(out.get());
  std::string error = ok ? std::string() : out->geterror() + buf.geterror();
  ok = out->close() && ok;
  if (!ok && error.empty()) error = out->geterror();
  return ok ? std::string() : "cannot write image: " + error;
}

std::string draw_text(int width, int height, float* rgb, const std::vector<Label>& labels,
                      const std::string& font) {
  // Wraps the caller's pixels: the text is drawn into them.
  OIIO::ImageBuf buf(OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::FLOAT), rgb);
  const float black[3] = {0.0f, 0.0f, 0.0f};
  for (const Label& l : labels)
    if (!OIIO::ImageBufAlgo::render_text(buf, l.x, l.y, l.text, l.size, font, black))
      return "cannot draw text: " + buf.geterror();
  return {};
}

std::string read(const std::string& file, int& width, int& height, int& channels,
                 std::vector<float>& values) {
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(file);
  if (!in) return "cannot read image (" + OIIO::geterror() + ")";
  const OIIO::ImageSpec& spec = in->spec();
  width = spec.width;
  height = spec.height;
  channels = spec.nchannels;
  values.resize(size_t(width) * size_t(height) * size_t(channels));
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, values.data()))
    return in->geterror();
  return {};
}

std::string write_frames(const std::string& file, const std::vector<Pixels>& frames, int fps_num,
                         int fps_den) {
  if (frames.empty()) return "no frames to write";
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(file);
  if (!out) return "cannot write this image format (" + OIIO::geterror() + ")";
  if (!out->supports("multiimage")) return "this format holds one picture, not an animation";
  std::vector<OIIO::ImageSpec> specs;
  for (const Pixels& px : frames) {
    const int nc = int(px.channel_names.size());
    OIIO::ImageSpec spec(px.width, px.height, nc, OIIO::TypeDesc::UINT8);
    spec.channelnames = px.channel_names;
    const int fps[2] = {fps_num, fps_den};
    spec.attribute("FramesPerSecond", OIIO::TypeRational, fps);
    spec.attribute("oiio:LoopCount", 0);  // loop for ever
    specs.push_back(spec);
  }
  bool ok = out->open(file, int(specs.size()), specs.data());
  for (size_t i = 0; ok && i < frames.size(); ++i) {
    if (i > 0) ok = out->open(file, specs[i], OIIO::ImageOutput::AppendSubimage);
    ok = ok && out->write_image(OIIO::TypeDesc::UINT8, frames[i].data);
  }
  std::string error = ok ? std::string() : out->geterror();
  ok = out->close() && ok;
  if (!ok && error.empty()) error = out->geterror();
  return ok ? std::string() : "cannot write the animation: " + error;
}

// Exceptions (bad_alloc, OIIO's own) do not cross into the core.
template <class F>
std::string guarded(F&& f) {
  try {
    return f();
  } catch (const std::exception& e) {
    return e.what();
  }
}

const rayscope::image_files::Functions kFunctions = {
    rayscope::image_files::kVersion,
    [](const std::string& file, const Pixels& px) {
      return guarded([&] { return write(file, px); });
    },
    [](int width, int height, float* rgb, const std::vector<Label>& labels,
       const std::string& font) {
      return guarded([&] { return draw_text(width, height, rgb, labels, font); });
    },
    [](const std::string& file, int& w, int& h, int& c, std::vector<float>& v) {
      return guarded([&] { return read(file, w, h, c, v); });
    },
    [](const std::string& file, const std::vector<Pixels>& frames, int fps_num, int fps_den) {
      return guarded([&] { return write_frames(file, frames, fps_num, fps_den); });
    }};

}  // namespace

extern "C" __attribute__((visibility("default"))) const rayscope::image_files::Functions*
rayscope_image_files() {
  return &kFunctions;
}
