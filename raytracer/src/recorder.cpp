#include "rayscope/recorder.h"

#include <algorithm>

namespace rayscope {

const char* to_string(TraversalStep::Kind kind) {
  switch (kind) {
    case TraversalStep::Kind::Enter:
      return "enter";
    case TraversalStep::Kind::BoxHit:
      return "box hit";
    case TraversalStep::Kind::BoxMiss:
      return "box missed";
    case TraversalStep::Kind::Cull:
      return "culled";
  }
  return "?";
}

std::vector<uint32_t> TraversalRecord::nodes() const {
  std::vector<uint32_t> out;
  for (const TraversalStep& s : steps)
    if (s.kind == TraversalStep::Kind::Enter) out.push_back(s.node);
  return out;
}

uint32_t TraversalRecord::boxes_tested() const {
  return uint32_t(std::count_if(steps.begin(), steps.end(), [](const TraversalStep& s) {
    return s.kind == TraversalStep::Kind::BoxHit || s.kind == TraversalStep::Kind::BoxMiss;
  }));
}

uint32_t TraversalRecord::culled() const {
  return uint32_t(std::count_if(steps.begin(), steps.end(), [](const TraversalStep& s) {
    return s.kind == TraversalStep::Kind::Cull;
  }));
}

}  // namespace rayscope
