#include "rayscope/input_file.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <system_error>

namespace rayscope {

std::string input_file_problem(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec && ec != std::errc::no_such_file_or_directory) {
    // status() reports a loop of links (ELOOP) and unreadable folders here,
    // which exists() would call "not found".
    if (ec == std::errc::too_many_symbolic_link_levels) return "is a loop of symbolic links";
    return ec.message();
  }
  if (!fs::exists(st)) {
    std::error_code lec;
    if (fs::is_symlink(fs::symlink_status(path, lec)))
      return "is a symbolic link to a file that does not exist";
    return "file not found";
  }
  if (fs::is_directory(st)) return "is a directory, not a file";
  if (!fs::is_regular_file(st)) return "is not a regular file";
  return {};
}

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

}  // namespace rayscope
