"""One run of the MPI test (tests/paraview/test_mpi.py runs it under
`mpiexec -n N pvbatch`; the script runs on rank 0, ParaView's pipeline on every
rank).

    mpi_render.py OUT_DIR image   writes OUT_DIR/ray_trace.raw (the Ray Trace
                                  filter's LinearColor, Depth and ObjectId bytes)
                                  OUT_DIR/view.raw (the RayScope view's
                                  screenshot, RGB bytes) of scene.pvtp and
                                  OUT_DIR/tree.raw (View Ray Tree of a pixel),
                                  OUT_DIR/process.txt (pixels each rank traced)
                                  and OUT_DIR/passes.txt (the view's
                                  progressive passes, render by render)
    mpi_render.py OUT_DIR bad     the same Ray Trace with MaxDepth -1: exits 1
                                  when its output is empty, as it must be
    mpi_render.py OUT_DIR image HOST:PORT
                                  run by pvpython as the client of a pvserver
                                  (on its MPI ranks), rendering on the server

scene.pvtp (written here on rank 0 before any rank reads it) has two pieces:
a sphere, and a floor under it with a wall behind it. ParaView's reader hands
piece k of 2 to rank k (on 3 ranks, rank 2 gets nothing), so on several ranks
the sphere's shadow and its reflections fall on geometry another rank holds.
"""
import os
import sys

from paraview.simple import *
from paraview import servermanager as sm
from paraview.vtk.vtkFiltersSources import vtkPlaneSource, vtkSphereSource
from paraview.vtk.vtkFiltersCore import vtkAppendPolyData
from paraview.vtk.vtkIOXML import vtkXMLPolyDataWriter
from paraview.vtk.vtkIOImage import vtkPNGReader

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rayscope_views import new_view  # noqa: E402

out, mode = sys.argv[1], sys.argv[2]
if len(sys.argv) > 3:
    host, port = sys.argv[3].rsplit(":", 1)
    Connect(host, int(port))
    # Render on the server's ranks whatever the data's size (ParaView would
    # otherwise deliver this small geometry to the client and render there).
    GetSettingsProxy("RenderViewSettings").RemoteRenderThreshold = 0.0
W, H = 160, 120
ranks = sm.ActiveConnection.GetNumberOfDataPartitions()


def write_piece(name, algorithms):
    append = vtkAppendPolyData()
    for a in algorithms:
        append.AddInputConnection(a.GetOutputPort())
    append.Update()
    data = append.GetOutput()
    data.GetPointData().RemoveArray("TextureCoordinates")
    writer = vtkXMLPolyDataWriter()
    writer.SetFileName(os.path.join(out, name))
    writer.SetInputData(data)
    writer.Write()


sphere = vtkSphereSource()
sphere.SetCenter(0.0, 1.0, 0.0)
sphere.SetThetaResolution(48)
sphere.SetPhiResolution(24)
floor, wall = vtkPlaneSource(), vtkPlaneSource()
floor.SetOrigin(-4.0, 0.0, -4.0)
floor.SetPoint1(4.0, 0.0, -4.0)
floor.SetPoint2(-4.0, 0.0, 4.0)
wall.SetOrigin(-4.0, 0.0, -2.0)
wall.SetPoint1(4.0, 0.0, -2.0)
wall.SetPoint2(-4.0, 4.0, -2.0)
write_piece("scene_0.vtp", [sphere])
write_piece("scene_1.vtp", [floor, wall])
with open(os.path.join(out, "scene.pvtp"), "w") as f:
    f.write("""<?xml version="1.0"?>
<VTKFile type="PPolyData" version="1.0" byte_order="LittleEndian">
  <PPolyData GhostLevel="0">
    <PPointData Normals="Normals"><PDataArray type="Float32" Name="Normals" NumberOfComponents="3"/></PPointData>
    <PPoints><PDataArray type="Float32" NumberOfComponents="3"/></PPoints>
    <Piece Source="scene_0.vtp"/>
    <Piece Source="scene_1.vtp"/>
  </PPolyData>
</VTKFile>
""")

scene = XMLPartitionedPolydataReader(FileName=[os.path.join(out, "scene.pvtp")])
camera = dict(CameraPosition=[3.0, 3.5, 6.0], CameraFocalPoint=[0.0, 0.8, 0.0], CameraViewUp=[0.0, 1.0, 0.0])

rt = RayTrace(Input=[scene], ImageSize=[W, H], Samples=2, Reflectivity=0.3,
              AutoCamera=0, Position=camera["CameraPosition"], FocalPoint=camera["CameraFocalPoint"],
              ViewUp=camera["CameraViewUp"])
if mode == "bad":
    rt.MaxDepth = -1
image = sm.Fetch(rt, 0)  # rank 0's output: the whole image
if image.GetNumberOfPoints() != W * H:
    print(f"mpi_render: {ranks} ranks: the Ray Trace image is empty", file=sys.stderr)
    sys.exit(1)
with open(os.path.join(out, "ray_trace.raw"), "wb") as f:
    for name in ("LinearColor", "Depth", "ObjectId", "Color"):
        f.write(bytes(memoryview(image.GetPointData().GetArray(name))))
# Pixels per rank (the Process array, on several ranks): tiles handed out by
# estimated cost, every rank tracing some.
process = image.GetPointData().GetArray("Process")
counts = [0] * ranks
for i in range(process.GetNumberOfTuples() if process else 0):
    counts[int(process.GetValue(i))] += 1
with open(os.path.join(out, "process.txt"), "w") as f:
    f.write(repr(counts))

view = new_view((W, H), (0.1, 0.2, 0.3))
for k, v in camera.items():
    setattr(view, k, v)
display = Show(scene, view)
display.ColorArrayName = ["POINTS", ""]
display.DiffuseColor = [0.9, 0.7, 0.2]
# Progressive refinement on the ranks: each still render adds a sample per
# pixel (2 x 2 in all) until the image is complete; the screenshot then shows
# the refined image.
view.Samples = 2
passes = []
while not passes or (passes[-1][0] < passes[-1][1] and len(passes) < 10):
    Render(view)
    view.UpdatePropertyInformation()
    passes.append(list(view.GetPropertyValue("ImagePasses")))
with open(os.path.join(out, "passes.txt"), "w") as f:
    f.write(repr(passes))
png = os.path.join(out, "view.png")
SaveScreenshot(png, view, ImageResolution=[W, H])
reader = vtkPNGReader()
reader.SetFileName(png)
reader.Update()
with open(os.path.join(out, "view.raw"), "wb") as f:
    f.write(bytes(memoryview(reader.GetOutput().GetPointData().GetScalars())))
# The ray tree of a pixel on the sphere, whose shadow and reflection rays meet
# the other piece: made once (by rank 0), the serial tree.
tree = sm.Fetch(ViewRayTree(View=view, Pixel=[W // 2, H // 2]))
with open(os.path.join(out, "tree.raw"), "wb") as f:
    f.write(bytes(memoryview(tree.GetPoints().GetData())))
    for name in ("Kind", "Depth", "Hit"):
        f.write(bytes(memoryview(tree.GetCellData().GetArray(name))))
    f.write(bytes(memoryview(tree.GetFieldData().GetArray("PixelColor"))))
print(f"mpi_render: {ranks} ranks: images written")
