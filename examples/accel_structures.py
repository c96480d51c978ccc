#!/usr/bin/python3
"""Show the acceleration structures side by side on one mesh: one OpenGL
viewport per structure, the mesh in gray and the structure's leaves (BVH
leaves, kD-tree, grid and octree cells, bounding spheres) colored by how often
the rays of the whole frame visited them (blue: rarely, red: often); for the
BSP tree, its split planes of the top levels, clipped to their cells.

    PYTHONPATH=<build>/lib/python3/dist-packages xvfb-run -a /usr/bin/python3 \\
        examples/accel_structures.py -o structures.png \\
        --structures bvh,kdtree,grid,octree,bsp/split,spheres

The mesh is the Stanford bunny of Debian's glmark2-data when installed, else a
superquadric, simplified to about --triangles triangles so that the cells stay
big enough to see. Each viewport names its structure and counts its leaves,
and the numbers are printed too. Needs a display (OpenGL): use xvfb-run on a
headless machine.
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
ALG = rayscope.vtkRayScopeImageAlgorithm


def dataset(triangles):
    if os.path.exists(BUNNY):
        source = vtk.vtkOBJReader()
        source.SetFileName(BUNNY)
    else:
        source = vtk.vtkSuperquadricSource()
        source.SetThetaResolution(96)
        source.SetPhiResolution(96)
        source.SetThetaRoundness(0.3)
        source.SetPhiRoundness(1.5)
    tri = vtk.vtkTriangleFilter()
    tri.SetInputConnection(source.GetOutputPort())
    tri.Update()
    n = tri.GetOutput().GetNumberOfPolys()
    if n <= triangles:
        return tri
    dec = vtk.vtkQuadricDecimation()
    dec.SetInputConnection(tri.GetOutputPort())
    dec.SetTargetReduction(1.0 - triangles / n)
    return dec


# The BSP tree is drawn by its split planes (convex polygons clipped to their
# cells) of this many top levels: deeper ones are too small to see.
BSP_PLANE_LEVELS = 6


def bsp_planes(source, levels):
    """The split polygons of the BSP tree's top `levels` levels, with their
    VisitCount and NodeId: the structure source draws every node's cell box
    as lines and then each inner node's plane as a polygon."""
    source.OnlyLeavesOff()
    source.SetLevelRange(0, levels - 1)
    source.Update()
    full = source.GetOutput()
    planes = vtk.vtkPolyData()
    planes.SetPoints(full.GetPoints())
    planes.SetPolys(full.GetPolys())
    first = full.GetNumberOfLines()  # lines come first among a polydata's cells
    for name in ("VisitCount", "NodeId", "PrimitiveCount"):
        src = full.GetCellData().GetArray(name)
        dst = vtk.vtkIntArray()
        dst.SetName(name)
        for c in range(first, full.GetNumberOfCells()):
            dst.InsertNextValue(int(src.GetValue(c)))
        planes.GetCellData().AddArray(dst)
    planes.GetFieldData().ShallowCopy(full.GetFieldData())
    return planes


def accel_of(name):
    """'kdtree' or 'octree/smallest-cell' -> (Accel, Storage) values of the
    image algorithm (its ACCEL_* and STORAGE_* constants)."""
    kind, _, storage = name.partition("/")
    names = {"bvh": "BVH", "bvh2": "BINARY_BVH", "kdtree": "KDTREE"}
    accel = getattr(ALG, "ACCEL_" + names.get(kind, kind.upper()), None)
    store = getattr(ALG, "STORAGE_" + (storage or "every-cell").upper().replace("-", "_"), None)
    if accel is None or store is None:
        sys.exit(f"accel_structures.py: --structures: unknown structure '{name}'")
    return accel, store


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", default="accel_structures.png")
    ap.add_argument("--structures", default="bvh,kdtree,grid,octree",
                    help="comma-separated --accel names, a storage after a slash "
                         "(octree/smallest-cell)")
    ap.add_argument("--triangles", type=int, default=3000, help="simplify the mesh to about this")
    ap.add_argument("--size", type=int, default=300, help="viewport size in pixels")
    args = ap.parse_args()
    names = [s for s in args.structures.split(",") if s]
    kinds = [accel_of(s) for s in names]

    source = dataset(args.triangles)
    source.Update()
    cols = min(3, len(names))
    rows = (len(names) + cols - 1) // cols
    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(cols * args.size, rows * args.size)
    mesh_mapper = vtk.vtkPolyDataMapper()
    mesh_mapper.SetInputConnection(source.GetOutputPort())
    mesh_mapper.ScalarVisibilityOff()
    camera = None
    for k, (name, (accel, storage)) in enumerate(zip(names, kinds)):
        # The scene: the mesh seen by a camera fitted to it; the visit counts
        # come from ray tracing a 160x120 image from that camera.
        tracer = ALG()
        tracer.AddInputConnection(source.GetOutputPort())
        tracer.SetSize(160, 120)
        tracer.SetSamples(1)
        tracer.SetPosition(0.3, 0.4, 1.0)
        tracer.ResetCamera()
        tracer.SetAccel(accel)
        tracer.SetStorage(storage)
        leaves = rayscope.vtkRayScopeAccelSource()
        leaves.SetSceneSource(tracer)
        leaves.SetVisitModeToFrame()
        leaves.OnlyLeavesOn()
        leaves.Update()
        out = leaves.GetOutput()
        if out.GetFieldData().GetAbstractArray("Structure").GetValue(0) == "bsp":
            out = bsp_planes(leaves, BSP_PLANE_LEVELS)
        drawn = out.GetFieldData().GetAbstractArray("Structure").GetValue(0)
        depth = int(out.GetFieldData().GetArray("TreeDepth").GetValue(0))
        node = out.GetCellData().GetArray("NodeId")
        count = out.GetCellData().GetArray("PrimitiveCount")
        cells = {int(node.GetValue(c)): int(count.GetValue(c)) for c in range(out.GetNumberOfCells())}
        held = [n for n in cells.values() if n > 0]
        if camera is None:
            camera = vtk.vtkCamera()
            camera.SetPosition(tracer.GetPosition())
            camera.SetFocalPoint(tracer.GetFocalPoint())
            camera.SetViewUp(tracer.GetViewUp())
            camera.SetViewAngle(tracer.GetViewAngle())

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
        actor = vtk.vtkActor()
        actor.SetMapper(mapper)
        actor.GetProperty().SetLineWidth(1.2)
        if out.GetNumberOfPolys():
            actor.GetProperty().SetOpacity(0.45)
        actor.GetProperty().LightingOff()
        mesh_actor = vtk.vtkActor()
        mesh_actor.SetMapper(mesh_mapper)
        mesh_actor.GetProperty().SetColor(0.75, 0.75, 0.75)
        mesh_actor.GetProperty().SetOpacity(0.35)

        ren = vtk.vtkRenderer()
        r, c = divmod(k, cols)
        ren.SetViewport(c / cols, 1 - (r + 1) / rows, (c + 1) / cols, 1 - r / rows)
        ren.SetBackground(0.12, 0.12, 0.15)
        ren.AddActor(mesh_actor)
        ren.AddActor(actor)
        ren.SetActiveCamera(camera)
        label = (f"{name}: planes of levels 0-{BSP_PLANE_LEVELS - 1}, {depth} levels"
                 if out.GetNumberOfPolys() else f"{name}: {len(cells)} leaves, {depth} levels")
        text = vtk.vtkTextActor()
        text.SetInput(label)
        text.GetTextProperty().SetFontSize(15)
        text.SetPosition(8, 8)
        ren.AddViewProp(text)
        window.AddRenderer(ren)
        mean = sum(held) / len(held) if held else 0.0
        if out.GetNumberOfPolys():
            print(f"{name} (drawn: {drawn}): {len(cells)} split planes in levels 0-"
                  f"{BSP_PLANE_LEVELS - 1}, {depth} levels")
        else:
            print(f"{name} (drawn: {drawn}): {len(cells)} leaves, {len(held)} holding primitives "
                  f"({mean:.1f} on average), {depth} levels")
    for ren in window.GetRenderers():
        ren.ResetCameraClippingRange()
    save_window(window, args.output)
    triangles = source.GetOutput().GetNumberOfPolys()
    print(f"wrote {args.output}: {len(names)} structures over {triangles} triangles")


if __name__ == "__main__":
    main()
