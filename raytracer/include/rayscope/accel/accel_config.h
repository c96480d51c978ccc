// How the aggregate builds its structure: the kind (accel_kind.h), the one
// storage choice and loose factor for every structure, and each builder's
// own settings.
#pragma once

#include "rayscope/accel/accel_kind.h"
#include "rayscope/accel/bsp.h"
#include "rayscope/accel/bvh.h"
#include "rayscope/accel/grid.h"
#include "rayscope/accel/kdtree.h"
#include "rayscope/accel/octree.h"
#include "rayscope/accel/prim_storage.h"
#include "rayscope/accel/sphere_tree.h"

namespace rayscope {

/// How commit() builds the aggregate; every field has a documented default.
struct AccelConfig {
  AccelKind kind = AccelKind::Bvh;
  BvhBuildConfig bvh;        ///< Settings of the SAH builder (bvh.h).
  KdTreeBuildConfig kdtree;  ///< Settings of the kD-tree builder (kdtree.h), for AccelKind::KdTree.
  GridBuildConfig grid;      ///< Settings of the grid builder (grid.h), for AccelKind::Grid.
  OctreeBuildConfig octree;  ///< Settings of the octree builder (octree.h), for AccelKind::Octree.
  BspBuildConfig bsp;        ///< Settings of the BSP builder (bsp.h), for AccelKind::Bsp.
  /// Settings of the sphere tree builder (sphere_tree.h), for AccelKind::Spheres.
  SphereTreeBuildConfig spheres;
  /// How a spatial subdivision stores a primitive that straddles its cuts: the
  /// one setting for every structure, checked by accel_storage_error() (the
  /// BVH kinds and the sphere tree take only the default, every-cell; the BSP
  /// tree also takes split). The factory (accel_build.h) hands it to the
  /// builder as an argument of its build().
  PrimStorage storage = PrimStorage::EveryCell;
  /// SmallestCell's loose factor, the one setting for the kD-tree, grid and
  /// octree (handed to their builders like `storage`): each cell enlarged by
  /// this fraction of its extent on every side, 0 .. kMaxLooseFactor, checked
  /// by loose_factor_error() (Aggregate::build throws std::invalid_argument
  /// with it).
  float loose_factor = kDefaultLooseFactor;
  /// Let scenes with at most Aggregate::kBruteForceMax bounded primitives skip
  /// the structure and test them all. Off only to measure what the skip saves.
  bool allow_brute_force = true;
};

/// Why `config` cannot be built, in one line; empty when it can: the storage
/// the kind cannot take (accel_storage_error()) or a loose factor out of
/// range (loose_factor_error()). The one check of a whole configuration.
std::string accel_config_error(const AccelConfig& config);

}  // namespace rayscope
