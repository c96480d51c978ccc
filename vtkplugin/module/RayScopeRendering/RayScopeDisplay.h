// What a ray-traced image shows on screen (private header of
// RayScope::Rendering): the render pass's and the viewer's display modes, as
// RGB bytes, made in one place.
#pragma once

#include <string>
#include <vector>

class vtkImageData;
class vtkLookupTable;

namespace rayscope_vtkmodule {

/// Display modes (vtkRayScopePass::DisplayModes and
/// vtkRayScopeViewer::ImageModes use these values).
enum DisplayMode {
  kDisplayColor = 0,     ///< the "Color" array (sRGB)
  kDisplayCost = 1,      ///< "Cost" (BVH nodes visited) on the heat-map scale, 0 .. max
  kDisplayNormal = 2,    ///< "Normal" as (n + 1) / 2; misses black
  kDisplayDepth = 3,     ///< "Depth", near white to far dark on a log scale; misses black
  kDisplayObjectId = 4,  ///< "ObjectId", one color per object; misses black
  kDisplayModes = 5
};

/// Name of a display mode ("color", "cost", ...).
const char* display_mode_name(int mode);

/// The color scale of a mode that maps one value per pixel (cost, depth):
/// `table` gets its colors over the range the image holds, `title` what it
/// measures. False for the other modes (and an image without the array).
bool display_scale(vtkImageData* image, int mode, vtkLookupTable* table, std::string& title);

/// RGB bytes of `image` (a vtkRayScopeImageAlgorithm output, VTK row order)
/// in `mode`; empty when the image lacks the array the mode needs.
std::vector<unsigned char> display_pixels(vtkImageData* image, int mode);

}  // namespace rayscope_vtkmodule
