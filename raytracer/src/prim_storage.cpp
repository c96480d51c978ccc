#include "rayscope/prim_storage.h"

namespace rayscope {

const char* to_string(PrimStorage storage) {
  switch (storage) {
    case PrimStorage::EveryCell:
      return "every-cell";
    case PrimStorage::SmallestCell:
      return "smallest-cell";
    case PrimStorage::Split:
      return "split";
  }
  return "?";
}

bool parse_prim_storage(std::string_view name, PrimStorage& storage) {
  for (PrimStorage s : kPrimStorages)
    if (name == to_string(s)) {
      storage = s;
      return true;
    }
  return false;
}

}  // namespace rayscope
