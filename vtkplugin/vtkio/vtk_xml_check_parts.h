// The parts of the VTK XML checks (vtk_xml_checks.cpp) that the checks of
// files naming other files (vtk_xml_file_list_checks.cpp: parallel and
// composite files) share with them; internal to rayscope_vtkio.
#pragma once

#include <array>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <vtkNew.h>
#include <vtkXMLDataParser.h>

class vtkXMLDataElement;

namespace rayscope_vtkio::checks {

/// A VTK XML file parsed by VTK's own parser (vtkXMLDataParser, the one the
/// readers use), with a second stream for the checks' own reads.
struct XmlDocument;

/// A deleter, so that XmlDocument can stay defined in vtk_xml_checks.cpp.
struct XmlDocumentDeleter {
  void operator()(XmlDocument* d) const;
};
using XmlDocumentPtr = std::unique_ptr<XmlDocument, XmlDocumentDeleter>;

/// Parses `path`, whose root must be a VTKFile of type `type` (e.g.
/// "PPolyData", "vtkMultiBlockDataSet"), with its header type, byte order,
/// compressor and appended data understood as the readers understand them.
/// Fails "FILE: problem" otherwise.
XmlDocumentPtr parse_vtk_xml(const std::filesystem::path& path, std::string_view type);

/// The root element (VTKFile) of a parsed document.
vtkXMLDataElement* root_of(const XmlDocument& doc);

/// The arrays of a FieldData element (may be null) of the document hold what
/// they declare (as in check_vtk_xml_file()).
void check_field_data(const XmlDocument& doc, vtkXMLDataElement* field_data);

/// One DataArray a file declares: where ("Points", "PointData", "CellData"),
/// its name, value type and components.
struct XmlArray {
  std::string section, name, type;
  int components = 1;
  bool operator==(const XmlArray&) const = default;
};

/// Appends to `out` the arrays `section` (may be null) declares in nested
/// elements named `element` ("DataArray"; a parallel file's "PDataArray"),
/// each under the section name `name`.
void note_arrays(vtkXMLDataElement* section, std::string_view element, const char* name,
                 std::vector<XmlArray>& out);

/// What check_vtk_xml_dataset() saw in a file that passed.
struct XmlDatasetSummary {
  /// The arrays of its first piece.
  std::vector<XmlArray> arrays;
  /// ImageData: the extent of each piece, and the whole extent.
  std::vector<std::array<long long, 6>> extents;
  std::array<long long, 6> whole_extent{};
};

/// check_vtk_xml_file(), and what it saw.
XmlDatasetSummary check_vtk_xml_dataset(const std::filesystem::path& path,
                                        std::string_view dataset_type);

/// The points of an extent (0 when it is empty on an axis).
unsigned long long extent_points(const std::array<long long, 6>& e);

}  // namespace rayscope_vtkio::checks
