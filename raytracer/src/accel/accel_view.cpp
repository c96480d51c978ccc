#include "rayscope/accel/accel_view.h"

#include <algorithm>

#include "rayscope/aggregate.h"

namespace rayscope {

void finish_levels(AccelView& v) {
  for (AccelViewNode& n : v.nodes) {
    n.level = 0;
    for (int32_t p = n.parent; p >= 0; p = v.nodes[size_t(p)].parent) ++n.level;
    v.depth = std::max(v.depth, n.level + 1);
  }
}

AccelView make_accel_view(const Aggregate& accel) {
  AccelView v = std::visit([](const auto& s) { return s.view(); }, accel.structure());
  const std::vector<PrimRecord>& records = accel.records();
  for (uint32_t& r : v.refs) r = records[r].id;
  return v;
}

}  // namespace rayscope
