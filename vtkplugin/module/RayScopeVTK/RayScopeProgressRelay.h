// Rendering with progress reported on the calling thread (private header of
// vtkRayScopeImageAlgorithm).
#pragma once

#include <functional>

#include "rayscope/image.h"
#include "rayscope/render_settings.h"

namespace rayscope {
class Scene;
struct RayCounters;
}  // namespace rayscope

namespace rayscope_vtkmodule {

/// rayscope::render_into(fb, scene, settings, counters) on a worker thread
/// (`fb` kept from frame to frame by the caller), while the
/// calling thread passes its progress to `report` (a fraction in [0, 1], in
/// steps of at least 1%, as VTK's filters report). The core calls its progress
/// function from its worker threads, but ProgressEvent observers (Python
/// callbacks included) must run on the thread that called Update(): this is
/// that relay. Rethrows what the render threw.
void render_relaying_progress(rayscope::Framebuffer& fb, rayscope::Scene& scene,
                              const rayscope::RenderSettings& settings,
                              rayscope::RayCounters* counters,
                              const std::function<void(double)>& report);

}  // namespace rayscope_vtkmodule
