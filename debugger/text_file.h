// Text output of the subcommands (inspect -o, query -o, accel compare --csv).
#pragma once

#include <string>

namespace rayscope::cli {

/// Writes `text` to `path` through a temporary file in the same folder that is
/// renamed over it, so that a failed run never leaves a half-written file.
/// Throws std::runtime_error "PATH: problem".
void write_text_file(const std::string& path, const std::string& text);

/// A command's text output: to standard output when `path` is empty, else
/// write_text_file(path, text).
void write_text_output(const std::string& text, const std::string& path);

}  // namespace rayscope::cli
