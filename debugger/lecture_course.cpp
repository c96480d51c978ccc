#include "lecture_course.h"

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace rayscope::cli {

namespace {

// The first "# " heading of a Markdown page, without the "# " and the
// chapter's number ("3. "), which the viewer shows beside the count.
std::string page_title(const std::filesystem::path& page) {
  std::ifstream in(page);
  if (!in) throw std::runtime_error("cannot read its page " + page.string());
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("# ", 0) != 0) continue;
    const size_t digits = line.find_first_not_of("0123456789", 2);
    return digits > 2 && line.compare(digits, 2, ". ") == 0 ? line.substr(digits + 2)
                                                            : line.substr(2);
  }
  throw std::runtime_error("its page " + page.string() + " has no \"# \" title");
}

}  // namespace

std::vector<CourseChapter> read_course(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot read the course file");
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(path + ": not JSON: " + e.what());
  }
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  if (!doc.is_object() || !doc.contains("chapters") || !doc["chapters"].is_array() ||
      doc["chapters"].empty())
    throw std::runtime_error(path + ": expected {\"chapters\": [...]} with at least one chapter");
  std::vector<CourseChapter> chapters;
  for (size_t k = 0; k < doc["chapters"].size(); ++k) {
    const nlohmann::json& c = doc["chapters"][k];
    const std::string where = path + ": chapter " + std::to_string(k + 1) + ": ";
    try {
      for (const auto& [key, value] : c.items())
        if (key != "page" && key != "scene" && key != "options" && key != "caption")
          throw std::runtime_error("unknown key \"" + key + "\"");
      CourseChapter ch;
      ch.page = (dir / c.at("page").get<std::string>()).string();
      ch.title = page_title(ch.page);
      ch.caption = c.at("caption").get<std::string>();
      if (c.contains("scene"))
        ch.view_args.push_back((dir / c["scene"].get<std::string>()).string());
      if (c.contains("options"))
        for (const nlohmann::json& o : c["options"]) ch.view_args.push_back(o.get<std::string>());
      chapters.push_back(std::move(ch));
    } catch (const nlohmann::json::exception& e) {
      throw std::runtime_error(where + e.what());
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(where + e.what());
    }
  }
  return chapters;
}

}  // namespace rayscope::cli
