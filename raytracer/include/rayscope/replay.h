// Ray trees of chosen pixels: one pixel replayed alone (record_pixel), or
// listed pixels recorded during a full render (render_and_record, the frame
// loop with a policy that records the selected pixels). Both go through
// render_pixel(), the frame loop's per-pixel body, so a recorded pixel has
// exactly the color it has in the image, and its tree shows the walk that
// render made.
#pragma once

#include <vector>

#include <glm/vec2.hpp>

#include "rayscope/recorder.h"
#include "rayscope/render.h"

namespace rayscope {

/// Throws std::out_of_range, naming the image's size, for a pixel (x, y) (top-left
/// origin) or a sample (0..N*N-1, or -1 for all) outside the image `settings`
/// renders: the check of every replay.
void check_replay(const RenderSettings& settings, int x, int y, int sample = -1);

/// Replays pixel (x, y) (top-left origin) of a render with these settings,
/// recording its ray tree (one sample, or all with sample == -1). scene.camera
/// must be prepared for the settings (prepare_frame(), or render()). Throws
/// std::out_of_range for a pixel or sample outside the image.
PixelRecord record_pixel(const Scene& scene, const RenderSettings& settings, int x, int y,
                         int sample = -1);

/// Renders the whole image exactly like render() and, in the same pass, records
/// the full ray trees (all samples) of the listed pixels into `records` (one per
/// listed pixel, in order). With an empty list, recording is present but idle.
/// Throws std::out_of_range for a pixel outside the image, std::invalid_argument
/// for bad settings or settings.statistics (recording and statistics are
/// separate policies).
Framebuffer render_and_record(Scene& scene, const RenderSettings& settings,
                              const std::vector<glm::ivec2>& pixels,
                              std::vector<PixelRecord>& records, RayCounters* counters = nullptr);

}  // namespace rayscope
