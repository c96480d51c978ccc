// Checks of input that VTK's readers and filters take on trust: run before
// any VTK code sees the data, so that damaged or hostile input gives one
// clear error instead of a crash inside VTK or a silently partial mesh.
// Used by the mesh files of the rayscope command (mesh_files.cpp) and, through
// convert_dataset(), by the VTK module's converter: one check for both.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

class vtkDataSet;

namespace rayscope_vtkio {

/// Size of a binary STL file's header: 80 bytes of text, then the uint32
/// triangle count.
inline constexpr std::uintmax_t kStlHeaderBytes = 84;
/// Size of one binary STL triangle: normal and three corners (12 floats) and
/// a uint16 attribute byte count.
inline constexpr std::uintmax_t kStlTriangleBytes = 50;

/// Structured datasets (legacy STRUCTURED_POINTS, STRUCTURED_GRID and
/// RECTILINEAR_GRID, XML ImageData) declare their size by their dimensions or
/// extent alone; VTK's surface filter then makes their outer faces. More
/// points than this (a 512^3 volume) are refused rather than handed to it.
inline constexpr std::uint64_t kMaxStructuredPoints = std::uint64_t(1) << 27;

/**
 * An STL file VTK's reader can read in full. A file VTK's reader takes for
 * text (vtksys::SystemTools::DetectFileType, as the reader decides) is ASCII
 * and checked by the reader itself (see mesh_files.cpp). Any other file is
 * binary, and its size must hold exactly the triangles its header declares:
 * VTK's reader reads triangles until the end of the file whatever the header
 * says, so a truncated file would lose triangles without a word and extra
 * bytes (or a sparse 2 GB file) would be read as triangles. Throws
 * std::runtime_error "FILE: problem" (what the header declares, what the file
 * holds).
 */
void check_stl_file(const std::filesystem::path& path);

/**
 * A PLY file VTK's reader can read without running past its end or writing
 * through a wrong pointer: the header is complete ("ply", a known format,
 * elements with known property types, "end_header") and has the layout the
 * reader needs (vertex x, y, z scalars, no vertex lists; face list
 * "vertex_indices", no other face lists but "texcoord"; a property of the
 * other kind crashes the reader), and the body holds every element the header
 * declares
 * (binary: the bytes of every item, lists included; ASCII: one line per item
 * with as many numbers as its properties need). VTK's PLY reader trusts the
 * header and crashes on a body that ends early. Throws std::runtime_error
 * "FILE: problem" naming the element and item where the body falls short.
 */
void check_ply_file(const std::filesystem::path& path);

/**
 * A legacy .vtk file whose every section VTK's legacy readers can read: a
 * DATASET of a supported type (POLYDATA, UNSTRUCTURED_GRID,
 * STRUCTURED_POINTS, STRUCTURED_GRID, RECTILINEAR_GRID), known section
 * keywords and value types (an unknown type makes the reader go on with a
 * null array and crash), every section holding the values it declares (ASCII
 * numbers or binary bytes), cell sections whose counts or offsets fit their
 * values (old files: each cell's point count and ids; version 5: OFFSETS
 * from 0 up to the CONNECTIVITY's size), and point and cell data with one
 * tuple per point and cell. Point ids are checked after reading
 * (check_cell_point_ids()). Throws std::runtime_error "FILE: legacy VTK:
 * problem" naming the section.
 */
void check_legacy_vtk_file(const std::filesystem::path& path);

/// An OBJ file whose faces, lines and points name only vertices, texture
/// coordinates and normals defined before them (1-based, or negative and
/// relative). VTK's OBJ reader copies the named tuples unchecked and crashes
/// on an index out of range. Throws std::runtime_error "FILE: line N: problem".
void check_obj_file(const std::filesystem::path& path);

/**
 * A VTK XML file (.vtp: `dataset_type` "PolyData", .vtu: "UnstructuredGrid",
 * .vti: "ImageData") whose sizes VTK's XML reader can trust: the reader
 * allocates by numbers in the file before it reads what they describe (each
 * piece's point and cell counts, an image's whole extent, each binary array's
 * header: its byte count or its compression blocks, and the last cell offset,
 * which sizes the connectivity), so a few damaged bytes make it allocate
 * gigabytes. Each is held against the bytes the file has: counts against the
 * values their arrays hold, a header against the bytes after it (a compressed
 * block may expand at most kMaxCompressionRatio times), the offsets' last
 * value against the connectivity, polyhedron face streams against their
 * offsets, an image's whole extent against its pieces' extents (within it, and
 * holding as many points) and kMaxStructuredPoints. The XML structure is read
 * by VTK's own parser (vtkXMLDataParser). Throws std::runtime_error "FILE:
 * problem" naming the array or piece.
 */
void check_vtk_xml_file(const std::filesystem::path& path, const char* dataset_type);

/**
 * A parallel VTK XML file (.pvtp: `dataset_type` "PolyData", .pvtu:
 * "UnstructuredGrid", .pvti: "ImageData") and every piece file it names,
 * before VTK's parallel reader joins them: each piece named once, present
 * (a missing one is the error, naming it) and passing check_vtk_xml_file()
 * as a file of `dataset_type`; the arrays the parallel file declares
 * (PPoints, PPointData, PCellData), which the reader allocates for all
 * pieces and copies each piece's into, present in every piece with the same
 * type and components; for images, each piece's extent as the parallel file
 * says, within its whole extent, the pieces holding every point of it.
 * Returns the piece files, in order. Throws std::runtime_error "FILE:
 * problem" (for a piece: "FILE: piece file 'NAME': PIECE: problem").
 */
std::vector<std::filesystem::path> check_vtk_xml_parallel_file(const std::filesystem::path& path,
                                                               const char* dataset_type);

/**
 * A composite VTK XML file (.vtm: `composite_type` "vtkMultiBlockDataSet",
 * .vtpc: "vtkPartitionedDataSetCollection") and every block file it names,
 * before VTK's reader reads them: a file format version 1 or later, only the
 * elements the reader knows where it knows them (a .vtpc DataSet outside
 * Partitions crashes VTK 9.1's reader), every "index" within its siblings'
 * count (the reader sizes its block lists by it), at most
 * kMaxCompositeDepth levels, field data holding what it declares, and each
 * block file named once, present (a missing one is the error, naming it),
 * with an extension VTK reads it by that RayScope checks (.vtp, .vtu, .vti)
 * and passing check_vtk_xml_file(). Throws std::runtime_error "FILE:
 * problem" (for a block: "FILE: block file 'NAME': BLOCK: problem").
 */
void check_vtk_xml_composite_file(const std::filesystem::path& path, const char* composite_type);

/// How deep the blocks of a composite file may nest.
inline constexpr int kMaxCompositeDepth = 32;

/**
 * An Exodus II file vtkExodusIIReader can read: netCDF's classic formats
 * (CDF1, CDF2, CDF5 magic), whose header (dimensions, attributes, variables)
 * is read in full and every variable's data held against the file's length,
 * and whose element blocks' connectivity ("connect1"...) names only nodes
 * 1..num_nodes (the reader indexes its node maps with them unchecked); or an
 * HDF5-based (netCDF-4) file, recognised by its signature and left to the
 * HDF5 library's own checks. Anything else is refused. Throws
 * std::runtime_error "FILE: Exodus: problem".
 */
void check_exodus_file(const std::filesystem::path& path);

/// Empty when every cell of `data` names existing points (ids in
/// 0..points-1), else the first offending cell and id, e.g. "cell 0 refers to
/// point 7 but the data has 3 points", or a cell array whose offsets do not
/// fit its ids (vtkCellArray::IsValid()). VTK's filters (vtkPolyDataNormals,
/// vtkTriangleFilter) index the points with these ids unchecked. Datasets
/// whose cells are implicit (images, structured grids) always pass.
std::string check_cell_point_ids(vtkDataSet* data);

/// Removes from `data` every point array with fewer tuples than it has points
/// and every cell array with fewer tuples than it has cells, and describes
/// each, e.g. "point array 'Normals' has 1 tuple but the data has 4 points".
/// VTK's filters and mappers index these arrays by point and cell id
/// unchecked, reading past their end; vtkOBJReader makes one from a valid
/// file, attaching the 'vn' lines as point normals when no face names them.
/// (The conversion ignores such normals instead: usable_normals() in
/// mesh_conversion.cpp.)
std::vector<std::string> remove_short_attribute_arrays(vtkDataSet* data);

}  // namespace rayscope_vtkio
