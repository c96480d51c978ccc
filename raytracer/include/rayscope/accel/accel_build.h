// The one factory of acceleration structures: builds the kind an AccelConfig
// asks for over the aggregate's records, handing each builder the config's
// one storage choice and loose factor.
#pragma once

#include <chrono>
#include <memory>
#include <span>
#include <variant>

#include "rayscope/accel/accel_config.h"
#include "rayscope/accel/brute_force.h"
#include "rayscope/accel/bvh_walk.h"
#include "rayscope/accel/prim_record.h"

namespace rayscope {

/// Every structure the aggregate can walk, one alternative per AccelKind
/// (Bvh and BinaryBvh share BvhWalk, at arity 8 or 2).
using AccelStructureVariant =
    std::variant<BvhWalk, BruteForce, KdTree, UniformGrid, Octree, BspTree, SphereTree>;

static_assert(AccelStructure<BvhWalk> && AccelStructure<BruteForce> && AccelStructure<KdTree> &&
              AccelStructure<UniformGrid> && AccelStructure<Octree> && AccelStructure<BspTree> &&
              AccelStructure<SphereTree>);

/// Builds config.kind over `records`, the primitives in the leaf order of
/// `hierarchy` (the binary BVH built over `bounds`, the primitives' bounds in
/// the scene's order: records[i] is primitive hierarchy->prim_indices[i]);
/// records with id >= num_triangles are spheres or capsules (by their
/// PrimRecord::shape). Throws
/// std::invalid_argument when accel_config_error(config) says why not.
/// `build_start`: when the binary BVH's build began (the BVH kinds count it
/// in their build time).
AccelStructureVariant build_accel(const AccelConfig& config, std::shared_ptr<const Bvh> hierarchy,
                                  std::span<const PrimRecord> records,
                                  std::span<const Bounds3> bounds, uint32_t num_triangles,
                                  std::chrono::steady_clock::time_point build_start);

}  // namespace rayscope
