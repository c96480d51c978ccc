"""vtkRayScopePass from Python: a VTK application switches to ray tracing with
renderer.SetPass(pass).

1. A renderer with the Stanford bunny (read by vtkOBJReader, colored by point
   scalars through its mapper's lookup table), a reflective floor and a glass
   sphere is rendered through the pass; the window shows byte for byte the
   image vtkRayScopeImageAlgorithm renders after CopyRenderer(renderer).
2. The pass's scene is the scene source of a vtkRayScopeRayTreeSource: the
   primary ray of a pixel of the window starts at the camera and hits the
   object the pass's ObjectId image shows there.
3. The OpenGL image of the same renderer (no pass) covers the same pixels
   with geometry as the ray-traced one (silhouettes agree except at edges).

Runs under xvfb-run (OpenGL). Writes render_pass.png to RAYSCOPE_TEST_OUTPUT.
"""
import os
import sys

import vtk
import rayscope

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from script_checks import check, finish  # noqa: E402

W, H = 200, 150
OUT = os.environ.get("RAYSCOPE_TEST_OUTPUT", ".")
BUNNY = "/usr/share/glmark2/models/bunny.obj"


def grab(window):
    w2i = vtk.vtkWindowToImageFilter()
    w2i.SetInput(window)
    w2i.ReadFrontBufferOff()
    w2i.ShouldRerenderOff()
    w2i.Update()
    img = vtk.vtkImageData()
    img.DeepCopy(w2i.GetOutput())
    return img


def max_diff(a, b):
    sa, sb = a.GetPointData().GetScalars(), b.GetPointData().GetScalars()
    if sa.GetNumberOfTuples() != sb.GetNumberOfTuples():
        return 1000
    m = 0
    for i in range(sb.GetNumberOfTuples()):
        for k in range(3):
            m = max(m, abs(sa.GetComponent(i, k) - sb.GetComponent(i, k)))
    return m


# The scene: ordinary VTK actors. scripts/setup installs the bunny
# (glmark2-data); a missing file is a failure, not a reason to test less.
check(os.path.exists(BUNNY), "%s exists (scripts/setup installs glmark2-data)" % BUNNY)
reader = vtk.vtkOBJReader()
reader.SetFileName(BUNNY)
source = reader
source.Update()
bounds = source.GetOutput().GetBounds()
elevation = vtk.vtkElevationFilter()
elevation.SetInputConnection(source.GetOutputPort())
elevation.SetLowPoint(0, bounds[2], 0)
elevation.SetHighPoint(0, bounds[3], 0)
mapper = vtk.vtkPolyDataMapper()
mapper.SetInputConnection(elevation.GetOutputPort())
bunny = vtk.vtkActor()
bunny.SetMapper(mapper)
bunny.GetProperty().SetSpecular(0.3)
bunny.GetProperty().SetSpecularPower(20)

size = max(bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4])
cx, cz = 0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[4] + bounds[5])
plane = vtk.vtkPlaneSource()
plane.SetOrigin(cx - 2 * size, bounds[2], cz + 2 * size)
plane.SetPoint1(cx + 2 * size, bounds[2], cz + 2 * size)
plane.SetPoint2(cx - 2 * size, bounds[2], cz - 2 * size)
floor_mapper = vtk.vtkPolyDataMapper()
floor_mapper.SetInputConnection(plane.GetOutputPort())
floor = vtk.vtkActor()
floor.SetMapper(floor_mapper)
floor.GetProperty().SetColor(0.75, 0.75, 0.8)
rayscope.vtkRayScopeMaterial.SetPropertyReflectivity(floor.GetProperty(), 0.35)

ball = vtk.vtkSphereSource()
ball.SetRadius(0.22 * size)
ball.SetThetaResolution(48)
ball.SetPhiResolution(24)
ball_mapper = vtk.vtkPolyDataMapper()
ball_mapper.SetInputConnection(ball.GetOutputPort())
glass = vtk.vtkActor()
glass.SetMapper(ball_mapper)
glass.SetPosition(bounds[1] + 0.1 * size, bounds[2] + 0.22 * size, bounds[5])
glass.GetProperty().SetOpacity(0.05)

renderer = vtk.vtkRenderer()
for a in (bunny, floor, glass):
    renderer.AddActor(a)
light = vtk.vtkLight()
light.SetLightTypeToSceneLight()
light.SetPositional(True)
light.SetConeAngle(90)
light.SetPosition(cx + size, bounds[3] + 2 * size, cz + 2 * size)
renderer.AddLight(light)
renderer.SetBackground(0.15, 0.15, 0.2)
camera = renderer.GetActiveCamera()
camera.SetFocalPoint(cx, 0.5 * (bounds[2] + bounds[3]), cz)
camera.SetPosition(cx + 0.6 * size, bounds[3] + 0.6 * size, cz + 2.6 * size)
camera.SetViewAngle(35)

window = vtk.vtkRenderWindow()
window.SetSize(W, H)
window.SetOffScreenRendering(1)
window.AddRenderer(renderer)

# 3 first: the OpenGL image, before the pass is set.
window.Render()
opengl = grab(window)

rt_pass = rayscope.vtkRayScopePass()
rt_pass.GetImageAlgorithm().SetSamples(2)  # the pass renders with its algorithm's settings
renderer.SetPass(rt_pass)
window.Render()
shown = grab(window)
check(rt_pass.GetNumberOfRenderedProps() == 3, "the pass traced 3 actors")
print("pass render: %.3f s (%d x %d, 2x2 samples)" % (rt_pass.GetLastRenderTime(), W, H))

# 1. The image algorithm on the same renderer.
alg = rayscope.vtkRayScopeImageAlgorithm()
check(alg.CopyRenderer(renderer) == 3, "CopyRenderer found 3 actors")
alg.SetSamples(2)
alg.Update()
traced = alg.GetOutput()
check(max_diff(shown, traced) == 0, "window == image algorithm, byte for byte")

writer = vtk.vtkPNGWriter()
writer.SetInputData(shown)
writer.SetFileName(os.path.join(OUT, "render_pass.png"))
writer.Write()

# 2. The ray tree of the pixel under the bunny's center, from the pass's scene.
ids = rt_pass.GetLastImage().GetPointData().GetArray("ObjectId")
pixel = None
for j in range(H // 2, H):
    for i in range(W // 2 - 20, W // 2 + 20):
        if ids.GetValue(j * W + i) == 0:
            pixel = (i, j)
            break
    if pixel:
        break
check(pixel is not None, "a pixel shows the bunny")
tree = rayscope.vtkRayScopeRayTreeSource()
tree.SetSceneSource(rt_pass.GetImageAlgorithm())
tree.SetPixel(*pixel)
tree.SetSample(0)
tree.Update()
poly = tree.GetOutput()
cd = poly.GetCellData()
kinds = cd.GetArray("Kind")
first_line = None
for c in range(poly.GetNumberOfCells()):
    if poly.GetCellType(c) == vtk.VTK_LINE and kinds.GetValue(c) == 0:
        first_line = c
        break
check(first_line is not None, "the tree has a primary ray")
if first_line is not None:
    p0 = poly.GetPoint(poly.GetCell(first_line).GetPointId(0))
    eye = camera.GetPosition()
    d = max(abs(p0[k] - eye[k]) for k in range(3))
    check(d < 1e-4 * size, "the primary ray starts at the camera (off by %.2g)" % d)
    check(cd.GetArray("ObjectId").GetValue(first_line) == 0, "the primary ray hits the bunny")

# 3. Silhouettes: pixels covered by geometry in the OpenGL and ray-traced images.
bg = [round(255 * v) for v in renderer.GetBackground()]


def covered(img, i):
    s = img.GetPointData().GetScalars()
    return any(abs(s.GetComponent(i, k) - bg[k]) > 2 for k in range(3))


n = W * H
differ = sum(1 for i in range(n) if covered(opengl, i) != covered(shown, i))
print("coverage differs at %d of %d pixels" % (differ, n))
# The two rasterisations differ along silhouettes (and where the ray tracer
# shows the background through glass); a wrong camera or a missing actor
# would differ in thousands of pixels.
check(differ < 0.01 * n, "OpenGL and ray-traced coverage agree (< 1% of pixels differ)")

finish("render pass")
