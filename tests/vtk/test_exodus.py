"""An Exodus II file, the format of many simulation codes, through VTK's own
reader into vtkRayScopeImageAlgorithm: the file is made here by VTK's
vtkExodusIIWriter (two element blocks: a floor and a sphere above it);
vtkExodusIIReader gives a multiblock of its blocks, which is one scene: one
image, an object per element block (ObjectFlatIndex says which), the sphere's
shadow on the floor (against the floor block read alone), the same colors as
the blocks merged into one dataset (vtkCompositeDataGeometryFilter) first.
"""
import os
import sys
import tempfile

import vtk
import rayscope

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from script_checks import check, finish  # noqa: E402



W, H = 96, 72


def write_exodus(path):
    sphere = vtk.vtkSphereSource()
    sphere.SetCenter(0.0, 0.1, 0.0)
    sphere.SetRadius(0.4)
    sphere.SetThetaResolution(32)
    sphere.SetPhiResolution(16)
    floor = vtk.vtkPlaneSource()
    floor.SetOrigin(-2.0, -0.5, 2.0)
    floor.SetPoint1(2.0, -0.5, 2.0)
    floor.SetPoint2(-2.0, -0.5, -2.0)
    blocks = vtk.vtkMultiBlockDataSet()
    for i, source in enumerate((floor, sphere)):
        tri = vtk.vtkTriangleFilter()
        tri.SetInputConnection(source.GetOutputPort())
        grid = vtk.vtkAppendFilter()  # Exodus element blocks are unstructured grids
        grid.AddInputConnection(tri.GetOutputPort())
        grid.Update()
        blocks.SetBlock(i, grid.GetOutput())
    writer = vtk.vtkExodusIIWriter()
    writer.SetFileName(path)
    writer.SetInputData(blocks)
    writer.WriteAllTimeStepsOff()
    writer.Write()


def trace(connection):
    alg = rayscope.vtkRayScopeImageAlgorithm()
    alg.SetInputConnection(connection)
    alg.SetSize(W, H)
    alg.SetPosition(0.0, 1.5, 3.0)
    alg.SetFocalPoint(0.0, -0.2, 0.0)
    alg.SetViewAngle(40.0)
    alg.SetHeadlight(0)
    alg.AddPointLight(0.2, 3.0, 0.2, 1.0, 1.0, 1.0, 1.0)
    alg.ComputeCostOff()
    alg.Update()
    return alg.GetOutput()


def values(array):
    return [array.GetValue(i) for i in range(array.GetNumberOfValues())]


out = os.environ.get("RAYSCOPE_TEST_OUTPUT", tempfile.gettempdir())
path = os.path.join(out, "two_blocks.e")
write_exodus(path)
reader = vtk.vtkExodusIIReader()
reader.SetFileName(path)
reader.UpdateInformation()
check(reader.GetNumberOfObjects(vtk.vtkExodusIIReader.ELEM_BLOCK) == 2, "two element blocks")

image = trace(reader.GetOutputPort())
check(image is not None and image.GetNumberOfPoints() == W * H, "one image of the whole file")
ids = values(image.GetPointData().GetArray("ObjectId"))
check(ids.count(0) > 100 and ids.count(1) > 100, "both element blocks are seen")
flat = values(image.GetFieldData().GetAbstractArray("ObjectFlatIndex"))
check(len(flat) == 2 and flat[0] < flat[1], f"one object per element block (flat indices {flat})")

merged = vtk.vtkCompositeDataGeometryFilter()  # every block appended into one polydata
merged.SetInputConnection(reader.GetOutputPort())
one = trace(merged.GetOutputPort())
same = values(one.GetPointData().GetArray("Color")) == values(image.GetPointData().GetArray("Color"))
check(same, "the same pixels as the blocks merged first")

# The sphere's shadow: floor pixels darker than with the floor block alone.
floor_reader = vtk.vtkExodusIIReader()
floor_reader.SetFileName(path)
floor_reader.UpdateInformation()
floor_reader.SetObjectStatus(vtk.vtkExodusIIReader.ELEM_BLOCK, 1, 0)  # the sphere's block off
floor_only = trace(floor_reader.GetOutputPort())
floor_ids = values(floor_only.GetPointData().GetArray("ObjectId"))
color, floor_color = image.GetPointData().GetArray("Color"), floor_only.GetPointData().GetArray("Color")
shadowed = sum(1 for i in range(W * H) if ids[i] == 0 and floor_ids[i] == 0
               and color.GetValue(3 * i) + 30 < floor_color.GetValue(3 * i))
check(shadowed > 50, f"the sphere shadows the floor ({shadowed} pixels)")

finish("exodus")
