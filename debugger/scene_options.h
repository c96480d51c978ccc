// Options shared by the subcommands that load a scene and render settings.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "rayscope/scene_io.h"

namespace rayscope::cli {

/// The structures' names (rayscope::kAccelKinds, as --accel takes them)
/// joined by `sep`, the last two by `last_sep`: "bvh, bvh2, ... or none".
std::string accel_kind_names(const char* sep, const char* last_sep);

/// Parses n comma-separated integers ("X,Y" or "X,Y,W,H") into out; false when
/// the text is not exactly that.
bool parse_ints(const std::string& s, int n, int* out);
/// The same for n numbers (strtod's syntax, so "nan" and "inf" parse, for
/// the caller to refuse as non-finite with the value in its message).
bool parse_numbers(const std::string& s, int n, double* out);

/// A --pixel X,Y option: parsed (throws std::invalid_argument "--pixel:
/// expected X,Y, got '...'"), and checked against the image once the settings
/// are known (throws std::out_of_range "--pixel: (X,Y) is outside the WxH
/// image"). Pixels count from the top-left corner.
/// Parses WIDTHxHEIGHT; throws std::invalid_argument naming `option` else.
void parse_size(const std::string& option, const std::string& text, int& w, int& h);
void parse_pixel_option(const std::string& text, int xy[2]);
void check_pixel_option(const std::string& text, const int xy[2], const RenderSettings& settings);

struct SceneOptions {
  std::string scene;  ///< Empty: the built-in default scene.
  std::string size;
  std::optional<int> width, height, samples, max_depth;
  std::optional<uint32_t> seed;
  std::optional<float> min_contribution;
  std::optional<int> max_samples;
  std::optional<float> target_error;
  bool texture_filter = false;
  bool single_rays = false;
  int threads = 0;
  /// The structure rays walk (rayscope::parse_accel_kind names it): "bvh",
  /// "bvh2" (the binary teaching walk), "kdtree", "grid", "octree", "bsp",
  /// "spheres" or "none".
  std::string accel = to_string(AccelConfig{}.kind);
  /// How a spatial subdivision stores a straddling primitive
  /// (rayscope::parse_prim_storage names it): "every-cell" (default),
  /// "smallest-cell" or "split"; checked against the structure by
  /// rayscope::accel_storage_error.
  std::string storage = to_string(PrimStorage::EveryCell);
  /// SmallestCell's loose factor (AccelConfig::loose_factor; unset: the
  /// lecture's kDefaultLooseFactor), checked by rayscope::loose_factor_error.
  std::optional<float> loose_factor;
  /// The kD-tree's split rule (rayscope::parse_kd_split_rule names it):
  /// "sah" (default) or "median".
  std::string kd_split = to_string(KdSplitRule::Sah);
  /// The uniform grid's cells per axis, "N" or "NX,NY,NZ" (0 on an axis:
  /// chosen from the object count; empty: all automatic), checked by
  /// rayscope::grid_resolution_error.
  std::string grid_resolution;

  /// Adds the scene argument, the render-setting options (unless
  /// `render_settings` is false: commands that render nothing) and, with
  /// `walk_option`, --accel, --storage, --loose-factor, --kd-split and --grid-resolution (a command
  /// that chooses the structures itself, such as accel compare, leaves them out).
  void add_to(CLI::App* cmd, bool render_settings = true, bool walk_option = true);
  /// Loads (and commits) the scene and applies the option overrides. Throws
  /// std::exception with a one-line message naming the file.
  LoadedScene load() const;
  /// The options that reproduce `settings` and the scene's walk (the
  /// structure, its storage, loose factor and kD-tree split rule, each only
  /// when not the default) on another command line.
  static std::string replay_args(const std::string& scene, const RenderSettings& settings,
                                 const AccelConfig& accel);
};

}  // namespace rayscope::cli
