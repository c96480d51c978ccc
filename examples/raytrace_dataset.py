#!/usr/bin/python3
"""Ray-trace a VTK dataset to a PNG file.

A superquadric torus colored by elevation through a lookup table (exactly the
colors a vtkPolyDataMapper would show), a mirror sphere and a glass sphere on a
reflective floor, lit by the headlight and a point light with hard shadows.

    PYTHONPATH=<build>/lib/python3/dist-packages /usr/bin/python3 \\
        examples/raytrace_dataset.py -o torus.png --size 640x480 --samples 3

Needs no display: ray tracing does not use OpenGL.
"""
import argparse

import vtk
import rayscope


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", default="raytraced.png")
    ap.add_argument("--size", default="480x360", help="WIDTHxHEIGHT")
    ap.add_argument("--samples", type=int, default=2, help="N for N x N samples per pixel")
    args = ap.parse_args()
    width, height = (int(v) for v in args.size.split("x"))

    # The dataset: any vtkDataSet works (polydata, unstructured grids, ...).
    torus = vtk.vtkSuperquadricSource()
    torus.ToroidalOn()
    torus.SetThetaResolution(96)
    torus.SetPhiResolution(48)
    torus.SetThetaRoundness(0.4)
    torus.SetPhiRoundness(0.8)
    torus.SetScale(0.9, 0.9, 0.9)
    torus.SetCenter(0.0, 0.15, 0.0)
    elevation = vtk.vtkElevationFilter()
    elevation.SetInputConnection(torus.GetOutputPort())
    elevation.SetLowPoint(-0.9, 0, 0)
    elevation.SetHighPoint(0.9, 0, 0)

    mirror = vtk.vtkSphereSource()
    mirror.SetCenter(1.3, -0.05, -0.9)
    mirror.SetRadius(0.45)
    mirror.SetThetaResolution(64)
    mirror.SetPhiResolution(32)
    glass = vtk.vtkSphereSource()
    glass.SetCenter(-1.2, -0.1, 0.9)
    glass.SetRadius(0.4)
    glass.SetThetaResolution(64)
    glass.SetPhiResolution(32)
    floor = vtk.vtkPlaneSource()
    floor.SetOrigin(-4, -0.5, 4)
    floor.SetPoint1(4, -0.5, 4)
    floor.SetPoint2(-4, -0.5, -4)

    tracer = rayscope.vtkRayScopeImageAlgorithm()
    for source in (elevation, mirror, glass, floor):
        tracer.AddInputConnection(source.GetOutputPort())

    # Scalars are colored as by a mapper: configure the converter's mapper.
    lut = vtk.vtkLookupTable()
    lut.SetHueRange(0.66, 0.0)
    lut.Build()
    mapper = tracer.GetConverter().GetMapper()
    mapper.SetLookupTable(lut)
    mapper.SetScalarRange(0.0, 1.0)

    tracer.GetMaterial().SetAmbient(0.1)
    tracer.GetMaterial().SetDiffuse(0.9)
    tracer.GetMaterial().SetSpecular(0.3)
    tracer.GetMaterial().SetSpecularPower(40)
    materials = {1: dict(Color=(0.9, 0.9, 0.95), Reflectivity=0.8, Diffuse=0.2),
                 2: dict(Transparency=0.95, IndexOfRefraction=1.5, Diffuse=0.05),
                 3: dict(Color=(0.75, 0.7, 0.6), Reflectivity=0.25, Ambient=0.1, Diffuse=0.75)}
    for index, values in materials.items():
        m = rayscope.vtkRayScopeMaterial()
        for name, value in values.items():
            setter = getattr(m, "Set" + name)
            setter(*value) if isinstance(value, tuple) else setter(value)
        tracer.SetInputMaterial(index, m)

    tracer.SetPosition(0.0, 1.6, 4.8)
    tracer.SetFocalPoint(0.0, 0.0, 0.0)
    tracer.SetViewAngle(35)
    tracer.SetBackground(0.25, 0.3, 0.4)
    tracer.SetHeadlightIntensity(0.4)
    tracer.AddPointLight(3.0, 5.0, 4.0, 1.0, 1.0, 1.0, 0.8)
    tracer.SetSize(width, height)
    tracer.SetSamples(args.samples)
    tracer.SetMaxDepth(6)
    tracer.AddObserver("ProgressEvent",
                       lambda o, e: print(f"\rrendering {100 * o.GetProgress():3.0f}%", end=""))
    tracer.Update()
    print()

    writer = vtk.vtkPNGWriter()  # writes the active "Color" array (8-bit sRGB)
    writer.SetFileName(args.output)
    writer.SetInputConnection(tracer.GetOutputPort())
    writer.Write()
    rays = tracer.GetOutput().GetFieldData().GetArray("RayCounts").GetTuple(0)
    print(f"wrote {args.output}: {width}x{height}, {int(sum(rays))} rays "
          f"(primary {int(rays[0])}, shadow {int(rays[1])}, reflection {int(rays[2])}, "
          f"refraction {int(rays[3])})")


if __name__ == "__main__":
    main()
