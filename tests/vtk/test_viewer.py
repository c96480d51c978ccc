"""vtkRayScopeViewer from Python: the viewer on a VTK pipeline's scene in a
few lines, as its header shows.

1. A sphere and a floor traced by a vtkRayScopeImageAlgorithm: the viewer
   renders them (off the UI thread; WaitForRender finishes) and shows the
   image the algorithm itself makes.
2. A pixel on the sphere picked through the interactor (a synthesized click
   at the pixel's place in the image viewport): the rays shown are the rows
   of a vtkRayScopeRayTreeSource of the same pixel, kind by kind.
3. The walk of the primary ray played with the key t: the boxes entered are
   the first nodes of the ray tree's walk (the BVH source's "EntryOrder").

Runs under xvfb-run (OpenGL).
"""
import os
import sys

import vtk
import rayscope

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from script_checks import check, finish  # noqa: E402



def kinds(pd):
    out = {}
    kind = pd.GetCellData().GetArray("Kind")
    for c in range(pd.GetNumberOfCells()):
        if pd.GetCellType(c) == vtk.VTK_LINE:
            k = int(kind.GetValue(c))
            out[k] = out.get(k, 0) + 1
    return out


def make_tracer(sphere, floor):
    tracer = rayscope.vtkRayScopeImageAlgorithm()
    tracer.AddInputConnection(sphere.GetOutputPort())
    tracer.AddInputConnection(floor.GetOutputPort())
    tracer.SetSize(96, 72)
    tracer.SetPosition(0, 1, 3)
    tracer.SetFocalPoint(0, 0, 0)
    tracer.AddPointLight(2, 3, 2, 1, 1, 1, 1.0)
    tracer.GetMaterial().SetReflectivity(0.3)
    return tracer


def main():
    sphere = vtk.vtkSphereSource()
    sphere.SetThetaResolution(48)
    sphere.SetPhiResolution(32)
    floor = vtk.vtkPlaneSource()
    floor.SetOrigin(-3, -0.5, -3)
    floor.SetPoint1(3, -0.5, -3)
    floor.SetPoint2(-3, -0.5, 3)
    tracer = make_tracer(sphere, floor)

    viewer = rayscope.vtkRayScopeViewer()
    viewer.SetSceneSource(tracer)
    viewer.SetWindowSize(900, 600)
    check(viewer.Initialize() == 1, "Initialize: " + viewer.GetMessage())
    check(viewer.WaitForRender() == 1, "the first render finishes")

    ref = make_tracer(sphere, floor)  # a second algorithm: its own render
    ref.Update()
    want = ref.GetOutput().GetPointData().GetScalars()
    got = viewer.GetShownImage().GetPointData().GetScalars()
    same = want.GetNumberOfValues() == got.GetNumberOfValues() and all(
        want.GetValue(v) == got.GetValue(v) for v in range(want.GetNumberOfValues()))
    check(same, "the viewer shows the image the image algorithm makes")

    # A click on pixel (48, 36) of the image (VTK image coordinates).
    i, j = 48, 36
    ren = viewer.GetImageRenderer()
    ren.SetWorldPoint(i, j, 0, 1)
    ren.WorldToDisplay()
    x, y, _ = ren.GetDisplayPoint()
    iren = viewer.GetInteractor()
    iren.SetEventInformation(int(round(x)), int(round(y)), 0, 0)
    iren.InvokeEvent(vtk.vtkCommand.LeftButtonPressEvent)
    iren.InvokeEvent(vtk.vtkCommand.LeftButtonReleaseEvent)
    check(tuple(viewer.GetPickedPixel()) == (i, j),
          f"the click picked {tuple(viewer.GetPickedPixel())}")

    tree = rayscope.vtkRayScopeRayTreeSource()
    tree.SetSceneSource(tracer)
    tree.SetPixel(i, j)
    tree.Update()
    want_kinds = kinds(tree.GetOutput())
    check(kinds(viewer.GetShownRays()) == want_kinds and len(want_kinds) >= 3,
          f"rays by kind {kinds(viewer.GetShownRays())} == the ray tree source's {want_kinds}")

    viewer.HandleKey("t")
    viewer.HandleKey("t")
    boxes = viewer.GetShownBVH()
    order = boxes.GetCellData().GetArray("EntryOrder")
    node = boxes.GetCellData().GetArray("NodeId")
    entered = sorted({(int(order.GetValue(c)), int(node.GetValue(c)))
                      for c in range(boxes.GetNumberOfCells()) if order.GetValue(c) >= 0})
    bvh = rayscope.vtkRayScopeAccelSource()
    bvh.SetSceneSource(tracer)
    bvh.SetVisitModeToPixel()
    bvh.SetPixel(i, j)
    bvh.SetVisitRay(0)
    bvh.SetTraversalSteps(2)
    bvh.Update()
    check(bvh.GetNumberOfTraversalEntries() >= 2 and [e for e, _ in entered] == [0, 1],
          f"two nodes entered after two steps: {entered}")

    finish("viewer")
    return 0


if __name__ == "__main__":
    sys.exit(main())
