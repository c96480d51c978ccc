#include "rayscope/accel/accel_kind.h"

namespace rayscope {

bool parse_accel_kind(std::string_view word, AccelKind& kind) {
  for (const AccelKindName& n : kAccelKindNames)
    if (word == n.word) {
      kind = n.kind;
      return true;
    }
  return false;
}

bool accel_kind_of_vtk_id(int vtk_id, AccelKind& kind) {
  for (const AccelKindName& n : kAccelKindNames)
    if (n.vtk_id == vtk_id) {
      kind = n.kind;
      return true;
    }
  return false;
}

std::string accel_storage_error(AccelKind kind, PrimStorage storage) {
  const uint8_t takes = accel_kind_name(kind).storages;
  if (takes & detail::storage_bit(storage)) return {};
  const std::string what = std::string("storage ") + to_string(storage) + " is not available for " +
                           to_string(kind) + ": ";
  if (takes == detail::kOnce)
    return what +
           "the storage choice is for the spatial subdivisions (kdtree, grid, octree, bsp); a "
           "BVH, a sphere tree or no structure holds each primitive once";
  return what +
         "the kD-tree, grid and octree store a primitive in every cell it overlaps "
         "(every-cell) "
         "or once in its smallest loose cell (smallest-cell); splitting is the BSP tree's";
}

}  // namespace rayscope
