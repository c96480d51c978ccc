// The packet a pixel's primary ray travels in (lecture: "in practice:
// coherence"). The frame loop traces the primary rays of each block of
// kBlockSide x kBlockSide pixels as one packet (render_block.h); a replay
// traces that packet again with a log of its walk: each node it entered and
// which of its rays were active there, so that one sees where the block's
// rays walk together and where each one leaves the packet's walk. The ray
// trees (replay.h) show each ray's own single-ray walk; the hits are the same.
#pragma once

#include <string>
#include <vector>

#include "rayscope/accel/ray_packet.h"
#include "rayscope/render_settings.h"
#include "rayscope/scene.h"
#include "rayscope/tiles.h"

namespace rayscope {

/// One pixel's packet, replayed.
struct PacketReplay {
  int x = 0, y = 0;  ///< The pixel asked for (top-left origin).
  int sample = 0;    ///< The sample whose primary rays were traced.
  /// The block of pixels traced together; lane k is the ray of pixel
  /// (x0 + k % width, y0 + k / width), row by row.
  TileRect block{};
  int lane = 0;  ///< The lane of pixel (x, y).
  /// Why renders with these settings trace every ray alone
  /// (why_every_ray_alone(); empty: they trace this packet). The replay
  /// traces the block as a packet either way: the packet a plain render traces.
  std::string every_ray_alone;
  unsigned hits = 0;  ///< Lanes whose ray hit something.
  PrimHit hit[kPacketRays];
  /// Each node the packet entered, in walk order (none when it fell back).
  std::vector<PacketStep> steps;
  /// The box of each step's node (the root's, then each node's box in its
  /// parent), in the scene's coordinates.
  std::vector<Bounds3> boxes;
  /// The walk's work per lane (nodes entered while active, boxes, primitives,
  /// culls), the packet's node visits and active lanes, and whether its rays
  /// were traced one at a time instead (cost.fell_back: they disagree on a
  /// direction component's sign, or the structure is not the BVH).
  PacketWalkCost cost;

  int width() const { return block.x1 - block.x0; }
  int rays() const { return width() * (block.y1 - block.y0); }
};

/// Traces the primary rays of the block holding pixel (x, y) (top-left
/// origin) for `sample` as the frame loop does, logging the packet's walk.
/// scene.camera must be prepared for the settings (prepare_frame()). Throws
/// std::out_of_range for a pixel or sample outside the image.
PacketReplay record_packet(const Scene& scene, const RenderSettings& settings, int x, int y,
                           int sample = 0);

/// The replay as text: the block and the asked pixel's lane, the walk's
/// summary, per pixel of the block the nodes its ray was active in, the step
/// it left the walk at and whether it hit, then the walk step by step with
/// the active rays drawn as the block's rows ('#' active, '.' not).
std::string format_packet_text(const PacketReplay& replay, const Scene& scene);
/// The same as JSON, for tools: the block, the lane, per lane its pixel, hit
/// and work, and the steps with each one's active lanes (bit k for lane k).
std::string format_packet_json(const PacketReplay& replay, const Scene& scene, int indent = 2);

}  // namespace rayscope
