// The ray-traced framebuffer as the arrays of a vtkImageData: the output of
// vtkRayScopeImageAlgorithm (RayScope::VTK, whose class documentation lists
// the arrays) and the images of vtkRayScopeViewer (RayScope::Rendering), which
// fills them tile by tile while its renders run, so that both make the same
// arrays. The 8-bit "Color" array is rayscope::srgb_byte() of the linear color.
#pragma once

class vtkImageData;

namespace rayscope {
struct Framebuffer;
struct RayCounters;
}  // namespace rayscope

namespace rayscope_vtkio {

/// Replaces `image` with the framebuffer: extent [0, w-1] x [0, h-1] x [0, 0],
/// spacing 1, origin 0, row 0 at the bottom (the framebuffer's row h-1-j);
/// point data "Color" (active scalars), "LinearColor", "Depth", "Normal",
/// "ObjectId" and, when the framebuffer has costs, "Cost", "CostRays",
/// "CostBoxes", "CostPrimitives", and when it has sample counts (adaptive
/// sampling) "Samples"; field data "RayCounts",
/// "ShadowRaysOccluded" and, with costs, "NodesVisited", "BoxesTested",
/// "PrimitivesTested". The image's arrays are filled again when
/// prepare_image() finds them fitting, else replaced. The pixels are written
/// on `threads` threads (rayscope::thread_arena(): 0 for all). The three
/// functions below make the same image in steps.
void framebuffer_to_image(const rayscope::Framebuffer& fb, const rayscope::RayCounters& counters,
                          vtkImageData* image, int threads = 0);

/// Gives `image` the geometry and the point-data arrays of a w x h
/// framebuffer's image (with the cost arrays when `cost`, and "Samples" when
/// `samples`: the samples each pixel took under adaptive sampling), values
/// not set.
/// An image that has exactly them already, for that size, held by nothing
/// else (another data object's shallow copy, a Python reference), is left as
/// it is: an image filled frame after frame allocates its arrays once, and
/// arrays someone else kept are never overwritten.
void prepare_image(vtkImageData* image, int w, int h, bool cost, bool samples = false);

/// Writes the framebuffer's pixels [x0, x1) x [y0, y1) (framebuffer rows, 0 at
/// the top) into an image prepared for it, as framebuffer_to_image() does.
/// Rectangles that do not overlap may be written from several threads at once.
void framebuffer_rect_to_image(const rayscope::Framebuffer& fb, int x0, int y0, int x1, int y1,
                               vtkImageData* image);

/// Replaces the image's field data with the counters of its render (the cost
/// totals when the image has the "Cost" array).
void counters_to_image(const rayscope::RayCounters& counters, vtkImageData* image);

}  // namespace rayscope_vtkio
