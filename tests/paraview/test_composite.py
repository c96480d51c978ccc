"""The plugin's filters on composite data in pvpython: a two-block .vtm (a
floor and a sphere above it) read by ParaView's own reader.

- "Ray Trace" gives one image (not one per block), with both blocks as
  objects (ObjectId 0 and 1, ObjectFlatIndex 1 and 2 in the field data), the
  sphere's shadow on the floor, and the same colors, pixel for pixel, as
  Merge Blocks first, and as the blocks converted to a partitioned dataset
  collection.
- An Exodus II file (written here by VTK's vtkExodusIIWriter, two element
  blocks), opened by ParaView's own reader: one image, the same pixels as
  Merge Blocks first.
- "Ray Tree" and "Acceleration Structure" give one polydata.
- Show() of the Ray Trace output in a render view shows its true colors: the
  representation colors by "Color" with Map Scalars off.
"""
import os
import sys
import tempfile

from paraview.simple import *
from paraview import servermanager as sm

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from script_checks import check, finish  # noqa: E402

W, H = 96, 72


def ray_trace(source):
    t = RayTrace(Input=source)
    t.ImageSize = [W, H]
    t.AutoCamera = 0
    t.Position = [0.0, 1.5, 3.0]
    t.FocalPoint = [0.0, -0.2, 0.0]
    t.ViewUp = [0.0, 1.0, 0.0]
    t.ViewAngle = 40.0
    t.Headlight = 0
    t.Lights = [0, 0.2, 3.0, 0.2, 1, 1, 1, 1]
    t.ComputeCost = 0
    return t


def values(array):
    return [array.GetValue(i) for i in range(array.GetNumberOfValues())]


floor = Plane(Origin=[-2, -0.5, 2], Point1=[2, -0.5, 2], Point2=[-2, -0.5, -2])
ball = Sphere(Center=[0, 0.1, 0], Radius=0.4, ThetaResolution=32, PhiResolution=16)
group = GroupDatasets(Input=[floor, ball])
path = os.path.join(os.environ.get("RAYSCOPE_TEST_OUTPUT", tempfile.gettempdir()), "two_blocks.vtm")
SaveData(path, proxy=group)
blocks = OpenDataFile(path)

image = sm.Fetch(ray_trace(blocks))
check(image.IsA("vtkImageData"), f"Ray Trace of a .vtm gives one image, not {image.GetClassName()}")
check(image.GetDimensions()[:2] == (W, H), f"image size {image.GetDimensions()}")
ids = values(image.GetPointData().GetArray("ObjectId"))
check(ids.count(0) > 100 and ids.count(1) > 100, "both blocks are seen")
flat = image.GetFieldData().GetArray("ObjectFlatIndex")
check(flat is not None and values(flat) == [1, 2], "ObjectFlatIndex names the blocks")

# The sphere shadows the floor: floor pixels darker than a render of the floor alone.
floor_only = sm.Fetch(ray_trace(GroupDatasets(Input=[floor])))
color = image.GetPointData().GetArray("Color")
floor_color = floor_only.GetPointData().GetArray("Color")
floor_ids = values(floor_only.GetPointData().GetArray("ObjectId"))
shadowed = sum(1 for i in range(W * H)
               if ids[i] == 0 and floor_ids[i] == 0
               and color.GetValue(3 * i) + 30 < floor_color.GetValue(3 * i))
check(shadowed > 50, f"the sphere's shadow on the floor ({shadowed} pixels)")

# The same colors as Merge Blocks first, and as a partitioned dataset collection.
for name, source in (("Merge Blocks", MergeBlocks(Input=blocks)),
                     ("a partitioned dataset collection",
                      ConvertToPartitionedDataSetCollection(Input=blocks))):
    other = sm.Fetch(ray_trace(source))
    check(other.IsA("vtkImageData"), f"{name}: one image")
    check(values(other.GetPointData().GetArray("Color")) == values(color),
          f"{name}: the same pixels")

# An Exodus file of the same two blocks, through ParaView's reader of .e files.
from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet
from vtkmodules.vtkFiltersCore import vtkAppendFilter, vtkTriangleFilter
from vtkmodules.vtkIOExodus import vtkExodusIIWriter

grids = vtkMultiBlockDataSet()
for i, source in enumerate((floor, ball)):
    triangles = vtkTriangleFilter()
    triangles.SetInputData(sm.Fetch(source))
    grid = vtkAppendFilter()  # element blocks are unstructured grids
    grid.AddInputConnection(triangles.GetOutputPort())
    grid.Update()
    grids.SetBlock(i, grid.GetOutput())
exodus_path = os.path.join(os.path.dirname(path), "two_blocks.e")
writer = vtkExodusIIWriter()
writer.SetFileName(exodus_path)
writer.SetInputData(grids)
writer.WriteAllTimeStepsOff()
writer.Write()
exodus = OpenDataFile(exodus_path)
exodus_image = sm.Fetch(ray_trace(exodus))
check(exodus_image.IsA("vtkImageData"), f"Ray Trace of an Exodus file ({exodus.GetXMLName()}): one image")
exodus_ids = values(exodus_image.GetPointData().GetArray("ObjectId"))
check(exodus_ids.count(0) > 100 and exodus_ids.count(1) > 100, "both element blocks are seen")
exodus_merged = sm.Fetch(ray_trace(MergeBlocks(Input=exodus)))
check(values(exodus_merged.GetPointData().GetArray("Color")) ==
      values(exodus_image.GetPointData().GetArray("Color")),
      "Exodus: the same pixels as Merge Blocks first")

tree = RayTree(Input=blocks)
tree.ImageSize = [W, H]
tree.Pixel = [W // 2, H // 2]
rays = sm.Fetch(tree)
check(rays.IsA("vtkPolyData") and rays.GetNumberOfCells() > 0,
      f"Ray Tree of a .vtm gives one polydata, not {rays.GetClassName()}")
boxes = sm.Fetch(AccelerationStructure(Input=blocks))
check(boxes.IsA("vtkPolyData") and boxes.GetNumberOfCells() > 0,
      f"Acceleration Structure of a .vtm gives one polydata, not {boxes.GetClassName()}")

# Shown in a render view: the image's own colors, not a color map's.
view = CreateRenderView()
display = Show(ray_trace(blocks), view)
check(display.ColorArrayName[1] == "Color", f"colored by {display.ColorArrayName}")
check(display.MapScalars == 0, "Map Scalars is off for the Color array")

finish("paraview.composite")
