// Subcommands of the `rayscope` executable.
#pragma once

#include <CLI/CLI.hpp>

namespace rayscope::cli {

/// Registers `rayscope render`; the callback sets `exit_code`.
void add_render_command(CLI::App& app, int& exit_code);
/// Registers `rayscope inspect`.
void add_inspect_command(CLI::App& app, int& exit_code);
/// Registers `rayscope query` (range queries: box, sphere, k nearest).
void add_query_command(CLI::App& app, int& exit_code);
/// Registers `rayscope accel compare`.
void add_accel_command(CLI::App& app, int& exit_code);
#ifdef RAYSCOPE_HAVE_VIEWER
/// Registers `rayscope view` (built with the VTK module).
void add_view_command(CLI::App& app, int& exit_code);
#endif

}  // namespace rayscope::cli
