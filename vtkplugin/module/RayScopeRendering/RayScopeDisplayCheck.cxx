#include "RayScopeDisplayCheck.h"

#include <cstdlib>

#include <vtkRenderWindow.h>

#if defined(RAYSCOPE_VIEWER_X11)
#include <X11/Xlib.h>
#endif

namespace rayscope_vtkmodule {

std::string connect_display(vtkRenderWindow* window) {
#if defined(RAYSCOPE_VIEWER_X11)
  if (window->GetOffScreenRendering() || !window->IsA("vtkXOpenGLRenderWindow")) return {};
  static Display* const display = XOpenDisplay(nullptr);
  if (display) {
    window->SetDisplayId(display);
    return {};
  }
  const char* name = std::getenv("DISPLAY");
  const std::string which = name && *name
                                ? "the X display '" + std::string(name) + "' does not answer"
                                : "no X display is set (DISPLAY is empty)";
  return "the viewer needs a display to open its window, and " + which +
         ": run it on a desktop, or under `xvfb-run -a` for a virtual one";
#else
  (void)window;
  return {};
#endif
}

}  // namespace rayscope_vtkmodule
