// rayscope: render scenes and inspect the ray tree behind any pixel (see README.md).
#include <cstdio>
#include <exception>

#include <vtkLogger.h>
#include <vtkOutputWindow.h>
#include <CLI/CLI.hpp>

#include "commands.h"
#include "rayscope/huge_pages.h"
#include "rayscope/printable_text.h"

int main(int argc, char** argv) {
  // Before anything allocates much: the scene's loading runs on a heap backed
  // by huge pages (page faults were 18% of a cold bunny render's CPU time).
  rayscope::use_huge_pages_for_heap();
  // VTK's readers print multi-line reports of a bad mesh file to standard
  // error; rayscope_vtkio::load_mesh() turns every failure into one exception naming the
  // file and the problem, printed below as the one error line.
  vtkOutputWindow::GetInstance()->SetDisplayModeToNever();
  vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
  CLI::App app{"RayScope: a Whitted ray tracer and ray-tree debugger for VTK data"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "rayscope 0.1.0");
  int exit_code = 0;
  rayscope::cli::add_render_command(app, exit_code);
  rayscope::cli::add_inspect_command(app, exit_code);
  rayscope::cli::add_query_command(app, exit_code);
  rayscope::cli::add_accel_command(app, exit_code);
#ifdef RAYSCOPE_HAVE_VIEWER
  rayscope::cli::add_view_command(app, exit_code);
#endif
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // One line, like every other error; --help tells the rest.
    std::fprintf(stderr, "rayscope: error: %s (see rayscope --help)\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    // Messages quote files' bytes: printable, and one line however long.
    std::fprintf(stderr, "rayscope: error: %s\n",
                 rayscope::printable_text(e.what(), rayscope::kMaxMessageBytes).c_str());
    return 1;
  }
  return exit_code;
}
