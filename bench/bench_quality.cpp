// bench_quality: run time against image error, rays against recursion depth,
// and RayScope against POV-Ray 3.7 on the same scene.
//
// For each scene (the built-in default scene, data/scenes/bunny_glass.json and
// data/scenes/refraction.json unless --scenes says otherwise):
//
//  1. A converged reference: N x N stratified samples per pixel (--ref-spp,
//     default 16, i.e. 256 spp), maximum depth --ref-depth (16) and cutoff
//     --ref-cutoff (1e-4; a cutoff of 0 at depth 16 would trace up to 2^17 rays
//     per sample in glass; the cutoff, like RenderSettings::min_contribution,
//     is a ray's weight within its sample). Cached as EXR in OUT/refs/, keyed
//     by scene, image size, reference settings and a hash of the scene file, so reruns skip it. How
//     far the reference's own cutoff moves the image is measured and printed (1 spp renders at
//     --ref-cutoff and at --ref-cutoff / 100).
//  2. Rays against depth: 1 spp, max depth 0..10 for each cutoff of
//     --cutoffs (default 0, 1e-3, 1e-2): rays traced by kind, against the
//     lecture's worst case O(n m 2^r) (a full binary ray tree has 2^(r+1) - 1
//     rays per primary ray; each hit adds one shadow ray per light), and the
//     median time of --rays-runs (5) rounds.
//  3. Time against error: N (--spp) against max depth (--depths) and cutoff
//     (--cutoffs). For each depth and cutoff, N rises until the render would
//     take longer than --max-seconds (estimated as N^2 times the 1 spp time
//     from step 2) or until the RMSE falls by less than --min-gain (10%) from
//     the previous N: the depth or cutoff error then dominates and larger N
//     only costs time (those configurations could not be on the Pareto front).
//     The cutoffs are RenderSettings::min_contribution: a secondary ray is
//     dropped when its weight within its sample is below the cutoff, whatever
//     N is.
//     Each configuration is rendered --runs times; the configurations take
//     turns (one render of each per round), so slow drifts of the machine hit
//     all alike; the median time is reported. The image of the first round is
//     compared with the reference:
//       rmse, psnr  OpenImageIO's ImageBufAlgo::compare on linear RGB (the
//                   renderer's float output, unclamped), PSNR = 20 log10(1 / RMSE);
//       ssim        SSIM (Wang, Bovik, Sheikh, Simoncelli 2004) of the luma
//                   Y' = 0.2126 R' + 0.7152 G' + 0.0722 B' of the sRGB-encoded
//                   image clamped to [0, 1] (what a PNG shows): 11 x 11 Gaussian
//                   window, sigma 1.5, K1 = 0.01, K2 = 0.03, L = 1, mean over the
//                   windows that lie inside the image.
//     A configuration is on the Pareto front when no other configuration of the
//     same scene is at least as fast and at least as accurate (and better in one).
//  4. Beside those fixed-sample configurations, in the same rounds and against
//     the same reference, for each depth of --frontier-depths and cutoff of
//     --frontier-cutoffs:
//       filtered   N x N samples with the checkerboard box-filtered over each
//                  sample's footprint (RenderSettings::texture_filter), N rising
//                  as above;
//       adaptive   adaptive sampling (RenderSettings::max_samples,
//                  target_error), batches of B x B from an M x M grid for each
//                  B:M of --adaptive and target of --targets, with and without
//                  the filter.
//     The reference is the converged unfiltered image (point-sampled checker,
//     256 spp): the true pixel integral, so the filter is judged by how close
//     it gets to that, not to itself. The summary lists, for RMSE thresholds,
//     the cheapest configuration of each kind and the ratio of the cheapest
//     fixed-sample time to the cheapest time overall.
//
// Peer comparison (--peer-scene, default bunny_glass): the loaded RayScope
// scene is written as a POV-Ray 3.7 scene (same camera, lights, Phong/Blinn
// finishes, the mesh as mesh2 with the same triangles, glass with the same ior
// and Fresnel reflection, the reflective checkerboard plane; max_trace_level =
// our max depth + 1 since POV-Ray counts the primary ray as level 1;
// adc_bailout = our cutoff; no radiosity, no photons; transparent objects
// cast opaque shadows through an invisible twin, as RayScope's shadow rays
// stop at glass) and rendered with
// `povray` at the same size and thread count (+WT), alternating with RayScope.
// Two settings: 1 sample at the pixel centre (POV-Ray -A) and 3 x 3 samples
// (POV-Ray +A0.0 +AM1 +R3 -J: every pixel supersampled on a 3 x 3 grid, plus
// its first centre ray). Rounds alternate RayScope and POV-Ray; medians of
// --peer-runs after a warm-up round. Reported:
//   render only     ours: render() in this process; POV-Ray: its "Trace Time";
//   whole program   the `rayscope render` and `povray` processes from start to
//                   exit, each reading its scene file (and the mesh), building
//                   its hierarchy, rendering and writing a PNG;
//   setup           ours: scene file, mesh and BVH in this process; POV-Ray:
//                   its "Parse Time" + "Bounding Time";
// and the fixed cost of a povray process (an empty scene), the ray counts both
// report, and how alike the two PNGs are (sRGB RMSE, SSIM). Without `povray`
// on PATH the peer is skipped with a message.
//
// Outputs in --out (default out/bench): quality.csv, rays_vs_depth.csv,
// peer.csv (each written to a temporary file and renamed), refs/, and the
// peer's .pov file and both renderers' PNGs. bench/plot_quality.py draws the
// plots; bench/run_quality does everything in one command.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <sys/wait.h>
#include <unistd.h>
#include <CLI/CLI.hpp>

#include "rayscope/image.h"
#include "rayscope/render.h"
#include "rayscope/scene_io.h"
#include "rayscope/shapes.h"
#include "rayscope_vtkio/mesh_files.h"

#ifndef RAYSCOPE_SOURCE_DIR
#define RAYSCOPE_SOURCE_DIR "."
#endif
#ifndef RAYSCOPE_CLI
#define RAYSCOPE_CLI "rayscope"
#endif

namespace {

using namespace rayscope;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point a) {
  return std::chrono::duration<double>(Clock::now() - a).count();
}

double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

// ---------------------------------------------------------------------------
// Options

struct Options {
  fs::path out = "out/bench";
  fs::path data = fs::path(RAYSCOPE_SOURCE_DIR) / "data" / "scenes";
  std::string res = "320x240";
  int width = 320, height = 240;
  int runs = 3;
  int threads = 2;
  std::vector<std::string> scenes{"default", "bunny_glass", "refraction"};
  std::vector<int> spp{1, 2, 3, 4, 5, 6, 7, 8};
  std::vector<int> depths{1, 2, 3, 4, 6, 10};
  std::vector<float> cutoffs{0.0f, 1e-3f, 1e-2f};
  std::vector<int> frontier_depths{4, 6};
  std::vector<float> frontier_cutoffs{1e-2f};
  std::vector<std::pair<int, int>> adaptive{{1, 4}, {2, 6}, {2, 8}};  // B:M
  std::vector<float> targets{0.04f, 0.02f, 0.01f, 0.005f, 0.0025f};
  bool no_frontier = false;
  int rays_max_depth = 10;
  int rays_runs = 5;
  double max_seconds = 3.0;
  double min_gain = 0.1;
  int ref_spp = 16, ref_depth = 16;
  float ref_cutoff = 1e-4f;
  std::string peer_scene = "bunny_glass";
  std::string povray = "povray";
  std::string rayscope = RAYSCOPE_CLI;
  int peer_depth = 5;
  float peer_cutoff = 1e-3f;
  int peer_runs = 5;  // 0: --runs
  bool no_peer = false;
  bool peer_only = false;
  bool quick = false;
};

// ---------------------------------------------------------------------------
// Scenes

struct SceneCase {
  std::string name;
  fs::path file;  // empty: the built-in default scene
  LoadedScene loaded;
  uint64_t hash = 0;  // of the scene file's text (0 for the built-in scene)
};

uint64_t fnv1a(const std::string& s) {
  uint64_t h = 1469598103934665603ull;
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
  return h;
}

fs::path scene_path(const Options& o, const std::string& name) {
  fs::path p(name);
  if (p.extension() == ".json") return p;
  return o.data / (name + ".json");
}

std::string scene_label(const std::string& name) {
  fs::path p(name);
  return p.extension() == ".json" ? p.stem().string() : name;
}

LoadedScene load_case(const std::string& name, const fs::path& file) {
  if (name == "default") {
    LoadedScene l;
    l.scene = make_default_scene();
    return l;
  }
  return load_scene(file, rayscope_vtkio::load_meshes);
}

// ---------------------------------------------------------------------------
// Images and metrics

using Rgb = std::vector<float>;  // width * height * 3, row-major

Rgb to_rgb(const Framebuffer& fb) {
  Rgb v(fb.color.size() * 3);
  for (size_t i = 0; i < fb.color.size(); ++i)
    for (int c = 0; c < 3; ++c) v[3 * i + c] = fb.color[i][c];
  return v;
}

/// RMSE and PSNR over all channels of two RGB float images (OpenImageIO).
void rmse_psnr(const Rgb& a, const Rgb& b, int w, int h, double& rmse, double& psnr) {
  OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::FLOAT);
  Rgb ca = a, cb = b;  // ImageBuf wraps non-const memory
  OIIO::ImageBuf A(spec, ca.data()), B(spec, cb.data());
  // Thresholds that no difference reaches: OpenImageIO reports "error" when
  // any value fails the threshold, and only RMSE is wanted here.
  OIIO::ImageBufAlgo::CompareResults r = OIIO::ImageBufAlgo::compare(A, B, 1e30f, 1e30f);
  if (r.error) throw std::runtime_error("image comparison failed: " + OIIO::geterror());
  rmse = r.rms_error;
  psnr = rmse > 0 ? 20.0 * std::log10(1.0 / rmse) : INFINITY;
}

/// Luma Y' of the sRGB encoding of linear RGB clamped to [0, 1]; `encoded`
/// says the input is already sRGB-encoded (8-bit PNGs read back).
std::vector<double> srgb_luma(const Rgb& rgb, bool encoded) {
  std::vector<double> y(rgb.size() / 3);
  for (size_t i = 0; i < y.size(); ++i) {
    double e[3];
    for (int c = 0; c < 3; ++c) {
      float v = std::clamp(rgb[3 * i + c], 0.0f, 1.0f);
      e[c] = encoded ? v : linear_to_srgb(v);
    }
    y[i] = 0.2126 * e[0] + 0.7152 * e[1] + 0.0722 * e[2];
  }
  return y;
}

/// Mean SSIM (Wang et al. 2004) of two single-channel images with values in
/// [0, 1]: 11 x 11 Gaussian window (sigma 1.5), K1 = 0.01, K2 = 0.03, L = 1,
/// averaged over window positions that lie inside the image ("valid").
double ssim(const std::vector<double>& x, const std::vector<double>& y, int w, int h) {
  constexpr int R = 5;  // window 2R + 1 = 11
  constexpr double kSigma = 1.5, C1 = 0.01 * 0.01, C2 = 0.03 * 0.03;
  if (w < 2 * R + 1 || h < 2 * R + 1) throw std::runtime_error("image too small for SSIM");
  double g[2 * R + 1], gs = 0;
  for (int i = -R; i <= R; ++i) gs += g[i + R] = std::exp(-0.5 * i * i / (kSigma * kSigma));
  for (double& v : g) v /= gs;
  // Separable filtering of x, y, x^2, y^2, xy: horizontal pass, then vertical.
  const int vw = w - 2 * R, vh = h - 2 * R;
  std::vector<double> in[5];
  for (auto& v : in) v.resize(size_t(w) * h);
  for (size_t i = 0; i < x.size(); ++i) {
    in[0][i] = x[i];
    in[1][i] = y[i];
    in[2][i] = x[i] * x[i];
    in[3][i] = y[i] * y[i];
    in[4][i] = x[i] * y[i];
  }
  std::vector<double> hor[5], out[5];
  for (int k = 0; k < 5; ++k) {
    hor[k].assign(size_t(vw) * h, 0.0);
    for (int r = 0; r < h; ++r)
      for (int c = 0; c < vw; ++c) {
        double s = 0;
        for (int i = 0; i <= 2 * R; ++i) s += g[i] * in[k][size_t(r) * w + c + i];
        hor[k][size_t(r) * vw + c] = s;
      }
    out[k].assign(size_t(vw) * vh, 0.0);
    for (int r = 0; r < vh; ++r)
      for (int c = 0; c < vw; ++c) {
        double s = 0;
        for (int i = 0; i <= 2 * R; ++i) s += g[i] * hor[k][size_t(r + i) * vw + c];
        out[k][size_t(r) * vw + c] = s;
      }
  }
  double sum = 0;
  for (size_t i = 0; i < out[0].size(); ++i) {
    double mx = out[0][i], my = out[1][i];
    double vx = out[2][i] - mx * mx, vy = out[3][i] - my * my, cxy = out[4][i] - mx * my;
    sum += ((2 * mx * my + C1) * (2 * cxy + C2)) / ((mx * mx + my * my + C1) * (vx + vy + C2));
  }
  return sum / double(out[0].size());
}

struct Metrics {
  double rmse = 0, psnr = 0, ssim = 1;
};

Metrics compare_linear(const Rgb& img, const Rgb& ref, int w, int h) {
  Metrics m;
  rmse_psnr(img, ref, w, h, m.rmse, m.psnr);
  m.ssim = ssim(srgb_luma(img, false), srgb_luma(ref, false), w, h);
  return m;
}

// ---------------------------------------------------------------------------
// CSV written under a temporary name and renamed.

void write_atomic(const fs::path& path, const std::string& text) {
  fs::path tmp = path;
  tmp += ".tmp" + std::to_string(::getpid());
  {
    std::ofstream f(tmp, std::ios::binary);
    f << text;
    f.flush();
    if (!f) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw std::runtime_error(path.string() + ": cannot write");
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw std::runtime_error(path.string() + ": cannot rename: " + ec.message());
  }
}

std::string rays_csv(const RayCounters& c) {
  std::ostringstream s;
  for (int k = 0; k < kRayKindCount; ++k) s << c.rays[k] << ",";
  s << c.total_rays();
  return s.str();
}
constexpr const char* kRaysHeader =
    "rays_primary,rays_shadow,rays_reflection,rays_refraction,rays_total";

// ---------------------------------------------------------------------------
// Rendering helpers

RenderSettings settings_for(const Options& o, int n, int depth, float cutoff, bool filter = false,
                            int max_n = 0, float target = 0.0f) {
  RenderSettings rs;
  rs.texture_filter = filter;
  rs.max_samples = max_n;
  rs.target_error = target;
  rs.width = o.width;
  rs.height = o.height;
  rs.samples = n;
  rs.max_depth = depth;
  rs.min_contribution = cutoff;
  rs.threads = o.threads;
  rs.seed = 0;
  rs.validate();
  return rs;
}

double timed_render(Scene& scene, const RenderSettings& rs, RayCounters* counters,
                    Framebuffer* image) {
  auto t0 = Clock::now();
  Framebuffer fb = render(scene, rs, counters);
  double t = seconds_since(t0);
  if (image) *image = std::move(fb);
  return t;
}

std::string cutoff_str(float c) {
  return c == 0.0f ? std::string("0") : fmt("%g", double(c));
}

/// The reference image of a scene, from the cache or rendered (and cached).
Rgb reference_image(const Options& o, SceneCase& sc) {
  fs::path dir = o.out / "refs";
  fs::create_directories(dir);
  char key[256];
  std::snprintf(key, sizeof key, "ref_%s_%dx%d_n%d_d%d_c%sps_%016llx", sc.name.c_str(), o.width,
                o.height, o.ref_spp, o.ref_depth, cutoff_str(o.ref_cutoff).c_str(),
                (unsigned long long)sc.hash);
  fs::path exr = dir / (std::string(key) + ".exr");
  if (fs::exists(exr)) {
    int w = 0, h = 0;
    try {
      Rgb img = read_image_rgb(exr, w, h);
      if (w == o.width && h == o.height) {
        std::printf("  reference: cached %s\n", exr.string().c_str());
        return img;
      }
    } catch (const std::exception& e) {
      std::printf("  reference: cache unreadable (%s), rendering again\n", e.what());
    }
  }
  RenderSettings rs = settings_for(o, o.ref_spp, o.ref_depth, o.ref_cutoff);
  RayCounters c;
  Framebuffer fb;
  std::printf("  reference: rendering %d spp, depth %d, cutoff %s ...\n", o.ref_spp * o.ref_spp,
              o.ref_depth, cutoff_str(o.ref_cutoff).c_str());
  std::fflush(stdout);
  double t = timed_render(sc.loaded.scene, rs, &c, &fb);
  write_image(exr, fb);
  write_image(dir / (std::string(key) + ".png"), fb);
  std::printf("  reference: %.1f s, %.3g rays, written %s\n", t, double(c.total_rays()),
              exr.string().c_str());
  // EXR stores 32-bit floats: reading back gives exactly the rendered values,
  // so cached and fresh references are the same.
  return to_rgb(fb);
}

// ---------------------------------------------------------------------------
// Sweeps

struct RaysRow {
  int depth;
  float cutoff;
  double time;
  RayCounters c;
};

struct QualityRow {
  int n, depth;
  float cutoff;
  std::vector<double> times;
  RayCounters c;
  Metrics m;
  bool pareto_rmse = false, pareto_ssim = false;
  bool filter = false;  ///< RenderSettings::texture_filter
  int max_n = 0;        ///< RenderSettings::max_samples (0: fixed N x N)
  float target = 0.0f;  ///< RenderSettings::target_error

  /// "fixed", "filtered", "adaptive" or "adaptive+filtered".
  std::string kind() const {
    if (max_n > 0) return filter ? "adaptive+filtered" : "adaptive";
    return filter ? "filtered" : "fixed";
  }
  /// "16" for fixed N x N, "4..64" (first batch .. most) for adaptive.
  std::string spp_label() const {
    return max_n > 0 ? std::to_string(n * n) + ".." + std::to_string(max_n * max_n)
                     : std::to_string(n * n);
  }
};

void mark_pareto(std::vector<QualityRow>& rows, bool by_ssim) {
  auto err = [&](const QualityRow& r) { return by_ssim ? 1.0 - r.m.ssim : r.m.rmse; };
  for (QualityRow& a : rows) {
    double ta = median(a.times), ea = err(a);
    bool dominated = false;
    for (const QualityRow& b : rows) {
      double tb = median(b.times), eb = err(b);
      if (&a != &b && tb <= ta && eb <= ea && (tb < ta || eb < ea)) {
        dominated = true;
        break;
      }
    }
    (by_ssim ? a.pareto_ssim : a.pareto_rmse) = !dominated;
  }
}

// ---------------------------------------------------------------------------
// POV-Ray

std::string pov_vec(const Vec3& v) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "<%.9g, %.9g, %.9g>", double(v.x), double(v.y), double(v.z));
  return buf;
}

std::string pov_texture(const Material& m) {
  std::ostringstream s;
  const float opaque = std::max(0.0f, 1.0f - m.reflectivity - m.transparency);
  auto col = [&](const Color& c) {
    return m.transparency > 0.0f ? "rgbt <" + fmt("%.9g", c.x) + ", " + fmt("%.9g", c.y) + ", " +
                                       fmt("%.9g", c.z) + ", " + fmt("%.9g", m.transparency) + ">"
                                 : "rgb " + pov_vec(c);
  };
  s << "texture {\n    pigment { ";
  if (m.checker)
    s << "checker color " << col(m.color) << " color " << col(m.checker_color) << " scale "
      << m.checker_size;
  else
    s << "color " << col(m.color);
  s << " }\n    finish { ambient " << opaque * m.ambient << " diffuse " << opaque * m.diffuse;
  if (m.specular > 0.0f) {
    if (m.model == ShadingModel::Phong)
      s << " phong " << m.specular << " phong_size " << m.shininess;
    else
      s << " specular " << m.specular << " roughness " << 1.0f / m.shininess;
  }
  if (m.transparency > 0.0f)
    s << " reflection { " << m.reflectivity << ", " << m.reflectivity + m.transparency
      << " fresnel on } conserve_energy";
  else if (m.reflectivity > 0.0f)
    s << " reflection " << m.reflectivity;
  s << " }\n  }";
  return s.str();
}

/// Writes the committed, prepared scene as a POV-Ray 3.7 scene. Notes what it
/// cannot translate exactly into `notes`.
std::string pov_scene(const Scene& scene, const RenderSettings& rs, std::string& notes) {
  std::ostringstream s;
  s << "// Written by RayScope's bench_quality from the loaded RayScope scene.\n"
       "#version 3.7;\n";
  s << "global_settings {\n  assumed_gamma 1.0\n  max_trace_level " << rs.max_depth + 1
    << "  // POV-Ray counts the primary ray as level 1\n  adc_bailout "
    << fmt("%.9g", rs.min_contribution) << "\n  ambient_light rgb " << pov_vec(scene.ambient_light)
    << "\n}\n";
  s << "background { rgb " << pov_vec(scene.background) << " }\n";
  // The camera from RayScope's own basis: the image plane at distance 1 spans
  // +-half width along `right` and +-half height along `up`.
  const Camera& cam = scene.camera;
  const float aspect = float(rs.width) / float(rs.height);
  const float hh =
      cam.parallel ? cam.parallel_scale : std::tan(0.5f * glm::radians(cam.vfov_degrees));
  s << "camera {\n  " << (cam.parallel ? "orthographic" : "perspective") << "\n  location "
    << pov_vec(cam.eye) << "\n  direction " << pov_vec(cam.forward()) << "\n  right "
    << pov_vec(cam.right() * (2.0f * hh * aspect)) << "\n  up "
    << pov_vec(cam.up_vector() * (2.0f * hh)) << "\n}\n";
  for (const Light& l : scene.lights) {
    const Color c = l.color * l.intensity;
    s << "light_source {\n  ";
    if (l.type == Light::Type::Point) {
      s << pov_vec(l.position) << " color rgb " << pov_vec(c);
      if (l.attenuation != Vec3(1.0f, 0.0f, 0.0f)) notes += " light attenuation ignored;";
    } else {
      const Vec3 d = glm::normalize(l.direction);
      s << pov_vec(-1.0e4f * d) << " color rgb " << pov_vec(c) << "\n  parallel point_at "
        << pov_vec(Vec3(0.0f));
    }
    if (!l.casts_shadows) s << "\n  shadowless";
    s << "\n}\n";
  }
  for (size_t i = 0; i < scene.materials.size(); ++i)
    s << "#declare M" << i << " = " << pov_texture(scene.materials[i]) << "\n";
  // RayScope's shadow rays stop at any surface, glass included; POV-Ray's pass
  // through transparent objects (filtered). To trace the same light transport,
  // transparent objects cast no shadow themselves (no_shadow) and an invisible
  // opaque twin (no_image no_reflection) casts theirs.
  auto emit = [&](const std::string& geometry, uint32_t material) {
    const bool transparent = scene.materials[material].transparency > 0.0f;
    s << "object { " << geometry << " texture { M" << material << " }";
    if (transparent)
      s << " interior { ior " << fmt("%.9g", scene.materials[material].ior) << " } no_shadow";
    s << " }\n";
    if (transparent)
      s << "object { " << geometry << " pigment { rgb 0 } no_image no_reflection }\n";
  };
  for (size_t k = 0; k < scene.meshes.size(); ++k) {
    const TriangleMesh& m = scene.meshes[k];
    if (!m.colors.empty()) notes += " vertex colors ignored;";
    s << "#declare G" << k << " = mesh2 {\n  vertex_vectors { " << m.positions.size();
    for (const Vec3& p : m.positions) s << ",\n    " << pov_vec(p);
    s << "\n  }\n";
    if (!m.normals.empty()) {
      s << "  normal_vectors { " << m.normals.size();
      for (const Vec3& n : m.normals) s << ",\n    " << pov_vec(n);
      s << "\n  }\n";
    }
    s << "  face_indices { " << m.triangles.size();
    for (const glm::uvec3& t : m.triangles)
      s << ",\n    <" << t.x << ", " << t.y << ", " << t.z << ">";
    s << "\n  }\n}\n";
    emit("G" + std::to_string(k), m.material);
  }
  for (const Sphere& sp : scene.spheres)
    emit("sphere { " + pov_vec(sp.center) + ", " + fmt("%.9g", sp.radius) + " }", sp.material);
  for (const Plane& p : scene.planes) {
    const Vec3 n = glm::normalize(p.normal);
    emit("plane { " + pov_vec(n) + ", " + fmt("%.9g", glm::dot(n, p.point)) + " }", p.material);
  }
  return s.str();
}

/// Full path of `prog` when it is an executable on PATH (or a path itself).
std::string find_program(const std::string& prog) {
  if (prog.find('/') != std::string::npos) return ::access(prog.c_str(), X_OK) == 0 ? prog : "";
  const char* path = std::getenv("PATH");
  std::stringstream ss(path ? path : "");
  std::string dir;
  while (std::getline(ss, dir, ':')) {
    fs::path p = fs::path(dir.empty() ? "." : dir) / prog;
    if (::access(p.c_str(), X_OK) == 0 && fs::is_regular_file(p)) return p.string();
  }
  return "";
}

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

struct PovRun {
  double wall = 0, parse = NAN, bounding = NAN, trace = NAN;
  double rays = NAN, shadow_tests = NAN, reflected = NAN, refracted = NAN;
};

/// The number in "(X seconds)" after `label` in POV-Ray's statistics.
double pov_seconds(const std::string& log, const std::string& label) {
  size_t p = log.find(label);
  if (p == std::string::npos) return NAN;
  size_t a = log.find('(', p), e = log.find('\n', p);
  if (a == std::string::npos || a > e) return NAN;
  return std::atof(log.c_str() + a + 1);
}
double pov_count(const std::string& log, const std::string& label) {
  size_t p = log.find(label);
  if (p == std::string::npos) return NAN;
  return std::atof(log.c_str() + p + label.size());
}

struct Process {
  double wall = 0;
  std::string log;  // stdout and stderr
};

/// Runs a shell command, timing it from start to exit. Throws with the end of
/// its output when it fails or `expect` is missing afterwards.
Process run_process(const std::string& what, const std::string& cmd, const fs::path& expect) {
  Process r;
  std::error_code ec;
  fs::remove(expect, ec);
  auto t0 = Clock::now();
  FILE* p = ::popen((cmd + " 2>&1").c_str(), "r");
  if (!p) throw std::runtime_error("cannot start " + what);
  char buf[4096];
  size_t got;
  while ((got = std::fread(buf, 1, sizeof buf, p)) > 0) r.log.append(buf, got);
  const int status = ::pclose(p);
  r.wall = seconds_since(t0);
  if (status != 0 || !fs::exists(expect)) {
    std::string tail = r.log.size() > 600 ? r.log.substr(r.log.size() - 600) : r.log;
    throw std::runtime_error(what + " failed (exit status " +
                             std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
                             "): " + tail);
  }
  return r;
}

PovRun run_povray(const std::string& povray, const fs::path& dir, const std::string& pov,
                  const std::string& png, const Options& o, const std::string& aa) {
  // POV-Ray's default security policy allows writing only in the working
  // directory (and /tmp), so it runs inside the output folder.
  const std::string cmd = "cd " + shell_quote(dir.string()) + " && " + shell_quote(povray) + " +I" +
                          shell_quote(pov) + " +O" + shell_quote(png) + " +W" +
                          std::to_string(o.width) + " +H" + std::to_string(o.height) + " +WT" +
                          std::to_string(o.threads) + " -D +FN8 File_Gamma=sRGB " + aa;
  Process p = run_process("povray", cmd, dir / png);
  const std::string& log = p.log;
  PovRun r;
  r.wall = p.wall;
  r.parse = pov_seconds(log, "Parse Time:");
  r.bounding = pov_seconds(log, "Bounding Time:");
  r.trace = pov_seconds(log, "Trace Time:");
  r.rays = pov_count(log, "Rays:");
  r.shadow_tests = pov_count(log, "Shadow Ray Tests:");
  r.reflected = pov_count(log, "Reflected Rays:");
  r.refracted = pov_count(log, "Refracted Rays:");
  if (std::isnan(r.refracted)) r.refracted = pov_count(log, "Transmitted Rays:");
  return r;
}

struct PeerConfig {
  std::string name;
  int n;               // our N x N samples
  std::string pov_aa;  // POV-Ray's antialiasing options
  std::string pov_aa_desc;
};

/// Runs the peer comparison; returns CSV rows (without header).
std::string peer_comparison(const Options& o, const SceneCase& sc) {
  const std::string povray = find_program(o.povray);
  if (povray.empty()) {
    std::printf("\npeer: povray not installed, skipped\n");
    return "";
  }
  const int runs = o.peer_runs > 0 ? o.peer_runs : o.runs;
  std::printf(
      "\n== Peer: RayScope vs POV-Ray (%s), scene %s, %dx%d, %d thread(s), depth %d, "
      "cutoff %g, median of %d runs ==\n",
      povray.c_str(), sc.name.c_str(), o.width, o.height, o.threads, o.peer_depth,
      double(o.peer_cutoff), runs);
  const fs::path dir = fs::absolute(o.out);
  // The .pov file comes from the scene exactly as RayScope loads it.
  Scene scene = sc.loaded.scene;
  RenderSettings rs = settings_for(o, 1, o.peer_depth, o.peer_cutoff);
  scene.commit();
  scene.camera.prepare(rs.width, rs.height);
  std::string notes;
  const std::string pov = sc.name + ".pov";
  write_atomic(dir / pov, pov_scene(scene, rs, notes));
  if (!notes.empty()) std::printf("  note: not translated:%s\n", notes.c_str());
  std::printf("  wrote %s\n", (dir / pov).string().c_str());

  // What the povray process costs by itself: an empty scene (camera and
  // background only) at the same size and thread count.
  {
    const std::string empty = "empty.pov";
    write_atomic(dir / empty,
                 "#version 3.7;\nglobal_settings { assumed_gamma 1.0 }\nbackground { rgb 0 }\n"
                 "camera { location <0, 0, -5> look_at <0, 0, 0> }\n");
    std::vector<double> wall;
    for (int r = 0; r < runs; ++r)
      wall.push_back(run_povray(povray, dir, empty, "empty.png", o, "-A").wall);
    std::printf("  POV-Ray process on an empty scene (start-up, shut-down, PNG): %.3f s\n",
                median(wall));
    std::error_code ec;
    fs::remove(dir / empty, ec);
    fs::remove(dir / "empty.png", ec);
  }

  const std::vector<PeerConfig> configs = {
      {"1spp", 1, "-A", "-A (one ray through each pixel centre)"},
      {"3x3", 3, "+A0.0 +AM1 +R3 -J", "+A0.0 +AM1 +R3 -J (every pixel: centre ray + 3x3 grid)"}};
  // RayScope's command-line program, timed as a process like povray.
  std::string cli = o.rayscope.empty() ? std::string() : find_program(o.rayscope);
  if (cli.empty())
    std::printf("  note: rayscope program not found (%s); whole-program time not measured\n",
                o.rayscope.c_str());
  if (sc.file.empty()) cli.clear();  // the built-in scene has no file to pass

  std::ostringstream csv;
  for (const PeerConfig& pc : configs) {
    // RayScope's cutoff, like POV-Ray's adc_bailout, applies to a ray's weight
    // within its sample, whatever the antialiasing: the same threshold.
    RenderSettings prs = settings_for(o, pc.n, o.peer_depth, o.peer_cutoff);
    const std::string our_png = sc.name + "_rayscope_" + pc.name + ".png";
    const std::string cli_png = sc.name + "_rayscope_cli_" + pc.name + ".png";
    const std::string pov_png = sc.name + "_povray_" + pc.name + ".png";
    const std::string cli_cmd =
        shell_quote(cli) + " render -q " + shell_quote(fs::absolute(sc.file).string()) +
        " --size " + std::to_string(o.width) + "x" + std::to_string(o.height) + " --spp " +
        std::to_string(pc.n) + " --max-depth " + std::to_string(o.peer_depth) +
        " --min-contribution " + fmt("%.9g", prs.min_contribution) + " --seed 0 --threads " +
        std::to_string(o.threads) + " -o " + shell_quote((dir / cli_png).string());
    std::vector<double> setup, our_render, cli_wall, pv_wall, pv_parse, pv_bound, pv_trace;
    RayCounters our_c;
    PovRun last{};
    for (int r = 0; r < runs + 1; ++r) {  // round 0 is a warm-up for all
      // In this process: parse the scene file, read the mesh, build the BVH
      // (setup), render (timed alone), write the PNG.
      auto t0 = Clock::now();
      LoadedScene l = load_case(sc.name, sc.file);
      l.scene.commit();
      const double ts = seconds_since(t0);
      auto t1 = Clock::now();
      RayCounters c;
      Framebuffer fb = render(l.scene, prs, &c);
      const double tr = seconds_since(t1);
      write_image(dir / our_png, fb);
      const double tc = cli.empty() ? NAN : run_process("rayscope", cli_cmd, dir / cli_png).wall;
      PovRun pr = run_povray(povray, dir, pov, pov_png, o, pc.pov_aa);
      if (r == 0) continue;
      setup.push_back(ts);
      our_render.push_back(tr);
      cli_wall.push_back(tc);
      our_c = c;
      pv_wall.push_back(pr.wall);
      pv_parse.push_back(pr.parse);
      pv_bound.push_back(pr.bounding);
      pv_trace.push_back(pr.trace);
      last = pr;
    }
    // How alike the images are (8-bit sRGB PNGs as written).
    auto agree = [&](const std::string& f1, const std::string& f2, double& rmse, double& ss) {
      int w1, h1, w2, h2;
      Rgb a = read_image_rgb(dir / f1, w1, h1), b = read_image_rgb(dir / f2, w2, h2);
      double psnr;
      rmse = ss = NAN;
      if (w1 != w2 || h1 != h2) return;
      rmse_psnr(a, b, w1, h1, rmse, psnr);
      ss = ssim(srgb_luma(a, true), srgb_luma(b, true), w1, h1);
    };
    double rmse, ss;
    agree(our_png, pov_png, rmse, ss);
    const double ost = median(setup), orr = median(our_render), oc = median(cli_wall),
                 pw = median(pv_wall), pt = median(pv_trace), pp = median(pv_parse),
                 pb = median(pv_bound);
    const double our_tree =
        double(our_c.rays[int(RayKind::Primary)] + our_c.rays[int(RayKind::Reflection)] +
               our_c.rays[int(RayKind::Refraction)]);
    std::printf(
        "  %s: RayScope %dx%d samples per pixel, cutoff %g per sample; "
        "POV-Ray %s, adc_bailout %g\n",
        pc.name.c_str(), pc.n, pc.n, double(prs.min_contribution), pc.pov_aa_desc.c_str(),
        double(o.peer_cutoff));
    std::printf(
        "    render only    RayScope %7.3f s   POV-Ray %7.3f s   POV-Ray/RayScope %.2f"
        "   (render(); POV-Ray's Trace Time)\n",
        orr, pt, pt / orr);
    if (!cli.empty()) {
      double crmse, css;
      agree(our_png, cli_png, crmse, css);
      std::printf(
          "    whole program  RayScope %7.3f s   POV-Ray %7.3f s   POV-Ray/RayScope %.2f"
          "   (`rayscope render` and `povray` processes, start to exit)\n",
          oc, pw, pw / oc);
      if (crmse != 0.0)
        std::printf("    warning: rayscope's image differs from this process's (RMSE %g)\n", crmse);
    }
    std::printf(
        "    setup          RayScope %7.3f s (scene file, mesh, BVH, in process); POV-Ray "
        "parse %.3f s + bounding %.3f s\n",
        ost, pp, pb);
    std::printf(
        "    rays           RayScope %.4g camera/reflection/refraction + %.4g shadow; "
        "POV-Ray %.4g (reflected %.4g, transmitted %.4g) + %.4g shadow tests\n",
        our_tree, double(our_c.rays[int(RayKind::Shadow)]), last.rays, last.reflected,
        last.refracted, last.shadow_tests);
    std::printf("    images         %s vs %s: sRGB RMSE %.4f, SSIM %.4f\n", our_png.c_str(),
                pov_png.c_str(), rmse, ss);
    std::fflush(stdout);
    auto row = [&](const char* who, double process_s, double render_s, double setup_s, double tree,
                   double shadow, const std::string& png) {
      csv << sc.name << "," << o.width << "," << o.height << "," << o.threads << "," << pc.name
          << "," << who << "," << runs << "," << process_s << "," << render_s << "," << setup_s
          << "," << tree << "," << shadow << "," << png << "," << rmse << "," << ss << "\n";
    };
    row("rayscope", oc, orr, ost, our_tree, double(our_c.rays[int(RayKind::Shadow)]), our_png);
    row("povray", pw, pt, pp + pb, last.rays, last.shadow_tests, pov_png);
  }
  return csv.str();
}

// ---------------------------------------------------------------------------

std::vector<float> parse_floats(const std::string& s, const std::string& what = "--cutoffs") {
  std::vector<float> v;
  std::stringstream ss(s);
  std::string t;
  while (std::getline(ss, t, ',')) {
    size_t used = 0;
    float f = -1.0f;
    try {
      f = std::stof(t, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != t.size() || !(f >= 0.0f && f <= 1.0f))
      throw std::invalid_argument(what + ": expected numbers in [0, 1], got '" + t + "'");
    v.push_back(f);
  }
  return v;
}

int run(Options& o) {
  int used = 0;
  if (std::sscanf(o.res.c_str(), "%dx%d%n", &o.width, &o.height, &used) != 2 ||
      size_t(used) != o.res.size() || o.width < 16 || o.height < 16 || o.width > 8192 ||
      o.height > 8192)
    throw std::invalid_argument("--res: expected WIDTHxHEIGHT (16..8192), got '" + o.res + "'");
  fs::create_directories(o.out);

  std::printf("bench_quality: %dx%d, %d thread(s), %d run(s), output %s\n", o.width, o.height,
              o.threads, o.runs, o.out.string().c_str());
  std::printf("  sweep: N in {");
  for (int n : o.spp) std::printf(" %d", n);
  std::printf(" } (N x N spp), depth in {");
  for (int d : o.depths) std::printf(" %d", d);
  std::printf(" }, cutoff in {");
  for (float c : o.cutoffs) std::printf(" %g", double(c));
  std::printf(" }; N stops at %.2f s per render or an RMSE gain below %.0f%%\n", o.max_seconds,
              o.min_gain * 100);
  std::printf("  reference: %dx%d spp, depth %d, cutoff %g per sample\n", o.ref_spp, o.ref_spp,
              o.ref_depth, double(o.ref_cutoff));
  std::printf("  errors: RMSE/PSNR on linear RGB; SSIM on sRGB luma (11x11 Gaussian)\n");

  std::ostringstream qcsv, rcsv;
  qcsv << "scene,width,height,threads,spp_n,spp,max_depth,min_contribution,runs,time_s,"
          "time_min_s,"
       << kRaysHeader
       << ",depth_cutoffs,weight_cutoffs,mrays_per_s,rmse_linear,psnr_linear_db,ssim_srgb_luma,"
          "pareto_rmse,pareto_ssim,kind,texture_filter,max_spp_n,target_error,mean_spp\n";
  rcsv << "scene,width,height,spp,max_depth,min_contribution,time_s," << kRaysHeader
       << ",tree_rays_per_primary,bound_tree_rays_per_primary,lights,triangles_spheres_planes,"
          "bound_rays_total\n";
  std::string peer_rows;
  const auto t_start = Clock::now();
  int failures = 0, done = 0;

  for (const std::string& arg : o.scenes) {
    SceneCase sc;
    sc.name = scene_label(arg);
    if (o.peer_only && sc.name != o.peer_scene) continue;
    if (arg != "default") sc.file = scene_path(o, arg);
    std::printf("\n== Scene %s ==\n", sc.name.c_str());
    try {
      auto t0 = Clock::now();
      sc.loaded = load_case(arg, sc.file);
      if (!sc.file.empty()) {
        std::ifstream f(sc.file, std::ios::binary);
        std::stringstream text;
        text << f.rdbuf();
        sc.hash = fnv1a(text.str());
      }
      sc.loaded.scene.commit();
      const SceneSummary& sum = sc.loaded.scene.summary();
      std::printf("  %zu triangles, %zu spheres, %zu planes, %zu lights; loaded in %.2f s\n",
                  sum.triangles, sum.spheres, sum.planes, sum.lights, seconds_since(t0));
    } catch (const std::exception& e) {
      std::printf("  scene %s skipped: %s\n", sc.name.c_str(), e.what());
      ++failures;
      continue;
    }
    Scene& scene = sc.loaded.scene;
    const SceneSummary& sum = scene.summary();
    const double pixels = double(o.width) * o.height;

    auto peer = [&] {
      if (o.no_peer || sc.name != o.peer_scene) return;
      try {
        peer_rows += peer_comparison(o, sc);
      } catch (const std::exception& e) {
        std::printf("peer: %s\n", e.what());
        ++failures;
      }
    };
    if (o.peer_only) {
      peer();
      continue;
    }

    // Warm-up (page faults, thread pool).
    timed_render(scene, settings_for(o, 1, 5, 1e-3f), nullptr, nullptr);

    const Rgb ref = reference_image(o, sc);
    {
      // The reference's own cutoff error: 1 spp at its cutoff and at 1/100 of it.
      RayCounters c1, c2;
      Framebuffer a, b;
      timed_render(scene, settings_for(o, 1, o.ref_depth, o.ref_cutoff), &c1, &a);
      timed_render(scene, settings_for(o, 1, o.ref_depth, o.ref_cutoff / 100), &c2, &b);
      Metrics m = compare_linear(to_rgb(a), to_rgb(b), o.width, o.height);
      std::printf(
          "  reference cutoff check (1 spp, depth %d): cutoff %g vs %g: RMSE %.2e, "
          "SSIM %.6f (rays %.3g vs %.3g)\n",
          o.ref_depth, double(o.ref_cutoff), double(o.ref_cutoff / 100), m.rmse, m.ssim,
          double(c1.total_rays()), double(c2.total_rays()));
    }

    // Rays against depth (1 spp).
    std::printf(
        "\n  Rays against depth (1 spp, %.0f primary rays; lecture worst case: a full "
        "binary tree, 2^(r+1)-1 rays per primary ray):\n",
        pixels);
    std::printf("  %5s %12s", "depth", "bound/prim");
    for (float c : o.cutoffs)
      std::printf("   cut %-6s rays/prim   total rays", cutoff_str(c).c_str());
    std::printf("\n");
    // Every (depth, cutoff) once per round, --rays-runs rounds (these renders
    // are short, so more of them); the counts are the same in every round
    // (renders are deterministic).
    std::map<std::pair<int, float>, double> t1;  // median 1 spp time by (depth, cutoff)
    std::vector<RaysRow> rays_rows;
    for (int d = 0; d <= o.rays_max_depth; ++d)
      for (float c : o.cutoffs) rays_rows.push_back({d, c, 0.0, {}});
    std::vector<std::vector<double>> rays_times(rays_rows.size());
    for (int r = 0; r < o.rays_runs; ++r)
      for (size_t k = 0; k < rays_rows.size(); ++k) {
        RaysRow& row = rays_rows[k];
        RayCounters rc;
        rays_times[k].push_back(
            timed_render(scene, settings_for(o, 1, row.depth, row.cutoff), &rc, nullptr));
        row.c = rc;
      }
    const double nprims = double(sum.triangles + sum.spheres + sum.planes);
    for (size_t k = 0; k < rays_rows.size(); ++k) {
      RaysRow& row = rays_rows[k];
      row.time = median(rays_times[k]);
      t1[{row.depth, row.cutoff}] = row.time;
      const RayCounters& rc = row.c;
      const double bound = std::ldexp(1.0, row.depth + 1) - 1.0;
      const double tree = double(rc.rays[0] + rc.rays[2] + rc.rays[3]) / double(rc.rays[0]);
      if (row.cutoff == o.cutoffs.front()) std::printf("  %5d %12.0f", row.depth, bound);
      std::printf("   %16.3f %12.4g", tree, double(rc.total_rays()));
      if (row.cutoff == o.cutoffs.back()) std::printf("\n");
      rcsv << sc.name << "," << o.width << "," << o.height << ",1," << row.depth << ","
           << cutoff_str(row.cutoff) << "," << row.time << "," << rays_csv(rc) << "," << tree << ","
           << bound << "," << sum.lights << "," << nprims << ","
           << pixels * bound * (1.0 + double(sum.lights)) << "\n";
    }
    std::fflush(stdout);
    write_atomic(o.out / "rays_vs_depth.csv", rcsv.str());

    // Time against error. Round 1 walks each (depth, cutoff) with N ascending
    // and measures the error; N stops growing when the render would take
    // longer than --max-seconds, or when the RMSE fell by less than
    // --min-gain against the previous N (the depth or cutoff error then
    // dominates: more samples only cost time). Later rounds time the same
    // configurations again, one render of each per round.
    std::vector<int> spp = o.spp;
    std::sort(spp.begin(), spp.end());
    std::vector<QualityRow> rows;
    int over_time = 0, saturated = 0;
    for (int d : o.depths)
      for (float c : o.cutoffs) {
        auto it = t1.find({d, c});
        const double base = it != t1.end()
                                ? it->second
                                : timed_render(scene, settings_for(o, 1, d, c), nullptr, nullptr);
        double prev_rmse = -1;
        for (size_t k = 0; k < spp.size(); ++k) {
          const int n = spp[k];
          if (base * n * n > o.max_seconds) {
            over_time += int(spp.size() - k);
            break;
          }
          QualityRow q{n, d, c, {}, {}, {}};
          Framebuffer fb;
          q.times.push_back(timed_render(scene, settings_for(o, n, d, c), &q.c, &fb));
          q.m = compare_linear(to_rgb(fb), ref, o.width, o.height);
          rows.push_back(q);
          if (prev_rmse >= 0 && q.m.rmse > (1.0 - o.min_gain) * prev_rmse) {
            saturated += int(spp.size() - k - 1);
            break;
          }
          prev_rmse = q.m.rmse;
        }
      }
    const size_t fixed_rows = rows.size();
    if (!o.no_frontier) {
      auto measure = [&](QualityRow q) {
        Framebuffer fb;
        q.times.push_back(timed_render(
            scene, settings_for(o, q.n, q.depth, q.cutoff, q.filter, q.max_n, q.target), &q.c,
            &fb));
        q.m = compare_linear(to_rgb(fb), ref, o.width, o.height);
        rows.push_back(q);
        return q;
      };
      for (int d : o.frontier_depths)
        for (float c : o.frontier_cutoffs) {
          // Filtered N x N: N rises as for the fixed configurations.
          const double base = timed_render(scene, settings_for(o, 1, d, c, true), nullptr, nullptr);
          double prev_rmse = -1;
          for (int n : spp) {
            if (base * n * n > o.max_seconds) break;
            QualityRow q{n, d, c, {}, {}, {}};
            q.filter = true;
            q = measure(q);
            if (prev_rmse >= 0 && q.m.rmse > (1.0 - o.min_gain) * prev_rmse) break;
            prev_rmse = q.m.rmse;
          }
          // Adaptive, with and without the filter.
          for (auto [b, m] : o.adaptive)
            for (float t : o.targets)
              for (bool f : {false, true}) {
                QualityRow q{b, d, c, {}, {}, {}};
                q.filter = f;
                q.max_n = m;
                q.target = t;
                measure(q);
              }
        }
    }
    std::printf(
        "\n  Time against error: %zu configurations rendered (%zu fixed-sample, %zu filtered or "
        "adaptive); not rendered: %d estimated slower than %.2f s, %d beyond an N whose RMSE "
        "gain was below %.0f%%\n",
        rows.size(), fixed_rows, rows.size() - fixed_rows, over_time, o.max_seconds, saturated,
        o.min_gain * 100);
    std::printf("  round 1 done (%.0f s so far)\n", seconds_since(t_start));
    std::fflush(stdout);
    for (int r = 1; r < o.runs; ++r) {
      for (QualityRow& q : rows)
        q.times.push_back(timed_render(
            scene, settings_for(o, q.n, q.depth, q.cutoff, q.filter, q.max_n, q.target), nullptr,
            nullptr));
      std::printf("  round %d done (%.0f s so far)\n", r + 1, seconds_since(t_start));
      std::fflush(stdout);
    }
    mark_pareto(rows, false);
    mark_pareto(rows, true);
    std::sort(rows.begin(), rows.end(), [](const QualityRow& a, const QualityRow& b) {
      return median(a.times) < median(b.times);
    });
    std::printf("  Pareto front (time against linear RMSE; * also on the 1-SSIM front):\n");
    std::printf("  %-17s %7s %7s %5s %7s %10s %11s %10s %9s %9s\n", "kind", "spp", "target",
                "depth", "cutoff", "time ms", "rays", "RMSE", "PSNR dB", "SSIM");
    auto print_row = [&](const QualityRow& q, const char* tail) {
      std::printf("  %-17s %7s %7s %5d %7s %10.2f %11.4g %10.3e %9.2f %9.5f%s\n", q.kind().c_str(),
                  q.spp_label().c_str(), q.max_n > 0 ? fmt("%g", double(q.target)).c_str() : "-",
                  q.depth, cutoff_str(q.cutoff).c_str(), median(q.times) * 1e3,
                  double(q.c.total_rays()), q.m.rmse, q.m.psnr, q.m.ssim, tail);
    };
    for (const QualityRow& q : rows) {
      const double t = median(q.times);
      if (q.pareto_rmse) print_row(q, q.pareto_ssim ? " *" : "");
      qcsv << sc.name << "," << o.width << "," << o.height << "," << o.threads << "," << q.n << ","
           << q.n * q.n << "," << q.depth << "," << cutoff_str(q.cutoff) << "," << q.times.size()
           << "," << t << "," << *std::min_element(q.times.begin(), q.times.end()) << ","
           << rays_csv(q.c) << "," << q.c.depth_cutoffs << "," << q.c.weight_cutoffs << ","
           << double(q.c.total_rays()) / t * 1e-6 << "," << q.m.rmse << "," << q.m.psnr << ","
           << q.m.ssim << "," << int(q.pareto_rmse) << "," << int(q.pareto_ssim) << "," << q.kind()
           << "," << int(q.filter) << "," << q.max_n << "," << q.target << ","
           << double(q.c.rays[int(RayKind::Primary)]) / pixels << "\n";
    }
    write_atomic(o.out / "quality.csv", qcsv.str());
    // The cheapest configuration of each kind reaching each RMSE, and the
    // cheapest fixed-sample time over the cheapest time of all (same run).
    std::printf(
        "\n  Cheapest configuration reaching an RMSE (median times of this run; ratio = cheapest "
        "fixed-sample time / this time):\n");
    std::printf("  %-8s %-17s %7s %7s %5s %7s %10s %10s %11s %7s\n", "RMSE <=", "kind", "spp",
                "target", "depth", "cutoff", "time ms", "RMSE", "mean spp", "ratio");
    for (double thr : {0.035, 0.02, 0.015, 0.01, 0.0075}) {
      const QualityRow* fixed_best = nullptr;
      std::map<std::string, const QualityRow*> best;
      for (const QualityRow& q : rows) {
        if (q.m.rmse > thr) continue;
        const QualityRow*& b = best[q.kind()];
        if (!b || median(q.times) < median(b->times)) b = &q;
      }
      if (best.count("fixed")) fixed_best = best["fixed"];
      for (const char* k : {"fixed", "filtered", "adaptive", "adaptive+filtered"}) {
        auto it = best.find(k);
        if (it == best.end()) {
          std::printf("  %-8g %-17s   (none reaches it)\n", thr, k);
          continue;
        }
        const QualityRow& q = *it->second;
        std::printf(
            "  %-8g %-17s %7s %7s %5d %7s %10.2f %10.3e %11.2f %7s\n", thr, k,
            q.spp_label().c_str(), q.max_n > 0 ? fmt("%g", double(q.target)).c_str() : "-", q.depth,
            cutoff_str(q.cutoff).c_str(), median(q.times) * 1e3, q.m.rmse,
            double(q.c.rays[int(RayKind::Primary)]) / pixels,
            fixed_best ? fmt("%.2f", median(fixed_best->times) / median(q.times)).c_str() : "-");
      }
    }
    std::fflush(stdout);

    peer();
    ++done;
  }
  if (!o.no_peer && std::find_if(o.scenes.begin(), o.scenes.end(), [&](const std::string& n) {
                      return scene_label(n) == o.peer_scene;
                    }) == o.scenes.end())
    std::printf("\npeer: scene %s not among --scenes, skipped\n", o.peer_scene.c_str());
  if (!peer_rows.empty())
    write_atomic(o.out / "peer.csv",
                 "scene,width,height,threads,config,renderer,runs,process_s,render_s,setup_s,"
                 "rays_camera_reflection_refraction,rays_shadow,image,image_rmse_srgb,"
                 "image_ssim\n" +
                     peer_rows);
  if (done == 0 && peer_rows.empty()) {
    std::printf("\nNo scene was measured; nothing written\n");
    return 1;
  }
  std::printf("\nWrote");
  if (!o.peer_only)
    std::printf(" %s, %s", (o.out / "quality.csv").string().c_str(),
                (o.out / "rays_vs_depth.csv").string().c_str());
  if (!peer_rows.empty())
    std::printf("%s %s", o.peer_only ? "" : ",", (o.out / "peer.csv").string().c_str());
  std::printf(" in %.0f s\n", seconds_since(t_start));
  return failures ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{
      "bench_quality: render time against image error, rays against depth, and "
      "POV-Ray on the same scene"};
  std::string cutoffs;
  app.add_option("--out", o.out, "Output folder")->capture_default_str();
  app.add_option("--data", o.data, "Folder of the scene files")->capture_default_str();
  app.add_option("--res", o.res, "Image size WIDTHxHEIGHT")->capture_default_str();
  app.add_option("--runs", o.runs, "Timed renders per configuration (median)")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  app.add_option("--threads", o.threads, "Render threads (and POV-Ray +WT)")
      ->check(CLI::Range(1, 1024))
      ->capture_default_str();
  app.add_option("--scenes", o.scenes, "default, names in --data, or .json paths")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--spp", o.spp, "N values (N x N samples per pixel)")
      ->delimiter(',')
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  app.add_option("--depths", o.depths, "Maximum depths")
      ->delimiter(',')
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  app.add_option("--cutoffs", cutoffs,
                 "Minimum contributions (a ray's weight within its sample); default 0,0.001,0.01");
  app.add_option("--rays-max-depth", o.rays_max_depth, "Rays-against-depth sweep: 0..this")
      ->check(CLI::Range(0, 24))
      ->capture_default_str();
  app.add_option("--rays-runs", o.rays_runs, "Rays-against-depth sweep: rounds (median time)")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  app.add_option("--max-seconds", o.max_seconds,
                 "Stop raising N when a render is estimated slower than this")
      ->check(CLI::Range(1e-3, 1e6))
      ->capture_default_str();
  app.add_option("--min-gain", o.min_gain,
                 "Stop raising N when the RMSE falls by less than this fraction")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--ref-spp", o.ref_spp, "Reference: N (N x N spp)")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  app.add_option("--ref-depth", o.ref_depth, "Reference: maximum depth")
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  app.add_option("--ref-cutoff", o.ref_cutoff,
                 "Reference: minimum contribution of a ray within its sample")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--peer-scene", o.peer_scene, "Scene rendered by POV-Ray too")
      ->capture_default_str();
  app.add_option("--povray", o.povray, "POV-Ray executable")->capture_default_str();
  app.add_option("--rayscope", o.rayscope, "RayScope's program, timed like povray")
      ->capture_default_str();
  app.add_option("--peer-depth", o.peer_depth, "Peer comparison: maximum depth")
      ->check(CLI::Range(0, 60))
      ->capture_default_str();
  app.add_option("--peer-runs", o.peer_runs, "Peer comparison runs (0: --runs)")
      ->capture_default_str()
      ->check(CLI::Range(0, 100));
  std::string frontier_cutoffs, adaptive, targets;
  app.add_option("--frontier-depths", o.frontier_depths,
                 "Filtered and adaptive configurations: maximum depths")
      ->delimiter(',')
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  app.add_option("--frontier-cutoffs", frontier_cutoffs,
                 "Filtered and adaptive configurations: minimum contributions; default 0.01");
  app.add_option("--adaptive", adaptive,
                 "Adaptive sampling configurations B:M (batches of B x B from an M x M grid); "
                 "default 1:4,2:6,2:8");
  app.add_option("--targets", targets,
                 "Adaptive sampling's target errors; default 0.04,0.02,0.01,0.005,0.0025");
  app.add_flag("--no-frontier", o.no_frontier,
               "Only the fixed-sample configurations (no filtered or adaptive ones)");
  app.add_flag("--no-peer", o.no_peer, "Skip the POV-Ray comparison");
  app.add_flag("--peer-only", o.peer_only, "Only the POV-Ray comparison (no sweeps)");
  app.add_flag("--quick", o.quick,
               "Smoke test: 160x120, 1 run, few configurations, small reference");
  CLI11_PARSE(app, argc, argv);
  try {
    if (!cutoffs.empty()) o.cutoffs = parse_floats(cutoffs);
    if (!frontier_cutoffs.empty())
      o.frontier_cutoffs = parse_floats(frontier_cutoffs, "--frontier-cutoffs");
    if (!targets.empty()) o.targets = parse_floats(targets, "--targets");
    if (!adaptive.empty()) {
      o.adaptive.clear();
      std::stringstream ss(adaptive);
      std::string t;
      while (std::getline(ss, t, ',')) {
        int b = 0, m = 0, used = 0;
        RenderSettings probe;
        if (std::sscanf(t.c_str(), "%d:%d%n", &b, &m, &used) != 2 || size_t(used) != t.size())
          throw std::invalid_argument("--adaptive: expected B:M pairs, got '" + t + "'");
        probe.samples = b;
        probe.max_samples = m;
        try {
          probe.validate();
        } catch (const std::invalid_argument& e) {
          throw std::invalid_argument("--adaptive " + t + ": " + e.what());
        }
        o.adaptive.emplace_back(b, m);
      }
    }
    auto dedupe = [](auto& v) {  // keep the first of repeated values, in order
      for (size_t i = 0; i < v.size(); ++i)
        for (size_t j = v.size(); j-- > i + 1;)
          if (v[j] == v[i]) v.erase(v.begin() + long(j));
    };
    dedupe(o.cutoffs);
    dedupe(o.spp);
    dedupe(o.depths);
    dedupe(o.scenes);
    if (o.cutoffs.empty() || o.spp.empty() || o.depths.empty() || o.scenes.empty())
      throw std::invalid_argument("--spp, --depths, --cutoffs and --scenes need a value");
    if (o.quick) {
      if (app.count("--res") == 0) o.res = "160x120";
      if (app.count("--runs") == 0) o.runs = 1;
      if (app.count("--spp") == 0) o.spp = {1, 2, 4};
      if (app.count("--depths") == 0) o.depths = {1, 3, 5};
      if (app.count("--rays-max-depth") == 0) o.rays_max_depth = 6;
      if (app.count("--rays-runs") == 0) o.rays_runs = 1;
      if (app.count("--ref-spp") == 0) o.ref_spp = 6;
      if (app.count("--ref-depth") == 0) o.ref_depth = 10;
      if (app.count("--peer-runs") == 0) o.peer_runs = 1;
    }
    return run(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_quality: %s\n", e.what());
    return 1;
  }
}
