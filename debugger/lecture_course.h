// A course file (data/lecture/course.json): the lecture's chapters in order,
// each as `rayscope view` opens it in lecture mode (view --lecture).
#pragma once

#include <string>
#include <vector>

namespace rayscope::cli {

/// One chapter: its title (the first "# " heading of its page, so that the
/// page owns it), the one-line caption of what to look at, and the
/// arguments of the `rayscope view` command that shows it (the scene file,
/// resolved against the course file's folder, first; none for the default
/// scene; then options such as --accel, --pixel and --keys).
struct CourseChapter {
  std::string page;  ///< The chapter's page, resolved against the course file's folder.
  std::string title;
  std::string caption;
  std::vector<std::string> view_args;
};

/// Reads a course file:
///   {"chapters": [{"page": "../../docs/lecture/03-shadows.md",
///                  "scene": "shadows.json", "options": ["--pixel", "40,130"],
///                  "caption": "..."}, ...]}
/// ("scene" and "options" may be left out). Throws std::runtime_error
/// "FILE: problem" (naming the chapter) for a file that cannot be read, is
/// not such JSON, has no chapters, or names a page without a "# " title.
std::vector<CourseChapter> read_course(const std::string& path);

}  // namespace rayscope::cli
