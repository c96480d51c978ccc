// A recorded ray tree (recorder.h) as text, for people (`rayscope inspect`),
// and as JSON, for tools.
#pragma once

#include <string>

#include "rayscope/recorder.h"

namespace rayscope {

/// The ray tree as indented text, one ray per line with its details and its
/// walk through the acceleration structure, with a legend of the walk's terms.
std::string format_text(const PixelRecord& rec, const Scene& scene);
/// The ray tree as JSON (for tools and the VTK module).
std::string format_json(const PixelRecord& rec, const Scene& scene, int indent = 2);

}  // namespace rayscope
