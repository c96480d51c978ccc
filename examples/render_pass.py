#!/usr/bin/python3
"""Switch an ordinary VTK application to ray tracing with renderer.SetPass().

The scene is plain VTK: actors, mappers coloring by scalars, vtkProperty
(opacity < 1 makes glass), vtkLights and the camera. Two extra properties tell
RayScope what vtkProperty lacks: reflectivity and index of refraction. The
left viewport is VTK's OpenGL rendering, the right one the same renderer
content ray-traced by vtkRayScopePass (hard shadows, reflection, refraction).

    PYTHONPATH=<build>/lib/python3/dist-packages xvfb-run -a /usr/bin/python3 \\
        examples/render_pass.py -o pass.png [--samples 2] [--interactive]

With --interactive (and a display) the window stays open: rotate the camera
and the right viewport is ray-traced again at every frame; the scene (and its
BVH) is kept between frames, only the camera changes.
"""
import argparse

import vtk
import rayscope


def build_actors():
    """The scene as any VTK application would build it."""
    actors = []
    # A dataset colored by scalars through its mapper's lookup table.
    torus = vtk.vtkParametricTorus()
    torus.SetRingRadius(0.7)
    torus.SetCrossSectionRadius(0.28)
    source = vtk.vtkParametricFunctionSource()
    source.SetParametricFunction(torus)
    source.SetUResolution(96)
    source.SetVResolution(48)
    elevation = vtk.vtkElevationFilter()
    elevation.SetInputConnection(source.GetOutputPort())
    elevation.SetLowPoint(-1, 0, 0)
    elevation.SetHighPoint(1, 0, 0)
    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputConnection(elevation.GetOutputPort())
    lut = vtk.vtkLookupTable()
    lut.SetHueRange(0.6, 0.0)
    lut.Build()
    mapper.SetLookupTable(lut)
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.RotateX(-62)  # the actor's matrix moves the geometry, as in OpenGL
    actor.SetPosition(0, 0.12, 0)
    actor.GetProperty().SetSpecular(0.4)
    actor.GetProperty().SetSpecularPower(40)
    actors.append(actor)

    # A glass sphere (opacity < 1 is a dielectric; index of refraction 1.5).
    ball = vtk.vtkSphereSource()
    ball.SetRadius(0.35)
    ball.SetThetaResolution(64)
    ball.SetPhiResolution(32)
    glass = vtk.vtkActor()
    glass.SetMapper(vtk.vtkPolyDataMapper())
    glass.GetMapper().SetInputConnection(ball.GetOutputPort())
    glass.SetPosition(1.25, -0.3, 0.6)
    glass.GetProperty().SetOpacity(0.1)
    rayscope.vtkRayScopeMaterial.SetPropertyIndexOfRefraction(glass.GetProperty(), 1.5)
    actors.append(glass)

    # A mirror-like floor.
    plane = vtk.vtkPlaneSource()
    plane.SetOrigin(-3, -0.65, 3)
    plane.SetPoint1(3, -0.65, 3)
    plane.SetPoint2(-3, -0.65, -3)
    floor = vtk.vtkActor()
    floor.SetMapper(vtk.vtkPolyDataMapper())
    floor.GetMapper().SetInputConnection(plane.GetOutputPort())
    floor.GetProperty().SetColor(0.8, 0.8, 0.85)
    rayscope.vtkRayScopeMaterial.SetPropertyReflectivity(floor.GetProperty(), 0.4)
    actors.append(floor)
    return actors


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", default="render_pass.png")
    ap.add_argument("--size", default="320x240", help="WIDTHxHEIGHT of each viewport")
    ap.add_argument("--samples", type=int, default=2, help="N for N x N samples per pixel")
    ap.add_argument("--interactive", action="store_true")
    args = ap.parse_args()
    width, height = (int(v) for v in args.size.split("x"))

    light = vtk.vtkLight()
    light.SetLightTypeToSceneLight()
    light.SetPositional(True)
    light.SetConeAngle(90)
    light.SetPosition(2.0, 3.5, 2.5)
    camera = vtk.vtkCamera()
    camera.SetPosition(0.6, 1.6, 4.6)
    camera.SetFocalPoint(0.15, -0.2, 0.0)
    camera.SetViewAngle(35)

    window = vtk.vtkRenderWindow()
    window.SetSize(2 * width, height)
    if not args.interactive:
        window.SetOffScreenRendering(1)
    for k in range(2):
        renderer = vtk.vtkRenderer()
        renderer.SetViewport(0.5 * k, 0, 0.5 * (k + 1), 1)
        for actor in build_actors():
            renderer.AddActor(actor)
        renderer.AddLight(light)
        renderer.SetActiveCamera(camera)  # both viewports share the camera
        renderer.SetBackground(0.12, 0.14, 0.2)
        if k == 1:
            # The one line that switches this renderer to ray tracing.
            rt_pass = rayscope.vtkRayScopePass()
            settings = rt_pass.GetImageAlgorithm()  # holds the render settings
            settings.SetSamples(args.samples)
            settings.SetMaxDepth(6)
            renderer.SetPass(rt_pass)
        window.AddRenderer(renderer)
    window.Render()
    print("ray-traced %dx%d with %dx%d samples in %.3f s" %
          (width, height, args.samples, args.samples, rt_pass.GetLastRenderTime()))

    if args.interactive:
        interactor = vtk.vtkRenderWindowInteractor()
        interactor.SetRenderWindow(window)
        interactor.SetInteractorStyle(vtk.vtkInteractorStyleTrackballCamera())
        interactor.Start()
        return
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.ReadFrontBufferOff()
    writer = vtk.vtkPNGWriter()
    writer.SetInputConnection(grab.GetOutputPort())
    writer.SetFileName(args.output)
    writer.Write()
    print("wrote", args.output)


if __name__ == "__main__":
    main()
