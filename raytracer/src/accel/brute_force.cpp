#include "rayscope/accel/brute_force.h"

namespace rayscope {

AccelFigures BruteForce::figures() const {
  AccelFigures f;
  f.refs_per_prim = records_ == 0 ? 0.0 : 1.0;
  return f;
}

AccelView BruteForce::view() const {
  return hierarchy_ ? hierarchy_->get().view() : AccelView{};
}

std::string BruteForce::stats_line() const {
  return "none: every primitive is tested against every ray";
}

std::string BruteForce::walk_legend() const {
  return "no structure; every primitive is tested (primitives tested = all of them)";
}

}  // namespace rayscope
