// The output arrays of the module's algorithms (private header): the image
// algorithm, the ray-tree source and the structure source make every point, cell and
// field array they output with these functions (make_array() and
// add_field_tuple() are rayscope_vtkio's, which the image arrays use too).
#pragma once

#include "vtkFieldData.h"
#include "vtkPoints.h"
#include "vtkSmartPointer.h"
#include "vtkType.h"

#include "rayscope/scene.h"
#include "rayscope_vtkio/data_arrays.h"

namespace rayscope_vtkmodule {

using rayscope_vtkio::add_field_tuple;
using rayscope_vtkio::make_array;

/// Points in world coordinates for `n` positions of `scene` (local to
/// Scene::origin; set them with set_world_point): float, or double when the
/// scene's origin is not the world's, where float would lose the precision
/// the local coordinates keep.
inline vtkSmartPointer<vtkPoints> make_world_points(const rayscope::Scene& scene, vtkIdType n) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataType(scene.origin == rayscope::DVec3(0.0) ? VTK_FLOAT : VTK_DOUBLE);
  points->SetNumberOfPoints(n);
  return points;
}

/// Point i of `points` at the world position of the scene-local `local`.
inline void set_world_point(vtkPoints* points, vtkIdType i, const rayscope::Scene& scene,
                            const rayscope::Vec3& local) {
  const rayscope::DVec3 w = scene.to_world(local);
  points->SetPoint(i, w.x, w.y, w.z);
}

/// A box's corners are numbered by bits (bit 0: x high, bit 1: y high, bit 2:
/// z high); its 12 edges and its 6 faces (outward facing) as corner numbers.
inline constexpr int kBoxEdges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                         {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
inline constexpr int kBoxFaces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                        {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};

}  // namespace rayscope_vtkmodule
