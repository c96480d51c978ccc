#!/usr/bin/python3
"""Overlay the ray tree of one pixel on the OpenGL view of the scene.

Left: the ray-traced image with the chosen pixel marked. Right: the scene drawn
by VTK's OpenGL renderer from a side camera, with every ray behind that pixel
as a tube colored by kind (RayScope's colors: primary yellow, shadow blue,
reflection green, refraction magenta), hit points as small spheres with their shading normals as
arrows, and occluded shadow rays ending at their occluder.

    PYTHONPATH=<build>/lib/python3/dist-packages xvfb-run -a /usr/bin/python3 \\
        examples/raytree_overlay.py -o overlay.png

Needs a display (OpenGL): use xvfb-run on a headless machine.
"""
import argparse
import os
import sys

import vtk
import rayscope

# The atomic PNG writer of the benchmark plots.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "bench"))
from plot_quality import save_window  # noqa: E402



def kind_color(kind):
    """RayScope's color of a ray kind (0 primary .. 3 refraction), as RGB in [0, 1]."""
    rgb = [0.0, 0.0, 0.0]
    rayscope.vtkRayScopeRayTreeSource.GetKindColor(kind, rgb)
    return rgb


def sphere(center, radius):
    s = vtk.vtkSphereSource()
    s.SetCenter(*center)
    s.SetRadius(radius)
    s.SetThetaResolution(64)
    s.SetPhiResolution(32)
    return s


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", default="raytree_overlay.png")
    ap.add_argument("--pixel", nargs=2, type=int, metavar=("I", "J"),
                    help="pixel in VTK image coordinates (default: on the glass sphere)")
    args = ap.parse_args()

    glass = sphere((-0.5, 0.0, 0.3), 0.5)
    mirror = sphere((0.75, -0.05, -0.4), 0.45)
    floor = vtk.vtkPlaneSource()
    floor.SetOrigin(-3, -0.5, 3)
    floor.SetPoint1(3, -0.5, 3)
    floor.SetPoint2(-3, -0.5, -3)
    sources = [glass, mirror, floor]

    tracer = rayscope.vtkRayScopeImageAlgorithm()
    for s in sources:
        tracer.AddInputConnection(s.GetOutputPort())
    for index, (name, values) in enumerate([
            ("glass", dict(Transparency=0.9, IndexOfRefraction=1.5, Diffuse=0.1)),
            ("mirror", dict(Reflectivity=0.7, Diffuse=0.3, Color=(1.0, 0.6, 0.5))),
            ("floor", dict(Reflectivity=0.2, Diffuse=0.8, Color=(0.7, 0.75, 0.8)))]):
        m = rayscope.vtkRayScopeMaterial()
        for key, value in values.items():
            getattr(m, "Set" + key)(*value) if isinstance(value, tuple) else \
                getattr(m, "Set" + key)(value)
        tracer.SetInputMaterial(index, m)
    tracer.SetPosition(0.0, 1.2, 4.0)
    tracer.SetFocalPoint(0.0, -0.1, 0.0)
    tracer.SetBackground(0.3, 0.35, 0.45)
    tracer.SetHeadlightIntensity(0.3)
    tracer.AddPointLight(2.0, 3.5, 2.5, 1.0, 1.0, 1.0, 0.9)
    tracer.SetSize(320, 240)
    tracer.SetSamples(2)
    tracer.Update()
    image = tracer.GetOutput()

    if args.pixel:
        i, j = args.pixel
    else:  # a pixel left of the glass sphere's center, where rays refract
        ids = image.GetPointData().GetArray("ObjectId")
        pix = [(k % 320, k // 320) for k in range(ids.GetNumberOfTuples()) if ids.GetValue(k) == 0]
        ci = sum(p[0] for p in pix) / len(pix)
        cj = sum(p[1] for p in pix) / len(pix)
        i, j = int(ci - 0.45 * (max(p[0] for p in pix) - ci)), int(cj + 5)
    tree = rayscope.vtkRayScopeRayTreeSource()
    tree.SetSceneSource(tracer)
    tree.SetPixel(i, j)
    tree.SetSample(0)
    tree.SetMissLength(2.0)  # rays that leave the scene: drawn 2 units long
    tree.Update()
    rays = tree.GetOutput()
    kinds = [rays.GetCellData().GetArray("Kind").GetValue(c)
             for c in range(rays.GetNumberOfVerts(), rays.GetNumberOfCells())]
    print(f"pixel ({i}, {j}): {len(kinds)} rays, " + ", ".join(
        f"{kinds.count(k)} {n}" for k, n in enumerate(("primary", "shadow", "reflection",
                                                      "refraction"))))

    # Right: the OpenGL view with the ray tree.
    scene_ren = vtk.vtkRenderer()
    scene_ren.SetViewport(0.5, 0.0, 1.0, 1.0)
    scene_ren.SetBackground(0.12, 0.12, 0.15)
    for s, color, opacity in ((glass, (0.8, 0.9, 1.0), 0.25), (mirror, (1.0, 0.6, 0.5), 1.0),
                              (floor, (0.7, 0.75, 0.8), 1.0)):
        mapper = vtk.vtkPolyDataMapper()
        mapper.SetInputConnection(s.GetOutputPort())
        actor = vtk.vtkActor()
        actor.SetMapper(mapper)
        actor.GetProperty().SetColor(*color)
        actor.GetProperty().SetOpacity(opacity)
        scene_ren.AddActor(actor)

    lut = vtk.vtkLookupTable()
    lut.SetNumberOfTableValues(4)
    for k in range(4):
        lut.SetTableValue(k, *kind_color(k), 1.0)
    lut.SetRange(0, 3)
    lines = vtk.vtkPolyData()
    lines.SetPoints(rays.GetPoints())
    lines.SetLines(rays.GetLines())
    kind = vtk.vtkIntArray()
    kind.SetName("Kind")
    for k in kinds:
        kind.InsertNextValue(k)
    lines.GetCellData().SetScalars(kind)
    tubes = vtk.vtkTubeFilter()
    tubes.SetInputData(lines)
    tubes.SetRadius(0.012)
    tubes.SetNumberOfSides(12)
    tube_mapper = vtk.vtkPolyDataMapper()
    tube_mapper.SetInputConnection(tubes.GetOutputPort())
    tube_mapper.SetLookupTable(lut)
    tube_mapper.SetScalarModeToUseCellData()
    tube_mapper.SetScalarRange(0, 3)
    tube_actor = vtk.vtkActor()
    tube_actor.SetMapper(tube_mapper)
    scene_ren.AddActor(tube_actor)

    # Hit points and their shading normals.
    hits = vtk.vtkPolyData()
    hits.SetPoints(rays.GetPoints())
    hits.SetVerts(rays.GetVerts())
    hits.GetPointData().SetNormals(rays.GetPointData().GetNormals())
    clean = vtk.vtkCleanPolyData()  # keep only the points the vertices use
    clean.SetInputData(hits)
    ball = vtk.vtkSphereSource()
    ball.SetRadius(0.035)
    balls = vtk.vtkGlyph3D()
    balls.SetInputConnection(clean.GetOutputPort())
    balls.SetSourceConnection(ball.GetOutputPort())
    balls.SetScaleModeToDataScalingOff()
    arrow = vtk.vtkArrowSource()
    arrows = vtk.vtkGlyph3D()
    arrows.SetInputConnection(clean.GetOutputPort())
    arrows.SetSourceConnection(arrow.GetOutputPort())
    arrows.SetVectorModeToUseNormal()
    arrows.SetScaleModeToDataScalingOff()
    arrows.SetScaleFactor(0.3)
    for glyphs, color in ((balls, (1.0, 0.25, 0.2)), (arrows, (0.3, 1.0, 0.4))):
        m = vtk.vtkPolyDataMapper()
        m.SetInputConnection(glyphs.GetOutputPort())
        m.ScalarVisibilityOff()
        a = vtk.vtkActor()
        a.SetMapper(m)
        a.GetProperty().SetColor(*color)
        scene_ren.AddActor(a)
    cam = scene_ren.GetActiveCamera()
    cam.SetPosition(4.6, 2.6, 5.6)
    cam.SetFocalPoint(-0.4, 0.3, 1.3)
    cam.SetViewUp(0, 1, 0)
    cam.SetViewAngle(24)
    scene_ren.ResetCameraClippingRange()
    legend = vtk.vtkTextActor()
    legend.SetInput("rays: primary yellow, shadow blue,\nreflection green, refraction magenta;\nhits red, normals green")
    legend.GetTextProperty().SetFontSize(15)
    legend.SetPosition(8, 8)
    scene_ren.AddViewProp(legend)

    # Left: the ray-traced image, the pixel marked by a red square.
    image_ren = vtk.vtkRenderer()
    image_ren.SetViewport(0.0, 0.0, 0.5, 1.0)
    image_actor = vtk.vtkImageActor()
    image_actor.GetMapper().SetInputData(image)
    image_ren.AddActor(image_actor)
    marker = vtk.vtkCubeSource()
    marker.SetBounds(i - 3, i + 3, j - 3, j + 3, 0.5, 0.5)
    outline = vtk.vtkOutlineFilter()
    outline.SetInputConnection(marker.GetOutputPort())
    mm = vtk.vtkPolyDataMapper()
    mm.SetInputConnection(outline.GetOutputPort())
    ma = vtk.vtkActor()
    ma.SetMapper(mm)
    ma.GetProperty().SetColor(1, 0.1, 0.1)
    ma.GetProperty().SetLineWidth(2)
    image_ren.AddActor(ma)
    image_ren.ResetCamera()
    image_ren.GetActiveCamera().ParallelProjectionOn()
    image_ren.GetActiveCamera().SetParallelScale(121)
    caption = vtk.vtkTextActor()
    caption.SetInput(f"ray-traced, pixel ({i}, {j})")
    caption.GetTextProperty().SetFontSize(15)
    caption.SetPosition(8, 8)
    image_ren.AddViewProp(caption)

    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(960, 360)
    window.SetMultiSamples(8)
    window.AddRenderer(image_ren)
    window.AddRenderer(scene_ren)
    save_window(window, args.output)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
