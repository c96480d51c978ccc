// check_exodus_file() (mesh_checks.h): what vtkExodusIIReader and the netCDF
// library under it take on trust, checked before they run.
//
// An Exodus II file is a netCDF file. In netCDF's classic formats (CDF1
// "classic", CDF2 "64-bit offset", CDF5 "64-bit data") a header lists the
// dimensions, global attributes and variables, each variable with its shape
// and where its data begins; the data follows. The header is read here in
// full, as the format's specification lays it out, and every variable's data
// is held against the file's length. Exodus keeps each element block's
// connectivity in a variable "connectN" of 1-based node numbers, which the
// reader turns into indices of its node maps without a check: those are read
// here and held against the dimension "num_nodes". netCDF-4 files (HDF5) are
// recognised by their signature and opened by the netCDF library; their
// structure is HDF5's to check.
#include <array>
#include <cstdint>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <vtk_netcdf.h>

#include "check_util.h"
#include "rayscope_vtkio/mesh_checks.h"

namespace rayscope_vtkio {
namespace {

using namespace checks;
using u64 = std::uint64_t;

constexpr u64 kNoSize = std::numeric_limits<u64>::max();

// a * b, or kNoSize when it overflows.
u64 times(u64 a, u64 b) {
  if (a == kNoSize || b == kNoSize) return kNoSize;
  if (a != 0 && b > kNoSize / a) return kNoSize;
  return a * b;
}
u64 plus(u64 a, u64 b) {
  return a == kNoSize || b == kNoSize || b > kNoSize - a ? kNoSize : a + b;
}

/// Bytes of one value of a netCDF type (NC_BYTE = 1 ... NC_UINT64 = 11), 0
/// when the format has no such type.
int type_size(u64 type, int version) {
  static constexpr int kSizes[] = {0, 1, 1, 2, 4, 4, 8, 1, 2, 4, 8, 8};
  if (type == 0 || type > (version == 5 ? 11u : 6u)) return 0;
  return kSizes[type];
}

/// An attribute: its netCDF type and, for one value of an integer type
/// (NC_SHORT, NC_INT), that value.
struct Attribute {
  u64 type = 0;
  std::optional<long long> integer;
};
using Attributes = std::map<std::string, Attribute, std::less<>>;

struct Variable {
  std::string name;
  std::vector<u64> dims, dim_ids;
  Attributes attributes;
  u64 type = 0, begin = 0;
};

// The header, read front to back; every read is held against the file's end.
class Header {
 public:
  Header(const fs::path& path, std::ifstream& in, u64 size) : path_(path), in_(in), size_(size) {}

  [[noreturn]] void error(const std::string& problem) const { fail(path_, "Exodus: " + problem); }

  u64 read(int bytes, const char* what) {
    unsigned char b[8];
    if (u64(bytes) > size_ - at_) error(std::string("the header ends inside ") + what);
    in_.read(reinterpret_cast<char*>(b), bytes);
    if (!in_) error(std::string("cannot read ") + what);
    at_ += u64(bytes);
    return u64(binary_integer(b, bytes, false, true));
  }
  void skip(u64 bytes, const char* what) {
    if (bytes > size_ - at_) error(std::string("the header ends inside ") + what);
    at_ += bytes;
    in_.seekg(std::streamoff(at_));
  }
  std::string name(int count_bytes, const char* what) {
    const u64 n = read(count_bytes, what);
    if (n > size_ - at_) error(std::string("the header ends inside ") + what);
    std::string s(size_t(n), '\0');
    in_.read(s.data(), std::streamsize(n));
    at_ += n;
    skip((4 - n % 4) % 4, what);
    return s;
  }
  u64 size() const { return size_; }

 private:
  const fs::path& path_;
  std::ifstream& in_;
  u64 size_ = 0, at_ = 0;
};

constexpr u64 kDimensionTag = 10, kVariableTag = 11, kAttributeTag = 12;

}  // namespace

void check_exodus_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open the file");
  const u64 size = size_of(path);
  unsigned char magic[8] = {};
  in.read(reinterpret_cast<char*>(magic), 8);
  const std::string_view m(reinterpret_cast<const char*>(magic), size_t(in.gcount()));
  if (m == std::string_view("\x89HDF\r\n\x1a\n", 8)) {
    // netCDF-4: HDF5's structure, for the netCDF library to check. It is
    // opened here first, quietly: the Exodus library, opening a file netCDF
    // refuses, prints its own lines to stderr whatever its options say.
    int id = 0;
    if (const int status = nc_open(path.c_str(), NC_NOWRITE, &id); status != NC_NOERR)
      fail(path, std::string("Exodus: a netCDF-4 (HDF5) file netCDF cannot open: ") +
                     nc_strerror(status));
    nc_close(id);
    return;
  }
  if (m.size() < 4 || m.substr(0, 3) != "CDF" || (magic[3] != 1 && magic[3] != 2 && magic[3] != 5))
    fail(path, "Exodus: not a netCDF file (an Exodus II file is one)");
  const int version = magic[3];
  const int count_bytes = version == 5 ? 8 : 4;  // counts, lengths, dimension ids, vsize
  const int offset_bytes = version == 1 ? 4 : 8;
  in.clear();
  Header header(path, in, size);
  header.skip(4, "the magic number");
  const u64 records = header.read(count_bytes, "the record count");
  if (records == (version == 5 ? kNoSize : 0xFFFFFFFFu))
    header.error("a file still being written (its record count is 'streaming')");

  // Dimensions: their lengths; 0 is the record dimension.
  std::vector<u64> dims;
  std::map<std::string, u64, std::less<>> dim_by_name;  // name -> id
  auto list = [&](u64 tag, const char* what) -> u64 {
    const u64 t = header.read(4, what);
    const u64 n = header.read(count_bytes, what);
    if (t == 0 && n == 0) return 0;  // absent
    if (t != tag) header.error(std::string("the ") + what + " are not where the format puts them");
    // Each entry takes at least 8 bytes.
    if (n > header.size() / 8) header.error(std::string("more ") + what + " than the file holds");
    return n;
  };
  // Reads an attribute list.
  auto attributes = [&](const char* what) {
    Attributes out;
    const u64 n = list(kAttributeTag, what);
    for (u64 i = 0; i < n; ++i) {
      std::string name = header.name(count_bytes, what);
      Attribute a;
      a.type = header.read(4, what);
      const int bytes = type_size(a.type, version);
      if (!bytes)
        header.error(std::string("an attribute of unknown type ") + std::to_string(a.type));
      const u64 values = header.read(count_bytes, what);
      const u64 length = times(values, u64(bytes));
      if (length == kNoSize || length > header.size())
        header.error(std::string("an attribute longer than the file"));
      constexpr u64 kShort = 3, kInt = 4;
      if ((a.type == kShort || a.type == kInt) && values == 1) {
        const u64 bits = header.read(bytes, what);
        a.integer =
            a.type == kShort ? (long long)std::int16_t(bits) : (long long)std::int32_t(bits);
        header.skip(u64((4 - bytes % 4) % 4), what);
      } else {
        header.skip(length + (4 - length % 4) % 4, what);
      }
      out.emplace(std::move(name), a);
    }
    return out;
  };
  const u64 ndims = list(kDimensionTag, "dimensions");
  bool record_dim = false;
  for (u64 i = 0; i < ndims; ++i) {
    std::string name = header.name(count_bytes, "the dimensions");
    const u64 length = header.read(count_bytes, "the dimensions");
    if (length == 0) {
      if (record_dim) header.error("two unlimited (record) dimensions");
      record_dim = true;
    }
    dim_by_name.emplace(std::move(name), dims.size());
    dims.push_back(length);
  }
  // The longest name the file says it holds: the reader sizes its name
  // buffers by it (a damaged value made it ask for 4 GB). The Exodus library
  // takes names of 1 to NC_MAX_NAME characters.
  const Attributes global = attributes("global attributes");
  if (const auto it = global.find("maximum_name_length"); it != global.end())
    if (!it->second.integer || *it->second.integer < 0 || *it->second.integer > NC_MAX_NAME)
      header.error("the attribute 'maximum_name_length' is not a number of 0 to " +
                   std::to_string(NC_MAX_NAME) + " characters");
  const u64 nvars = list(kVariableTag, "variables");
  std::vector<Variable> vars;
  for (u64 i = 0; i < nvars; ++i) {
    Variable v;
    v.name = header.name(count_bytes, "the variables");
    const u64 rank = header.read(count_bytes, "the variables");
    if (rank > size / u64(count_bytes)) header.error("a variable with more dimensions than bytes");
    for (u64 k = 0; k < rank; ++k) {
      const u64 id = header.read(count_bytes, "the variables");
      if (id >= ndims)
        header.error("variable '" + rayscope::printable_text(v.name, rayscope::kMaxQuotedBytes) +
                     "' names dimension " + std::to_string(id) + " of " + std::to_string(ndims));
      if (dims[size_t(id)] == 0 && k != 0)
        header.error("variable '" + rayscope::printable_text(v.name, rayscope::kMaxQuotedBytes) +
                     "' has the record dimension other than first");
      v.dims.push_back(dims[size_t(id)]);
      v.dim_ids.push_back(id);
    }
    v.attributes = attributes("variable attributes");
    v.type = header.read(4, "the variables");
    if (!type_size(v.type, version))
      header.error("variable '" + rayscope::printable_text(v.name, rayscope::kMaxQuotedBytes) +
                   "' of unknown type " + std::to_string(v.type));
    header.read(count_bytes, "the variables");  // vsize: recomputed below, as netCDF does
    v.begin = header.read(offset_bytes, "the variables");
    vars.push_back(std::move(v));
  }

  // Each variable's data within the file. A record variable's records are
  // interleaved with the other record variables': one record of all of them
  // is `record_size` bytes (each padded to 4 bytes unless it is the only one).
  auto bytes_per_record = [&](const Variable& v) {
    u64 n = u64(type_size(v.type, version));
    for (size_t k = v.dims.empty() || v.dims[0] != 0 ? 0 : 1; k < v.dims.size(); ++k)
      n = times(n, v.dims[k]);
    return n;
  };
  auto is_record = [](const Variable& v) { return !v.dims.empty() && v.dims[0] == 0; };
  u64 record_size = 0, record_vars = 0;
  for (const Variable& v : vars)
    if (is_record(v)) ++record_vars;
  for (const Variable& v : vars)
    if (is_record(v)) {
      const u64 n = bytes_per_record(v);
      record_size = plus(record_size, record_vars == 1 ? n : plus(n, (4 - n % 4) % 4));
    }
  for (const Variable& v : vars) {
    const u64 n = bytes_per_record(v);
    u64 end = plus(v.begin, n);
    if (is_record(v)) end = records == 0 ? v.begin : plus(end, times(records - 1, record_size));
    if (end > size)
      fail(path, "Exodus: the data of variable '" +
                     rayscope::printable_text(v.name, rayscope::kMaxQuotedBytes) +
                     "' runs past the end of the file (a truncated or damaged file)");
  }

  // The element blocks, as Exodus lays them out: "num_el_blk" blocks, their
  // ids in "eb_prop1", block I's elements and nodes per element in the
  // dimensions "num_el_in_blkI" and "num_nod_per_elI" and its connectivity in
  // "connectI" of those two dimensions, with a text attribute "elem_type"
  // naming the element; an empty block has none of the three. The reader
  // lists a block lacking some of them in one place but not in another and
  // crashes (a damaged dimension name, or a damaged attribute name, made a
  // NULL dereference in vtkExodusIIReaderPrivate::GetSortedObjectInfo).
  auto dim = [&](const std::string& name) -> std::optional<u64> {
    const auto it = dim_by_name.find(name);
    if (it == dim_by_name.end()) return std::nullopt;
    return it->second;
  };
  auto var = [&](const std::string& name) -> const Variable* {
    for (const Variable& v : vars)
      if (v.name == name) return &v;
    return nullptr;
  };
  if (const std::optional<u64> blocks = dim("num_el_blk")) {
    const Variable* ids = var("eb_prop1");
    if (!ids || ids->dim_ids != std::vector<u64>{*blocks})
      fail(path, "Exodus: the element block ids 'eb_prop1' do not match 'num_el_blk'");
    for (u64 b = 1; b <= dims[size_t(*blocks)]; ++b) {
      const std::string n = std::to_string(b);
      const std::optional<u64> elements = dim("num_el_in_blk" + n);
      const std::optional<u64> per_element = dim("num_nod_per_el" + n);
      const Variable* connect = var("connect" + n);
      if (!elements && !per_element && !connect) continue;  // an empty block
      if (!elements || !per_element || !connect ||
          connect->dim_ids != std::vector<u64>{*elements, *per_element})
        fail(path, "Exodus: element block " + n +
                       " lacks or mismatches its dimensions num_el_in_blk" + n +
                       ", num_nod_per_el" + n + " or its variable connect" + n);
      constexpr u64 kText = 2;  // NC_CHAR
      const auto type = connect->attributes.find("elem_type");
      if (type == connect->attributes.end() || type->second.type != kText)
        fail(path, "Exodus: element block " + n + " has no element type (text attribute " +
                       "'elem_type' of connect" + n + ")");
    }
  }

  // The element blocks' connectivity: node numbers 1..num_nodes.
  const std::optional<u64> nodes_dim = dim("num_nodes");
  const u64 nodes = nodes_dim ? dims[size_t(*nodes_dim)] : 0;
  for (const Variable& v : vars) {
    if (v.name.rfind("connect", 0) != 0 || is_record(v)) continue;
    const int bytes = type_size(v.type, version);
    const bool integer_type = v.type == 4 || v.type == 9 || v.type == 10 || v.type == 11;
    if (!integer_type)
      fail(path, "Exodus: connectivity '" +
                     rayscope::printable_text(v.name, rayscope::kMaxQuotedBytes) +
                     "' is not of an integer type");
    const u64 count = bytes_per_record(v) / u64(bytes);
    in.clear();
    in.seekg(std::streamoff(v.begin));
    std::vector<unsigned char> buffer(size_t(std::min<u64>(count, 1 << 16)) * size_t(bytes));
    for (u64 done = 0; done < count;) {
      const u64 chunk = std::min<u64>(count - done, 1 << 16);
      in.read(reinterpret_cast<char*>(buffer.data()), std::streamsize(chunk * u64(bytes)));
      if (!in)
        fail(path, "Exodus: cannot read '" +
                       rayscope::printable_text(v.name, rayscope::kMaxQuotedBytes) + "'");
      for (u64 k = 0; k < chunk; ++k) {
        const long long node = binary_integer(buffer.data() + k * u64(bytes), bytes,
                                              v.type == 4 || v.type == 10, true);
        if (node < 1 || u64(node) > nodes)
          fail(path, "Exodus: '" + rayscope::printable_text(v.name, rayscope::kMaxQuotedBytes) +
                         "' names node " + std::to_string(node) + " but the file has " +
                         std::to_string(nodes) + " nodes");
      }
      done += chunk;
    }
  }
}

}  // namespace rayscope_vtkio
