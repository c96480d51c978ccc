#include "rayscope_vtkio/image_arrays.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <limits>

#include "vtkCellData.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkIntArray.h"
#include "vtkPointData.h"
#include "vtkTypeInt64Array.h"
#include "vtkUnsignedCharArray.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "rayscope/image.h"
#include "rayscope/stats.h"
#include "rayscope/thread_arena.h"
#include "rayscope_vtkio/data_arrays.h"

namespace rayscope_vtkio {

namespace {

constexpr const char* kCostArrays[4] = {"Cost", "CostRays", "CostBoxes", "CostPrimitives"};
constexpr int kPixelArrays = 5;  // Color, LinearColor, Depth, Normal, ObjectId

// The image's array `name` if it is an A with `components` components and
// `tuples` tuples that nothing but the image holds: an array someone else
// holds (a shallow copy of an earlier output, a Python reference) is theirs
// to keep as it is.
template <class A>
A* fitting_array(vtkPointData* pd, const char* name, int components, vtkIdType tuples) {
  A* a = A::FastDownCast(pd->GetAbstractArray(name));
  return a && a->GetNumberOfComponents() == components && a->GetNumberOfTuples() == tuples &&
                 a->GetReferenceCount() == 1
             ? a
             : nullptr;
}

template <class A>
typename A::ValueType* values(vtkPointData* pd, const char* name) {
  return A::FastDownCast(pd->GetAbstractArray(name))->GetPointer(0);
}

}  // namespace

void prepare_image(vtkImageData* image, int w, int h, bool cost, bool samples) {
  const vtkIdType np = vtkIdType(w) * vtkIdType(h);
  vtkPointData* pd = image->GetPointData();
  const int* dims = image->GetDimensions();
  bool fits = dims[0] == w && dims[1] == h && dims[2] == 1 &&
              fitting_array<vtkUnsignedCharArray>(pd, "Color", 3, np) &&
              pd->GetScalars() == pd->GetArray("Color") &&
              fitting_array<vtkFloatArray>(pd, "LinearColor", 3, np) &&
              fitting_array<vtkFloatArray>(pd, "Depth", 1, np) &&
              fitting_array<vtkFloatArray>(pd, "Normal", 3, np) &&
              fitting_array<vtkIntArray>(pd, "ObjectId", 1, np);
  for (const char* name : kCostArrays)
    fits = fits && (cost ? fitting_array<vtkIntArray>(pd, name, 1, np) != nullptr
                         : pd->GetAbstractArray(name) == nullptr);
  fits = fits && (samples ? fitting_array<vtkIntArray>(pd, "Samples", 1, np) != nullptr
                          : pd->GetAbstractArray("Samples") == nullptr);
  fits = fits &&
         pd->GetNumberOfArrays() ==
             kPixelArrays + (cost ? int(std::size(kCostArrays)) : 0) + (samples ? 1 : 0) &&
         image->GetCellData()->GetNumberOfArrays() == 0;
  if (fits) return;
  image->Initialize();
  image->SetExtent(0, w - 1, 0, h - 1, 0, 0);
  image->SetSpacing(1.0, 1.0, 1.0);
  image->SetOrigin(0.0, 0.0, 0.0);
  pd = image->GetPointData();
  pd->SetScalars(make_array<vtkUnsignedCharArray>("Color", 3, np));
  pd->AddArray(make_array<vtkFloatArray>("LinearColor", 3, np));
  pd->AddArray(make_array<vtkFloatArray>("Depth", 1, np));
  pd->AddArray(make_array<vtkFloatArray>("Normal", 3, np));
  pd->AddArray(make_array<vtkIntArray>("ObjectId", 1, np));
  if (cost)
    for (const char* name : kCostArrays) pd->AddArray(make_array<vtkIntArray>(name, 1, np));
  if (samples) pd->AddArray(make_array<vtkIntArray>("Samples", 1, np));
}

// framebuffer_rect_to_image() copies rows of colors and normals as floats.
static_assert(sizeof(rayscope::Color) == 3 * sizeof(float) &&
              sizeof(rayscope::Vec3) == 3 * sizeof(float));

void framebuffer_rect_to_image(const rayscope::Framebuffer& fb, int x0, int y0, int x1, int y1,
                               vtkImageData* image) {
  if (x0 >= x1 || y0 >= y1) return;
  const int w = fb.width, h = fb.height;
  vtkPointData* pd = image->GetPointData();
  unsigned char* color = values<vtkUnsignedCharArray>(pd, "Color");
  float* linear = values<vtkFloatArray>(pd, "LinearColor");
  float* depth = values<vtkFloatArray>(pd, "Depth");
  float* normal = values<vtkFloatArray>(pd, "Normal");
  int* object = values<vtkIntArray>(pd, "ObjectId");
  const bool cost = !fb.cost.empty() && pd->GetAbstractArray("Cost");
  int* cost_nodes = cost ? values<vtkIntArray>(pd, "Cost") : nullptr;
  int* cost_rays = cost ? values<vtkIntArray>(pd, "CostRays") : nullptr;
  int* cost_boxes = cost ? values<vtkIntArray>(pd, "CostBoxes") : nullptr;
  int* cost_prims = cost ? values<vtkIntArray>(pd, "CostPrimitives") : nullptr;
  const bool has_samples = !fb.samples.empty() && pd->GetAbstractArray("Samples");
  int* samples = has_samples ? values<vtkIntArray>(pd, "Samples") : nullptr;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const size_t n = size_t(x1 - x0);
  for (int y = y0; y < y1; ++y) {
    const size_t c = fb.index(x0, y);
    const size_t v = size_t(h - 1 - y) * size_t(w) + size_t(x0);  // VTK row 0 is the bottom row
    // Color and Normal are 3 floats a pixel with no padding (static_asserts above).
    rayscope::srgb_bytes(&fb.color[c][0], 3 * n, color + 3 * v);
    std::memcpy(linear + 3 * v, &fb.color[c][0], 3 * n * sizeof(float));
    std::memcpy(normal + 3 * v, &fb.normal[c][0], 3 * n * sizeof(float));
    for (size_t k = 0; k < n; ++k) {
      depth[v + k] = std::isfinite(fb.depth[c + k]) ? fb.depth[c + k] : nan;
      object[v + k] = int(fb.object_id[c + k]);
    }
    if (cost)
      for (size_t k = 0; k < n; ++k) {
        const rayscope::PixelCost& pc = fb.cost[c + k];
        cost_nodes[v + k] = int(pc.nodes);
        cost_rays[v + k] = int(pc.rays);
        cost_boxes[v + k] = int(pc.boxes);
        cost_prims[v + k] = int(pc.prims);
      }
    if (has_samples)
      for (size_t k = 0; k < n; ++k) samples[v + k] = int(fb.samples[c + k]);
  }
}

void counters_to_image(const rayscope::RayCounters& counters, vtkImageData* image) {
  vtkFieldData* fd = image->GetFieldData();
  fd->Initialize();
  auto i64 = [](uint64_t v) { return vtkTypeInt64(v); };
  add_field_tuple<vtkTypeInt64Array>(
      fd, "RayCounts",
      {i64(counters.rays[0]), i64(counters.rays[1]), i64(counters.rays[2]), i64(counters.rays[3])});
  add_field_tuple<vtkTypeInt64Array>(fd, "ShadowRaysOccluded", {i64(counters.shadow_occluded)});
  if (image->GetPointData()->GetAbstractArray("Cost")) {
    add_field_tuple<vtkTypeInt64Array>(fd, "NodesVisited", {i64(counters.nodes_visited)});
    add_field_tuple<vtkTypeInt64Array>(fd, "BoxesTested", {i64(counters.boxes_tested)});
    add_field_tuple<vtkTypeInt64Array>(fd, "PrimitivesTested", {i64(counters.prims_tested)});
  }
}

void framebuffer_to_image(const rayscope::Framebuffer& fb, const rayscope::RayCounters& counters,
                          vtkImageData* image, int threads) {
  prepare_image(image, fb.width, fb.height, !fb.cost.empty(), !fb.samples.empty());
  // Bands of rows on the render's threads: at 1280x720 one thread took as
  // long as a tenth of the frame's tracing.
  constexpr int kBandRows = 16;
  rayscope::thread_arena(threads).execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, fb.height, kBandRows), [&](const auto& rows) {
      framebuffer_rect_to_image(fb, 0, rows.begin(), fb.width, rows.end(), image);
    });
  });
  counters_to_image(counters, image);
}

}  // namespace rayscope_vtkio
