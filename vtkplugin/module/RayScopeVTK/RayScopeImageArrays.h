// The ray-traced framebuffer as the arrays of a vtkImageData (private header
// of vtkRayScopeImageAlgorithm, whose class documentation lists the arrays).
#pragma once

class vtkImageData;

namespace rayscope {
struct Framebuffer;
struct RayCounters;
}  // namespace rayscope

namespace rayscope_vtk {

/// Replaces `image` with the framebuffer: extent [0, w-1] x [0, h-1] x [0, 0],
/// spacing 1, origin 0, row 0 at the bottom (the framebuffer's row h-1-j);
/// point data "Color" (active scalars), "LinearColor", "Depth", "Normal",
/// "ObjectId" and, when the framebuffer has costs, "Cost", "CostRays",
/// "CostBoxes", "CostPrimitives"; field data "RayCounts",
/// "ShadowRaysOccluded" and, with costs, "NodesVisited", "BoxesTested",
/// "PrimitivesTested".
void framebuffer_to_image(const rayscope::Framebuffer& fb, const rayscope::RayCounters& counters,
                          vtkImageData* image);

}  // namespace rayscope_vtk
