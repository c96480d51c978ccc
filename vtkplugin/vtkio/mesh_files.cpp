#include "rayscope_vtkio/mesh_files.h"

#include <algorithm>
#include <cctype>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <vtkCellData.h>
#include <vtkColorTransferFunction.h>
#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkDataSetMapper.h>
#include <vtkDataSetReader.h>
#include <vtkExodusIIReader.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkOBJReader.h>
#include <vtkOutputWindow.h>
#include <vtkPLYReader.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSTLReader.h>
#include <vtkUnsignedCharArray.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLMultiBlockDataReader.h>
#include <vtkXMLPImageDataReader.h>
#include <vtkXMLPPolyDataReader.h>
#include <vtkXMLPUnstructuredGridReader.h>
#include <vtkXMLPartitionedDataSetCollectionReader.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLReader.h>
#include <vtkXMLUnstructuredGridReader.h>
#include <vtk_exodusII.h>

#include "rayscope/input_file.h"
#include "rayscope/printable_text.h"
#include "rayscope_vtkio/dataset_leaves.h"
#include "rayscope_vtkio/line_conversion.h"
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

// The arrays of `data` that color_by would look in.
vtkFieldData* color_by_arrays(vtkDataSet* data, const MeshColorBy& c) {
  if (c.association == MeshColorBy::Association::Cell) return data->GetCellData();
  return data->GetPointData();
}

// The mapper that colors every dataset of `leaves` that has the array
// `color_by` names as it says: one lookup table over the range of the array
// in all of them (or the range given). `lacking` gets the leaves without it.
vtkSmartPointer<vtkMapper> color_by_mapper(const std::vector<DatasetLeaf>& leaves,
                                           const MeshColorBy& c, const std::string& file,
                                           std::vector<const DatasetLeaf*>& lacking) {
  const bool cell = c.association == MeshColorBy::Association::Cell;
  const char* kind = cell ? "cell" : "point";
  int component = 0;  // -1: magnitude
  double range[2] = {std::numeric_limits<double>::infinity(),
                     -std::numeric_limits<double>::infinity()};
  bool found = false;
  std::string names;
  for (const DatasetLeaf& leaf : leaves) {
    vtkFieldData* fd = color_by_arrays(leaf.data, c);
    vtkAbstractArray* a = fd->GetAbstractArray(c.array.c_str());
    if (!a) {
      if (const std::string n = array_names(fd); !n.empty() && names.find(n) == std::string::npos)
        names += (names.empty() ? "" : ", ") + n;
      lacking.push_back(&leaf);
      continue;
    }
    auto* values = vtkDataArray::SafeDownCast(a);
    if (!values)
      throw rayscope::MeshOptionError("color_by.array: " + std::string(kind) + " array '" +
                                      c.array + "' of " + file + " is not numeric");
    if (!found) component = values->GetNumberOfComponents() == 1 ? 0 : -1;
    found = true;
    double r[2];
    values->GetRange(r, component);
    range[0] = std::min(range[0], r[0]);
    range[1] = std::max(range[1], r[1]);
  }
  if (!found)
    throw rayscope::MeshOptionError("color_by.array: " + file + " has no " + kind + " array '" +
                                    c.array + "' (" +
                                    (names.empty() ? std::string("it has no ") + kind + " arrays"
                                                   : std::string(kind) + " arrays: " + names) +
                                    ")");
  if (c.range) {
    range[0] = (*c.range)[0];
    range[1] = (*c.range)[1];
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

// Updates `reader` (reading `file`) and returns its output, or throws
// "FILE: VTK's first error".
vtkSmartPointer<vtkDataObject> read_with(vtkAlgorithm* reader, const std::string& file) {
  CaptureMessages messages;
  reader->Update();
  messages.Check(file);
  return reader->GetOutputDataObject(0);
}

// The label of a composite file's leaf: "block N" or "block N (NAME)".
std::string leaf_label(const DatasetLeaf& leaf) {
  std::string label = "block " + std::to_string(leaf.flat_index);
  if (!leaf.name.empty())
    label += " (" + rayscope::printable_text(leaf.name, rayscope::kMaxQuotedBytes) + ")";
  return label;
}

// `data`'s triangles, or none; "FILE: [LABEL: ]problem" for data the
// conversion refuses or with non-finite vertices. A file is refused whole
// for those: the tracer would leave such triangles out (as the VTK module
// does, with a warning), and a picture with holes is wrong.
rayscope::TriangleMesh convert(vtkDataSet* data, const std::string& where,
                               const SurfaceOptions& surface, vtkMapper* coloring,
                               const glm::dmat4& to_scene = glm::dmat4(1.0)) {
  vtkNew<vtkPolyData> converted;
  try {
    convert_dataset(data, surface, coloring, converted);
  } catch (const std::invalid_argument& e) {  // data convert_dataset() refuses
    throw std::runtime_error(where + ": " + e.what());
  }
  rayscope::TriangleMesh m;
  mesh_from_converted(converted, m, to_scene);
  if (const size_t bad = m.nonfinite_triangles())
    throw std::runtime_error(where + ": " + std::to_string(bad) + " of " +
                             std::to_string(m.triangles.size()) +
                             " triangles have non-finite (NaN or infinite) vertex coordinates");
  return m;
}

// The radii of a file's tubes and spheres: the options', or the automatic
// radius, automatic_radius() of the diagonal of the leaves' bounds in the
// scene (their finite bounds' corners moved by options.to_scene), as the
// VTK module sizes them at VTK's default line width and point size of 1.
CurveRadii curve_radii(const rayscope::MeshOptions& options,
                       const std::vector<DatasetLeaf>& leaves) {
  double b[6];
  double diagonal = 0.0;
  if (finite_bounds(leaf_datasets(leaves), b)) {
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
    for (int corner = 0; corner < 8; ++corner) {
      const glm::dvec4 p =
          options.to_scene *
          glm::dvec4(b[corner & 1 ? 1 : 0], b[corner & 2 ? 3 : 2], b[corner & 4 ? 5 : 4], 1.0);
      lo = glm::min(lo, glm::dvec3(p));
      hi = glm::max(hi, glm::dvec3(p));
    }
    diagonal = glm::length(hi - lo);
  }
  const double automatic = automatic_radius(diagonal);
  CurveRadii radii;
  radii.line = options.line_radius > 0.0 ? options.line_radius : automatic;
  radii.point = options.point_radius > 0.0 ? options.point_radius : automatic;
  radii.array = options.radius_array;
  return radii;
}

// The line cells of `data` as `tubes` and its vertex cells as `points`
// (convert_lines_and_points()). A file is refused for non-finite points on
// them, as convert() refuses it for non-finite triangles.
void convert_curves(vtkDataSet* data, const std::string& where, const CurveRadii& radii,
                    vtkMapper* coloring, const glm::dmat4& to_scene, rayscope::TubeSet& tubes,
                    rayscope::PointSet& points) {
  try {
    convert_lines_and_points(data, coloring, radii, tubes, points, to_scene);
  } catch (const std::invalid_argument& e) {
    vtkDataArray* a =
        radii.array.empty() ? nullptr : data->GetPointData()->GetArray(radii.array.c_str());
    if (!radii.array.empty() && (!a || a->GetNumberOfComponents() != 1))
      throw rayscope::MeshOptionError("radius_array: " + where + ": has no point array '" +
                                      radii.array + "' of one component");
    throw std::runtime_error(where + ": " + e.what());
  }
  using rayscope::all_finite;
  size_t bad = 0;
  for (const glm::uvec2& s : tubes.segments)
    bad += !all_finite(tubes.positions[s.x]) || !all_finite(tubes.positions[s.y]);
  if (bad)
    throw std::runtime_error(where + ": " + std::to_string(bad) + " of " +
                             std::to_string(tubes.segments.size()) +
                             " line segments have a non-finite (NaN or infinite) end");
  bad = size_t(std::count_if(points.positions.begin(), points.positions.end(),
                             [](const rayscope::Vec3& p) { return !all_finite(p); }));
  if (bad)
    throw std::runtime_error(where + ": " + std::to_string(bad) + " of " +
                             std::to_string(points.positions.size()) +
                             " vertices have non-finite (NaN or infinite) coordinates");
}

// The format of `path` in kMeshFileFormats, or null.
const MeshFileFormat* format_of(const std::filesystem::path& path) {
  const std::string ext = rayscope::lower_extension(path);
  for (const MeshFileFormat& f : kMeshFileFormats)
    if (f.extension == ext) return &f;
  return nullptr;
}

[[noreturn]] void unsupported(const std::filesystem::path& path, bool composite_too) {
  throw std::runtime_error(path.string() + ": unsupported mesh format '" +
                           rayscope::lower_extension(path) + "' (use " +
                           mesh_file_extensions(composite_too) + ")");
}

// The dataset type of VTK's XML files "vtp", "vtu", "vti".
const char* xml_type(std::string_view kind) {
  return kind == "vtp" ? "PolyData" : kind == "vtu" ? "UnstructuredGrid" : "ImageData";
}

// VTK's reader of XML files "vtp", "vtu" or "vti", or of their parallel files.
// (The format-specific readers: vtkXMLGenericDataObjectReader::CanReadFile
// rejects every file in VTK 9.1.)
vtkSmartPointer<vtkXMLReader> xml_reader(std::string_view kind, bool parallel) {
  if (kind == "vtp")
    return parallel ? vtkSmartPointer<vtkXMLReader>(vtkSmartPointer<vtkXMLPPolyDataReader>::New())
                    : vtkSmartPointer<vtkXMLReader>(vtkSmartPointer<vtkXMLPolyDataReader>::New());
  if (kind == "vtu")
    return parallel ? vtkSmartPointer<vtkXMLReader>(
                          vtkSmartPointer<vtkXMLPUnstructuredGridReader>::New())
                    : vtkSmartPointer<vtkXMLReader>(
                          vtkSmartPointer<vtkXMLUnstructuredGridReader>::New());
  return parallel ? vtkSmartPointer<vtkXMLReader>(vtkSmartPointer<vtkXMLPImageDataReader>::New())
                  : vtkSmartPointer<vtkXMLReader>(vtkSmartPointer<vtkXMLImageDataReader>::New());
}

// A serial VTK XML file of `kind` ("vtp", "vtu", "vti"), checked, then read.
vtkSmartPointer<vtkDataObject> read_xml_file(const std::filesystem::path& path,
                                             std::string_view kind) {
  const std::string f = path.string();
  vtkSmartPointer<vtkXMLReader> r = xml_reader(kind, false);
  if (!r->CanReadFile(f.c_str()))
    throw std::runtime_error(f + ": not a VTK XML ." + std::string(kind) + " file");
  check_vtk_xml_file(path, xml_type(kind));
  r->SetFileName(f.c_str());
  return read_with(r, f);
}

// A composite file read by `reader` (its checks passed), as a composite dataset.
vtkSmartPointer<vtkDataObject> read_composite(vtkAlgorithm* reader, const std::string& f) {
  vtkSmartPointer<vtkDataObject> data = read_with(reader, f);
  if (!data || !data->IsA("vtkCompositeDataSet"))
    throw std::runtime_error(f + ": could not read a composite dataset");
  return data;
}

// Exodus II: every element block (VTK's default too, made explicit), no sets,
// at the first time step.
vtkSmartPointer<vtkDataObject> read_exodus(const std::filesystem::path& path) {
  const std::string f = path.string();
  check_exodus_file(path);
  vtkNew<vtkExodusIIReader> r;
  // The Exodus library prints its errors to stderr in verbose mode: quiet,
  // so that VTK's error (captured) is the one line.
  ex_opts(EX_DEFAULT);
  r->SetFileName(f.c_str());
  {
    CaptureMessages messages;
    r->UpdateInformation();
    messages.Check(f);
  }
  r->SetAllArrayStatus(vtkExodusIIReader::ELEM_BLOCK, 1);
  r->SetTimeStep(0);
  return read_composite(r, f);
}

}  // namespace

bool has_dataset_file_extension(const std::filesystem::path& path) {
  const MeshFileFormat* f = format_of(path);
  return f && !f->composite;
}

std::string mesh_file_extensions(bool composite_too) {
  std::string known;
  for (const MeshFileFormat& f : kMeshFileFormats) {
    if (!composite_too && f.composite) continue;
    if (!known.empty()) known += ' ';
    known += f.extension;
  }
  return known;
}

vtkSmartPointer<vtkDataSet> read_dataset_file(const std::filesystem::path& path) {
  const std::string f = path.string();
  if (const std::string problem = rayscope::input_file_problem(path); !problem.empty())
    throw std::runtime_error(f + ": " + problem);
  const MeshFileFormat* format = format_of(path);
  if (!format || format->composite) unsupported(path, false);
  const std::string_view ext = format->extension;
  vtkSmartPointer<vtkDataObject> data;
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
  } else {
    const bool parallel = ext.substr(0, 2) == ".p";
    const std::string_view kind = ext.substr(parallel ? 2 : 1);  // vtp, vtu, vti
    if (!parallel) {
      data = read_xml_file(path, kind);
    } else {
      vtkSmartPointer<vtkXMLReader> r = xml_reader(kind, true);
      if (!r->CanReadFile(f.c_str()))
        throw std::runtime_error(f + ": not a VTK XML " + std::string(ext) + " file");
      // VTK's parallel reader goes on joining the pieces after one's reader
      // failed (a .pvtu whose piece lacks NumberOfPoints crashed it): every
      // piece is read on its own first, the way it reads them, and refused
      // with the owner's name.
      for (const std::filesystem::path& piece : check_vtk_xml_parallel_file(path, xml_type(kind))) {
        try {
          vtkSmartPointer<vtkDataSet> d = vtkDataSet::SafeDownCast(read_xml_file(piece, kind));
          if (!d) throw std::runtime_error(piece.string() + ": could not read a dataset");
          if (std::string e = check_cell_point_ids(d); !e.empty())
            throw std::runtime_error(piece.string() + ": " + e);
        } catch (const std::runtime_error& e) {
          throw std::runtime_error(f + ": piece file '" + piece.filename().string() +
                                   "': " + e.what());
        }
      }
      r->SetFileName(f.c_str());
      data = read_with(r, f);
    }
  }
  vtkSmartPointer<vtkDataSet> dataset = vtkDataSet::SafeDownCast(data);
  if (!dataset) throw std::runtime_error(f + ": could not read a dataset");
  // VTK's readers copy the files' point ids unchecked, and VTK's filters
  // index the points with them (a legacy file naming point 7 of 3).
  if (std::string e = check_cell_point_ids(dataset); !e.empty())
    throw std::runtime_error(f + ": " + e);
  return dataset;
}

vtkSmartPointer<vtkDataObject> read_mesh_data_file(const std::filesystem::path& path) {
  const std::string f = path.string();
  const MeshFileFormat* format = format_of(path);
  if (!format || !format->composite) return read_dataset_file(path);
  if (const std::string problem = rayscope::input_file_problem(path); !problem.empty())
    throw std::runtime_error(f + ": " + problem);
  vtkSmartPointer<vtkDataObject> data;
  if (format->extension == ".vtm" || format->extension == ".vtpc") {
    const bool vtm = format->extension == ".vtm";
    vtkSmartPointer<vtkXMLReader> r;
    if (vtm)
      r = vtkSmartPointer<vtkXMLMultiBlockDataReader>::New();
    else
      r = vtkSmartPointer<vtkXMLPartitionedDataSetCollectionReader>::New();
    if (!r->CanReadFile(f.c_str()))
      throw std::runtime_error(f + ": not a VTK XML " + std::string(format->extension) + " file");
    check_vtk_xml_composite_file(path,
                                 vtm ? "vtkMultiBlockDataSet" : "vtkPartitionedDataSetCollection");
    r->SetFileName(f.c_str());
    data = read_composite(r, f);
  } else {
    data = read_exodus(path);
  }
  for (const DatasetLeaf& leaf : dataset_leaves(data).leaves)
    if (std::string e = check_cell_point_ids(leaf.data); !e.empty())
      throw std::runtime_error(f + ": " + leaf_label(leaf) + ": " + e);
  return data;
}

rayscope::LoadedMeshFile load_meshes(const rayscope::MeshOptions& options) {
  return load_meshes_from(options, read_mesh_data_file(options.file));
}

rayscope::LoadedMeshFile load_meshes_from(const rayscope::MeshOptions& options,
                                          vtkDataObject* data) {
  const std::string file = options.file.string();
  const bool composite = !vtkDataSet::SafeDownCast(data);
  const DatasetLeaves found = dataset_leaves(data);
  rayscope::LoadedMeshFile loaded;
  for (const std::string& skipped : found.skipped)
    loaded.warnings.push_back(file + ": " + skipped + ": not a dataset, left out");
  SurfaceOptions surface;
  surface.compute_normals = options.smooth;
  std::vector<const DatasetLeaf*> lacking;
  vtkSmartPointer<vtkMapper> color_by;
  if (options.color_by) color_by = color_by_mapper(found.leaves, *options.color_by, file, lacking);
  const CurveRadii radii = curve_radii(options, found.leaves);
  for (const DatasetLeaf& leaf : found.leaves) {
    const std::string label = composite ? leaf_label(leaf) : std::string();
    const std::string where = composite ? file + ": " + label : file;
    const bool uncolored = std::find(lacking.begin(), lacking.end(), &leaf) != lacking.end();
    vtkSmartPointer<vtkMapper> coloring =
        options.color_by && !uncolored ? color_by : direct_color_mapper(leaf.data);
    rayscope::TriangleMesh m = convert(leaf.data, where, surface, coloring, options.to_scene);
    rayscope::TubeSet tubes;
    rayscope::PointSet points;
    convert_curves(leaf.data, where, radii, coloring, options.to_scene, tubes, points);
    if (m.triangles.empty() && tubes.segments.empty() && points.positions.empty()) {
      if (composite)
        loaded.warnings.push_back(where + ": no surface triangles, lines or vertices, left out");
      continue;
    }
    if (uncolored)
      loaded.warnings.push_back(
          where + ": has no " +
          (options.color_by->association == MeshColorBy::Association::Cell ? "cell" : "point") +
          " array '" + options.color_by->array + "', drawn in the material's color");
    const std::string space = label.empty() ? "" : " ";
    if (!tubes.segments.empty()) {
      tubes.name = label + space + "lines";
      loaded.tubes.push_back(std::move(tubes));
    }
    if (!points.positions.empty()) {
      points.name = label + space + "vertices";
      loaded.points.push_back(std::move(points));
    }
    if (m.triangles.empty()) continue;
    if (!options.smooth) m.normals.clear();  // the file's own normals too
    m.name = label;
    loaded.meshes.push_back(std::move(m));
  }
  if (loaded.meshes.empty() && loaded.tubes.empty() && loaded.points.empty())
    throw std::runtime_error(file + ": contains no surface triangles, lines or vertices");
  return loaded;
}

rayscope::TriangleMesh load_mesh(const rayscope::MeshOptions& options) {
  const std::string file = options.file.string();
  rayscope::LoadedMeshFile loaded = load_meshes(options);
  if (loaded.meshes.empty())
    throw std::runtime_error(file + ": contains no surface triangles (only lines or vertices)");
  if (loaded.meshes.size() != 1)
    throw std::runtime_error(file + ": holds " + std::to_string(loaded.meshes.size()) +
                             " meshes (a composite file), not one");
  loaded.meshes[0].name = options.file.filename().string();
  return std::move(loaded.meshes[0]);
}

rayscope::TriangleMesh read_mesh_file(const std::filesystem::path& path) {
  vtkSmartPointer<vtkDataSet> data = read_dataset_file(path);
  SurfaceOptions surface;
  surface.compute_normals = false;
  rayscope::TriangleMesh m = convert(data, path.string(), surface, direct_color_mapper(data));
  if (m.triangles.empty())
    throw std::runtime_error(path.string() + ": contains no surface triangles");
  m.name = path.filename().string();
  return m;
}

}  // namespace rayscope_vtkio
