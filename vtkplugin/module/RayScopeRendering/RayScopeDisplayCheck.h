// Whether a render window can be shown: an on-screen X window needs an X
// server to connect to. VTK 9.1's X interactor dereferences a null display
// when there is none, so the viewer connects first and says what is missing.
#pragma once

#include <string>

class vtkRenderWindow;

namespace rayscope_vtkmodule {

/// Empty when `window` can open: it draws off screen, is not an X window, or
/// an X server answers, in which case the window is given that connection
/// (one per process, kept open: closing the only client's connection makes
/// a server started without -noreset, as xvfb-run starts it, reset and
/// refuse the window's own connection for a moment). Else one sentence
/// naming the missing display and how to get one.
std::string connect_display(vtkRenderWindow* window);

}  // namespace rayscope_vtkmodule
