#include "vtkRayScopeMeshReader.h"

#include <exception>
#include <filesystem>
#include <string>
#include <system_error>

#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPolyData.h"
#include "vtkRectilinearGrid.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStructuredGrid.h"

#include "rayscope/input_file.h"
#include "rayscope_vtkio/mesh_checks.h"
#include "rayscope_vtkio/mesh_files.h"

vtkStandardNewMacro(vtkRayScopeMeshReader);

vtkRayScopeMeshReader::vtkRayScopeMeshReader() : FileName(nullptr) {
  this->SetNumberOfInputPorts(0);
  this->SetNumberOfOutputPorts(1);
}

vtkRayScopeMeshReader::~vtkRayScopeMeshReader() {
  this->SetFileName(nullptr);
}

int vtkRayScopeMeshReader::CanReadFile(const char* name) {
  if (!name || !*name) return 0;
  const std::filesystem::path path(name);
  return rayscope_vtkio::has_dataset_file_extension(path) &&
                 rayscope::input_file_problem(path).empty()
             ? 1
             : 0;
}

int vtkRayScopeMeshReader::FillOutputPortInformation(int, vtkInformation* info) {
  info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkDataSet");
  return 1;
}

void vtkRayScopeMeshReader::ReadFile() {
  this->Data = nullptr;
  this->Error.clear();
  this->Warning.clear();
  if (!this->FileName || !*this->FileName) {
    this->Error = "no file to read: FileName is not set";
    return;
  }
  try {
    this->Data = rayscope_vtkio::read_dataset_file(this->FileName);
  } catch (const std::exception& e) {  // "FILE: problem" (std::bad_alloc too, for a huge file)
    this->Data = nullptr;
    this->Error = e.what();
    return;
  }
  // VTK's readers read an empty file, or a text file cut off before its first
  // point (an OBJ of comments, an ASCII STL of "solid" and "endsolid"), as an
  // empty dataset without a word: refused, so that a dataset from this reader
  // always holds something.
  if (this->Data->GetNumberOfPoints() == 0) {
    this->Data = nullptr;
    this->Error = std::string(this->FileName) +
                  ": holds no points (an empty file, or one cut off before its first point)";
    return;
  }
  // Arrays VTK's filters would read past the end of go, with a warning.
  for (const std::string& removed : rayscope_vtkio::remove_short_attribute_arrays(this->Data))
    this->Warning +=
        (this->Warning.empty() ? std::string(this->FileName) + ": removed " : "; ") + removed;
}

// The output's type is the type of the dataset VTK's reader gives, which for
// a legacy .vtk file only the file says: so the file is read here, in the
// first pass of every update after FileName (or Modified()) changed, and the
// dataset is kept for RequestInformation and RequestData. After an error the
// output keeps its type (a vtkPolyData when it has none yet), to be emptied
// by RequestData.
int vtkRayScopeMeshReader::RequestDataObject(vtkInformation*, vtkInformationVector**,
                                             vtkInformationVector* outputVector) {
  this->ReadFile();
  vtkInformation* info = outputVector->GetInformationObject(0);
  vtkDataObject* current = info->Get(vtkDataObject::DATA_OBJECT());
  vtkSmartPointer<vtkDataObject> output;
  if (this->Data) {
    if (!current || std::string(current->GetClassName()) != this->Data->GetClassName())
      output = vtkSmartPointer<vtkDataObject>::Take(this->Data->NewInstance());
  } else if (!vtkDataSet::SafeDownCast(current)) {
    output = vtkSmartPointer<vtkPolyData>::New();
  }
  if (output) info->Set(vtkDataObject::DATA_OBJECT(), output);
  return 1;
}

// Structured datasets (image data, structured and rectilinear grids) announce
// their whole extent, as VTK's readers of them do, so that the streaming
// pipeline and downstream image filters request the extent the file has.
int vtkRayScopeMeshReader::RequestInformation(vtkInformation*, vtkInformationVector**,
                                              vtkInformationVector* outputVector) {
  vtkInformation* info = outputVector->GetInformationObject(0);
  int extent[6];
  bool structured = true;
  if (auto* image = vtkImageData::SafeDownCast(this->Data)) {
    image->GetExtent(extent);
    info->Set(vtkDataObject::ORIGIN(), image->GetOrigin(), 3);
    info->Set(vtkDataObject::SPACING(), image->GetSpacing(), 3);
  } else if (auto* grid = vtkStructuredGrid::SafeDownCast(this->Data)) {
    grid->GetExtent(extent);
  } else if (auto* rgrid = vtkRectilinearGrid::SafeDownCast(this->Data)) {
    rgrid->GetExtent(extent);
  } else {
    structured = false;
  }
  if (structured)
    info->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  else
    info->Remove(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT());
  return 1;
}

int vtkRayScopeMeshReader::RequestData(vtkInformation*, vtkInformationVector**,
                                       vtkInformationVector* outputVector) {
  vtkDataSet* output = vtkDataSet::GetData(outputVector, 0);
  if (!output) {  // RequestDataObject always makes one; a guard, not a path
    vtkErrorMacro(<< "the pipeline gave no output dataset");
    return 0;
  }
  output->Initialize();
  if (!this->Data) {
    vtkErrorMacro(<< this->Error);
    return 0;
  }
  if (!this->Warning.empty()) vtkWarningMacro(<< this->Warning);
  // The output shares the kept dataset's points, cells and arrays (no copy).
  output->ShallowCopy(this->Data);
  return 1;
}

void vtkRayScopeMeshReader::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "Data: "
     << (this->Data ? this->Data->GetClassName() : (this->Error.empty() ? "(not read)" : "(error)"))
     << "\n";
  if (!this->Error.empty()) os << indent << "Error: " << this->Error << "\n";
  if (!this->Warning.empty()) os << indent << "Warning: " << this->Warning << "\n";
}
