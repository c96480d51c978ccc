// Handing an image's tiles out to the processes of a parallel render by cost,
// so that a process whose tiles are cheap (background, diffuse surfaces) takes
// more of them than one whose tiles are expensive (reflections, refractions,
// dense geometry). The cost of a tile is estimated before the render by
// tracing a few of its pixels, one sample each, and counting the work (the
// statistics' rays, node visits and primitive tests; kBalanceProbes^2 probes
// per tile: 2 x 2 left the counted work of shares of the default scene up to 5%
// apart, 3 x 3 within 3%, see test_frame ShareBalance); the tiles then go, the
// most expensive first, each to the share with the least estimated work so far
// (longest processing time first, within 4/3 of the best possible split).
#pragma once

#include <cstdint>
#include <vector>

#include "rayscope/render_settings.h"
#include "rayscope/scene.h"

namespace rayscope {

/// Probe pixels per tile side: the centers of a tile's kBalanceProbes x
/// kBalanceProbes cells estimate its cost.
inline constexpr int kBalanceProbes = 3;

/// The estimated work of each tile of settings.share (tiles.h numbers them;
/// the other tiles' entries are 0, so that the processes of a render can each
/// estimate their own share and sum the vectors): the traversal work of its
/// probe pixels, one sample each, through the integrator as the render traces
/// them (about 9 / 256 of a one-sample render of those tiles at the default
/// tile size). prepare_frame()s the committed scene for settings; takes
/// settings.threads.
std::vector<uint64_t> estimate_tile_costs(Scene& scene, const RenderSettings& settings);

/// An owner map for TileShare::owners: tile t goes to share owners[t] of
/// `count`, so that the shares' summed costs are as even as the greedy
/// handout makes them (ties to the lower tile and share index: the map
/// depends only on the costs).
std::vector<int> balance_shares(const std::vector<uint64_t>& costs, int count);

}  // namespace rayscope
