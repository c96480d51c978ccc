// How many fragments the BSP tree's split storage makes as n grows (lecture:
// "a general BSP tree needs O(n^2) fragments in the worst case, about
// O(n log n) in practice").
//
// Usage: bench_bsp_fragments [MESH]   (default: /usr/share/glmark2/models/bunny.obj)
//
// For random triangle soups (uniform centers in a cube, edges about 1/20 of
// it, random orientations) and for the first n triangles of the mesh (in file
// order, so a connected patch that grows), builds BspTree with
// PrimStorage::Split and the default BspBuildConfig, and prints n, fragments,
// fragments / n, fragments / (n log2 n), triangles cut, depth and build time.
// Deterministic (fixed seed); no timing is asserted.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "rayscope/accel/bsp.h"
#include "rayscope/scene_io.h"
#include "rayscope_vtkio/mesh_files.h"

namespace {

using namespace rayscope;

void row(const char* what, const std::vector<BspPrim>& prims) {
  BspTree t;
  t.build(prims, {}, PrimStorage::Split);
  const BspQuality q = t.quality();
  const double n = double(prims.size());
  std::printf("%-6s %8zu %10zu %8.2f %10.3f %9zu %6u %9.3f\n", what, prims.size(), q.fragments,
              double(q.fragments) / n, double(q.fragments) / (n * std::log2(n)), q.split_prims,
              q.depth, q.build_seconds);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mesh_file = argc > 1 ? argv[1] : "/usr/share/glmark2/models/bunny.obj";
  std::printf("%-6s %8s %10s %8s %10s %9s %6s %9s\n", "input", "n", "fragments", "frag/n",
              "/(nlog2n)", "cut", "depth", "build s");
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (size_t n : {250u, 1000u, 4000u, 16000u, 64000u}) {
    std::vector<BspPrim> soup;
    for (size_t i = 0; i < n; ++i) {
      const Vec3 c(u(rng), u(rng), u(rng));
      auto corner = [&] { return c + 0.05f * Vec3(u(rng), u(rng), u(rng)); };
      soup.push_back(BspPrim::triangle(corner(), corner(), corner()));
    }
    row("soup", soup);
  }
  if (!std::filesystem::exists(mesh_file)) {
    std::printf("mesh: %s not found, skipped\n", mesh_file.c_str());
    return 0;
  }
  MeshOptions options;
  options.file = mesh_file;
  options.smooth = false;
  const TriangleMesh mesh = rayscope_vtkio::load_mesh(options);
  for (size_t n : {250u, 1000u, 4000u, 16000u, 64000u}) {
    if (n > mesh.triangles.size()) break;
    std::vector<BspPrim> prims;
    for (size_t i = 0; i < n; ++i) {
      const glm::uvec3& t = mesh.triangles[i];
      prims.push_back(
          BspPrim::triangle(mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z]));
    }
    row("mesh", prims);
  }
  return 0;
}
