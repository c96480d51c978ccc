// What `rayscope view` hands the viewer module (view_module.cpp), which the
// executable loads only for `view`: the VTK rendering libraries it needs
// (OpenGL, interaction, fonts: about 260 shared libraries) would otherwise be
// loaded and relocated by every `rayscope` process, which took longer than
// loading the bunny and building its BVH.
#pragma once

#include <string>
#include <vector>

#include "rayscope/scene_io.h"

namespace rayscope::cli {

/// A chapter of a lecture (view --lecture): its scene loaded and its
/// options checked as a `rayscope view` command's.
struct ViewChapter {
  std::string title, caption;
  LoadedScene loaded;
  bool pick = false;
  int pixel[2] = {-1, -1};  ///< Picked on entering it, from the top-left (when pick).
  std::vector<std::string> keys;
};

/// A checked `rayscope view` request: the scene is loaded and every option
/// that can be checked without a window has been.
struct ViewRequest {
  /// A lecture's chapters (then `loaded` is null), and the one shown first.
  std::vector<ViewChapter> chapters;
  int chapter = 0;
  LoadedScene* loaded = nullptr;
  bool pick = false;
  int pixel[2] = {-1, -1};  ///< Picked at the start, from the top-left (when pick).
  std::vector<std::string> keys;
  std::string screenshot;
  std::string record;      ///< An animated GIF of the window after the pick and each key.
  double fps = 1.0;        ///< Its frames per second.
  int window[2] = {0, 0};  ///< Window size in pixels (0: the viewer's default).
  bool aim = false;        ///< view_camera holds the 3D view's eye and look-at point.
  double view_camera[6] = {0, 0, 0, 0, 0, 0};
  double font_scale = 1.0;
};

/// The module's entry points (extern "C", looked up by name).
using ViewHelpFn = const char* (*)();
using ViewRunFn = int (*)(const ViewRequest& request, std::string& error);
inline constexpr const char* kViewHelpSymbol = "rayscope_view_help";
inline constexpr const char* kViewRunSymbol = "rayscope_view_run";

}  // namespace rayscope::cli
