#!/usr/bin/python3
"""Show a BVH level by level: one OpenGL viewport per level, the mesh in gray
and the boxes of that level colored by how often the rays of the whole frame
visited them (blue: rarely, red: often).

    PYTHONPATH=<build>/lib/python3/dist-packages xvfb-run -a /usr/bin/python3 \\
        examples/bvh_levels.py -o bvh.png --levels 0 5

The mesh is the Stanford bunny of Debian's glmark2-data when installed, else a
superquadric. Needs a display (OpenGL): use xvfb-run on a headless machine.
"""
import argparse
import os
import sys

import vtk
import rayscope

# The atomic PNG writer of the benchmark plots.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "bench"))
from plot_quality import save_window  # noqa: E402

BUNNY = "/usr/share/glmark2/models/bunny.obj"


def dataset():
    if os.path.exists(BUNNY):
        reader = vtk.vtkOBJReader()
        reader.SetFileName(BUNNY)
        return reader
    sq = vtk.vtkSuperquadricSource()
    sq.SetThetaResolution(64)
    sq.SetPhiResolution(64)
    sq.SetThetaRoundness(0.3)
    sq.SetPhiRoundness(1.5)
    return sq


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", default="bvh_levels.png")
    ap.add_argument("--levels", nargs=2, type=int, default=(0, 5), metavar=("FIRST", "LAST"))
    ap.add_argument("--size", type=int, default=300, help="viewport size in pixels")
    args = ap.parse_args()
    first, last = args.levels

    source = dataset()
    # The scene: the dataset seen by a camera fitted to it (the visit counts
    # come from ray tracing a 160x120 image from that camera).
    tracer = rayscope.vtkRayScopeImageAlgorithm()
    tracer.AddInputConnection(source.GetOutputPort())
    tracer.SetSize(160, 120)
    tracer.SetPosition(0.3, 0.4, 1.0)
    tracer.ResetCamera()

    bvh = rayscope.vtkRayScopeAccelSource()
    bvh.SetSceneSource(tracer)
    bvh.SetVisitModeToFrame()

    levels = list(range(first, last + 1))
    cols = min(3, len(levels))
    rows = (len(levels) + cols - 1) // cols
    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(cols * args.size, rows * args.size)
    camera = vtk.vtkCamera()
    camera.SetPosition(tracer.GetPosition())
    camera.SetFocalPoint(tracer.GetFocalPoint())
    camera.SetViewUp(tracer.GetViewUp())
    camera.SetViewAngle(tracer.GetViewAngle())

    mesh_mapper = vtk.vtkPolyDataMapper()
    mesh_mapper.SetInputConnection(source.GetOutputPort())
    mesh_mapper.ScalarVisibilityOff()
    for k, level in enumerate(levels):
        boxes = rayscope.vtkRayScopeAccelSource()
        boxes.SetSceneSource(tracer)
        boxes.SetVisitModeToFrame()
        boxes.SetLevelRange(level, level)
        boxes.Update()
        out = boxes.GetOutput()
        visits = out.GetCellData().GetArray("VisitCount")
        mapper = vtk.vtkPolyDataMapper()
        mapper.SetInputData(out)
        mapper.SetScalarModeToUseCellFieldData()
        mapper.SelectColorArray("VisitCount")
        mapper.SetScalarRange(visits.GetRange() if visits.GetNumberOfTuples() else (0, 1))
        lut = vtk.vtkLookupTable()
        lut.SetHueRange(0.66, 0.0)
        lut.Build()
        mapper.SetLookupTable(lut)
        box_actor = vtk.vtkActor()
        box_actor.SetMapper(mapper)
        box_actor.GetProperty().SetLineWidth(1.5)
        box_actor.GetProperty().LightingOff()
        mesh_actor = vtk.vtkActor()
        mesh_actor.SetMapper(mesh_mapper)
        mesh_actor.GetProperty().SetColor(0.75, 0.75, 0.75)
        mesh_actor.GetProperty().SetOpacity(0.35)

        ren = vtk.vtkRenderer()
        r, c = divmod(k, cols)
        ren.SetViewport(c / cols, 1 - (r + 1) / rows, (c + 1) / cols, 1 - r / rows)
        ren.SetBackground(0.12, 0.12, 0.15)
        ren.AddActor(mesh_actor)
        ren.AddActor(box_actor)
        ren.SetActiveCamera(camera)
        text = vtk.vtkTextActor()
        n = out.GetNumberOfCells() // 12
        text.SetInput(f"level {level}: {n} box" + ("es" if n != 1 else ""))
        text.GetTextProperty().SetFontSize(16)
        text.SetPosition(8, 8)
        ren.AddViewProp(text)
        window.AddRenderer(ren)
        print(f"level {level}: {out.GetNumberOfCells() // 12} boxes, "
              f"visits {int(visits.GetRange()[1]) if visits.GetNumberOfTuples() else 0} max")
    window.GetRenderers().GetFirstRenderer().ResetCameraClippingRange()
    for ren in window.GetRenderers():
        ren.ResetCameraClippingRange()
    save_window(window, args.output)
    bvh.SetLevelRange(0, 1000)
    bvh.Update()
    print(f"wrote {args.output}; the hierarchy has "
          f"{int(bvh.GetOutput().GetFieldData().GetArray('TreeDepth').GetValue(0))} levels, "
          f"SAH cost {bvh.GetOutput().GetFieldData().GetArray('SAHCostTotal').GetValue(0):.1f}")


if __name__ == "__main__":
    main()
