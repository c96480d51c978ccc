#include "RayScopeDisplay.h"

#include <algorithm>
#include <cmath>

#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkIntArray.h"
#include "vtkPointData.h"
#include "vtkUnsignedCharArray.h"

#include "rayscope/image.h"

namespace rayscope_vtk {

namespace {

unsigned char to_byte(float linear) {
  return (unsigned char)std::lround(255.0f *
                                    rayscope::linear_to_srgb(std::clamp(linear, 0.0f, 1.0f)));
}

// Evenly spread hues for object ids (golden-angle steps), as linear RGB.
rayscope::Color id_color(int id) {
  const float h = std::fmod(float(id) * 0.618034f, 1.0f) * 6.0f;
  const float x = 1.0f - std::abs(std::fmod(h, 2.0f) - 1.0f);
  const int sector = int(h);
  const rayscope::Color table[6] = {{1, x, 0}, {x, 1, 0}, {0, 1, x},
                                    {0, x, 1}, {x, 0, 1}, {1, 0, x}};
  return table[std::clamp(sector, 0, 5)] * 0.8f + rayscope::Color(0.1f);
}

}  // namespace

const char* display_mode_name(int mode) {
  switch (mode) {
    case kDisplayColor:
      return "color";
    case kDisplayCost:
      return "cost heat map";
    case kDisplayNormal:
      return "normals";
    case kDisplayDepth:
      return "depth";
    case kDisplayObjectId:
      return "object ids";
  }
  return "?";
}

std::vector<unsigned char> display_pixels(vtkImageData* image, int mode) {
  vtkPointData* pd = image->GetPointData();
  const vtkIdType n = image->GetNumberOfPoints();
  std::vector<unsigned char> rgb;
  auto fill = [&](auto&& color_of) {
    rgb.resize(size_t(n) * 3);
    for (vtkIdType i = 0; i < n; ++i) {
      const rayscope::Color c = color_of(i);
      for (int k = 0; k < 3; ++k) rgb[size_t(i) * 3 + size_t(k)] = to_byte(c[k]);
    }
  };
  switch (mode) {
    case kDisplayColor: {
      auto* color = vtkUnsignedCharArray::SafeDownCast(pd->GetArray("Color"));
      if (!color || color->GetNumberOfComponents() != 3) return {};
      const unsigned char* p = color->GetPointer(0);
      rgb.assign(p, p + size_t(n) * 3);
      break;
    }
    case kDisplayCost: {
      // The heat-map scale of `rayscope render --aov cost`: 0 .. the image's maximum.
      auto* cost = vtkIntArray::SafeDownCast(pd->GetArray("Cost"));
      if (!cost) return {};
      int max_cost = 1;
      for (vtkIdType i = 0; i < n; ++i) max_cost = std::max(max_cost, cost->GetValue(i));
      fill([&](vtkIdType i) {
        return rayscope::heat_color(float(cost->GetValue(i)) / float(max_cost));
      });
      break;
    }
    case kDisplayNormal: {
      auto* normal = vtkFloatArray::SafeDownCast(pd->GetArray("Normal"));
      if (!normal) return {};
      fill([&](vtkIdType i) {
        rayscope::Color c;
        for (int k = 0; k < 3; ++k) c[k] = normal->GetTypedComponent(i, k);
        return c == rayscope::Color(0.0f) ? c : 0.5f * (c + rayscope::Color(1.0f));
      });
      break;
    }
    case kDisplayDepth: {
      auto* depth = vtkFloatArray::SafeDownCast(pd->GetArray("Depth"));
      if (!depth) return {};
      float lo = INFINITY, hi = 0.0f;
      for (vtkIdType i = 0; i < n; ++i)
        if (std::isfinite(depth->GetValue(i))) {
          lo = std::min(lo, depth->GetValue(i));
          hi = std::max(hi, depth->GetValue(i));
        }
      fill([&](vtkIdType i) {
        const float d = depth->GetValue(i);
        if (!std::isfinite(d)) return rayscope::Color(0.0f);
        return rayscope::Color(1.0f - 0.85f * (d - lo) / std::max(hi - lo, 1e-30f));
      });
      break;
    }
    case kDisplayObjectId: {
      auto* ids = vtkIntArray::SafeDownCast(pd->GetArray("ObjectId"));
      if (!ids) return {};
      fill([&](vtkIdType i) {
        return ids->GetValue(i) < 0 ? rayscope::Color(0.0f) : id_color(ids->GetValue(i));
      });
      break;
    }
    default:
      return {};
  }
  return rgb;
}

}  // namespace rayscope_vtk
