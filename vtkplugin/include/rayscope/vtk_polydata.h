// Header-only helpers shared by the mesh-file reader (rayscope_vtkio) and the
// VTK module's converter: triangulated polydata to core mesh geometry, and the
// sRGB decoding of VTK's display colors.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>

#include "rayscope/scene.h"

namespace rayscope {

/// Replaces m's positions, triangles and normals with those of pd (only its
/// 3-point polygons; point normals when pd has them) and clears m's colors.
inline void polydata_geometry(vtkPolyData* pd, TriangleMesh& m) {
  m.positions.clear();
  m.triangles.clear();
  m.normals.clear();
  m.colors.clear();
  if (!pd) return;
  const vtkIdType np = pd->GetNumberOfPoints();
  m.positions.resize(size_t(np));
  for (vtkIdType i = 0; i < np; ++i) {
    double p[3];
    pd->GetPoint(i, p);
    m.positions[size_t(i)] = Vec3(float(p[0]), float(p[1]), float(p[2]));
  }
  vtkCellArray* polys = pd->GetPolys();
  m.triangles.reserve(size_t(polys->GetNumberOfCells()));
  vtkNew<vtkIdList> ids;
  for (polys->InitTraversal(); polys->GetNextCell(ids);)
    if (ids->GetNumberOfIds() == 3)
      m.triangles.emplace_back(uint32_t(ids->GetId(0)), uint32_t(ids->GetId(1)),
                               uint32_t(ids->GetId(2)));
  if (vtkDataArray* n = pd->GetPointData()->GetNormals();
      n && n->GetNumberOfComponents() == 3 && n->GetNumberOfTuples() == np) {
    m.normals.resize(size_t(np));
    for (vtkIdType i = 0; i < np; ++i) {
      double v[3];
      n->GetTuple(i, v);
      m.normals[size_t(i)] = Vec3(float(v[0]), float(v[1]), float(v[2]));
    }
  }
}

/// sRGB-encoded value in [0, 1] -> linear (VTK's colors are sRGB display values).
inline float srgb_to_linear(double v) {
  float s = float(v);
  if (!(s > 0.0f)) return 0.0f;
  if (s >= 1.0f) return 1.0f;
  return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
}

/// The linear values of the 256 sRGB bytes.
inline const std::array<float, 256>& srgb_byte_table() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[size_t(i)] = srgb_to_linear(double(i) / 255.0);
    return t;
  }();
  return table;
}

}  // namespace rayscope
