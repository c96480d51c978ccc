"""RayScope in ParaView's own render view: CreateView('RayScopeView').

Run with ParaView's pvpython, the plugin on PV_PLUGIN_PATH (docs/paraview.md):

    PV_PLUGIN_PATH=build/paraview/install/lib/paraview-5.11/plugins/RayScope \\
      xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" build/paraview/pvpython \\
        examples/paraview_view.py -o view.png

ParaView's Wavelet contoured at one value and colored by elevation through a
lookup table, a red sphere beside it and a floor under both, shown in a
RayScope view: ParaView's representations, lights and camera, ray-traced with
hard shadows. Left: ParaView's OpenGL Render View of the same
representations; right: the RayScope view.
"""
import argparse

from paraview.simple import *

ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
ap.add_argument("-o", "--output", default="paraview_view.png")
ap.add_argument("--samples", type=int, default=2, help="N: N x N samples per pixel")
args = ap.parse_args()

W, H = 480, 480
wavelet = Wavelet()
contour = Contour(Input=wavelet, ContourBy=["POINTS", "RTData"], Isosurfaces=[157.0])
elevation = Elevation(Input=contour, LowPoint=[0, -10, 0], HighPoint=[0, 10, 0])
ball = Sphere(Center=[-17, -4, 4], Radius=6, ThetaResolution=48, PhiResolution=24)
floor = Plane(Origin=[-40, -11, -30], Point1=[30, -11, -30], Point2=[-40, -11, 30])

layout = CreateLayout("RayScope")
views = []
for kind in ("RenderView", "RayScopeView"):
    view = CreateView(kind)
    AssignViewToLayout(view, layout)
    view.ViewSize = [W, H]
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.Background = [0.32, 0.34, 0.43]
    shown = Show(elevation, view)
    ColorBy(shown, ("POINTS", "Elevation"))
    for source, color in ((ball, [0.85, 0.15, 0.1]), (floor, [0.8, 0.8, 0.75])):
        d = Show(source, view)
        d.ColorArrayName = ["POINTS", ""]
        d.DiffuseColor = color
        d.AmbientColor = color
    view.CameraPosition = [30, 40, 75]
    view.CameraFocalPoint = [-4, -3, 0]
    view.CameraViewUp = [0, 1, 0]
    view.CameraViewAngle = 30
    views.append(view)
GetColorTransferFunction("Elevation").ApplyPreset("Rainbow Uniform", True)
views[1].Samples = args.samples
SaveScreenshot(args.output, layout, ImageResolution=[2 * W, H])
print(f"wrote {args.output} ({2 * W}x{H})")
