#include "rayscope/accel/accel_build.h"

#include <stdexcept>
#include <string>
#include <vector>

namespace rayscope {
namespace {

// A cell structure (kD-tree, grid, octree) over the records' bounds (the
// binary BVH's, prim_box()), so that its references are record indices, with
// its builder's own settings and the config's one storage choice and loose
// factor (checked by build_accel() before).
template <class Tree, class BuildConfig>
Tree build_cells(const BuildConfig& own, const AccelConfig& config, size_t count,
                 const RecordSource& record_at, uint32_t num_triangles) {
  std::vector<Bounds3> bounds(count);
  for (size_t i = 0; i < count; ++i) bounds[i] = prim_box(record_at(i), num_triangles).bounds;
  Tree tree;
  tree.build(bounds, own, config.storage, config.loose_factor);
  return tree;
}

}  // namespace

std::string accel_config_error(const AccelConfig& config) {
  if (std::string e = accel_storage_error(config.kind, config.storage); !e.empty()) return e;
  return loose_factor_error(config.loose_factor);
}

AccelStructureVariant build_accel(const AccelConfig& config, const Bvh& built,
                                  std::shared_ptr<const BvhOnDemand> hierarchy,
                                  const RecordSource& record_at, uint32_t num_triangles,
                                  std::chrono::steady_clock::time_point build_start) {
  if (const std::string e = accel_config_error(config); !e.empty()) throw std::invalid_argument(e);
  const size_t count = built.prim_indices.size();
  switch (config.kind) {
    case AccelKind::Bvh:
    case AccelKind::BinaryBvh: {
      BvhWalk walk;
      walk.build(config.kind, built, std::move(hierarchy), record_at, num_triangles);
      walk.set_build_seconds(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - build_start).count());
      return walk;
    }
    case AccelKind::None:
      return BruteForce(uint32_t(count), std::move(hierarchy));
    case AccelKind::KdTree:
      return build_cells<KdTree>(config.kdtree, config, count, record_at, num_triangles);
    case AccelKind::Grid:
      return build_cells<UniformGrid>(config.grid, config, count, record_at, num_triangles);
    case AccelKind::Octree:
      return build_cells<Octree>(config.octree, config, count, record_at, num_triangles);
    case AccelKind::Bsp: {
      // The BSP tree's planes go through the triangles: it is built over
      // their geometry.
      std::vector<BspPrim> prims(count);
      for (size_t i = 0; i < count; ++i) {
        const PrimRecord r = record_at(i);
        prims[i] = r.id < num_triangles            ? BspPrim::triangle(r.a, r.b, r.c)
                   : r.shape == PrimShape::Capsule ? BspPrim::make_capsule(r.a, r.b, r.c.x)
                                                   : BspPrim::make_sphere(r.a, r.b.x);
      }
      BspTree tree;
      tree.build(prims, config.bsp, config.storage);
      return tree;
    }
    case AccelKind::Spheres: {
      // A triangle's smallest enclosing sphere, a sphere itself, the sphere
      // around a capsule's two end balls (its smallest, rounded out).
      std::vector<BoundingSphere> spheres(count);
      for (size_t i = 0; i < count; ++i) {
        const PrimRecord r = record_at(i);
        if (r.id < num_triangles)
          spheres[i] = min_triangle_sphere(r.a, r.b, r.c);
        else if (r.shape == PrimShape::Capsule)
          spheres[i] = enclosing_sphere(BoundingSphere{r.a, r.c.x}, BoundingSphere{r.b, r.c.x});
        else
          spheres[i] = BoundingSphere{r.a, r.b.x};
      }
      SphereTree tree;
      tree.build(spheres, config.spheres);
      return tree;
    }
  }
  throw std::invalid_argument("build_accel: unknown structure");
}

}  // namespace rayscope
