// bench_intersect: cost per call of the primitive tests in rayscope/intersect.h.
// Each benchmark cycles through 1024 fixed pseudo-random rays, about half of
// which hit the primitive, so that neither the branch predictor nor the
// compiler can learn a single answer.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "rayscope/intersect.h"

namespace {

using namespace rayscope;

constexpr size_t kRays = 1024;  // power of two: index with a mask

struct Rays {
  std::vector<Ray> rays;
  std::vector<TrianglePrecomp> pre;
  std::vector<Vec3> inv_dir;
};

// Rays from points around z = -3 toward random points of the square [-1, 1]^2
// in the plane z = 0, where the primitives sit.
const Rays& rays() {
  static const Rays r = [] {
    Rays r;
    std::mt19937 rng(12345);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (size_t i = 0; i < kRays; ++i) {
      Vec3 o(0.2f * u(rng), 0.2f * u(rng), -3.0f);
      Vec3 target(u(rng), u(rng), 0.0f);
      Ray ray{o, target - o, kInfinity};
      r.rays.push_back(ray);
      r.pre.emplace_back(ray);
      r.inv_dir.push_back(1.0f / ray.dir);
    }
    return r;
  }();
  return r;
}

void BM_TrianglePrecomp(benchmark::State& state) {
  const Rays& r = rays();
  size_t i = 0;
  for (auto _ : state) {
    TrianglePrecomp pre(r.rays[i]);
    benchmark::DoNotOptimize(pre);
    i = (i + 1) & (kRays - 1);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_TrianglePrecomp);

void BM_IntersectTriangle(benchmark::State& state) {
  const Rays& r = rays();
  const Vec3 p0(-1.0f, -1.0f, 0.0f), p1(1.0f, -1.0f, 0.0f), p2(0.0f, 1.0f, 0.0f);
  size_t i = 0, hits = 0;
  for (auto _ : state) {
    TriangleHit hit;
    bool h = intersect_triangle(r.pre[i], r.rays[i].tmax, p0, p1, p2, hit);
    benchmark::DoNotOptimize(h);
    benchmark::DoNotOptimize(hit);
    hits += h;
    i = (i + 1) & (kRays - 1);
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["hit_rate"] = double(hits) / double(state.iterations());
}
BENCHMARK(BM_IntersectTriangle);

void BM_IntersectSphere(benchmark::State& state) {
  const Rays& r = rays();
  const Vec3 center(0.0f);
  size_t i = 0, hits = 0;
  for (auto _ : state) {
    float t = 0.0f;
    bool h = intersect_sphere(r.rays[i], center, 0.8f, kInfinity, t);
    benchmark::DoNotOptimize(h);
    benchmark::DoNotOptimize(t);
    hits += h;
    i = (i + 1) & (kRays - 1);
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["hit_rate"] = double(hits) / double(state.iterations());
}
BENCHMARK(BM_IntersectSphere);

void BM_IntersectBox(benchmark::State& state) {
  const Rays& r = rays();
  const Vec3 lo(-0.7f, -0.7f, -0.1f), hi(0.7f, 0.7f, 0.1f);
  size_t i = 0, hits = 0;
  for (auto _ : state) {
    float t = intersect_box(lo, hi, r.rays[i].origin, r.inv_dir[i], kInfinity);
    benchmark::DoNotOptimize(t);
    hits += t != kInfinity;
    i = (i + 1) & (kRays - 1);
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["hit_rate"] = double(hits) / double(state.iterations());
}
BENCHMARK(BM_IntersectBox);

}  // namespace

BENCHMARK_MAIN();
