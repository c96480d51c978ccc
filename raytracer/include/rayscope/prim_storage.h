// How a spatial subdivision (kD-tree, grid, octree, BSP tree) stores an
// extended primitive that straddles a cell boundary: the lecture's three
// solutions ("Extended objects").
#pragma once

#include <cstdint>
#include <string_view>

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

}  // namespace rayscope
