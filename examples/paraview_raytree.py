"""RayScope in ParaView: the ray tree of one pixel over the data, and the image.

Run with ParaView's pvpython, the plugin on PV_PLUGIN_PATH (docs/paraview.md):

    PV_PLUGIN_PATH=build/paraview/install/lib/paraview-5.11/plugins/RayScope \\
      xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" build/paraview/pvpython \\
        examples/paraview_raytree.py -o raytree.png

The scene is ParaView's Wavelet contoured at one value (a closed surface)
with a glass Sphere in front of it. Left: a render view with the contour
(translucent), the sphere and the ray tree of one pixel, rays colored by kind
in RayScope's one palette (the tree's KindColor array), hit points as spheres. Right: the
"Ray Trace" image of the same scene, with that pixel marked.
"""
import argparse

from paraview.simple import *

ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
ap.add_argument("-o", "--output", default="paraview_raytree.png")
ap.add_argument("--pixel", type=int, nargs=2, default=[150, 118],
                help="pixel of the ray-traced image, (0, 0) bottom-left")
args = ap.parse_args()

W, H = 320, 240
wavelet = Wavelet()
surface = Contour(Input=wavelet, ContourBy=["POINTS", "RTData"], Isosurfaces=[157.0])
glass = Sphere(Center=[0, 0, 14], Radius=4, ThetaResolution=48, PhiResolution=24)

# One set of scene settings for the image and the tree: the camera fitted to
# the data, looking down -z; a point light above; glass-like material.
settings = dict(ImageSize=[W, H], Samples=1, MaxDepth=4, Headlight=0,
                Lights=[0, 10, 30, 40, 1, 1, 1, 1.0], AmbientLight=[1, 1, 1], Ambient=0.1,
                Diffuse=0.6, Specular=0.4, SpecularPower=40, Reflectivity=0.2,
                Transparency=0.6, IndexOfRefraction=1.5, Background=[0.1, 0.1, 0.15])
image = RayTrace(Input=[surface, glass], **settings)
tree = RayTree(Input=[surface, glass], Pixel=args.pixel, **settings)

layout = CreateLayout("RayScope")
layout.SplitHorizontal(0, 0.6)
view = CreateView("RenderView")
AssignViewToLayout(view=view, layout=layout, hint=1)
view.OrientationAxesVisibility = 0
view.Background = [1, 1, 1]
view.UseColorPaletteForBackground = 0

shown = Show(surface, view)
shown.Opacity = 0.35
shown.ColorArrayName = ["POINTS", ""]
shown.DiffuseColor = [0.75, 0.75, 0.8]
glass_shown = Show(glass, view)
glass_shown.ColorArrayName = ["POINTS", ""]
glass_shown.Opacity = 0.3
glass_shown.DiffuseColor = [0.6, 0.8, 1.0]

rays = Show(tree, view)
rays.LineWidth = 4
rays.RenderLinesAsTubes = 1
# Each ray in its kind's color as the tree carries it (KindColor: RayScope's
# one palette, the viewer's too), shown as it is rather than mapped.
ColorBy(rays, ("CELLS", "KindColor"))
rays.MapScalars = 0
key = Text(Text="rays: primary yellow, shadow blue, reflection green, refraction magenta")
key_shown = Show(key, view)
key_shown.WindowLocation = "Upper Left Corner"
key_shown.FontSize = 12
key_shown.Color = [0, 0, 0]

hits = Glyph(Input=tree, GlyphType="Sphere", ScaleArray=["POINTS", "No scale array"],
             ScaleFactor=0.6, GlyphMode="All Points")
hit_shown = Show(hits, view)
hit_shown.ColorArrayName = ["POINTS", ""]
hit_shown.DiffuseColor = [0.8, 0.1, 0.1]

view.CameraPosition = [-62, 28, 68]
view.CameraFocalPoint = [0, 0, 5]
view.CameraViewUp = [0, 1, 0]
view.CameraViewAngle = 30

# The ray-traced image, in a second view beside the first, with the pixel marked.
image_view = CreateView("RenderView")
AssignViewToLayout(view=image_view, layout=layout, hint=2)
image_view.OrientationAxesVisibility = 0
image_view.InteractionMode = "2D"
image_view.Background = [1, 1, 1]
image_view.UseColorPaletteForBackground = 0
picture = Show(image, image_view)  # in its own colors: the plugin's default display
picture.SetRepresentationType("Slice")
marker = Box(Center=[args.pixel[0], args.pixel[1], 0.5], XLength=9, YLength=9, ZLength=1)
marker_shown = Show(marker, image_view)
marker_shown.SetRepresentationType("Wireframe")
marker_shown.AmbientColor = marker_shown.DiffuseColor = [1, 0, 0]
marker_shown.LineWidth = 2
ResetCamera(image_view)
image_view.CameraParallelScale = 0.55 * W * 480 / (0.4 * 960)  # the image fills the view's width

layout.SetSize(960, 480)
SaveScreenshot(args.output, layout, ImageResolution=[960, 480])
tree.UpdatePipeline()
n = tree.GetDataInformation().GetNumberOfCells()
print(f"wrote {args.output}: the ray tree of pixel {tuple(args.pixel)} ({n} cells) over the data")
