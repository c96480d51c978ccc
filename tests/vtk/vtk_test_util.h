// Helpers of the VTK module tests: small scenes made of VTK sources and an
// observer that captures error messages instead of printing them.
#pragma once

#include <string>

#include <vtkAlgorithm.h>
#include <vtkCommand.h>
#include <vtkExecutive.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkObject.h>
#include <vtkPlaneSource.h>
#include <vtkPointData.h>
#include <vtkSphereSource.h>

/// Collects ErrorEvent messages of the objects it observes.
class ErrorCatcher : public vtkCommand {
 public:
  static ErrorCatcher* New() { return new ErrorCatcher; }
  void Execute(vtkObject*, unsigned long, void* data) override {
    ++count;
    if (data) last = static_cast<const char*>(data);
  }
  int count = 0;
  std::string last;
};

inline void configure_sphere(vtkSphereSource* s, double x, double y, double z, double r,
                             int resolution = 48) {
  s->SetCenter(x, y, z);
  s->SetRadius(r);
  s->SetThetaResolution(resolution);
  s->SetPhiResolution(resolution / 2);
}

/// Square floor in the plane y = height, 2 * half wide, facing +y.
inline void configure_floor(vtkPlaneSource* p, double height, double half) {
  p->SetOrigin(-half, height, half);
  p->SetPoint1(half, height, half);
  p->SetPoint2(-half, height, -half);
}

/// Runs the pipeline; 1 on success, 0 when an algorithm failed.
inline int update(vtkAlgorithm* a) {
  return a->GetExecutive()->Update();
}

/// Pixels showing object `id` in a traced image (its "ObjectId" array).
inline int count_object(vtkImageData* img, int id) {
  auto* a = vtkIntArray::SafeDownCast(img->GetPointData()->GetArray("ObjectId"));
  int n = 0;
  for (vtkIdType k = 0; k < a->GetNumberOfTuples(); ++k) n += a->GetValue(k) == id;
  return n;
}
