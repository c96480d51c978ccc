#include <algorithm>
#include <cctype>
#include <stdexcept>
#include <string>

#include <vtkDataSet.h>
#include <vtkDataSetReader.h>
#include <vtkDataSetSurfaceFilter.h>
#include <vtkNew.h>
#include <vtkOBJReader.h>
#include <vtkPLYReader.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSTLReader.h>
#include <vtkSmartPointer.h>
#include <vtkTriangleFilter.h>
#include <vtkUnsignedCharArray.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "rayscope/vtk_mesh.h"
#include "rayscope/vtk_polydata.h"

namespace rayscope {

TriangleMesh mesh_from_vtk(vtkDataSet* data, const std::string& name) {
  if (!data) throw std::runtime_error(name + ": no data");
  vtkNew<vtkDataSetSurfaceFilter> surface;
  surface->SetInputData(data);
  surface->SetNonlinearSubdivisionLevel(1);
  vtkNew<vtkTriangleFilter> tri;
  tri->SetInputConnection(surface->GetOutputPort());
  tri->PassVertsOff();
  tri->PassLinesOff();
  tri->Update();
  vtkPolyData* pd = tri->GetOutput();

  TriangleMesh m;
  polydata_geometry(pd, m);
  m.name = name;
  const vtkIdType np = pd->GetNumberOfPoints();
  // Direct RGB(A) colors, as VTK's mappers show them with ColorModeToDirectScalars.
  if (auto* c = vtkUnsignedCharArray::SafeDownCast(pd->GetPointData()->GetScalars());
      c && (c->GetNumberOfComponents() == 3 || c->GetNumberOfComponents() == 4) &&
      c->GetNumberOfTuples() == np) {
    const std::array<float, 256>& lin = srgb_byte_table();
    m.colors.resize(size_t(np));
    for (vtkIdType i = 0; i < np; ++i)
      m.colors[size_t(i)] = Color(lin[c->GetTypedComponent(i, 0)], lin[c->GetTypedComponent(i, 1)],
                                  lin[c->GetTypedComponent(i, 2)]);
  }
  return m;
}

TriangleMesh read_mesh_file(const std::filesystem::path& path) {
  const std::string f = path.string();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw std::runtime_error(f + ": file not found");
  if (!std::filesystem::is_regular_file(path, ec)) throw std::runtime_error(f + ": not a file");
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  vtkSmartPointer<vtkDataSet> data;
  if (ext == ".stl") {
    vtkNew<vtkSTLReader> r;
    r->SetFileName(f.c_str());
    r->Update();
    data = r->GetOutput();
  } else if (ext == ".ply") {
    if (!vtkPLYReader::CanReadFile(f.c_str())) throw std::runtime_error(f + ": not a PLY file");
    vtkNew<vtkPLYReader> r;
    r->SetFileName(f.c_str());
    r->Update();
    data = r->GetOutput();
  } else if (ext == ".obj") {
    vtkNew<vtkOBJReader> r;
    r->SetFileName(f.c_str());
    r->Update();
    data = r->GetOutput();
  } else if (ext == ".vtk") {
    vtkNew<vtkDataSetReader> r;
    r->SetFileName(f.c_str());
    r->Update();
    data = r->GetOutput();
  } else if (ext == ".vtp" || ext == ".vtu") {
    // The format-specific XML readers: vtkXMLGenericDataObjectReader::CanReadFile
    // rejects every file in VTK 9.1.
    vtkSmartPointer<vtkXMLReader> r;
    if (ext == ".vtp")
      r = vtkSmartPointer<vtkXMLPolyDataReader>::New();
    else
      r = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
    if (!r->CanReadFile(f.c_str()))
      throw std::runtime_error(f + ": not a VTK XML " + ext + " file");
    r->SetFileName(f.c_str());
    r->Update();
    data = vtkDataSet::SafeDownCast(r->GetOutputDataObject(0));
  } else {
    throw std::runtime_error(f + ": unsupported mesh format '" + ext +
                             "' (use .vtp, .vtu, .vtk, .stl, .ply or .obj)");
  }
  if (!data) throw std::runtime_error(f + ": could not read a dataset");
  TriangleMesh m = mesh_from_vtk(data, path.filename().string());
  if (m.triangles.empty()) throw std::runtime_error(f + ": contains no surface triangles");
  return m;
}

}  // namespace rayscope
