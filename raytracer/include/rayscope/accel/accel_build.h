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
#include "rayscope/accel/bvh_on_demand.h"
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

/// Builds config.kind over the primitives in the leaf order of `built` (the
/// binary BVH built over their prim_box()es in the scene's order):
/// record_at(i) is primitive built.prim_indices[i], called once for each i
/// (the BVH walk calls it from several threads at once); records with id >=
/// num_triangles are spheres, points or capsules (by their PrimRecord::shape).
/// `hierarchy` is `built` as the tools ask for it later, kept by the
/// structures that show it. Throws std::invalid_argument when
/// accel_config_error(config) says why not. `build_start`: when the binary
/// BVH's build began (the BVH kinds count it in their build time).
AccelStructureVariant build_accel(const AccelConfig& config, const Bvh& built,
                                  std::shared_ptr<const BvhOnDemand> hierarchy,
                                  const RecordSource& record_at, uint32_t num_triangles,
                                  std::chrono::steady_clock::time_point build_start);

}  // namespace rayscope
