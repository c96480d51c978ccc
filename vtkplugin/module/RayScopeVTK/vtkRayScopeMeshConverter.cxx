#include "vtkRayScopeMeshConverter.h"

#include <unordered_map>

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataSetMapper.h"
#include "vtkDataSetSurfaceFilter.h"
#include "vtkFloatArray.h"
#include "vtkIdList.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataNormals.h"
#include "vtkScalarsToColors.h"
#include "vtkSmartPointer.h"
#include "vtkTriangleFilter.h"
#include "vtkUnsignedCharArray.h"

#include "rayscope/scene.h"
#include "rayscope/vtk_polydata.h"
#include "vtkRayScopeColor.h"

vtkStandardNewMacro(vtkRayScopeMeshConverter);

vtkRayScopeMeshConverter::vtkRayScopeMeshConverter()
    : ComputeNormals(1),
      Splitting(1),
      FeatureAngle(30.0),
      NonlinearSubdivisionLevel(1),
      Mapper(vtkDataSetMapper::New()),
      LastColorSource(NO_COLORS) {
  this->Mapper->GetLookupTable();  // create the default table now, not during a conversion
}

vtkRayScopeMeshConverter::~vtkRayScopeMeshConverter() {
  this->Mapper->UnRegister(this);
}

void vtkRayScopeMeshConverter::SetMapper(vtkMapper* mapper) {
  if (mapper == this->Mapper) return;
  this->Mapper->UnRegister(this);
  if (mapper) {
    this->Mapper = mapper;
    mapper->Register(this);
  } else {
    this->Mapper = vtkDataSetMapper::New();
  }
  this->Mapper->GetLookupTable();
  this->Modified();
}

vtkMTimeType vtkRayScopeMeshConverter::GetMTime() {
  vtkMTimeType t = this->Superclass::GetMTime();
  // vtkMapper::GetMTime() includes its lookup table.
  vtkMTimeType m = this->Mapper->GetMTime();
  return m > t ? m : t;
}

namespace {

// The surface the mapper would draw: triangles only, with point normals.
vtkSmartPointer<vtkPolyData> triangulate(vtkDataSet* input, bool compute_normals, bool splitting,
                                         double feature_angle, int subdivision) {
  vtkSmartPointer<vtkPolyData> surface = vtkPolyData::SafeDownCast(input);
  if (!surface) {
    vtkNew<vtkDataSetSurfaceFilter> sf;
    sf->SetInputData(input);
    sf->SetNonlinearSubdivisionLevel(subdivision);
    sf->Update();
    surface = sf->GetOutput();
  }
  vtkNew<vtkTriangleFilter> tf;
  tf->SetInputData(surface);
  tf->PassVertsOff();
  tf->PassLinesOff();
  tf->Update();
  vtkSmartPointer<vtkPolyData> tri = tf->GetOutput();
  vtkDataArray* n = tri->GetPointData()->GetNormals();
  if (compute_normals && (!n || n->GetNumberOfComponents() != 3) && tri->GetNumberOfPolys() > 0) {
    vtkNew<vtkPolyDataNormals> pn;
    pn->SetInputData(tri);
    pn->SetSplitting(splitting);
    pn->SetFeatureAngle(feature_angle);
    pn->ComputePointNormalsOn();
    pn->ComputeCellNormalsOff();
    pn->AutoOrientNormalsOff();
    pn->Update();
    tri = pn->GetOutput();
  }
  return tri;
}

}  // namespace

int vtkRayScopeMeshConverter::Convert(vtkDataSet* input, vtkPolyData* output) {
  if (!input || !output) {
    vtkErrorMacro(<< "Convert: " << (input ? "output" : "input") << " is null");
    return 0;
  }
  vtkSmartPointer<vtkPolyData> tri =
      triangulate(input, this->ComputeNormals, this->Splitting, this->FeatureAngle,
                  this->NonlinearSubdivisionLevel);

  // Colors by the mapper's own code, on the very surface it would draw.
  // The copy maps with a private copy of the lookup table: the mapper sets the
  // table's range, which must not modify the user's table (and so this
  // converter) on every conversion.
  vtkNew<vtkDataSetMapper> mapper;
  mapper->ShallowCopy(this->Mapper);
  if (vtkScalarsToColors* lut = this->Mapper->GetLookupTable()) {
    vtkSmartPointer<vtkScalarsToColors> copy = vtk::TakeSmartPointer(lut->NewInstance());
    copy->DeepCopy(lut);
    mapper->SetLookupTable(copy);
  }
  mapper->SetInterpolateScalarsBeforeMapping(0);
  mapper->SetInputData(tri);
  int cell_flag = 0;
  vtkSmartPointer<vtkUnsignedCharArray> mapped = mapper->MapScalars(tri, 1.0, cell_flag);

  const vtkIdType ntri = tri->GetNumberOfPolys();
  const vtkIdType npts = tri->GetNumberOfPoints();
  // One RGBA color per triangle (cell colors) or per point, or none.
  this->LastColorSource = NO_COLORS;
  vtkSmartPointer<vtkUnsignedCharArray> cell_colors, point_colors;
  if (mapped && mapped->GetNumberOfComponents() == 4) {
    const vtkIdType field_tuple = this->Mapper->GetFieldDataTupleId();
    if (cell_flag == 0 && mapped->GetNumberOfTuples() == npts) {
      point_colors = mapped;
      this->LastColorSource = POINT_COLORS;
    } else if (cell_flag == 1 && mapped->GetNumberOfTuples() == ntri) {
      cell_colors = mapped;
      this->LastColorSource = CELL_COLORS;
    } else if (cell_flag == 2 && field_tuple >= 0 && field_tuple < mapped->GetNumberOfTuples()) {
      point_colors = vtkSmartPointer<vtkUnsignedCharArray>::New();
      point_colors->SetNumberOfComponents(4);
      point_colors->SetNumberOfTuples(npts);
      for (vtkIdType i = 0; i < npts; ++i)
        for (int k = 0; k < 4; ++k)
          point_colors->SetTypedComponent(i, k, mapped->GetTypedComponent(field_tuple, k));
      this->LastColorSource = FIELD_COLORS;
    } else if (cell_flag == 2 && field_tuple < 0 && mapped->GetNumberOfTuples() >= ntri) {
      cell_colors = mapped;  // one field tuple per cell, as VTK draws it
      this->LastColorSource = FIELD_COLORS;
    }
  }

  vtkDataArray* in_normals = tri->GetPointData()->GetNormals();
  if (in_normals && in_normals->GetNumberOfComponents() != 3) in_normals = nullptr;

  // With cell colors, each (point, color) pair becomes one output point, so a
  // point shared by cells of different colors is duplicated once per color.
  std::vector<vtkIdType> source;    // output point -> input point
  std::vector<vtkIdType> color_of;  // output point -> color tuple (or -1)
  vtkNew<vtkCellArray> polys;
  polys->AllocateEstimate(ntri, 3);
  vtkNew<vtkIdList> ids;
  vtkCellArray* in_polys = tri->GetPolys();
  if (cell_colors) {
    std::unordered_map<uint64_t, vtkIdType> index;
    index.reserve(size_t(npts));
    vtkIdType cell = 0;
    for (in_polys->InitTraversal(); in_polys->GetNextCell(ids); ++cell) {
      if (ids->GetNumberOfIds() != 3) continue;
      uint32_t rgb = 0;
      for (int k = 0; k < 3; ++k) rgb = (rgb << 8) | cell_colors->GetTypedComponent(cell, k);
      vtkIdType out[3];
      for (int v = 0; v < 3; ++v) {
        vtkIdType p = ids->GetId(v);
        uint64_t key = (uint64_t(p) << 24) | rgb;
        auto [it, inserted] = index.emplace(key, vtkIdType(source.size()));
        if (inserted) {
          source.push_back(p);
          color_of.push_back(cell);
        }
        out[v] = it->second;
      }
      polys->InsertNextCell(3, out);
    }
  } else {
    source.resize(size_t(npts));
    for (vtkIdType i = 0; i < npts; ++i) source[size_t(i)] = i;
    if (point_colors) color_of = source;
    for (in_polys->InitTraversal(); in_polys->GetNextCell(ids);)
      if (ids->GetNumberOfIds() == 3) polys->InsertNextCell(ids);
  }

  const vtkIdType nout = vtkIdType(source.size());
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  points->SetNumberOfPoints(nout);
  for (vtkIdType i = 0; i < nout; ++i) points->SetPoint(i, tri->GetPoint(source[size_t(i)]));

  output->Initialize();
  output->SetPoints(points);
  output->SetPolys(polys);
  if (in_normals) {
    vtkNew<vtkFloatArray> normals;
    normals->SetName("Normals");
    normals->SetNumberOfComponents(3);
    normals->SetNumberOfTuples(nout);
    for (vtkIdType i = 0; i < nout; ++i)
      normals->SetTuple(i, in_normals->GetTuple(source[size_t(i)]));
    output->GetPointData()->SetNormals(normals);
  }
  vtkUnsignedCharArray* colors_in = cell_colors ? cell_colors.Get() : point_colors.Get();
  if (colors_in) {
    const auto& table = rayscope_vtk::srgb_byte_table();
    vtkNew<vtkUnsignedCharArray> colors;
    colors->SetName("Colors");
    colors->SetNumberOfComponents(4);
    colors->SetNumberOfTuples(nout);
    vtkNew<vtkFloatArray> linear;
    linear->SetName("LinearColors");
    linear->SetNumberOfComponents(3);
    linear->SetNumberOfTuples(nout);
    for (vtkIdType i = 0; i < nout; ++i) {
      const vtkIdType c = color_of[size_t(i)];
      for (int k = 0; k < 4; ++k) {
        unsigned char b = colors_in->GetTypedComponent(c, k);
        colors->SetTypedComponent(i, k, b);
        if (k < 3) linear->SetTypedComponent(i, k, table[b]);
      }
    }
    output->GetPointData()->SetScalars(colors);
    output->GetPointData()->AddArray(linear);
  }
  return 1;
}

void vtkRayScopeMeshConverter::MeshFromPolyData(vtkPolyData* pd, rayscope::TriangleMesh& m) {
  rayscope::polydata_geometry(pd, m);
  if (!pd) return;
  const vtkIdType np = pd->GetNumberOfPoints();
  if (vtkDataArray* c = pd->GetPointData()->GetArray("LinearColors");
      c && c->GetNumberOfComponents() == 3 && c->GetNumberOfTuples() == np) {
    m.colors.resize(size_t(np));
    for (vtkIdType i = 0; i < np; ++i) {
      double v[3];
      c->GetTuple(i, v);
      m.colors[size_t(i)] = rayscope::Color(float(v[0]), float(v[1]), float(v[2]));
    }
  }
}

bool vtkRayScopeMeshConverter::ConvertToMesh(vtkDataSet* input, rayscope::TriangleMesh& mesh) {
  vtkNew<vtkPolyData> pd;
  if (!this->Convert(input, pd)) return false;
  MeshFromPolyData(pd, mesh);
  return true;
}

void vtkRayScopeMeshConverter::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ComputeNormals: " << this->ComputeNormals << "\n";
  os << indent << "Splitting: " << this->Splitting << "\n";
  os << indent << "FeatureAngle: " << this->FeatureAngle << "\n";
  os << indent << "NonlinearSubdivisionLevel: " << this->NonlinearSubdivisionLevel << "\n";
  os << indent << "Mapper: " << this->Mapper->GetClassName() << " (" << this->Mapper << ")\n";
  os << indent << "LastColorSource: " << this->LastColorSource << "\n";
}
