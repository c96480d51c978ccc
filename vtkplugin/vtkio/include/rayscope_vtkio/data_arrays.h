// Named VTK arrays: the image arrays (image_arrays.h) and the output arrays of
// the VTK module's algorithms (its RayScopeArrays.h) are made with these.
#pragma once

#include <initializer_list>

#include "vtkFieldData.h"
#include "vtkSmartPointer.h"
#include "vtkType.h"

namespace rayscope_vtkio {

/// A new array of type A named `name` with `components` components and
/// `tuples` tuples (values not initialised).
template <class A>
vtkSmartPointer<A> make_array(const char* name, int components, vtkIdType tuples) {
  auto a = vtkSmartPointer<A>::New();
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(tuples);
  return a;
}

/// Adds to `fd` an array of type A named `name` with one tuple whose
/// components are `values` (the counters and totals of an output).
template <class A>
void add_field_tuple(vtkFieldData* fd, const char* name,
                     std::initializer_list<typename A::ValueType> values) {
  auto a = make_array<A>(name, int(values.size()), 1);
  int k = 0;
  for (typename A::ValueType v : values) a->SetTypedComponent(0, k++, v);
  fd->AddArray(a);
}

}  // namespace rayscope_vtkio
