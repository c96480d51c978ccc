#include "RayScopeImageArrays.h"

#include <cmath>
#include <limits>

#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkIntArray.h"
#include "vtkPointData.h"
#include "vtkTypeInt64Array.h"
#include "vtkUnsignedCharArray.h"

#include "RayScopeArrays.h"
#include "rayscope/image.h"
#include "rayscope/stats.h"

namespace rayscope_vtk {

void framebuffer_to_image(const rayscope::Framebuffer& fb, const rayscope::RayCounters& counters,
                          vtkImageData* image) {
  const int w = fb.width, h = fb.height;
  const vtkIdType np = vtkIdType(w) * vtkIdType(h);
  image->Initialize();
  image->SetExtent(0, w - 1, 0, h - 1, 0, 0);
  image->SetSpacing(1.0, 1.0, 1.0);
  image->SetOrigin(0.0, 0.0, 0.0);

  auto color = make_array<vtkUnsignedCharArray>("Color", 3, np);
  auto linear = make_array<vtkFloatArray>("LinearColor", 3, np);
  auto depth = make_array<vtkFloatArray>("Depth", 1, np);
  auto normal = make_array<vtkFloatArray>("Normal", 3, np);
  auto object = make_array<vtkIntArray>("ObjectId", 1, np);
  const bool cost = !fb.cost.empty();
  vtkSmartPointer<vtkIntArray> cost_nodes, cost_rays, cost_boxes, cost_prims;
  if (cost) {
    cost_nodes = make_array<vtkIntArray>("Cost", 1, np);
    cost_rays = make_array<vtkIntArray>("CostRays", 1, np);
    cost_boxes = make_array<vtkIntArray>("CostBoxes", 1, np);
    cost_prims = make_array<vtkIntArray>("CostPrimitives", 1, np);
  }
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int j = 0; j < h; ++j) {
    const int y = h - 1 - j;  // VTK row 0 is the bottom row
    for (int x = 0; x < w; ++x) {
      const size_t c = fb.index(x, y);
      const vtkIdType v = vtkIdType(j) * w + x;
      for (int k = 0; k < 3; ++k) {
        const float lin = fb.color[c][k];
        color->SetTypedComponent(
            v, k, (unsigned char)std::lround(255.0f * rayscope::linear_to_srgb(lin)));
        linear->SetTypedComponent(v, k, lin);
        normal->SetTypedComponent(v, k, fb.normal[c][k]);
      }
      depth->SetValue(v, std::isfinite(fb.depth[c]) ? fb.depth[c] : nan);
      object->SetValue(v, int(fb.object_id[c]));
      if (cost) {
        cost_nodes->SetValue(v, int(fb.cost[c].nodes));
        cost_rays->SetValue(v, int(fb.cost[c].rays));
        cost_boxes->SetValue(v, int(fb.cost[c].boxes));
        cost_prims->SetValue(v, int(fb.cost[c].prims));
      }
    }
  }
  vtkPointData* pd = image->GetPointData();
  pd->SetScalars(color);
  pd->AddArray(linear);
  pd->AddArray(depth);
  pd->AddArray(normal);
  pd->AddArray(object);
  if (cost) {
    pd->AddArray(cost_nodes);
    pd->AddArray(cost_rays);
    pd->AddArray(cost_boxes);
    pd->AddArray(cost_prims);
  }
  vtkFieldData* fd = image->GetFieldData();
  auto i64 = [](uint64_t v) { return vtkTypeInt64(v); };
  add_field_tuple<vtkTypeInt64Array>(
      fd, "RayCounts",
      {i64(counters.rays[0]), i64(counters.rays[1]), i64(counters.rays[2]), i64(counters.rays[3])});
  add_field_tuple<vtkTypeInt64Array>(fd, "ShadowRaysOccluded", {i64(counters.shadow_occluded)});
  if (cost) {
    add_field_tuple<vtkTypeInt64Array>(fd, "NodesVisited", {i64(counters.nodes_visited)});
    add_field_tuple<vtkTypeInt64Array>(fd, "BoxesTested", {i64(counters.boxes_tested)});
    add_field_tuple<vtkTypeInt64Array>(fd, "PrimitivesTested", {i64(counters.prims_tested)});
  }
}

}  // namespace rayscope_vtk
