"""RayScope on several MPI ranks: every rank traces a share of the image over
the whole scene.

Run with ParaView's pvbatch under MPI, the plugin on PV_PLUGIN_PATH
(docs/paraview.md):

    PV_PLUGIN_PATH=build/paraview/install/lib/paraview-5.11/plugins/RayScope \\
      xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \\
        mpiexec -n 2 build/paraview/pvbatch examples/paraview_mpi.py -o mpi.png

ParaView hands each rank a piece of the Wavelet (so of its contour), and the
sphere and the floor to rank 0. Left: the RayScope view, the surfaces colored
by the rank that holds them (ParaView's Process Id Scalars): the contour's pieces on
both ranks cast shadows on the floor and on each other, whoever holds them.
Right: the Ray Trace filter's image of the same scene and camera, the tiles
rank 0 traced darkened (its "Process" array): the ranks' shares of the
tiles, handed out by estimated cost.
"""
import argparse

from paraview.simple import *
from paraview import servermanager as sm

ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
ap.add_argument("-o", "--output", default="paraview_mpi.png")
args = ap.parse_args()

W, H = 480, 480
ranks = sm.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions()
wavelet = Wavelet()
contour = Contour(Input=wavelet, ContourBy=["POINTS", "RTData"], Isosurfaces=[157.0])
ball = Sphere(Center=[-17, -4, 4], Radius=6, ThetaResolution=48, PhiResolution=24)
floor = Plane(Origin=[-40, -11, -30], Point1=[30, -11, -30], Point2=[-40, -11, 30])
scene = [ProcessIdScalars(Input=source) for source in (contour, ball, floor)]
camera = dict(CameraPosition=[-30.0, 38.0, 62.0], CameraFocalPoint=[-6.0, -3.0, 0.0],
              CameraViewUp=[0.0, 1.0, 0.0], CameraViewAngle=30.0)
background = [0.32, 0.34, 0.43]

layout = CreateLayout("RayScope on MPI ranks")
view = CreateView("RayScopeView")
AssignViewToLayout(view, layout)
view.ViewSize = [W, H]
view.OrientationAxesVisibility = 0
view.UseColorPaletteForBackground = 0
view.Background = background
view.Samples = 2
rank_colors = GetColorTransferFunction("ProcessId")
rank_colors.InterpretValuesAsCategories = 1
rank_colors.Annotations = [str(r) for r in range(ranks) for _ in (0, 1)]
rank_colors.IndexedColors = [0.95, 0.62, 0.25, 0.35, 0.62, 0.95, 0.55, 0.85, 0.45][:3 * ranks]
rank_colors.RescaleTransferFunction(0.0, max(1.0, ranks - 1.0))
for source in scene:
    shown = Show(source, view)
    ColorBy(shown, ("POINTS", "ProcessId"))
    shown.LookupTable = rank_colors
for k, v in camera.items():
    setattr(view, k, v)

# The Ray Trace filter with the view's camera; its Process array darkens the
# pixels rank 0 traced.
traced = RayTrace(Input=scene, ImageSize=[W, H], Samples=2, AutoCamera=0, Coloring="Color Array",
                  ColorArray=["POINTS", "ProcessId"], LookupTable=rank_colors,
                  Position=camera["CameraPosition"], FocalPoint=camera["CameraFocalPoint"],
                  ViewUp=camera["CameraViewUp"], ViewAngle=camera["CameraViewAngle"], Background=background)
tint = Calculator(Input=traced, ResultArrayName="Tinted", ResultArrayType="Unsigned Char",
                  Function="Color * (0.6 + 0.4 * Process)")
image_view = CreateView("RenderView")
AssignViewToLayout(image_view, layout, 2)
image_view.ViewSize = [W, H]
image_view.OrientationAxesVisibility = 0
image_view.InteractionMode = "2D"
shown = Show(tint, image_view)
ColorBy(shown, ("POINTS", "Tinted"))
shown.MapScalars = 0
image_view.ResetCamera()
image_view.CameraParallelScale = H / 2
SaveScreenshot(args.output, layout, ImageResolution=[2 * W, H])
print(f"{args.output}: written on {ranks} ranks")
