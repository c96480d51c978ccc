#!/usr/bin/python3
"""Ray-trace lines as tubes and points as spheres, with their shadows.

Left: streamlines (vtkStreamTracer polylines through the gradient of VTK's
Wavelet) colored by the field through a lookup table, drawn as tubes over a
floor. Right: a point cloud (vtkPointSource vertices) colored by elevation,
drawn as spheres over the same floor. A point light above casts the shadows;
the radius of the tubes and spheres is the image algorithm's LineRadius and
PointRadius (0 would size them automatically from the data, as VTK's OSPRay
pass does).

    PYTHONPATH=<build>/lib/python3/dist-packages /usr/bin/python3 \\
        examples/lines_and_points.py -o lines_and_points.png --size 400x300

Needs no display: ray tracing does not use OpenGL.
"""
import argparse

import vtk
import rayscope


def floor_below(bounds, margin=0.6):
    """A floor under the bounds, larger than them by `margin` of their size."""
    dx, dz = bounds[1] - bounds[0], bounds[5] - bounds[4]
    floor = vtk.vtkPlaneSource()
    y = bounds[2] - 0.15 * (bounds[3] - bounds[2])
    floor.SetOrigin(bounds[0] - margin * dx, y, bounds[5] + margin * dz)
    floor.SetPoint1(bounds[1] + margin * dx, y, bounds[5] + margin * dz)
    floor.SetPoint2(bounds[0] - margin * dx, y, bounds[4] - margin * dz)
    return floor


def trace(data, floor, width, height, samples, line_radius, point_radius):
    """The image of `data` over `floor`, seen from the front, above and right."""
    tracer = rayscope.vtkRayScopeImageAlgorithm()
    tracer.AddInputConnection(data.GetOutputPort())
    tracer.AddInputConnection(floor.GetOutputPort())
    floor_material = rayscope.vtkRayScopeMaterial()
    floor_material.SetColor(0.85, 0.82, 0.75)
    tracer.SetInputMaterial(1, floor_material)
    tracer.SetLineRadius(line_radius)
    tracer.SetPointRadius(point_radius)
    b = data.GetOutput().GetBounds()
    center = [(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2]
    size = max(b[1] - b[0], b[3] - b[2], b[5] - b[4])
    tracer.SetSize(width, height)
    tracer.SetSamples(samples)
    tracer.SetFocalPoint(*center)
    tracer.SetPosition(center[0] + 0.6 * size, center[1] + 0.9 * size, center[2] + 1.6 * size)
    tracer.SetViewAngle(38.0)
    tracer.SetHeadlightIntensity(0.4)
    tracer.AddPointLight(center[0] - 0.5 * size, center[1] + 2.5 * size, center[2] + 0.5 * size,
                         1.0, 1.0, 1.0, 0.8)
    tracer.SetBackground(0.12, 0.14, 0.18)
    tracer.Update()
    return tracer


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", default="lines_and_points.png")
    ap.add_argument("--size", default="400x300", help="WIDTHxHEIGHT of each half")
    ap.add_argument("--samples", type=int, default=2, help="N for N x N samples per pixel")
    args = ap.parse_args()
    width, height = (int(v) for v in args.size.split("x"))

    # Streamlines: the gradient of the Wavelet, from seeds on a small sphere.
    wavelet = vtk.vtkRTAnalyticSource()
    wavelet.SetWholeExtent(-10, 10, -10, 10, -10, 10)
    gradient = vtk.vtkGradientFilter()
    gradient.SetInputConnection(wavelet.GetOutputPort())
    gradient.SetInputArrayToProcess(0, 0, 0, vtk.vtkDataObject.FIELD_ASSOCIATION_POINTS, "RTData")
    gradient.SetResultArrayName("Gradient")
    seeds = vtk.vtkPointSource()
    seeds.SetCenter(0.0, 0.0, 0.0)
    seeds.SetRadius(4.0)
    seeds.SetNumberOfPoints(60)
    seeds.SetRandomSequence(vtk.vtkMinimalStandardRandomSequence())
    streamlines = vtk.vtkStreamTracer()
    streamlines.SetInputConnection(gradient.GetOutputPort())
    streamlines.SetSourceConnection(seeds.GetOutputPort())
    streamlines.SetInputArrayToProcess(0, 0, 0, vtk.vtkDataObject.FIELD_ASSOCIATION_POINTS,
                                       "Gradient")
    streamlines.SetIntegrationDirectionToBoth()
    streamlines.SetMaximumPropagation(30.0)
    streamlines.Update()
    lines = trace(streamlines, floor_below(streamlines.GetOutput().GetBounds()), width, height,
                  args.samples, line_radius=0.12, point_radius=0.0)
    lines.GetConverter().GetMapper().SetScalarRange(streamlines.GetOutput().GetPointData()
                                                    .GetArray("RTData").GetRange())
    lines.GetConverter().GetMapper().SelectColorArray("RTData")
    lines.GetConverter().GetMapper().SetScalarModeToUsePointFieldData()
    lines.Update()

    # A point cloud: random points in a ball, colored by height.
    cloud = vtk.vtkPointSource()
    cloud.SetRadius(1.0)
    cloud.SetNumberOfPoints(400)
    cloud.SetRandomSequence(vtk.vtkMinimalStandardRandomSequence())
    colored = vtk.vtkElevationFilter()
    colored.SetInputConnection(cloud.GetOutputPort())
    colored.SetLowPoint(0, -1, 0)
    colored.SetHighPoint(0, 1, 0)
    colored.Update()
    points = trace(colored, floor_below(colored.GetOutput().GetBounds()), width, height,
                   args.samples, line_radius=0.0, point_radius=0.05)

    both = vtk.vtkImageAppend()
    both.SetAppendAxis(0)
    both.AddInputConnection(lines.GetOutputPort())
    both.AddInputConnection(points.GetOutputPort())
    writer = vtk.vtkPNGWriter()
    writer.SetFileName(args.output)
    writer.SetInputConnection(both.GetOutputPort())
    writer.Write()
    segments = sum(max(0, streamlines.GetOutput().GetCell(c).GetNumberOfPoints() - 1)
                   for c in range(streamlines.GetOutput().GetNumberOfCells()))
    print(f"{streamlines.GetOutput().GetNumberOfLines()} streamlines ({segments} tube segments), "
          f"{colored.GetOutput().GetNumberOfPoints()} points as spheres")
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
