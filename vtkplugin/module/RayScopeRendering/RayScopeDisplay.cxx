#include "RayScopeDisplay.h"

#include <algorithm>
#include <cmath>

#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkIntArray.h"
#include "vtkLookupTable.h"
#include "vtkPointData.h"
#include "vtkUnsignedCharArray.h"

#include "rayscope/image.h"

namespace rayscope_vtkmodule {

namespace {

// The sRGB byte of a linear value clamped to [0, 1], as the image's colors
// are made (std::lround(255 * linear_to_srgb(v)), from a table).
unsigned char to_byte(float linear) {
  return rayscope::srgb_byte(linear);
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

// The modes that map one value per pixel onto a color scale.
struct Scale {
  vtkDataArray* values = nullptr;
  double lo = 0.0, hi = 1.0;                    // the range shown, the image's own
  rayscope::Color (*color)(float t) = nullptr;  // t in [0, 1], linear RGB
  const char* title = "";
  /// Whether values map to t by their logarithm (lo > 0): depth, whose range
  /// on a scene with a floor to the horizon spans decades, so that a linear
  /// scale would leave everything near the camera one shade.
  bool log = false;

  /// Where value v lies on the scale, in [0, 1].
  float where(double v) const {
    if (!(hi > lo)) return 0.0f;
    return float(log ? std::log(v / lo) / std::log(hi / lo) : (v - lo) / (hi - lo));
  }
};

rayscope::Color cost_color(float t) {
  return rayscope::heat_color(t);  // the scale of `rayscope render --aov cost`
}
rayscope::Color depth_color(float t) {
  return rayscope::Color(1.0f - 0.85f * std::clamp(t, 0.0f, 1.0f));  // near white, far dark
}

bool scale_of(vtkImageData* image, int mode, Scale& sc) {
  vtkPointData* pd = image->GetPointData();
  if (mode == kDisplayCost) {
    sc.values = vtkIntArray::SafeDownCast(pd->GetArray("Cost"));
    sc.color = cost_color;
    sc.title = "BVH nodes visited";
    sc.lo = 0.0;
    sc.hi = 1.0;  // 0 .. the image's maximum (at least 1)
  } else if (mode == kDisplayDepth) {
    sc.values = vtkFloatArray::SafeDownCast(pd->GetArray("Depth"));
    sc.color = depth_color;
    sc.title = "distance to the first hit (log scale)";
    sc.lo = INFINITY;
    sc.hi = -INFINITY;
    sc.log = true;
  } else {
    return false;
  }
  if (!sc.values) return false;
  for (vtkIdType i = 0; i < sc.values->GetNumberOfTuples(); ++i) {
    const double v = sc.values->GetTuple1(i);
    if (!std::isfinite(v) || (sc.log && !(v > 0.0))) continue;
    if (mode != kDisplayCost) sc.lo = std::min(sc.lo, v);
    sc.hi = std::max(sc.hi, v);
  }
  if (!(sc.lo <= sc.hi)) sc.lo = sc.hi = 0.0;  // no hit at all
  return true;
}

}  // namespace

bool display_scale(vtkImageData* image, int mode, vtkLookupTable* table, std::string& title) {
  Scale sc;
  if (!scale_of(image, mode, sc)) return false;
  constexpr int kSteps = 256;
  table->SetNumberOfTableValues(kSteps);
  for (int k = 0; k < kSteps; ++k) {
    const rayscope::Color c = sc.color(float(k) / float(kSteps - 1));
    table->SetTableValue(k, to_byte(c[0]) / 255.0, to_byte(c[1]) / 255.0, to_byte(c[2]) / 255.0);
  }
  if (sc.log && sc.lo > 0.0 && sc.hi > sc.lo) {
    table->SetScaleToLog10();
    table->SetTableRange(sc.lo, sc.hi);
  } else {
    table->SetScaleToLinear();
    table->SetTableRange(sc.lo, std::max(sc.hi, sc.lo + 1e-30));
  }
  title = sc.title;
  return true;
}

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
    case kDisplayCost:
    case kDisplayDepth: {
      Scale sc;
      if (!scale_of(image, mode, sc)) return {};
      fill([&](vtkIdType i) {
        const double v = sc.values->GetTuple1(i);
        if (!std::isfinite(v) || (sc.log && !(v > 0.0))) return rayscope::Color(0.0f);
        return sc.color(sc.where(v));
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

}  // namespace rayscope_vtkmodule
