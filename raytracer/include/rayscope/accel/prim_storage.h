// How a spatial subdivision (kD-tree, grid, octree, BSP tree) stores an
// extended primitive that straddles a cell boundary: the lecture's three
// solutions ("Extended objects").
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "rayscope/math.h"

namespace rayscope {

enum class PrimStorage : uint8_t {
  /// "Store multiple times": a reference in every cell the primitive's bounds
  /// overlap; the walk tests it once per query all the same (mailbox.h).
  EveryCell,
  /// "Overlapping regions": cells enlarged by a loose factor, each primitive
  /// stored once, in the smallest cell whose enlarged box holds it (an inner
  /// node when it fits no child).
  SmallestCell,
  /// "Split objects": the primitive cut at the plane into fragments (the BSP
  /// tree's choice).
  Split,
};

/// Every storage choice, in the order the tools list them.
inline constexpr PrimStorage kPrimStorages[] = {PrimStorage::EveryCell, PrimStorage::SmallestCell,
                                                PrimStorage::Split};
/// "every-cell", "smallest-cell", "split".
const char* to_string(PrimStorage storage);
/// Parses the names to_string() gives; false for anything else.
bool parse_prim_storage(std::string_view name, PrimStorage& storage);

/// SmallestCell's loose factor: every cell's box is enlarged by this fraction
/// of its extent on every side. The lecture's 10%: a loose cell 1.2 times the
/// side, 1.2^3 = 1.73 times the volume of a cube.
inline constexpr float kDefaultLooseFactor = 0.1f;
/// The largest loose factor any structure takes (one range for all): a loose
/// grid cell then reaches half a cell into its 26 neighbours and no further,
/// so a ray that reaches a cell need only look at the lists of the cell and
/// its neighbours (grid.h).
inline constexpr float kMaxLooseFactor = 0.5f;
/// Why `factor` is no loose factor, in one line (no trailing period); empty
/// when it is one (finite, 0 <= factor <= kMaxLooseFactor). The one check:
/// build_accel() (accel_build.h) throws std::invalid_argument with it, the
/// CLI prints it; the builders take only factors it accepts.
std::string loose_factor_error(float factor);
/// "every-cell", "smallest-cell (loose factor F)" or "split": how the tools
/// name a structure's storage.
std::string storage_text(PrimStorage storage, float loose_factor);

/// `cell` enlarged by `factor` times its extent on every side: the loose box
/// of SmallestCell storage. The builders and the walks compute loose boxes
/// only this way, so they agree bit for bit.
inline Bounds3 loose_box(const Bounds3& cell, float factor) {
  const Vec3 e = factor * cell.extent();
  Bounds3 b;
  b.lo = cell.lo - e;
  b.hi = cell.hi + e;
  return b;
}

/// What a tree of cells holds, counted the same way for every structure whose
/// nodes store reference lists (`is_leaf()`, `count`): leaves, the deepest
/// level, references held by leaves and by inner nodes (smallest-cell and the
/// BSP node lists), the largest leaf list, the mean over the leaves.
struct CellRefCounts {
  uint32_t leaves = 0, depth = 0, max_leaf_refs = 0;
  size_t leaf_refs = 0, inner_refs = 0;
  double mean_leaf_refs = 0.0;
};

/// Counts `nodes` given each node's depth (`depths[i]`, the root 0).
template <class Node>
CellRefCounts count_cell_refs(const std::vector<Node>& nodes, const std::vector<uint32_t>& depths) {
  CellRefCounts c;
  for (size_t i = 0; i < nodes.size(); ++i) {
    const Node& n = nodes[i];
    c.depth = std::max(c.depth, depths[i]);
    if (n.is_leaf()) {
      c.leaves++;
      c.max_leaf_refs = std::max(c.max_leaf_refs, uint32_t(n.count));
      c.leaf_refs += n.count;
    } else {
      c.inner_refs += n.count;
    }
  }
  c.mean_leaf_refs = c.leaves ? double(c.leaf_refs) / c.leaves : 0.0;
  return c;
}

}  // namespace rayscope
