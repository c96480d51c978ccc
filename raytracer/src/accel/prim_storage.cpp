#include "rayscope/accel/prim_storage.h"

#include "rayscope/render_settings.h"

#include <cmath>
#include <sstream>

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

std::string loose_factor_error(float factor) {
  if (std::isfinite(factor) && factor >= 0.0f && factor <= kMaxLooseFactor) return {};
  std::ostringstream o;
  o << "loose factor must be a number from 0 to " << kMaxLooseFactor << " (a fraction of a cell's "
    << "size added on every side; the lecture's " << kDefaultLooseFactor << "), got " << factor;
  return o.str();
}

std::string storage_text(PrimStorage storage, float loose_factor) {
  std::string text = to_string(storage);
  if (storage == PrimStorage::SmallestCell)
    text += " (loose factor " + shortest_text(loose_factor) + ")";
  return text;
}

}  // namespace rayscope
