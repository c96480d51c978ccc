"""Frame times of the RayScope view against ParaView's OpenGL Render View, on
the same data in the same run (issue: the view while interacting).

Run with ParaView's pvpython and the plugin on PV_PLUGIN_PATH:

    PV_PLUGIN_PATH=$PWD/build/paraview/install/lib/paraview-5.11/plugins/RayScope \\
      xvfb-run -a -s "-screen 0 1920x1080x24 -noreset" build/paraview/pvpython --dr \\
        bench/paraview_view_frames.py [--size 1280x720] [--frames 12] [--mesh bunny.obj] \\
        [--samples 2]

Both views show the mesh (the Stanford bunny from glmark2-data by default)
over a floor, lit by ParaView's light kit, at the same size and camera. The
camera turns by 3 degrees per frame; each frame is an interactive render
(what ParaView does while the mouse drags; the RayScope view traces 1 sample
per pixel then, shadows on) and, separately, a still render. Frames of the
two views alternate; the median of each is reported, and the ratio.
"""
import argparse
import statistics
import time

from paraview.simple import *

ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
ap.add_argument("--size", default="1280x720")
ap.add_argument("--frames", type=int, default=12)
ap.add_argument("--mesh", default="/usr/share/glmark2/models/bunny.obj")
ap.add_argument("--samples", type=int, default=2,
                help="N: a still render of the RayScope view traces N x N samples per pixel")
args = ap.parse_args()
W, H = (int(v) for v in args.size.split("x"))

mesh = OpenDataFile(args.mesh)
bounds = mesh.GetDataInformation().GetBounds()
cx, cy, cz = ((bounds[2 * a] + bounds[2 * a + 1]) / 2 for a in range(3))
size = max(bounds[2 * a + 1] - bounds[2 * a] for a in range(3))
floor = Plane(Origin=[cx - size, bounds[2], cz - size], Point1=[cx + size, bounds[2], cz - size],
              Point2=[cx - size, bounds[2], cz + size])

views = {}
for kind in ("RenderView", "RayScopeView"):
    view = CreateView(kind)
    view.ViewSize = [W, H]
    view.OrientationAxesVisibility = 0
    Show(mesh, view)
    Show(floor, view)
    view.CameraPosition = [cx + 1.2 * size, cy + 0.8 * size, cz + 2.0 * size]
    view.CameraFocalPoint = [cx, cy, cz]
    view.CameraViewUp = [0, 1, 0]
    Render(view)  # builds the scene (the RayScope view: conversion and structure)
    views[kind] = view
views["RayScopeView"].Shadows = 1
views["RayScopeView"].Samples = args.samples
# A still render traces all N x N samples at once (with Refine Progressively,
# the default, the first still render after a move would trace one of them).
views["RayScopeView"].RefineProgressively = 0


def traced(view):
    """The RayScope view's last trace: (samples, seconds)."""
    view.UpdatePropertyInformation()
    return view.GetPropertyValue("TracedSamples"), view.GetPropertyValue("LastRenderSeconds")


times = {(k, m): [] for k in views for m in ("interactive", "still")}
trace = {"interactive": [], "still": []}
for frame in range(args.frames):
    for kind, view in views.items():
        view.GetActiveCamera().Azimuth(3.0)
        for mode in ("interactive", "still"):
            t = time.perf_counter()
            if mode == "interactive":
                view.SMProxy.InteractiveRender()
            else:
                view.StillRender()
            times[(kind, mode)].append(time.perf_counter() - t)
            if kind == "RayScopeView":
                samples, seconds = traced(view)
                assert samples == (1 if mode == "interactive" else view.Samples), samples
                trace[mode].append(seconds)

print(f"{args.mesh} over a floor, {W}x{H}, {args.frames} frames per view, median ms")
for mode in ("interactive", "still"):
    gl = statistics.median(times[("RenderView", mode)]) * 1e3
    rs = statistics.median(times[("RayScopeView", mode)]) * 1e3
    traced_ms = statistics.median(trace[mode]) * 1e3
    print(f"{mode:12s} OpenGL {gl:8.1f}  RayScope {rs:8.1f} (its trace {traced_ms:6.1f})"
          f"  RayScope/OpenGL {rs / gl:6.2f}")
