// check_vtk_xml_file() (mesh_checks.h): what VTK's XML readers (.vtp, .vtu)
// take on trust, checked before they run.
//
// The readers size their buffers from numbers in the file before reading the
// data those numbers describe: the piece's point and cell counts, each binary
// array's header (its byte count, or its compression blocks: how many, their
// sizes before and after compression), and, for the cells' connectivity, the
// last value of the offsets array. A few damaged bytes in any of them make
// the reader allocate gigabytes (an out-of-memory abort, not an exception).
// Here every such number is held against the bytes the file actually has:
// the XML structure comes from VTK's own parser (vtkXMLDataParser, the one
// the readers use), the array headers are decoded as the readers decode them,
// and the offsets' last values are read through that parser once their
// headers are known to be sound.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <vtkBase64Utilities.h>
#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkDataCompressor.h>
#include <vtkLZ4DataCompressor.h>
#include <vtkLZMADataCompressor.h>
#include <vtkNew.h>
#include <vtkSmartPointer.h>
#include <vtkType.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>
#include <vtkZLibDataCompressor.h>

#include "check_util.h"
#include "rayscope_vtkio/mesh_checks.h"
#include "vtk_xml_check_parts.h"

namespace rayscope_vtkio::checks {
namespace {

using u64 = std::uint64_t;

/// The most a compressed block may expand. zlib's format cannot exceed
/// 1032:1, LZ4's 255:1; LZMA on VTK's 32 KiB blocks stays far below either.
/// Twice zlib's limit leaves room for a writer with large blocks.
constexpr u64 kMaxCompressionRatio = 2048;

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r';
}

/// Bytes of one value of a DataArray "type", 0 if VTK's readers know no such
/// type; `vtk_type` is its VTK type id.
int word_size(std::string_view type, int& vtk_type) {
  struct Type {
    const char* name;
    int size, vtk;
  };
  static constexpr Type kTypes[] = {
      {"Int8", 1, VTK_TYPE_INT8},       {"UInt8", 1, VTK_TYPE_UINT8},
      {"Int16", 2, VTK_TYPE_INT16},     {"UInt16", 2, VTK_TYPE_UINT16},
      {"Int32", 4, VTK_TYPE_INT32},     {"UInt32", 4, VTK_TYPE_UINT32},
      {"Int64", 8, VTK_TYPE_INT64},     {"UInt64", 8, VTK_TYPE_UINT64},
      {"Float32", 4, VTK_TYPE_FLOAT32}, {"Float64", 8, VTK_TYPE_FLOAT64},
      {"String", 1, VTK_TYPE_UINT8},
  };
  for (const Type& t : kTypes)
    if (type == t.name) {
      vtk_type = t.vtk;
      return t.size;
    }
  return 0;
}

/// An inline DataArray's text in the file: where it starts (found as VTK's
/// parser finds it: past the element's '>' and any white space) and ends (at
/// the next '<'), and how many white-space separated words it has.
struct InlineText {
  u64 start = 0, end = 0, words = 0;
};

InlineText inline_text(std::ifstream& in, vtkXMLDataElement* a) {
  InlineText t;
  in.clear();
  in.seekg(std::streamoff(a->GetXMLByteIndex()));
  char c = 0;
  while (in.get(c) && c != '>') {
  }
  while (in.get(c) && is_space(c)) {
  }
  if (!in) return t;
  t.start = t.end = u64(std::streamoff(in.tellg())) - 1;
  bool in_word = false;
  do {
    if (c == '<') break;
    if (!is_space(c) && !in_word) ++t.words;
    in_word = !is_space(c);
    ++t.end;
  } while (in.get(c));
  return t;
}

/// The bytes an array's binary data starts with, decoded as the reader
/// decodes them (base64 in groups of four characters, or raw), and an upper
/// bound of how many there are: from byte `start` of the file up to `end`.
class BinarySource {
 public:
  BinarySource(std::ifstream& in, u64 start, u64 end, bool base64)
      : in_(in), start_(start), base64_(base64) {
    const u64 bytes = end > start ? end - start : 0;
    size_ = base64 ? bytes / 4 * 3 : bytes;
  }
  /// At most this many bytes can be read.
  u64 size() const { return size_; }
  /// The first `n` bytes (n <= size()), or nullopt if they cannot be read.
  std::optional<std::vector<unsigned char>> first(u64 n) {
    if (n > size_) return std::nullopt;
    // Base64: groups of four characters give at most three bytes ("=" pads).
    std::vector<unsigned char> read(size_t(base64_ ? (n + 2) / 3 * 4 : n));
    in_.clear();
    in_.seekg(std::streamoff(start_));
    in_.read(reinterpret_cast<char*>(read.data()), std::streamsize(read.size()));
    if (u64(in_.gcount()) != read.size()) return std::nullopt;
    if (!base64_) return read;
    std::vector<unsigned char> decoded(read.size());
    const size_t got =
        vtkBase64Utilities::DecodeSafely(read.data(), read.size(), decoded.data(), decoded.size());
    if (got < n) return std::nullopt;
    decoded.resize(size_t(n));
    return decoded;
  }

 private:
  std::ifstream& in_;
  u64 start_ = 0;
  bool base64_ = true;
  u64 size_ = 0;
};

}  // namespace

/// A VTK XML file as the checks read it.
struct XmlFile {
  const fs::path& path;
  std::ifstream& in;
  u64 file_size = 0;
  int header_bytes = 4;  // header_type UInt32 or UInt64
  bool big_endian = false;
  bool compressed = false;
  u64 appended_start = 0;  // 0: no appended data
  bool appended_base64 = false;
};

namespace {

u64 header_word(const XmlFile& f, const std::vector<unsigned char>& b, size_t index) {
  u64 v = 0;
  const size_t at = index * size_t(f.header_bytes);
  for (int k = 0; k < f.header_bytes; ++k) {
    const int byte = f.big_endian ? k : f.header_bytes - 1 - k;
    v = (v << 8) | b[at + size_t(byte)];
  }
  return v;
}

std::string array_name(vtkXMLDataElement* a) {
  const char* name = a->GetAttribute("Name");
  return std::string("DataArray '") + (name ? name : "") + "'";
}

/// How many values of its type an array holds, after its declared sizes are
/// checked against the bytes the file has for it.
u64 array_values(const XmlFile& f, vtkXMLDataElement* a) {
  const std::string what = array_name(a);
  int vtk_type = 0;
  const char* type = a->GetAttribute("type");
  const int word = type ? word_size(type, vtk_type) : 0;
  if (!word) fail(f.path, what + " has an unknown type '" + (type ? type : "") + "'");
  const char* format_attr = a->GetAttribute("format");
  const std::string_view format = format_attr ? format_attr : "";
  std::optional<BinarySource> source;
  if (format == "ascii") {
    // The reader parses every number there is; nothing is sized in advance.
    return inline_text(f.in, a).words;
  } else if (format == "binary") {
    const InlineText t = inline_text(f.in, a);
    source.emplace(f.in, t.start, t.end, true);
  } else if (format == "appended") {
    long long offset = -1;
    if (!f.appended_start) fail(f.path, what + " is appended but the file has no AppendedData");
    if (!a->GetScalarAttribute("offset", offset) || offset < 0)
      fail(f.path, what + " has no valid 'offset' into the appended data");
    source.emplace(f.in, f.appended_start + u64(offset), f.file_size, f.appended_base64);
  } else {
    fail(f.path, what + " has an unknown format '" + rayscope::printable_text(format) + "'");
  }

  const u64 hb = u64(f.header_bytes);
  const std::string short_data = what + ": its header declares more data than the file holds";
  if (!f.compressed) {
    auto header = source->first(hb);
    if (!header) fail(f.path, what + ": its data header is cut off");
    const u64 bytes = header_word(f, *header, 0);
    if (bytes > source->size() - hb) fail(f.path, short_data);
    return bytes / u64(word);
  }
  // Compressed: block count, block size, size of a partial last block, then
  // each block's compressed size; the blocks follow.
  auto head = source->first(3 * hb);
  if (!head) fail(f.path, what + ": its compression header is cut off");
  const u64 blocks = header_word(f, *head, 0);
  const u64 block_size = header_word(f, *head, 1);
  const u64 last_size = header_word(f, *head, 2);
  if (blocks > source->size() / hb - 3)
    fail(f.path, what + ": its compression header declares " + std::to_string(blocks) +
                     " blocks, more than the file holds");
  if (blocks == 0) return 0;
  if (block_size == 0 || last_size > block_size)
    fail(f.path, what + ": its compression header has invalid block sizes");
  auto sizes = source->first((3 + blocks) * hb);
  if (!sizes) fail(f.path, what + ": its compression header is cut off");
  u64 compressed = 0, uncompressed = 0;
  for (u64 b = 0; b < blocks; ++b) {
    const u64 c = header_word(f, *sizes, size_t(3 + b));
    const u64 u = b + 1 == blocks && last_size ? last_size : block_size;
    if (c == 0 || c > source->size() || u / kMaxCompressionRatio > c)
      fail(f.path, what + ": compressed block " + std::to_string(b) + " of " + std::to_string(c) +
                       " bytes cannot hold the " + std::to_string(u) + " bytes it declares");
    compressed += c;
    uncompressed += u;
  }
  if (compressed > source->size() - (3 + blocks) * hb) fail(f.path, short_data);
  return uncompressed / u64(word);
}

/// Finds the first child DataArray named `name` (as the readers do).
vtkXMLDataElement* data_array(vtkXMLDataElement* parent, const char* name) {
  if (!parent) return nullptr;
  for (int i = 0; i < parent->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* e = parent->GetNestedElement(i);
    const char* n = e->GetAttribute("Name");
    if (std::string_view(e->GetName()) == "DataArray" && (!name || (n && n == std::string(name))))
      return e;
  }
  return nullptr;
}

/// The first `n` values of an integer array, read through VTK's parser (the
/// array's header was checked by array_values(), so the reader's buffers are
/// sized by what the file holds).
std::vector<long long> read_values(vtkXMLDataParser* parser, const XmlFile& f, vtkXMLDataElement* a,
                                   u64 n) {
  int vtk_type = 0;
  const int word = word_size(a->GetAttribute("type"), vtk_type);
  std::vector<unsigned char> buffer(size_t(n) * size_t(word));
  const std::string_view format = a->GetAttribute("format");
  size_t got = 0;
  if (format == "appended") {
    long long offset = 0;
    a->GetScalarAttribute("offset", offset);
    got = parser->ReadAppendedData(offset, buffer.data(), 0, size_t(n), vtk_type);
  } else {
    got = parser->ReadInlineData(a, format == "ascii", buffer.data(), 0, size_t(n), vtk_type);
  }
  if (got != n) fail(f.path, array_name(a) + " could not be read");
  std::vector<long long> values(static_cast<size_t>(n));
  for (size_t i = 0; i < values.size(); ++i) {
    const unsigned char* v = buffer.data() + i * size_t(word);
    auto as = [v](auto t) {
      std::memcpy(&t, v, sizeof t);
      return t;
    };
    switch (vtk_type) {
      case VTK_TYPE_INT8:
        values[i] = as(std::int8_t());
        break;
      case VTK_TYPE_UINT8:
        values[i] = as(std::uint8_t());
        break;
      case VTK_TYPE_INT16:
        values[i] = as(std::int16_t());
        break;
      case VTK_TYPE_UINT16:
        values[i] = as(std::uint16_t());
        break;
      case VTK_TYPE_INT32:
        values[i] = as(std::int32_t());
        break;
      case VTK_TYPE_UINT32:
        values[i] = as(std::uint32_t());
        break;
      case VTK_TYPE_INT64:
        values[i] = as(std::int64_t());
        break;
      case VTK_TYPE_UINT64:
        values[i] = static_cast<long long>(
            std::min<u64>(as(u64()), u64(std::numeric_limits<long long>::max())));
        break;
      default:
        fail(f.path, array_name(a) + " holds cell offsets but is not of an integer type");
    }
  }
  return values;
}

/// A count attribute of a Piece ("NumberOfPoints"...): absent is 0, or an
/// error where the reader requires it (and would fail part-way).
u64 count(const XmlFile& f, vtkXMLDataElement* piece, const char* name, bool required = false) {
  if (!piece->GetAttribute(name)) {
    if (required) fail(f.path, std::string("Piece has no ") + name);
    return 0;
  }
  long long n = -1;
  if (!piece->GetScalarAttribute(name, n) || n < 0)
    fail(f.path,
         std::string("Piece has an invalid ") + name + " '" + piece->GetAttribute(name) + "'");
  return u64(n);
}

/// Every DataArray below `parent` must hold `tuples` tuples of its components
/// (the piece's points or cells, `of`); field data (`of` null) the
/// NumberOfTuples each array declares, which the reader allocates.
void check_attribute_arrays(const XmlFile& f, vtkXMLDataElement* parent, u64 tuples,
                            const char* of) {
  if (!parent) return;
  for (int i = 0; i < parent->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* a = parent->GetNestedElement(i);
    if (std::string_view(a->GetName()) != "DataArray") continue;
    int components = 1;
    if (a->GetAttribute("NumberOfComponents") &&
        (!a->GetScalarAttribute("NumberOfComponents", components) || components < 1))
      fail(f.path, array_name(a) + " has an invalid NumberOfComponents");
    if (!of) {
      long long n = 0;
      if (a->GetAttribute("NumberOfTuples") &&
          (!a->GetScalarAttribute("NumberOfTuples", n) || n < 0))
        fail(f.path, array_name(a) + " has an invalid NumberOfTuples");
      tuples = u64(n);
    }
    const u64 values = array_values(f, a);
    if (tuples > 0 && values / u64(components) < tuples)
      fail(f.path, array_name(a) + " holds " + std::to_string(values / u64(components)) +
                       " tuples but " +
                       (of ? "the piece declares " + std::to_string(tuples) + " " + of
                           : "declares " + std::to_string(tuples)));
  }
}

/// Polyhedra of an unstructured grid: "faceoffsets" gives, per cell, where
/// its faces end in "faces" (-1: not a polyhedron), and "faces" lists per
/// polyhedron its face count, then per face its point count and ids. The
/// reader sizes "faces" by the last offset and walks the counts unchecked.
void check_polyhedra(vtkXMLDataParser* parser, const XmlFile& f, vtkXMLDataElement* cells_section,
                     u64 cells) {
  vtkXMLDataElement* face_offsets = data_array(cells_section, "faceoffsets");
  vtkXMLDataElement* faces = data_array(cells_section, "faces");
  if (!face_offsets || !faces) return;
  if (array_values(f, face_offsets) < cells)
    fail(f.path, "Cells: 'faceoffsets' holds fewer values than the cells the piece declares");
  const std::vector<long long> ends = read_values(parser, f, face_offsets, cells);
  long long length = -1;
  for (long long e : ends) length = std::max(length, e);
  if (length <= 0) return;  // no polyhedra
  const std::string bad = "Cells: the polyhedra's 'faces' do not match their 'faceoffsets'";
  if (u64(length) > array_values(f, faces)) fail(f.path, bad);
  const std::vector<long long> stream = read_values(parser, f, faces, u64(length));
  long long at = 0;
  for (long long e : ends) {
    if (e < 0) continue;
    if (at >= length) fail(f.path, bad);
    const long long n = stream[size_t(at++)];
    for (long long k = 0; k < n; ++k) {
      if (at >= length || stream[size_t(at)] < 0 || stream[size_t(at)] >= length - at)
        fail(f.path, bad);
      at += stream[size_t(at)] + 1;
    }
    if (n < 0 || at != e) fail(f.path, bad);
  }
}

/// A cell section (Cells, Verts, Lines, Strips, Polys) declaring `cells`
/// cells: its offsets hold one per cell, and the last one, which the reader
/// sizes the connectivity by, does not exceed the connectivity's length.
void check_cell_section(vtkXMLDataParser* parser, const XmlFile& f, vtkXMLDataElement* section,
                        u64 cells, const char* name) {
  if (cells == 0) return;
  if (!section) fail(f.path, std::string("Piece declares cells but has no ") + name + " section");
  vtkXMLDataElement* offsets = data_array(section, "offsets");
  vtkXMLDataElement* connectivity = data_array(section, "connectivity");
  if (!offsets || !connectivity)
    fail(f.path, std::string(name) + " lacks its 'offsets' or 'connectivity' array");
  if (array_values(f, offsets) < cells)
    fail(f.path, std::string(name) + ": 'offsets' holds fewer values than the " +
                     std::to_string(cells) + " cells the piece declares");
  const u64 ids = array_values(f, connectivity);
  const long long last = read_values(parser, f, offsets, cells).back();
  if (last < 0 || u64(last) > ids)
    fail(f.path, std::string(name) + ": the offsets end at " + std::to_string(last) +
                     " but 'connectivity' holds " + std::to_string(ids) + " point ids");
  if (std::string_view(name) == "Cells")
    if (vtkXMLDataElement* types = data_array(section, "types");
        !types || array_values(f, types) < cells)
      fail(f.path, "Cells: 'types' holds fewer values than the " + std::to_string(cells) +
                       " cells the piece declares");
  check_polyhedra(parser, f, section, cells);
}

/// An Extent or WholeExtent attribute: six integers, each axis's end not
/// below its start by more than one (one below: empty).
std::array<long long, 6> extent_attribute(const fs::path& path, vtkXMLDataElement* e,
                                          const char* name) {
  std::array<long long, 6> x{};
  const char* text = e->GetAttribute(name);
  if (!text) fail(path, std::string(e->GetName()) + " has no " + name);
  const std::vector<std::string_view> w = words(text, Blanks::CSpace);
  bool ok = w.size() == 6;
  for (size_t i = 0; ok && i < 6; ++i) {
    const std::optional<long long> v = integer(w[i]);
    ok = v && *v > -(1ll << 40) && *v < (1ll << 40);
    if (ok) x[i] = *v;
  }
  for (int a = 0; ok && a < 3; ++a) ok = x[2 * a + 1] >= x[2 * a] - 1;
  if (!ok)
    fail(path, std::string(e->GetName()) + " has an invalid " + name + " '" +
                   rayscope::printable_text(text, rayscope::kMaxQuotedBytes) + "'");
  return x;
}

/// Cells of an image's extent: VTK counts an axis of one point as one cell
/// layer (a 2D image has cells), an empty axis as none.
u64 extent_cells(const std::array<long long, 6>& e) {
  u64 cells = 1;
  for (int a = 0; a < 3; ++a) {
    const long long d = e[2 * a + 1] - e[2 * a];
    cells *= d < 0 ? 0 : d == 0 ? 1 : u64(d);
  }
  return cells;
}

}  // namespace

void note_arrays(vtkXMLDataElement* section, std::string_view element, const char* name,
                 std::vector<XmlArray>& out) {
  if (!section) return;
  for (int i = 0; i < section->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* a = section->GetNestedElement(i);
    if (std::string_view(a->GetName()) != element) continue;
    XmlArray x;
    x.section = name;
    x.name = a->GetAttribute("Name") ? a->GetAttribute("Name") : "";
    x.type = a->GetAttribute("type") ? a->GetAttribute("type") : "";
    a->GetScalarAttribute("NumberOfComponents", x.components);
    out.push_back(x);
  }
}

struct XmlDocument {
  explicit XmlDocument(const fs::path& p)
      : path(p), in(p, std::ios::binary), data(p, std::ios::binary), f{path, data} {}
  fs::path path;
  // Two streams: one for VTK's parser, one for the checks' own reads.
  std::ifstream in, data;
  XmlFile f;
  vtkNew<vtkXMLDataParser> parser;
  vtkXMLDataElement* root = nullptr;
  // The parser's first error or warning (its later ones, e.g. while the
  // checks read values, are kept from VTK's output window too).
  std::string parse_error;
  vtkNew<vtkCallbackCommand> on_error;
};

void XmlDocumentDeleter::operator()(XmlDocument* d) const {
  delete d;
}

vtkXMLDataElement* root_of(const XmlDocument& doc) {
  return doc.root;
}

unsigned long long extent_points(const std::array<long long, 6>& e) {
  u64 points = 1;
  for (int a = 0; a < 3; ++a) {
    const long long d = e[2 * a + 1] - e[2 * a] + 1;
    points *= d <= 0 ? 0 : u64(d);
  }
  return points;
}

XmlDocumentPtr parse_vtk_xml(const fs::path& path, std::string_view type) {
  XmlDocumentPtr doc(new XmlDocument(path));
  if (!doc->in || !doc->data) fail(path, "cannot open the file");
  XmlFile& f = doc->f;
  f.file_size = size_of(path);

  // VTK's parser: the first error it reports is the message.
  vtkXMLDataParser* parser = doc->parser;
  parser->SetStream(&doc->in);
  std::string& parse_error = doc->parse_error;
  vtkCallbackCommand* on_error = doc->on_error;
  on_error->SetClientData(&parse_error);
  on_error->SetCallback([](vtkObject*, unsigned long, void* client, void* call) {
    auto* message = static_cast<std::string*>(client);
    if (message->empty() && call) *message = static_cast<const char*>(call);
  });
  parser->AddObserver(vtkCommand::ErrorEvent, on_error);
  parser->AddObserver(vtkCommand::WarningEvent, on_error);
  if (!parser->Parse() || !parser->GetRootElement()) {
    // "ERROR: In FILE, line N\nvtkXMLDataParser (0x...): message": the message.
    if (const size_t at = parse_error.find("): "); at != std::string::npos)
      parse_error = parse_error.substr(at + 3);
    for (char& c : parse_error)
      if (c == '\n' || c == '\r') c = ' ';
    while (!parse_error.empty() && parse_error.back() == ' ') parse_error.pop_back();
    fail(path, "not a valid VTK XML file" + (parse_error.empty() ? "" : ": " + parse_error));
  }
  vtkXMLDataElement* root = doc->root = parser->GetRootElement();
  if (std::string_view(root->GetName()) != "VTKFile")
    fail(path, "not a VTK XML file (its root element is not VTKFile)");
  const char* root_type = root->GetAttribute("type");
  if (!root_type || std::string_view(root_type) != type)
    fail(path, "not a VTK XML " + std::string(type) + " file (type '" +
                   rayscope::printable_text(root_type ? root_type : "", rayscope::kMaxQuotedBytes) +
                   "')");
  if (const char* h = root->GetAttribute("header_type")) {
    if (std::string_view(h) == "UInt64")
      f.header_bytes = 8;
    else if (std::string_view(h) != "UInt32")
      fail(path, std::string("unknown header_type '") + h + "'");
  }
  if (const char* order = root->GetAttribute("byte_order"))
    f.big_endian = std::string_view(order) == "BigEndian";
  vtkSmartPointer<vtkDataCompressor> compressor;
  if (const char* c = root->GetAttribute("compressor")) {
    const std::string_view name = c;
    if (name == "vtkZLibDataCompressor")
      compressor = vtkSmartPointer<vtkZLibDataCompressor>::New();
    else if (name == "vtkLZ4DataCompressor")
      compressor = vtkSmartPointer<vtkLZ4DataCompressor>::New();
    else if (name == "vtkLZMADataCompressor")
      compressor = vtkSmartPointer<vtkLZMADataCompressor>::New();
    else
      fail(path, std::string("unknown compressor '") + c + "'");
    f.compressed = true;
  }
  parser->SetCompressor(compressor);
  if (vtkXMLDataElement* appended = root->FindNestedElementWithName("AppendedData")) {
    const char* encoding = appended->GetAttribute("encoding");
    if (!encoding ||
        (std::string_view(encoding) != "raw" && std::string_view(encoding) != "base64"))
      fail(path, "AppendedData has an unknown encoding");
    f.appended_base64 = std::string_view(encoding) == "base64";
    f.appended_start = u64(parser->GetAppendedDataPosition());
    if (f.appended_start == 0 || f.appended_start > f.file_size)
      fail(path, "AppendedData has no data");
  }
  return doc;
}

void check_field_data(const XmlDocument& doc, vtkXMLDataElement* field_data) {
  check_attribute_arrays(doc.f, field_data, 0, nullptr);
}

XmlDatasetSummary check_vtk_xml_dataset(const fs::path& path, std::string_view dataset_type) {
  XmlDocumentPtr doc = parse_vtk_xml(path, dataset_type);
  const XmlFile& f = doc->f;
  vtkXMLDataParser* parser = doc->parser;
  XmlDatasetSummary summary;
  const std::string type(dataset_type);
  vtkXMLDataElement* dataset = doc->root->FindNestedElementWithName(type.c_str());
  if (!dataset) fail(path, "no " + type + " element");
  const bool poly = dataset_type == "PolyData";
  const bool image = dataset_type == "ImageData";
  // An image's pieces are parts of its whole extent, which the reader
  // allocates every array for: the whole must be within what the pieces hold
  // and within what the surface filter is given (kMaxStructuredPoints).
  u64 whole_points = 0, piece_points = 0;
  if (image) {
    summary.whole_extent = extent_attribute(path, dataset, "WholeExtent");
    whole_points = extent_points(summary.whole_extent);
    if (whole_points > kMaxStructuredPoints)
      fail(path, "ImageData's WholeExtent has more than " + std::to_string(kMaxStructuredPoints) +
                     " points");
  }
  check_attribute_arrays(f, dataset->FindNestedElementWithName("FieldData"), 0, nullptr);
  bool first_piece = true;
  for (int i = 0; i < dataset->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* piece = dataset->GetNestedElement(i);
    if (std::string_view(piece->GetName()) != "Piece") continue;
    u64 points = 0, cells = 0;
    if (image) {
      const std::array<long long, 6> e = extent_attribute(path, piece, "Extent");
      for (int a = 0; a < 3; ++a)
        if (extent_points(e) > 0 && (e[2 * a] < summary.whole_extent[2 * a] ||
                                     e[2 * a + 1] > summary.whole_extent[2 * a + 1]))
          fail(path, "a Piece's Extent lies outside the WholeExtent");
      summary.extents.push_back(e);
      points = extent_points(e);
      cells = points ? extent_cells(e) : 0;
      piece_points += points;
    } else {
      points = count(f, piece, "NumberOfPoints", true);
      if (points > 0) {
        vtkXMLDataElement* coords = data_array(piece->FindNestedElementWithName("Points"), nullptr);
        if (!coords) fail(path, "Piece declares points but has no Points array");
        check_attribute_arrays(f, piece->FindNestedElementWithName("Points"), points, "points");
      }
      if (poly) {
        for (const char* section : {"Verts", "Lines", "Strips", "Polys"}) {
          const u64 n = count(f, piece, (std::string("NumberOf") + section).c_str());
          check_cell_section(parser, f, piece->FindNestedElementWithName(section), n, section);
          cells += n;
        }
      } else {
        cells = count(f, piece, "NumberOfCells", true);
        check_cell_section(parser, f, piece->FindNestedElementWithName("Cells"), cells, "Cells");
      }
    }
    check_attribute_arrays(f, piece->FindNestedElementWithName("PointData"), points, "points");
    check_attribute_arrays(f, piece->FindNestedElementWithName("CellData"), cells, "cells");
    if (first_piece) {
      note_arrays(piece->FindNestedElementWithName("Points"), "DataArray", "Points",
                  summary.arrays);
      note_arrays(piece->FindNestedElementWithName("PointData"), "DataArray", "PointData",
                  summary.arrays);
      note_arrays(piece->FindNestedElementWithName("CellData"), "DataArray", "CellData",
                  summary.arrays);
      first_piece = false;
    }
  }
  if (image && piece_points < whole_points)
    fail(path, "ImageData's pieces hold " + std::to_string(piece_points) +
                   " points but its WholeExtent has " + std::to_string(whole_points));
  return summary;
}

}  // namespace rayscope_vtkio::checks

namespace rayscope_vtkio {

void check_vtk_xml_file(const std::filesystem::path& path, const char* dataset_type) {
  checks::check_vtk_xml_dataset(path, dataset_type);
}

}  // namespace rayscope_vtkio
