#include "vtkRayScopeMeshConverter.h"

#include <exception>

#include <glm/gtc/matrix_transform.hpp>

#include "vtkDataSetMapper.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPolyData.h"

#include "rayscope/scene.h"
#include "rayscope_vtkio/line_conversion.h"
#include "rayscope_vtkio/mesh_conversion.h"

vtkStandardNewMacro(vtkRayScopeMeshConverter);

namespace {
// The defaults are those of the conversion the rayscope command uses too.
const rayscope_vtkio::SurfaceOptions kDefaults;
}  // namespace

static_assert(int(rayscope_vtkio::ColorSource::None) == vtkRayScopeMeshConverter::NO_COLORS &&
              int(rayscope_vtkio::ColorSource::Point) == vtkRayScopeMeshConverter::POINT_COLORS &&
              int(rayscope_vtkio::ColorSource::Cell) == vtkRayScopeMeshConverter::CELL_COLORS &&
              int(rayscope_vtkio::ColorSource::Field) == vtkRayScopeMeshConverter::FIELD_COLORS);

vtkRayScopeMeshConverter::vtkRayScopeMeshConverter()
    : ComputeNormals(kDefaults.compute_normals),
      Splitting(kDefaults.splitting),
      FeatureAngle(kDefaults.feature_angle),
      NonlinearSubdivisionLevel(kDefaults.nonlinear_subdivision_level),
      Mapper(vtkDataSetMapper::New()),
      LastColorSource(NO_COLORS),
      LineWidth(1.0),
      PointSize(1.0) {
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

int vtkRayScopeMeshConverter::Convert(vtkDataSet* input, vtkPolyData* output) {
  if (!input || !output) {
    vtkErrorMacro(<< "Convert: " << (input ? "output" : "input") << " is null");
    return 0;
  }
  std::string why;
  if (!this->ConvertOrExplain(input, output, why)) {
    vtkErrorMacro(<< "Convert: " << input->GetClassName() << ": " << why);
    return 0;
  }
  return 1;
}

bool vtkRayScopeMeshConverter::ConvertOrExplain(vtkDataSet* input, vtkPolyData* output,
                                                std::string& why) {
  rayscope_vtkio::SurfaceOptions options;
  options.compute_normals = this->ComputeNormals != 0;
  options.splitting = this->Splitting != 0;
  options.feature_angle = this->FeatureAngle;
  options.nonlinear_subdivision_level = this->NonlinearSubdivisionLevel;
  try {
    this->LastColorSource =
        int(rayscope_vtkio::convert_dataset(input, options, this->Mapper, output));
  } catch (const std::exception& e) {  // input the conversion refuses, e.g. bad point ids
    output->Initialize();
    this->LastColorSource = NO_COLORS;
    why = e.what();
    return false;
  }
  return true;
}

void vtkRayScopeMeshConverter::MeshFromPolyData(vtkPolyData* pd, rayscope::TriangleMesh& m) {
  rayscope_vtkio::mesh_from_converted(pd, m);
}

bool vtkRayScopeMeshConverter::ConvertToMesh(vtkDataSet* input, rayscope::TriangleMesh& mesh,
                                             std::string* why, const double origin[3]) {
  vtkNew<vtkPolyData> pd;
  if (!why) {
    if (!this->Convert(input, pd)) return false;
  } else if (!input) {
    *why = "the input is null";
    return false;
  } else if (!this->ConvertOrExplain(input, pd, *why)) {
    return false;
  }
  const glm::dvec3 o = origin ? glm::dvec3(origin[0], origin[1], origin[2]) : glm::dvec3(0.0);
  rayscope_vtkio::mesh_from_converted(pd, mesh, glm::translate(glm::dmat4(1.0), -o));
  return true;
}

bool vtkRayScopeMeshConverter::ConvertLinesAndPoints(vtkDataSet* input,
                                                     const rayscope_vtkio::CurveRadii& radii,
                                                     rayscope::TubeSet& tubes,
                                                     rayscope::PointSet& points, std::string& why,
                                                     const double origin[3]) {
  const glm::dvec3 o = origin ? glm::dvec3(origin[0], origin[1], origin[2]) : glm::dvec3(0.0);
  try {
    rayscope_vtkio::convert_lines_and_points(input, this->Mapper, radii, tubes, points,
                                             glm::translate(glm::dmat4(1.0), -o));
  } catch (const std::exception& e) {
    why = e.what();
    return false;
  }
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
  os << indent << "LineWidth: " << this->LineWidth << "\n";
  os << indent << "PointSize: " << this->PointSize << "\n";
}
