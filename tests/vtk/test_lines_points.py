"""Lines as tubes and points as spheres in vtkRayScopeImageAlgorithm.

- Streamlines (vtkStreamTracer polylines) alone render: their tubes are seen,
  colored through the mapper's lookup table, named "input 0 lines"; no error.
- A point cloud (vtkPointSource vertices) alone renders as spheres.
- Mixed with a surface in one polydata, nothing is dropped: triangles, tubes
  and spheres are all seen, and the tubes shadow the surface.
- Every structure and storage gives the same image, bit for bit, as testing
  every primitive (ACCEL_NONE).
- LineRadius and PointRadius set the thickness (a larger radius covers more
  pixels); RadiusArray sets it per point; a negative radius is an error.
"""
import os
import sys

import vtk
import rayscope

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from script_checks import check, finish  # noqa: E402



W, H = 80, 60


class Errors:
    def __init__(self, obj):
        self.messages = []
        obj.AddObserver(vtk.vtkCommand.ErrorEvent, self.on_event)
        obj.AddObserver(vtk.vtkCommand.WarningEvent, self.on_event)

    def on_event(self, obj, event, message=None):
        self.messages.append(str(message))

    on_event.CallDataType = vtk.VTK_STRING


def tracer(*connections):
    alg = rayscope.vtkRayScopeImageAlgorithm()
    for c in connections:
        alg.AddInputConnection(c)
    alg.SetSize(W, H)
    alg.AutoCameraOn()
    alg.SetPosition(0.4, 0.6, 1.0)
    alg.ComputeCostOff()
    return alg


def values(array):
    return [array.GetValue(i) for i in range(array.GetNumberOfValues())]


def ids_of(alg):
    return values(alg.GetOutput().GetPointData().GetArray("ObjectId"))


def colors_of(alg):
    return values(alg.GetOutput().GetPointData().GetArray("Color"))


# ---- streamlines alone -------------------------------------------------------
wavelet = vtk.vtkRTAnalyticSource()
wavelet.SetWholeExtent(-8, 8, -8, 8, -8, 8)
gradient = vtk.vtkGradientFilter()
gradient.SetInputConnection(wavelet.GetOutputPort())
gradient.SetInputArrayToProcess(0, 0, 0, vtk.vtkDataObject.FIELD_ASSOCIATION_POINTS, "RTData")
gradient.SetResultArrayName("Gradient")
seeds = vtk.vtkPointSource()
seeds.SetRadius(3.0)
seeds.SetNumberOfPoints(20)
seeds.SetRandomSequence(vtk.vtkMinimalStandardRandomSequence())
streams = vtk.vtkStreamTracer()
streams.SetInputConnection(gradient.GetOutputPort())
streams.SetSourceConnection(seeds.GetOutputPort())
streams.SetInputArrayToProcess(0, 0, 0, vtk.vtkDataObject.FIELD_ASSOCIATION_POINTS, "Gradient")
streams.SetIntegrationDirectionToBoth()
streams.SetMaximumPropagation(20.0)
streams.Update()
check(streams.GetOutput().GetNumberOfLines() > 5, "the stream tracer made streamlines")

alg = tracer(streams.GetOutputPort())
alg.SetLineRadius(0.15)
mapper = alg.GetConverter().GetMapper()
mapper.SelectColorArray("RTData")
mapper.SetScalarModeToUsePointFieldData()
mapper.SetScalarRange(streams.GetOutput().GetPointData().GetArray("RTData").GetRange())
errors = Errors(alg)
alg.Update()
check(not errors.messages, f"streamlines alone: no error or warning ({errors.messages})")
ids = ids_of(alg)
# Object 0 is the (empty) mesh of input 0, object 1 its tube set.
tube_pixels = ids.count(1)
check(tube_pixels > 100, f"streamlines alone are drawn as tubes ({tube_pixels} pixels)")
names = alg.GetOutput().GetFieldData().GetAbstractArray("ObjectName")
check(names is not None and names.GetValue(1) == "input 0 lines", "the tube set is named")
c = colors_of(alg)
hues = {(c[3 * i] > c[3 * i + 2]) for i in range(W * H) if ids[i] == 1}
check(hues == {True, False}, "the tubes are colored through the lookup table (red and blue)")

# ---- a point cloud alone -----------------------------------------------------
cloud = vtk.vtkPointSource()
cloud.SetRadius(1.0)
cloud.SetNumberOfPoints(150)
cloud.SetRandomSequence(vtk.vtkMinimalStandardRandomSequence())
points = tracer(cloud.GetOutputPort())
points.SetPointRadius(0.06)
points.Update()
sphere_pixels = ids_of(points).count(1)  # object 1: input 0's point set (no tubes)
check(sphere_pixels > 100, f"a point cloud alone is drawn as spheres ({sphere_pixels} pixels)")
points.SetPointRadius(0.03)
points.Update()
check(ids_of(points).count(1) < sphere_pixels, "a smaller PointRadius covers fewer pixels")

# RadiusArray: the radius of each point from a point array.
radius = vtk.vtkArrayCalculator()
radius.SetInputConnection(cloud.GetOutputPort())
radius.AddCoordinateScalarVariable("x", 0)
radius.SetFunction("0.02 + 0.04 * (x + 1)")
radius.SetResultArrayName("radius")
by_array = tracer(radius.GetOutputPort())
by_array.SetRadiusArray("radius")
by_array.Update()
check(ids_of(by_array).count(1) > 50, "spheres sized by RadiusArray are drawn")

# One vertex alone: bounds of one point, no diagonal to size it by; a sphere
# of radius 1 there (rayscope_vtkio::automatic_radius), framed by the camera.
one = vtk.vtkPointSource()
one.SetNumberOfPoints(1)
one.SetRadius(0.0)
one.SetCenter(2.0, 3.0, 4.0)
single = tracer(one.GetOutputPort())
single_errors = Errors(single)
single.Update()
check(not single_errors.messages, f"one vertex: no error or warning ({single_errors.messages})")
check(ids_of(single).count(1) > W * H // 10, "one vertex alone is drawn as a sphere")

# ---- mixed with a surface: nothing dropped, every structure alike --------------
floor = vtk.vtkPlaneSource()
floor.SetOrigin(-9, -9, 9)
floor.SetPoint1(9, -9, 9)
floor.SetPoint2(-9, -9, -9)
mixed = vtk.vtkAppendPolyData()
mixed.AddInputConnection(floor.GetOutputPort())
mixed.AddInputConnection(streams.GetOutputPort())
scaled_cloud = vtk.vtkTransformFilter()
scale = vtk.vtkTransform()
scale.Scale(4, 4, 4)
scaled_cloud.SetTransform(scale)
scaled_cloud.SetInputConnection(cloud.GetOutputPort())
mixed.AddInputConnection(scaled_cloud.GetOutputPort())


def mixed_image(accel, storage=None):
    a = tracer(mixed.GetOutputPort())
    a.AutoCameraOff()
    a.SetPosition(14, 22, 26)
    a.SetFocalPoint(0, -3, 0)
    a.SetLineRadius(0.15)
    a.SetPointRadius(0.12)
    a.SetAccel(accel)
    if storage is not None:
        a.SetStorage(storage)
    a.SetHeadlight(0)
    a.AddPointLight(0, 40, 0, 1, 1, 1, 1)
    a.Update()
    return a


S = rayscope.vtkRayScopeSceneSettings
reference = mixed_image(S.ACCEL_NONE)
mixed_ids = ids_of(reference)
for obj, what in ((0, "the surface"), (1, "the tubes"), (2, "the spheres")):
    check(mixed_ids.count(obj) > 30, f"mixed: {what} are seen ({mixed_ids.count(obj)} pixels)")
cases = [(S.ACCEL_BVH, None), (S.ACCEL_BINARY_BVH, None), (S.ACCEL_SPHERES, None)]
for accel in (S.ACCEL_KDTREE, S.ACCEL_GRID, S.ACCEL_OCTREE, S.ACCEL_BSP):
    cases += [(accel, S.STORAGE_EVERY_CELL), (accel, S.STORAGE_SMALLEST_CELL)]
cases.append((S.ACCEL_BSP, S.STORAGE_SPLIT))
for accel, storage in cases:
    other = mixed_image(accel, storage)
    same = colors_of(other) == colors_of(reference) and ids_of(other) == mixed_ids
    check(same, f"accel {accel} storage {storage}: the same image as testing every primitive")

# The tubes and spheres shadow the floor: floor pixels darker than with the
# floor alone under the same camera and light.
floor_only = tracer(floor.GetOutputPort())
for a in (floor_only,):
    a.AutoCameraOff()
    a.SetPosition(*reference.GetPosition())
    a.SetFocalPoint(*reference.GetFocalPoint())
    a.SetHeadlight(0)
    a.AddPointLight(0, 40, 0, 1, 1, 1, 1)
    a.Update()
floor_ids, floor_colors, mixed_colors = ids_of(floor_only), colors_of(floor_only), colors_of(reference)
shadowed = sum(1 for i in range(W * H) if mixed_ids[i] == 0 and floor_ids[i] == 0
               and mixed_colors[3 * i] + 30 < floor_colors[3 * i])
check(shadowed > 20, f"the tubes and spheres shadow the floor ({shadowed} pixels)")

# ---- a negative radius is an error ---------------------------------------------
bad = tracer(cloud.GetOutputPort())
bad.SetPointRadius(-1.0)
bad_errors = Errors(bad)
bad.Update()
check(any("PointRadius" in m for m in bad_errors.messages), "a negative PointRadius is an error")
check(bad.GetOutput().GetNumberOfPoints() == 0, "and the output is empty")

finish("lines and points")
