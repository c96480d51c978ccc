// Options shared by the subcommands that load a scene and render settings.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "rayscope/scene_io.h"

namespace rayscope::cli {

/// The shortest text that reads back as the same float (std::to_chars): what a
/// printed command line or value needs to reproduce it exactly ("0.001", not
/// "0.00100000005").
std::string shortest(float v);

/// Parses n comma-separated integers ("X,Y" or "X,Y,W,H") into out; false when
/// the text is not exactly that.
bool parse_ints(const std::string& s, int n, int* out);

struct SceneOptions {
  std::string scene;  ///< Empty: the built-in default scene.
  std::string size;
  std::optional<int> width, height, samples, max_depth;
  std::optional<uint32_t> seed;
  std::optional<float> min_contribution;
  int threads = 0;

  /// Adds the scene argument and the render-setting options to a subcommand.
  void add_to(CLI::App* cmd);
  /// Loads (and commits) the scene and applies the option overrides. Throws
  /// std::exception with a one-line message naming the file.
  LoadedScene load() const;
  /// The options that reproduce `settings` on another command line.
  static std::string replay_args(const std::string& scene, const RenderSettings& settings);
};

}  // namespace rayscope::cli
