// Cost of ray-tree recording and statistics, and speedups from skipping work.
//
//  - plain:     render() with recording compiled out (NullRecorder).
//  - idle:      render_and_record() with no pixel selected: recording compiled in,
//               present, but idle (one table lookup per pixel).
//  - one pixel: render_and_record() recording one pixel's full tree.
//  - stats:     render() with the statistics policy (per-ray counters, cost AOVs).
// Each is the median of several runs, measured in the same process; ratios are
// against "plain". The target: idle within 1% of plain.
//
// Skipping: the same scene rendered by the integrator specialised for it versus
// the general integrator on an equivalent scene that forces every feature on
// (a light with zero intensity, a mirror with reflectivity so low that no ray
// passes the cutoff... both still cost the checks).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "rayscope/render.h"
#include "rayscope/replay.h"
#include "rayscope/shapes.h"
#include "rayscope_vtkio/mesh_files.h"

using namespace rayscope;

namespace {

double median_seconds(int runs, const std::function<void()>& f) {
  f();  // warm-up
  std::vector<double> t;
  for (int i = 0; i < runs; ++i) {
    auto a = std::chrono::steady_clock::now();
    f();
    auto b = std::chrono::steady_clock::now();
    t.push_back(std::chrono::duration<double>(b - a).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

Scene bunny_scene(const char* path) {
  Scene s = make_default_scene();
  MeshOptions bunny_file;
  bunny_file.file = path;
  TriangleMesh bunny = rayscope_vtkio::load_mesh(bunny_file);
  for (Vec3& p : bunny.positions) p = p * 0.9f + Vec3(-0.2f, 0.89f, -2.0f);
  for (Vec3& n : bunny.normals) n = glm::normalize(n);
  bunny.material = 3;
  s.meshes.push_back(std::move(bunny));
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 7, width = 480, height = 360, threads = 1;
  const char* mesh = "/usr/share/glmark2/models/bunny.obj";
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--runs" && i + 1 < argc)
      runs = std::atoi(argv[++i]);
    else if (a == "--threads" && i + 1 < argc)
      threads = std::atoi(argv[++i]);
    else if (a == "--size" && i + 1 < argc)
      std::sscanf(argv[++i], "%dx%d", &width, &height);
    else if (a == "--mesh" && i + 1 < argc)
      mesh = argv[++i];
    else {
      std::fprintf(stderr,
                   "usage: bench_recording [--runs N] [--threads N] [--size WxH] [--mesh F]\n");
      return 2;
    }
  }
  RenderSettings rs;
  rs.width = width;
  rs.height = height;
  rs.samples = 1;
  rs.threads = threads;

  std::vector<std::pair<std::string, Scene>> scenes;
  scenes.emplace_back("default", make_default_scene());
  try {
    scenes.emplace_back("default+bunny", bunny_scene(mesh));
  } catch (const std::exception& e) {
    std::printf("(bunny scene skipped: %s)\n", e.what());
  }

  std::printf("Recording overhead: %dx%d, 1 spp, %d thread(s), median of %d runs\n", width, height,
              threads, runs);
  std::printf("%-15s %10s %10s %8s %10s %8s %10s %8s\n", "scene", "plain ms", "idle ms", "ratio",
              "1 px ms", "ratio", "stats ms", "ratio");
  for (auto& [name, scene] : scenes) {
    scene.commit();
    std::vector<PixelRecord> records;
    const std::vector<glm::ivec2> none, one = {{width / 2, height / 2}};
    RenderSettings st = rs;
    st.statistics = true;
    // Interleave the variants so that drifts in machine speed hit all of them.
    std::vector<double> tp, ti, t1, ts;
    for (int round = 0; round < 3; ++round) {
      tp.push_back(median_seconds(runs, [&] { render(scene, rs); }));
      ti.push_back(median_seconds(runs, [&] { render_and_record(scene, rs, none, records); }));
      t1.push_back(median_seconds(runs, [&] { render_and_record(scene, rs, one, records); }));
      ts.push_back(median_seconds(runs, [&] { render(scene, st); }));
    }
    auto med = [](std::vector<double> v) {
      std::sort(v.begin(), v.end());
      return v[v.size() / 2];
    };
    double p = med(tp), i = med(ti), o = med(t1), s = med(ts);
    std::printf("%-15s %10.2f %10.2f %8.4f %10.2f %8.4f %10.2f %8.4f\n", name.c_str(), p * 1e3,
                i * 1e3, i / p, o * 1e3, o / p, s * 1e3, s / p);
  }

  // Skipping shadow rays: a scene without lights, rendered by the integrator
  // specialised for it, against the same scene with one light of zero intensity
  // (same image: it adds exactly 0, but its shadow rays are traced).
  std::printf("\nSkipping unneeded work (identical images, %dx%d, 1 spp):\n", width, height);
  Scene lean = make_default_scene();
  lean.lights.clear();
  for (Material& m : lean.materials) m.reflectivity = m.transparency = 0.0f;
  Scene dark = lean;
  Light off;
  off.name = "dark";
  off.position = Vec3(0, 10, 0);
  off.intensity = 0.0f;
  dark.lights.push_back(off);
  lean.commit();
  dark.commit();
  auto compare = [&](const char* what, Scene& fast, Scene& slow) {
    RayCounters cf, cs;
    Framebuffer a = render(fast, rs, &cf), b = render(slow, rs, &cs);
    size_t same = 0;
    for (size_t k = 0; k < a.color.size(); ++k) same += a.color[k] == b.color[k];
    double tf = median_seconds(runs, [&] { render(fast, rs); });
    double ts = median_seconds(runs, [&] { render(slow, rs); });
    std::printf(
        "  %-34s %8.2f ms vs %8.2f ms: %.2fx faster, rays %llu vs %llu, identical pixels "
        "%zu/%zu\n",
        what, tf * 1e3, ts * 1e3, ts / tf, (unsigned long long)cf.total_rays(),
        (unsigned long long)cs.total_rays(), same, a.color.size());
  };
  compare("no lights: no light loop/shadows", lean, dark);

  // Skipping the BVH: 1..4 spheres and a plane, tested directly or through a BVH.
  const std::vector<Sphere> all = {
      Sphere{"a", Vec3(-1.3f, 1, -0.6f), 1, 0}, Sphere{"b", Vec3(0.2f, 0.8f, 1.5f), 0.8f, 0},
      Sphere{"c", Vec3(1.6f, 0.4f, -1), 0.4f, 0}, Sphere{"d", Vec3(-2.2f, 0.3f, 1.2f), 0.3f, 0}};
  for (size_t n = 1; n <= all.size(); ++n) {
    Scene tiny;
    tiny.camera = lean.camera;
    tiny.materials = lean.materials;
    tiny.planes = lean.planes;
    tiny.spheres.assign(all.begin(), all.begin() + long(n));
    tiny.lights = make_default_scene().lights;
    Scene tiny_bvh = tiny;
    tiny.commit();
    AccelConfig always_bvh;
    always_bvh.allow_brute_force = false;
    tiny_bvh.commit(always_bvh);
    std::string what =
        std::to_string(n) +
        (tiny.summary().walks_structure ? " spheres: BVH (default)" : " spheres: no BVH vs BVH");
    compare(what.c_str(), tiny, tiny_bvh);
  }
  return 0;
}
