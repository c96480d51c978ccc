// Options shared by the subcommands that load a scene and render settings.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "rayscope/scene_io.h"

namespace rayscope::cli {

/// Parses n comma-separated integers ("X,Y" or "X,Y,W,H") into out; false when
/// the text is not exactly that.
bool parse_ints(const std::string& s, int n, int* out);

/// A --pixel X,Y option: parsed (throws std::invalid_argument "--pixel:
/// expected X,Y, got '...'"), and checked against the image once the settings
/// are known (throws std::out_of_range "--pixel: (X,Y) is outside the WxH
/// image"). Pixels count from the top-left corner.
void parse_pixel_option(const std::string& text, int xy[2]);
void check_pixel_option(const std::string& text, const int xy[2], const RenderSettings& settings);

/// Writes a command's text output to standard output (empty `path`) or to the
/// file `path`, under a temporary name renamed when complete. Throws
/// std::runtime_error naming the file when it cannot be written.
void write_text_output(const std::string& text, const std::string& path);

struct SceneOptions {
  std::string scene;  ///< Empty: the built-in default scene.
  std::string size;
  std::optional<int> width, height, samples, max_depth;
  std::optional<uint32_t> seed;
  std::optional<float> min_contribution;
  int threads = 0;
  /// The structure rays walk (rayscope::parse_accel_kind names it): "bvh",
  /// "bvh2" (the binary teaching walk), "kdtree" or "none".
  std::string accel = to_string(AccelKind::Bvh);

  /// Adds the scene argument, the render-setting options (unless
  /// `render_settings` is false: commands that render nothing) and --accel to
  /// a subcommand.
  void add_to(CLI::App* cmd, bool render_settings = true);
  /// Loads (and commits) the scene and applies the option overrides. Throws
  /// std::exception with a one-line message naming the file.
  LoadedScene load() const;
  /// The options that reproduce `settings` and the scene's walk (`accel`) on
  /// another command line.
  static std::string replay_args(const std::string& scene, const RenderSettings& settings,
                                 AccelKind accel);
};

}  // namespace rayscope::cli
