// The acceleration structures by name: the one table that says what each
// kind is called on the command line (and in scene files, JSON output and
// Python), which number the VTK classes give it, how ParaView labels it, and
// which storage choices (prim_storage.h) it can build with. Everything that
// lists, parses or shows the kinds reads this table.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "rayscope/accel/prim_storage.h"

namespace rayscope {

/// Which structure the aggregate walks. One is chosen per scene commit.
enum class AccelKind : uint8_t {
  /// The BVH walked through 8-wide nodes (bvh_walk.h, arity 8): what renders
  /// use.
  Bvh,
  /// The same BVH walked node by node, two child boxes per node (arity 2):
  /// the lecture's binary walk, for teaching. Same hits; more, smaller steps,
  /// each of which the tools can show.
  BinaryBvh,
  /// No structure: every primitive is tested against every ray (O(n) per ray).
  None,
  /// The kD-tree (kdtree.h): space cut by axis-aligned planes, walked front to
  /// back with mailboxing.
  KdTree,
  /// The uniform grid (grid.h): equal cells, walked cell by cell (3D-DDA).
  Grid,
  /// The octree (octree.h): a cube cut into 8 octants, recursively.
  Octree,
  /// The BSP tree (bsp.h): space cut by planes of any orientation, through the
  /// triangles (autopartition).
  Bsp,
  /// The hierarchy of bounding spheres (sphere_tree.h): the BVH's idea with
  /// the cheapest bounding volume to test, which fits worse than a box.
  Spheres,
};

/// One row of the table.
struct AccelKindName {
  AccelKind kind;
  /// The command line's --accel word, also used by scene files, JSON output,
  /// ray-tree files and the VTK classes' text output.
  const char* word;
  /// vtkRayScopeImageAlgorithm::ACCEL_* (the VTK classes' and ParaView's
  /// number for the kind; saved in ParaView state files, so it never changes).
  int vtk_id;
  /// ParaView's entry in the "Accel" drop-down (RayScope.xml, checked against
  /// this table by a test).
  const char* label;
  /// The PrimStorage values the structure can build with, one bit each
  /// (bit 1 << int(storage)).
  uint8_t storages;
  /// No structure: every primitive tested against every ray, O(n) per ray
  /// (the tools that try every kind skip it where that would take too long).
  bool brute_force = false;
};

namespace detail {
constexpr uint8_t storage_bit(PrimStorage s) {
  return uint8_t(1u << unsigned(s));
}
constexpr uint8_t kOnce = storage_bit(PrimStorage::EveryCell);
constexpr uint8_t kCells = kOnce | storage_bit(PrimStorage::SmallestCell);
constexpr uint8_t kAllStorages = kCells | storage_bit(PrimStorage::Split);
}  // namespace detail

/// Every kind, in the order the tools list them.
inline constexpr AccelKindName kAccelKindNames[] = {
    {AccelKind::Bvh, "bvh", 0, "BVH (8-wide walk)", detail::kOnce},
    {AccelKind::BinaryBvh, "bvh2", 1, "Binary BVH walk", detail::kOnce},
    {AccelKind::KdTree, "kdtree", 3, "kD-tree (SAH)", detail::kCells},
    {AccelKind::Grid, "grid", 4, "Uniform grid", detail::kCells},
    {AccelKind::Octree, "octree", 5, "Octree", detail::kCells},
    {AccelKind::Bsp, "bsp", 6, "BSP tree (planes through the triangles)", detail::kAllStorages},
    {AccelKind::Spheres, "spheres", 7, "Bounding spheres", detail::kOnce},
    {AccelKind::None, "none", 2, "None (test every primitive)", detail::kOnce, true},
};

/// Every kind, in the table's order.
inline constexpr std::array<AccelKind, std::size(kAccelKindNames)> kAccelKinds = [] {
  std::array<AccelKind, std::size(kAccelKindNames)> kinds{};
  for (size_t i = 0; i < kinds.size(); ++i) kinds[i] = kAccelKindNames[i].kind;
  return kinds;
}();

/// The table's row of `kind`.
constexpr const AccelKindName& accel_kind_name(AccelKind kind) {
  for (const AccelKindName& n : kAccelKindNames)
    if (n.kind == kind) return n;
  return kAccelKindNames[0];  // unreachable: every enumerator has a row (tested)
}
/// "bvh", "bvh2", "none", "kdtree", "grid", "octree", "bsp", "spheres".
inline const char* to_string(AccelKind kind) {
  return accel_kind_name(kind).word;
}
/// Parses the words to_string() gives; false for anything else.
bool parse_accel_kind(std::string_view word, AccelKind& kind);
/// The kind VTK numbers `vtk_id`; false for a number no kind has.
bool accel_kind_of_vtk_id(int vtk_id, AccelKind& kind);

/// Why structure `kind` cannot store primitives the `storage` way, in one line
/// (no trailing period); empty when it can. The one check of the pair: the
/// CLI, the VTK image algorithm and Aggregate::build (which throws
/// std::invalid_argument with it) all ask here.
std::string accel_storage_error(AccelKind kind, PrimStorage storage);

}  // namespace rayscope
