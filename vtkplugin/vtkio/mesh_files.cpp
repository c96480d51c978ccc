#include "rayscope_vtkio/mesh_files.h"

#include <algorithm>
#include <cctype>
#include <stdexcept>
#include <string>

#include <vtkCellData.h>
#include <vtkColorTransferFunction.h>
#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkDataSetMapper.h>
#include <vtkDataSetReader.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkOBJReader.h>
#include <vtkOutputWindow.h>
#include <vtkPLYReader.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSTLReader.h>
#include <vtkUnsignedCharArray.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "rayscope/input_file.h"
#include "rayscope/printable_text.h"
#include "rayscope_vtkio/mesh_checks.h"
#include "rayscope_vtkio/mesh_conversion.h"
#include "rayscope_vtkio/plain_obj.h"

namespace rayscope_vtkio {
namespace {

using rayscope::MeshColorBy;

// The lookup table of a named map over [lo, hi], from VTK's own tables.
vtkSmartPointer<vtkScalarsToColors> color_map(rayscope::ColorMap map, double lo, double hi) {
  switch (map) {
    case rayscope::ColorMap::CoolWarm: {
      // VTK's diverging color space between the end colors Moreland proposed
      // for it (the map ParaView calls "Cool to Warm").
      auto ctf = vtkSmartPointer<vtkColorTransferFunction>::New();
      ctf->SetColorSpaceToDiverging();
      ctf->AddRGBPoint(lo, 0.230, 0.299, 0.754);
      ctf->AddRGBPoint(hi, 0.706, 0.016, 0.150);
      return ctf;
    }
    case rayscope::ColorMap::Rainbow:
    case rayscope::ColorMap::Grayscale: {
      auto lut = vtkSmartPointer<vtkLookupTable>::New();
      if (map == rayscope::ColorMap::Rainbow) {
        lut->SetHueRange(2.0 / 3.0, 0.0);  // blue to red
      } else {
        lut->SetHueRange(0.0, 0.0);
        lut->SetSaturationRange(0.0, 0.0);
        lut->SetValueRange(0.0, 1.0);  // black to white
      }
      lut->SetTableRange(lo, hi);
      lut->Build();
      return lut;
    }
  }
  return nullptr;
}

std::string array_names(vtkFieldData* fd) {
  std::string names;
  for (int i = 0; i < fd->GetNumberOfArrays(); ++i)
    if (const char* n = fd->GetArrayName(i)) names += std::string(names.empty() ? "" : ", ") + n;
  return names;
}

// The mapper that colors `data` as `color_by` says.
vtkSmartPointer<vtkMapper> color_by_mapper(vtkDataSet* data, const MeshColorBy& c,
                                           const std::string& file) {
  const bool cell = c.association == MeshColorBy::Association::Cell;
  vtkFieldData* fd = cell ? static_cast<vtkFieldData*>(data->GetCellData())
                          : static_cast<vtkFieldData*>(data->GetPointData());
  const char* kind = cell ? "cell" : "point";
  vtkAbstractArray* a = fd->GetAbstractArray(c.array.c_str());
  if (!a) {
    const std::string names = array_names(fd);
    throw rayscope::MeshOptionError("color_by.array: " + file + " has no " + kind + " array '" +
                                    c.array + "' (" +
                                    (names.empty() ? std::string("it has no ") + kind + " arrays"
                                                   : std::string(kind) + " arrays: " + names) +
                                    ")");
  }
  auto* values = vtkDataArray::SafeDownCast(a);
  if (!values)
    throw rayscope::MeshOptionError("color_by.array: " + std::string(kind) + " array '" + c.array +
                                    "' of " + file + " is not numeric");
  const int component = values->GetNumberOfComponents() == 1 ? 0 : -1;  // -1: magnitude
  double range[2];
  if (c.range) {
    range[0] = (*c.range)[0];
    range[1] = (*c.range)[1];
  } else {
    values->GetRange(range, component);
  }
  vtkSmartPointer<vtkScalarsToColors> lut = color_map(c.map, range[0], range[1]);
  if (component < 0) lut->SetVectorModeToMagnitude();
  auto mapper = vtkSmartPointer<vtkDataSetMapper>::New();
  mapper->ScalarVisibilityOn();
  mapper->SetColorModeToMapScalars();
  if (cell)
    mapper->SetScalarModeToUseCellFieldData();
  else
    mapper->SetScalarModeToUsePointFieldData();
  mapper->SelectColorArray(c.array.c_str());
  mapper->SetLookupTable(lut);
  mapper->UseLookupTableScalarRangeOn();
  return mapper;
}

// The mapper that shows RGB(A) unsigned-char point scalars as they are, or
// null when the data has none.
vtkSmartPointer<vtkMapper> direct_color_mapper(vtkDataSet* data) {
  auto* c = vtkUnsignedCharArray::SafeDownCast(data->GetPointData()->GetScalars());
  if (!c || (c->GetNumberOfComponents() != 3 && c->GetNumberOfComponents() != 4)) return nullptr;
  auto mapper = vtkSmartPointer<vtkDataSetMapper>::New();
  mapper->ScalarVisibilityOn();
  mapper->SetColorModeToDefault();  // unsigned char scalars are colors
  mapper->SetScalarModeToUsePointData();
  return mapper;
}

// VTK's messages while a file is read. A reader that fails part-way, e.g. on
// a truncated legacy or XML file, still produces the part it read, which must
// not pass for the whole file. The failure is reported as an error of the
// reader, of an inner reader or parser it made, or as a generic warning (the
// legacy reader's "Error reading ascii data"), so the process's output window
// is replaced while the file is read and its first error or generic warning
// becomes the exception. Not thread-safe (VTK's output window is global): mesh
// files are read one at a time.
class CapturedMessages : public vtkOutputWindow {
 public:
  static CapturedMessages* New() { return new CapturedMessages; }
  void DisplayErrorText(const char* text) override { this->Keep(text); }
  void DisplayGenericWarningText(const char* text) override { this->Keep(text); }
  void DisplayText(const char*) override {}
  std::string first;

 private:
  void Keep(const char* text) {
    if (!first.empty() || !text) return;
    // "ERROR: In FILE, line N\nClass (0x...): message\n\n" -> "message".
    std::string m = text;
    if (m.find(": In ") != std::string::npos && m.find('\n') != std::string::npos)
      m = m.substr(m.find('\n') + 1);
    if (size_t p = m.find("): "); p != std::string::npos) m = m.substr(p + 3);
    for (char& c : m)
      if (c == '\n' || c == '\r') c = ' ';
    while (!m.empty() && m.back() == ' ') m.pop_back();
    // VTK's readers quote the file's bytes (a line of a binary file read as
    // text): escaped, and no more of them than an error line should hold.
    first = m.empty() ? "the reader reported an error"
                      : rayscope::printable_text(m, 2 * rayscope::kMaxQuotedBytes);
  }
};

class CaptureMessages {
 public:
  CaptureMessages() : previous_(vtkOutputWindow::GetInstance()) {
    vtkOutputWindow::SetInstance(captured_);
  }
  ~CaptureMessages() { vtkOutputWindow::SetInstance(previous_); }
  CaptureMessages(const CaptureMessages&) = delete;
  CaptureMessages& operator=(const CaptureMessages&) = delete;
  // Throws "FILE: first message" if VTK reported a problem.
  void Check(const std::string& file) const {
    if (!captured_->first.empty()) throw std::runtime_error(file + ": " + captured_->first);
  }

 private:
  vtkSmartPointer<vtkOutputWindow> previous_;
  vtkNew<CapturedMessages> captured_;
};

// Updates `reader` (reading `file`) and returns its dataset, or throws
// "FILE: VTK's first error".
vtkSmartPointer<vtkDataSet> read_with(vtkAlgorithm* reader, const std::string& file) {
  CaptureMessages messages;
  reader->Update();
  messages.Check(file);
  return vtkDataSet::SafeDownCast(reader->GetOutputDataObject(0));
}

rayscope::TriangleMesh convert(vtkDataSet* data, const std::filesystem::path& path,
                               const SurfaceOptions& surface, vtkMapper* coloring,
                               const glm::dmat4& to_scene = glm::dmat4(1.0)) {
  vtkNew<vtkPolyData> converted;
  try {
    convert_dataset(data, surface, coloring, converted);
  } catch (const std::invalid_argument& e) {  // data convert_dataset() refuses
    throw std::runtime_error(path.string() + ": " + e.what());
  }
  rayscope::TriangleMesh m;
  mesh_from_converted(converted, m, to_scene);
  m.name = path.filename().string();
  if (m.triangles.empty())
    throw std::runtime_error(path.string() + ": contains no surface triangles");
  // A file is refused whole: the tracer would leave these triangles out (as
  // the VTK module does, with a warning), and a picture with holes is wrong.
  if (const size_t bad = m.nonfinite_triangles())
    throw std::runtime_error(path.string() + ": " + std::to_string(bad) + " of " +
                             std::to_string(m.triangles.size()) +
                             " triangles have non-finite (NaN or infinite) vertex coordinates");
  return m;
}

}  // namespace

bool has_dataset_file_extension(const std::filesystem::path& path) {
  const std::string ext = rayscope::lower_extension(path);
  return std::find(kDatasetFileExtensions.begin(), kDatasetFileExtensions.end(), ext) !=
         kDatasetFileExtensions.end();
}

vtkSmartPointer<vtkDataSet> read_dataset_file(const std::filesystem::path& path) {
  const std::string f = path.string();
  if (const std::string problem = rayscope::input_file_problem(path); !problem.empty())
    throw std::runtime_error(f + ": " + problem);
  const std::string ext = rayscope::lower_extension(path);
  vtkSmartPointer<vtkDataSet> data;
  if (ext == ".stl") {
    check_stl_file(path);
    vtkNew<vtkSTLReader> r;
    r->SetFileName(f.c_str());
    data = read_with(r, f);
  } else if (ext == ".ply") {
    if (!vtkPLYReader::CanReadFile(f.c_str())) throw std::runtime_error(f + ": not a PLY file");
    check_ply_file(path);
    vtkNew<vtkPLYReader> r;
    r->SetFileName(f.c_str());
    data = read_with(r, f);
  } else if (ext == ".obj") {
    data = read_plain_obj_file(path);
    if (!data) {
      check_obj_file(path);
      vtkNew<vtkOBJReader> r;
      r->SetFileName(f.c_str());
      data = read_with(r, f);
    }
  } else if (ext == ".vtk") {
    check_legacy_vtk_file(path);
    vtkNew<vtkDataSetReader> r;
    r->SetFileName(f.c_str());
    data = read_with(r, f);
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
    check_vtk_xml_file(path, ext == ".vtp" ? "PolyData" : "UnstructuredGrid");
    r->SetFileName(f.c_str());
    data = read_with(r, f);
  } else {
    std::string known;
    for (std::string_view e : kDatasetFileExtensions)
      known += (known.empty()                        ? ""
                : e == kDatasetFileExtensions.back() ? " or "
                                                     : ", ") +
               std::string(e);
    throw std::runtime_error(f + ": unsupported mesh format '" + ext + "' (use " + known + ")");
  }
  if (!data) throw std::runtime_error(f + ": could not read a dataset");
  // VTK's readers copy the files' point ids unchecked, and VTK's filters
  // index the points with them (a legacy file naming point 7 of 3).
  if (std::string e = check_cell_point_ids(data); !e.empty())
    throw std::runtime_error(f + ": " + e);
  return data;
}

rayscope::TriangleMesh load_mesh(const rayscope::MeshOptions& options) {
  return load_mesh_from(options, read_dataset_file(options.file));
}

rayscope::TriangleMesh load_mesh_from(const rayscope::MeshOptions& options, vtkDataSet* data) {
  SurfaceOptions surface;
  surface.compute_normals = options.smooth;
  vtkSmartPointer<vtkMapper> coloring =
      options.color_by ? color_by_mapper(data, *options.color_by, options.file.string())
                       : direct_color_mapper(data);
  rayscope::TriangleMesh m = convert(data, options.file, surface, coloring, options.to_scene);
  if (!options.smooth) m.normals.clear();  // the file's own normals too
  return m;
}

rayscope::TriangleMesh read_mesh_file(const std::filesystem::path& path) {
  vtkSmartPointer<vtkDataSet> data = read_dataset_file(path);
  SurfaceOptions surface;
  surface.compute_normals = false;
  return convert(data, path, surface, direct_color_mapper(data));
}

}  // namespace rayscope_vtkio
