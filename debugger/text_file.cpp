#include "text_file.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace rayscope::cli {

void write_text_file(const std::string& path, const std::string& text) {
  namespace fs = std::filesystem;
  fs::path out(path);
  fs::path tmp = out;
  tmp += ".tmp";
  std::error_code ec;
  {
    std::ofstream f(tmp, std::ios::binary);
    if (!f) throw std::runtime_error(path + ": cannot write");
    f << text;
    if (!f.flush()) {
      f.close();
      fs::remove(tmp, ec);
      throw std::runtime_error(path + ": write failed");
    }
  }
  fs::rename(tmp, out, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw std::runtime_error(path + ": cannot rename temporary file");
  }
}

void write_text_output(const std::string& text, const std::string& path) {
  if (path.empty()) {
    std::fwrite(text.data(), 1, text.size(), stdout);
    return;
  }
  write_text_file(path, text);
}

}  // namespace rayscope::cli
