"""The RayScope view as the ParaView test scripts make it (run by pvpython or
pvbatch, which import it from this folder)."""
from paraview.simple import CreateView


def new_view(size, background, samples=2):
    """A RayScope view of `size` (width, height) pixels on a plain `background`
    (no color palette, no orientation axes), tracing `samples` x `samples`
    per pixel on still renders."""
    view = CreateView("RayScopeView")
    view.ViewSize = list(size)
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.Background = list(background)
    view.Samples = samples
    return view
