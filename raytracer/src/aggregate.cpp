#include "rayscope/aggregate.h"

#include "rayscope/huge_pages.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace rayscope {
namespace {

// Primitives per task of the parallel fills below (records, leaf blocks):
// large enough that a task's work dwarfs TBB's cost of handing it out.
constexpr size_t kParallelGrain = 16384;

}  // namespace

const char* to_string(AccelKind kind) {
  switch (kind) {
    case AccelKind::Bvh:
      return "bvh";
    case AccelKind::BinaryBvh:
      return "bvh2";
    case AccelKind::None:
      return "none";
    case AccelKind::KdTree:
      return "kdtree";
    case AccelKind::Grid:
      return "grid";
    case AccelKind::Octree:
      return "octree";
    case AccelKind::Bsp:
      return "bsp";
    case AccelKind::Spheres:
      return "spheres";
  }
  return "?";
}

bool parse_accel_kind(std::string_view name, AccelKind& kind) {
  for (AccelKind k : kAccelKinds)
    if (name == to_string(k)) {
      kind = k;
      return true;
    }
  return false;
}

std::string accel_storage_error(AccelKind kind, PrimStorage storage) {
  if (storage == PrimStorage::EveryCell) return {};  // the default: every kind takes it
  const std::string what = std::string("storage ") + to_string(storage) + " is not available for " +
                           to_string(kind) + ": ";
  switch (kind) {
    case AccelKind::Bvh:
    case AccelKind::BinaryBvh:
    case AccelKind::None:
    case AccelKind::Spheres:
      return what +
             "the storage choice is for the spatial subdivisions (kdtree, grid, octree, bsp); a "
             "BVH, a sphere tree or no structure holds each primitive once";
    case AccelKind::KdTree:
    case AccelKind::Grid:
    case AccelKind::Octree:
      if (storage == PrimStorage::SmallestCell) return {};
      return what +
             "the kD-tree, grid and octree store a primitive in every cell it overlaps "
             "(every-cell) "
             "or once in its smallest loose cell (smallest-cell); splitting is the BSP tree's";
    case AccelKind::Bsp:
      return {};  // every-cell, smallest-cell (node lists) and split (fragments)
  }
  return what + "unknown structure";
}

void Aggregate::build(std::span<const Bounds3> bounds, std::span<const Vec3> centroids,
                      const std::function<PrimRecord(size_t)>& record_of, uint32_t num_triangles,
                      std::vector<PlaneRecord> planes, const AccelConfig& config) {
  if (centroids.size() != bounds.size())
    throw std::invalid_argument("Aggregate::build: bounds and centroids differ in size");
  if (const std::string e = accel_storage_error(config.kind, config.storage); !e.empty())
    throw std::invalid_argument(e);
  if (const std::string e = loose_factor_error(config.loose_factor); !e.empty())
    throw std::invalid_argument(e);
  config_ = config;
  num_triangles_ = num_triangles;
  planes_ = std::move(planes);
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  bvh_.build(bounds, centroids, config.bvh);
  reserve_huge(records_, bounds.size());
  records_.resize(bounds.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, records_.size(), kParallelGrain),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t i = r.begin(); i < r.end(); ++i)
                        records_[i] = record_of(bvh_.prim_indices[i]);
                    });
  use_walk_ = config.kind != AccelKind::None &&
              (!config.allow_brute_force || records_.size() > kBruteForceMax);
  walk_ = WideBvh{};
  kdtree_ = KdTree{};
  octree_ = Octree{};
  grid_ = UniformGrid{};
  bsp_ = BspTree{};
  sphere_tree_ = SphereTree{};
  blocks_.clear();
  if (config.kind == AccelKind::Bsp) {
    // Over the records (leaf order), with their geometry: the BSP tree's
    // planes go through the triangles.
    std::vector<BspPrim> prims(records_.size());
    for (size_t i = 0; i < prims.size(); ++i) {
      const PrimRecord& r = records_[i];
      prims[i] = r.id < num_triangles ? BspPrim::triangle(r.a, r.b, r.c)
                                      : BspPrim::make_sphere(r.a, r.b.x);
    }
    BspBuildConfig bsp = config.bsp;
    bsp.storage = config.storage;
    bsp_.build(prims, bsp);
    build_seconds_ = bsp_.quality().build_seconds;
  } else if (config.kind == AccelKind::Spheres) {
    // Over the records (leaf order), so that its prim_indices are record
    // indices: a triangle's smallest enclosing sphere, a sphere itself.
    std::vector<BoundingSphere> spheres(records_.size());
    for (size_t i = 0; i < spheres.size(); ++i) {
      const PrimRecord& r = records_[i];
      spheres[i] =
          r.id < num_triangles ? min_triangle_sphere(r.a, r.b, r.c) : BoundingSphere{r.a, r.b.x};
    }
    sphere_tree_.build(spheres, config.spheres);
    build_seconds_ = sphere_tree_.quality().build_seconds;
  } else if (config.kind == AccelKind::KdTree || config.kind == AccelKind::Grid ||
             config.kind == AccelKind::Octree) {
    // Over the records (leaf order), so that its references are record
    // indices.
    std::vector<Bounds3> leaf_order_bounds(records_.size());
    for (size_t i = 0; i < leaf_order_bounds.size(); ++i)
      leaf_order_bounds[i] = bounds[bvh_.prim_indices[i]];
    // The one storage setting replaces the builder configs' own.
    if (config.kind == AccelKind::KdTree) {
      KdTreeBuildConfig kdtree = config.kdtree;
      kdtree.storage = config.storage;
      kdtree.loose_factor = config.loose_factor;
      kdtree_.build(leaf_order_bounds, kdtree);
      build_seconds_ = kdtree_.quality().build_seconds;
    } else if (config.kind == AccelKind::Grid) {
      GridBuildConfig grid = config.grid;
      grid.storage = config.storage;
      grid.loose_factor = config.loose_factor;
      grid_.build(leaf_order_bounds, grid);
      build_seconds_ = grid_.quality().build_seconds;
    } else {
      OctreeBuildConfig octree = config.octree;
      octree.storage = config.storage;
      octree.loose_factor = config.loose_factor;
      octree_.build(leaf_order_bounds, octree);
      build_seconds_ = octree_.quality().build_seconds;
    }
  } else if (config.kind != AccelKind::None) {
    build_walk(config.kind == AccelKind::BinaryBvh ? 2 : WideBvh::kRenderArity);
    build_seconds_ = std::chrono::duration<double>(Clock::now() - start).count();
  } else {
    build_seconds_ = 0.0;
  }
}

void Aggregate::build_walk(int arity) {
  constexpr int kLanes = TriangleBlock::kLanes;
  // Each leaf's first block (leaves in node order), the walk labelled with
  // them, then the blocks filled leaf by leaf on every core: each leaf writes
  // only its own blocks.
  std::vector<uint32_t> leaves;
  std::vector<uint32_t> leaf_blocks;  // [first record of a leaf]: its first block
  assign_huge(leaf_blocks, records_.size(), ~0u);
  uint32_t count = 0;
  for (uint32_t i = 0; i < bvh_.nodes.size(); ++i) {
    const BvhNode& n = bvh_.nodes[i];
    if (!n.is_leaf()) continue;
    leaves.push_back(i);
    leaf_blocks[n.index] = count;
    count += (n.count + kLanes - 1) / kLanes;
  }
  walk_.build(bvh_, arity, leaf_blocks);
  assign_huge(blocks_, count);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, leaves.size(), kParallelGrain / 4),
                    [&](const tbb::blocked_range<size_t>& range) {
                      for (size_t l = range.begin(); l < range.end(); ++l) {
                        const BvhNode& n = bvh_.nodes[leaves[l]];
                        const uint32_t first = leaf_blocks[n.index];
                        for (uint32_t j = 0; j < n.count; ++j) {
                          TriangleBlock& b = blocks_[first + j / kLanes];
                          const unsigned lane = j % kLanes;
                          if (lane == 0) b.first = n.index + j;
                          const PrimRecord& r = records_[n.index + j];
                          if (r.id >= num_triangles_) {
                            b.others |= uint8_t(1u << lane);
                            continue;
                          }
                          b.triangles |= uint8_t(1u << lane);
                          const Vec3* p[3] = {&r.a, &r.b, &r.c};
                          for (int i = 0; i < 3; ++i)
                            for (int axis = 0; axis < 3; ++axis) b.v[i][axis][lane] = (*p[i])[axis];
                        }
                      }
                    });
}

AccelFigures Aggregate::figures() const {
  AccelFigures f;
  f.build_seconds = build_seconds_;
  const size_t records =
      records_.size() * sizeof(PrimRecord) + planes_.size() * sizeof(PlaneRecord);
  const double prims = double(std::max<size_t>(1, records_.size()));
  switch (config_.kind) {
    case AccelKind::Bvh:
    case AccelKind::BinaryBvh: {
      const BvhQuality q = bvh_.quality();
      f.memory_bytes = walk_.memory_bytes() + triangle_block_bytes() + records;
      f.nodes = walk_.nodes.size() + q.leaves;  // inner wide nodes and the leaves they hold
      f.leaves = q.leaves;
      f.depth = walk_.depth();
      f.refs_per_prim = records_.empty() ? 0.0 : 1.0;
      break;
    }
    case AccelKind::KdTree: {
      const KdTreeQuality q = kdtree_.quality();
      f.memory_bytes = kdtree_.memory_bytes() + records;
      f.nodes = q.nodes;
      f.leaves = q.leaves - q.empty_leaves;
      f.depth = q.depth;
      f.refs_per_prim = double(q.references) / prims;
      break;
    }
    case AccelKind::Octree: {
      const OctreeQuality q = octree_.quality();
      f.memory_bytes = octree_.memory_bytes() + records;
      f.nodes = q.nodes;
      f.leaves = q.leaves;
      f.depth = q.depth;
      f.refs_per_prim = double(q.references) / prims;
      break;
    }
    case AccelKind::Bsp: {
      const BspQuality q = bsp_.quality();
      f.memory_bytes = bsp_.memory_bytes() + records;
      f.nodes = q.nodes;
      f.leaves = q.leaves;
      f.depth = q.depth;
      f.refs_per_prim = double(q.references) / prims;
      f.fragments = q.fragments;
      break;
    }
    case AccelKind::Spheres: {
      const SphereTreeQuality q = sphere_tree_.quality();
      f.memory_bytes = sphere_tree_.memory_bytes() + records;
      f.nodes = q.nodes;
      f.leaves = q.leaves;
      f.depth = q.depth;
      f.refs_per_prim = records_.empty() ? 0.0 : 1.0;
      break;
    }
    case AccelKind::Grid: {
      const GridQuality q = grid_.quality();
      f.memory_bytes = grid_.memory_bytes() + records;
      f.nodes = q.cells;
      f.leaves = q.cells - q.empty_cells;
      f.depth = 1;
      f.refs_per_prim = double(q.references) / prims;
      break;
    }
    case AccelKind::None:
      f.memory_bytes = records;
      f.refs_per_prim = records_.empty() ? 0.0 : 1.0;
      break;
  }
  return f;
}

size_t Aggregate::memory_bytes() const {
  return bvh_.nodes.size() * sizeof(BvhNode) + bvh_.prim_indices.size() * sizeof(uint32_t) +
         walk_.memory_bytes() + triangle_block_bytes() + kdtree_.memory_bytes() +
         grid_.memory_bytes() + octree_.memory_bytes() + bsp_.memory_bytes() +
         sphere_tree_.memory_bytes() + records_.size() * sizeof(PrimRecord) +
         planes_.size() * sizeof(PlaneRecord);
}

}  // namespace rayscope
