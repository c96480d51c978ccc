"""Bad input through Python, where the issue met it (issue 11): polydata whose
triangle names point 7 of 3 (it crashed the interpreter inside
vtkPolyDataNormals), an empty polydata and points without cells (a blank image
without a word; a 1-D image's lines are drawn as a tube), SetInputMaterial(5, m)
with one input (accepted silently), and (issue
31) polydata whose every point is NaN (a warning and a blank image). Each is now an
error or warning event on vtkRayScopeImageAlgorithm, with an empty output image
where nothing can be rendered. test_vtk_bad_input.cpp covers the same in C++.
"""
import os
import sys

import vtk
import rayscope

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from script_checks import check, finish  # noqa: E402



class Events:
    def __init__(self, obj, event):
        self.messages = []
        obj.AddObserver(event, self.on_event)

    def on_event(self, obj, event, message=None):
        self.messages.append(str(message))

    on_event.CallDataType = vtk.VTK_STRING


def traced(*inputs):
    alg = rayscope.vtkRayScopeImageAlgorithm()
    for d in inputs:
        alg.AddInputData(d)
    alg.SetSize(16, 12)
    alg.SetPosition(0.3, 0.3, 4.0)
    alg.SetFocalPoint(0.3, 0.3, 0.0)
    errors = Events(alg, vtk.vtkCommand.ErrorEvent)
    warnings = Events(alg, vtk.vtkCommand.WarningEvent)
    Events(alg.GetExecutive(), vtk.vtkCommand.ErrorEvent)  # keeps the log quiet
    ok = alg.GetExecutive().Update()
    return alg, ok, errors.messages, warnings.messages


def expect_error(name, data, text):
    alg, ok, errors, _ = traced(data)
    check(ok == 0, f"{name}: the update failed")
    check(len(errors) == 1 and text in errors[0], f"{name}: one error with '{text}': {errors}")
    check(alg.GetOutput().GetNumberOfPoints() == 0, f"{name}: empty output image")


def triangle(third):
    pts = vtk.vtkPoints()
    for p in ((0, 0, 0), (1, 0, 0), (0, 1, 0)):
        pts.InsertNextPoint(p)
    polys = vtk.vtkCellArray()
    polys.InsertNextCell(3, (0, 1, third))
    pd = vtk.vtkPolyData()
    pd.SetPoints(pts)
    pd.SetPolys(polys)
    return pd


expect_error("point id 7 of 3", triangle(7), "cell 0 refers to point 7 but the data has 3 points")
expect_error("empty polydata", vtk.vtkPolyData(), "has no surface triangles")
cloud = vtk.vtkPolyData()  # points without cells: nothing to draw
cloud_points = vtk.vtkPoints()
for i in range(4):
    cloud_points.InsertNextPoint(i, 0.0, 0.0)
cloud.SetPoints(cloud_points)
expect_error("points without cells", cloud,
             "(vtkPolyData with 4 points, 0 cells) has no surface triangles, lines or vertices")
# Every point NaN (it gave a warning and a blank image): an error, no image.
nan_triangle = triangle(2)
for i in range(3):
    nan_triangle.GetPoints().SetPoint(i, float("nan"), 0.0, float("inf"))
expect_error("all-NaN polydata", nan_triangle,
             "all 1 triangles have non-finite (NaN or infinite) vertex coordinates")

# The valid triangle renders; a material for input 5 of 1 is a warning.
tri = triangle(2)
alg = rayscope.vtkRayScopeImageAlgorithm()
alg.AddInputData(tri)
alg.SetSize(16, 12)
alg.SetPosition(0.3, 0.3, 4.0)
alg.SetFocalPoint(0.3, 0.3, 0.0)
alg.SetInputMaterial(5, rayscope.vtkRayScopeMaterial())
warnings = Events(alg, vtk.vtkCommand.WarningEvent)
check(alg.GetExecutive().Update() == 1, "valid triangle: rendered")
check(alg.GetOutput().GetNumberOfPoints() == 16 * 12, "valid triangle: full image")
check(len(warnings.messages) == 1 and "is set for input 5, but only 1 input is connected"
      in warnings.messages[0], f"SetInputMaterial(5): one warning: {warnings.messages}")

finish("bad input")
