#include "rayscope/packet_replay.h"

#include <algorithm>
#include <variant>

#include <nlohmann/json.hpp>

#include "rayscope/accel/wide_bvh.h"
#include "rayscope/printf_string.h"
#include "rayscope/render_block.h"
#include "rayscope/replay.h"

namespace rayscope {

PacketReplay record_packet(const Scene& scene, const RenderSettings& settings, int x, int y,
                           int sample) {
  check_replay(settings, x, y, sample);
  PacketReplay r;
  r.x = x;
  r.y = y;
  r.sample = std::max(sample, 0);
  r.block = pixel_block(TileGrid(settings), x, y);
  r.lane = (y - r.block.y0) * r.width() + (x - r.block.x0);
  r.every_ray_alone = why_every_ray_alone(scene, settings);
  // The rays render_block() traces for this sample.
  Ray rays[kPacketRays];
  RayDifferential diff;
  const int n = r.rays();
  for (int k = 0; k < n; ++k)
    rays[k] = primary_ray(scene, settings, r.block.x0 + k % r.width(), r.block.y0 + k / r.width(),
                          r.sample, &diff);
  r.cost.steps = &r.steps;
  r.hits = scene.intersect_packet(std::span<const Ray>(rays, size_t(n)), r.hit, &r.cost);
  r.cost.steps = nullptr;
  // The steps' boxes: the root's (the first node entered), then for each
  // node the box of the slot that holds it in its parent, an inner node
  // entered before it. A slot holds the node when its child and count are the
  // step's: an empty slot's child is kLeaf, as the leaf labelled 0's is, but
  // its count is 0.
  const BvhWalk* walk = std::get_if<BvhWalk>(&scene.accel().structure());
  if (!r.steps.empty() && walk != nullptr) {
    const std::vector<WideBvhNode>& nodes = walk->walk().nodes;
    r.boxes.push_back(walk->walk().root_bounds());
    for (size_t i = 1; i < r.steps.size(); ++i) {
      Bounds3 box;
      for (size_t j = i; j-- > 0 && box.lo.x == kInfinity;) {
        if (r.steps[j].child & WideBvhNode::kLeaf) continue;
        const WideBvhNode& n = nodes[r.steps[j].child];
        for (int k = 0; k < WideBvhNode::kWidth; ++k)
          if (n.child[k] == r.steps[i].child && n.count[k] == r.steps[i].count)
            box = Bounds3(Vec3(n.lo_x[k], n.lo_y[k], n.lo_z[k]),
                          Vec3(n.hi_x[k], n.hi_y[k], n.hi_z[k]));
      }
      r.boxes.push_back(box);
    }
  }
  return r;
}

namespace {

// The lanes of `lanes` as the block's rows, '#' for a lane in it.
std::string rows(const PacketReplay& r, unsigned lanes) {
  std::string s;
  for (int k = 0; k < r.rays(); ++k) {
    if (k > 0 && k % r.width() == 0) s += ' ';
    s += (lanes >> k & 1u) ? '#' : '.';
  }
  return s;
}

// Per lane: the last step it was active in (where it left the walk; 0:
// none).
std::vector<int> last_steps(const PacketReplay& r) {
  std::vector<int> last(kPacketRays, 0);
  for (size_t i = 0; i < r.steps.size(); ++i)
    for (unsigned m = r.steps[i].lanes; m != 0; m &= m - 1)
      last[size_t(__builtin_ctz(m))] = int(i) + 1;
  return last;
}

// What lane k's ray hit.
std::string hit_text(const PacketReplay& r, const Scene& scene, int k) {
  if (!(r.hits >> k & 1u)) return "missed everything";
  const PrimHit& h = r.hit[k];
  if (h.plane >= 0)
    return "hit \"" + scene.object_name(scene.plane_object(uint32_t(h.plane))) +
           "\" at t = " + printf_string("%.6g", double(h.t));
  return "hit \"" + scene.object_name(scene.prim_object(h.prim)) + "\" (primitive " +
         std::to_string(h.prim) + ") at t = " + printf_string("%.6g", double(h.t));
}

}  // namespace

std::string format_packet_text(const PacketReplay& r, const Scene& scene) {
  const int n = r.rays(), w = r.width();
  std::string s = printf_string(
      "packet of pixel (%d, %d), sample %d: the primary rays of the %dx%d pixels "
      "from (%d, %d) to (%d, %d), traced together\n",
      r.x, r.y, r.sample, w, r.block.y1 - r.block.y0, r.block.x0, r.block.y0, r.block.x1 - 1,
      r.block.y1 - 1);
  s += printf_string(
      "  lane %d is this pixel (row %d, column %d of the block); lanes run row by row\n", r.lane,
      r.lane / w, r.lane % w);
  if (!r.every_ray_alone.empty())
    s += "  these settings trace every ray alone (" + r.every_ray_alone +
         "): this is the packet a plain render traces\n";
  s += "  this pixel's ray " + hit_text(r, scene, r.lane) + "\n";
  if (r.cost.fell_back) {
    s += "  the packet was traced one ray at a time: its rays disagree on the sign of a "
         "direction component, or the structure is not the BVH (the ray trees show each walk)\n";
    return s;
  }
  const double mean =
      r.cost.node_visits ? double(r.cost.active_lanes) / double(r.cost.node_visits) : 0.0;
  s += printf_string(
      "  walk: %u nodes entered, %.1f of %d rays active per node on average; this "
      "pixel's ray was active in %u of them\n",
      r.cost.node_visits, mean, n, r.cost.nodes[r.lane]);
  const std::vector<int> last = last_steps(r);
  s += "per pixel of the block (* this pixel): nodes entered while its ray was active, the step "
       "it left the walk at, hit or miss\n";
  for (int row = 0; row * w < n; ++row) {
    s += printf_string("  row %d:", row);
    for (int k = row * w; k < std::min(n, (row + 1) * w); ++k)
      s += printf_string(" %c%4u @%-4d %-4s", k == r.lane ? '*' : ' ', r.cost.nodes[k],
                         last[size_t(k)], (r.hits >> k & 1u) ? "hit" : "miss");
    s += "\n";
  }
  s += "step  node                  rays  active (the block's rows, '#' active)  this pixel\n";
  for (size_t i = 0; i < r.steps.size(); ++i) {
    const PacketStep& st = r.steps[i];
    const std::string node =
        (st.child & WideBvhNode::kLeaf)
            ? printf_string("leaf, %u primitive%s", st.count, st.count == 1 ? "" : "s")
            : printf_string("node %u", st.child);
    s += printf_string("%4zu  %-20s  %4d  %-*s  %s\n", i + 1, node.c_str(),
                       __builtin_popcount(st.lanes), std::max(n + (n - 1) / w, 37),
                       rows(r, st.lanes).c_str(), (st.lanes >> r.lane & 1u) ? "in" : "");
  }
  // No line ends in the padding of an empty last column.
  std::string out;
  for (char c : s) {
    if (c == '\n')
      while (!out.empty() && out.back() == ' ') out.pop_back();
    out += c;
  }
  return out;
}

std::string format_packet_json(const PacketReplay& r, const Scene& scene, int indent) {
  using json = nlohmann::json;
  const std::vector<int> last = last_steps(r);
  json lanes = json::array();
  for (int k = 0; k < r.rays(); ++k) {
    const bool hit = r.hits >> k & 1u;
    const PrimHit& h = r.hit[k];
    json lane = {{"pixel", {r.block.x0 + k % r.width(), r.block.y0 + k / r.width()}},
                 {"hit", hit},
                 {"nodes", r.cost.nodes[k]},
                 {"boxes_tested", r.cost.boxes[k]},
                 {"primitives_tested", r.cost.prims[k]},
                 {"culled", r.cost.culled[k]},
                 {"left_at_step", last[size_t(k)]}};
    if (hit) {
      lane["t"] = h.t;
      lane["object"] = scene.object_name(h.plane >= 0 ? scene.plane_object(uint32_t(h.plane))
                                                      : scene.prim_object(h.prim));
      if (h.plane < 0) lane["primitive"] = h.prim;
    }
    lanes.push_back(std::move(lane));
  }
  json steps = json::array();
  for (const PacketStep& st : r.steps) {
    const bool leaf = st.child & WideBvhNode::kLeaf;
    json step = {{"leaf", leaf}, {"active", __builtin_popcount(st.lanes)}, {"lanes", st.lanes}};
    if (leaf)
      step["primitives"] = st.count;
    else
      step["node"] = st.child;
    steps.push_back(std::move(step));
  }
  const json j = {
      {"pixel", {r.x, r.y}},
      {"sample", r.sample},
      {"block", {{"x0", r.block.x0}, {"y0", r.block.y0}, {"x1", r.block.x1}, {"y1", r.block.y1}}},
      {"lane", r.lane},
      {"every_ray_alone", r.every_ray_alone.empty() ? json(nullptr) : json(r.every_ray_alone)},
      {"fell_back", r.cost.fell_back},
      {"node_visits", r.cost.node_visits},
      {"active_lanes", r.cost.active_lanes},
      {"lanes", std::move(lanes)},
      {"steps", std::move(steps)}};
  return j.dump(indent);
}

}  // namespace rayscope
