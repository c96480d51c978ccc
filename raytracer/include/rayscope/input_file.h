// The one check that an input path (a scene file, a mesh file) names a file
// that can be read, with the problem in words: the scene parser and the mesh
// loaders of every front end ask it before they open anything.
#pragma once

#include <filesystem>
#include <string>

namespace rayscope {

/// Empty when `path` is a regular file (after following symbolic links), else
/// what it is instead: "file not found", "is a directory, not a file", "is a
/// loop of symbolic links", "is not a regular file" (a device, pipe or
/// socket) or the system's reason it cannot be looked at (e.g. "permission
/// denied").
std::string input_file_problem(const std::filesystem::path& path);

/// The extension of `path` in lower case, with its dot ("" without one): what
/// the front ends choose a file's format by.
std::string lower_extension(const std::filesystem::path& path);

}  // namespace rayscope
