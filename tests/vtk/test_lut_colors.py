"""Scalars are ray-traced in the colors VTK shows them in.

A flat, unlit plane (ambient 1, diffuse 0, no lights) seen head-on with a
parallel projection shows its surface colors unchanged, so every pixel can be
predicted exactly:

1. Cell scalars: each pixel is exactly the lookup table's color of the cell
   under its center (vtkLookupTable.MapValue with the mapper's scalar range),
   and exactly what vtkPolyDataMapper draws with OpenGL (lighting off).

2. Point scalars: each vertex gets exactly the lookup table's color. Inside a
   triangle RayScope interpolates the decoded (linear) colors and encodes the
   result; OpenGL interpolates the encoded bytes. Each rendering is checked
   against its own model (barycentric weights of the pixel center) within one
   level (rounding), and at each pixel the two renderings differ only by the
   difference of the two models there (plus rounding). The test reports the
   largest such difference (a few levels inside triangles whose vertex colors
   are far apart; 0 at the vertices).

Runs under xvfb-run (OpenGL).
"""
import math
import os
import sys

import vtk
import rayscope

W, H = 160, 120
SCALE = 1.5  # parallel scale: half the image height in world units
OUT = os.environ.get("RAYSCOPE_TEST_OUTPUT", ".")
BACKGROUND = (26, 51, 76)  # bytes: b / 255 encodes back to b exactly


def srgb_decode(b):
    s = b / 255.0
    return s / 12.92 if s <= 0.04045 else ((s + 0.055) / 1.055) ** 2.4


def srgb_encode(v):
    if v <= 0.0:
        return 0.0
    if v >= 1.0:
        return 1.0
    return 12.92 * v if v <= 0.0031308 else 1.055 * v ** (1.0 / 2.4) - 0.055


def make_plane(nx, ny):
    plane = vtk.vtkPlaneSource()
    plane.SetOrigin(-1.6, -1.2, 0.0)
    plane.SetPoint1(1.6, -1.2, 0.0)
    plane.SetPoint2(-1.6, 1.2, 0.0)
    plane.SetResolution(nx, ny)
    tri = vtk.vtkTriangleFilter()  # both renderers get the same triangles
    tri.SetInputConnection(plane.GetOutputPort())
    tri.Update()
    pd = vtk.vtkPolyData()
    pd.DeepCopy(tri.GetOutput())
    pd.GetPointData().Initialize()
    pts = vtk.vtkDoubleArray()
    pts.SetName("wave")
    for i in range(pd.GetNumberOfPoints()):
        x, y, _ = pd.GetPoint(i)
        pts.InsertNextValue(0.5 + 0.55 * math.sin(1.3 * x) * math.cos(1.1 * y))  # some out of range
    pd.GetPointData().SetScalars(pts)
    cells = vtk.vtkDoubleArray()
    cells.SetName("region")
    for c in range(pd.GetNumberOfCells()):
        cells.InsertNextValue(float((c // 2) % 7))  # quads keep one value for both triangles
    pd.GetCellData().SetScalars(cells)
    return pd


def make_lut():
    lut = vtk.vtkLookupTable()
    lut.SetNumberOfTableValues(64)
    lut.SetHueRange(0.66, 0.0)
    lut.SetSaturationRange(0.9, 0.6)
    lut.SetValueRange(0.35, 1.0)
    lut.Build()
    return lut


def reference_table(lut, lo, hi):
    """A copy of the table with the mapper's range. Build() completes the copy's
    out-of-range colors, as a mapper's MapScalars does before mapping."""
    ref = vtk.vtkLookupTable()
    ref.DeepCopy(lut)
    ref.Build()
    ref.SetRange(lo, hi)
    return ref


def configure(mapper, lut, cell):
    mapper.SetLookupTable(lut)
    if cell:
        mapper.SetScalarModeToUseCellData()
        mapper.SetScalarRange(0.0, 6.0)
    else:
        mapper.SetScalarModeToUsePointData()
        mapper.SetScalarRange(0.1, 0.9)


def ray_trace(pd, lut, cell):
    alg = rayscope.vtkRayScopeImageAlgorithm()
    alg.AddInputData(pd)
    configure(alg.GetConverter().GetMapper(), lut, cell)
    m = alg.GetMaterial()
    m.SetAmbient(1.0)
    m.SetDiffuse(0.0)
    alg.HeadlightOff()
    alg.SetBackground(*(b / 255.0 for b in BACKGROUND))
    alg.SetSize(W, H)
    alg.SetPosition(0, 0, 5)
    alg.ParallelProjectionOn()
    alg.SetParallelScale(SCALE)
    alg.Update()
    return alg.GetOutput().GetPointData().GetArray("Color")


def opengl(pd, lut, cell):
    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputData(pd)
    configure(mapper, lut, cell)
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().LightingOff()
    ren = vtk.vtkRenderer()
    ren.AddActor(actor)
    ren.SetBackground(*(b / 255.0 for b in BACKGROUND))
    cam = ren.GetActiveCamera()
    cam.SetPosition(0, 0, 5)
    cam.SetFocalPoint(0, 0, 0)
    cam.SetViewUp(0, 1, 0)
    cam.ParallelProjectionOn()
    cam.SetParallelScale(SCALE)
    ren.ResetCameraClippingRange()
    win = vtk.vtkRenderWindow()
    win.SetOffScreenRendering(1)
    win.SetMultiSamples(0)
    win.AddRenderer(ren)
    win.SetSize(W, H)
    win.Render()
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(win)
    grab.SetInputBufferTypeToRGB()
    grab.ReadFrontBufferOff()
    grab.Update()
    img = grab.GetOutput()
    assert img.GetDimensions()[:2] == (W, H), img.GetDimensions()
    return img.GetPointData().GetScalars()


def pixel_world(i, j):
    s = 2.0 * SCALE / H
    return ((i + 0.5 - W / 2) * s, (j + 0.5 - H / 2) * s, 0.0)


def inside(x, y, margin):
    return abs(x) < 1.6 - margin and abs(y) < 1.2 - margin


def save(colors, name):
    img = vtk.vtkImageData()
    img.SetDimensions(W, H, 1)
    img.GetPointData().SetScalars(colors)
    w = vtk.vtkPNGWriter()
    w.SetFileName(os.path.join(OUT, name))
    w.SetInputData(img)
    w.Write()


def test_cell_scalars():
    pd = make_plane(12, 9)
    lut = make_lut()
    ours = ray_trace(pd, lut, cell=True)
    gl = opengl(pd, lut, cell=True)
    save(ours, "lut_cells_rayscope.png")
    save(gl, "lut_cells_opengl.png")
    ref = reference_table(lut, 0.0, 6.0)
    expected = ref.MapScalars(pd.GetCellData().GetScalars(), vtk.VTK_COLOR_MODE_MAP_SCALARS, 0)
    loc = vtk.vtkCellLocator()
    loc.SetDataSet(pd)
    loc.BuildLocator()
    gen = vtk.vtkGenericCell()
    pc, wts = [0.0] * 3, [0.0] * 3
    checked = gl_checked = 0
    max_gl = 0
    for j in range(H):
        for i in range(W):
            x, y, z = pixel_world(i, j)
            got = ours.GetTuple3(j * W + i)
            if not inside(x, y, 0.0):
                assert got == BACKGROUND, (i, j, got)
                continue
            c = loc.FindCell((x, y, z), 1e-9, gen, pc, wts)
            assert c >= 0, (i, j)
            want = expected.GetTuple4(c)[:3]
            assert got == want, (i, j, got, want)
            checked += 1
            # OpenGL: compare where the pixel's neighbourhood is one cell color
            # (rasterisation rules decide edge pixels differently).
            if not inside(x, y, 2.0 * 2.0 * SCALE / H):
                continue
            same = all(ours.GetTuple3((j + dj) * W + i + di) == got
                       for dj in (-1, 0, 1) for di in (-1, 0, 1))
            if same:
                g = gl.GetTuple3(j * W + i)
                max_gl = max(max_gl, max(abs(a - b) for a, b in zip(g, got)))
                gl_checked += 1
    print(f"cell scalars: {checked} pixels == lookup table exactly; "
          f"{gl_checked} pixels vs OpenGL, max difference {max_gl} levels")
    assert checked > W * H // 2
    assert gl_checked > W * H // 3
    assert max_gl == 0, max_gl


def test_point_scalars():
    pd = make_plane(48, 36)
    lut = make_lut()
    # The converter's vertex colors are the lookup table's colors exactly.
    conv = rayscope.vtkRayScopeMeshConverter()
    configure(conv.GetMapper(), lut, cell=False)
    tri = vtk.vtkPolyData()
    assert conv.Convert(pd, tri) == 1
    assert tri.GetNumberOfPoints() == pd.GetNumberOfPoints()
    ref = reference_table(lut, 0.1, 0.9)
    colors = tri.GetPointData().GetArray("Colors")
    expected = ref.MapScalars(pd.GetPointData().GetScalars(), vtk.VTK_COLOR_MODE_MAP_SCALARS, 0)
    for p in range(pd.GetNumberOfPoints()):
        assert colors.GetTuple4(p) == expected.GetTuple4(p), p

    ours = ray_trace(pd, lut, cell=False)
    gl = opengl(pd, lut, cell=False)
    save(ours, "lut_points_rayscope.png")
    save(gl, "lut_points_opengl.png")
    loc = vtk.vtkCellLocator()
    loc.SetDataSet(tri)
    loc.BuildLocator()
    gen = vtk.vtkGenericCell()
    pc, wts = [0.0] * 3, [0.0] * 3
    ids = vtk.vtkIdList()
    max_ours = max_gl = max_models = max_diff = 0.0
    n = 0
    for j in range(H):
        for i in range(W):
            x, y, z = pixel_world(i, j)
            if not inside(x, y, 2.0 * 2.0 * SCALE / H):
                continue
            c = loc.FindCell((x, y, z), 1e-9, gen, pc, wts)
            assert c >= 0
            tri.GetCellPoints(c, ids)
            vb = [colors.GetTuple4(ids.GetId(k))[:3] for k in range(3)]
            for ch in range(3):
                linear = sum(wts[k] * srgb_decode(vb[k][ch]) for k in range(3))
                model_ours = 255.0 * srgb_encode(linear)
                model_gl = sum(wts[k] * vb[k][ch] for k in range(3))
                o = ours.GetTuple3(j * W + i)[ch]
                g = gl.GetTuple3(j * W + i)[ch]
                max_ours = max(max_ours, abs(o - model_ours))
                max_gl = max(max_gl, abs(g - model_gl))
                max_models = max(max_models, abs(model_ours - model_gl))
                max_diff = max(max_diff, abs(o - g))
                # Per pixel: the renderings differ by the models' difference,
                # up to the rounding of each (half a level each).
                assert abs(o - g) <= abs(model_ours - model_gl) + 1.0, (i, j, ch, o, g)
            n += 1
    print(f"point scalars: {n} pixels; RayScope vs its model (linear interpolation) "
          f"{max_ours:.3f}, OpenGL vs its model (byte interpolation) {max_gl:.3f}, "
          f"models differ by up to {max_models:.3f}, renderings by up to {max_diff:.0f} levels")
    assert n > W * H // 2
    assert max_ours <= 0.5 + 1e-3, max_ours  # rounding only
    assert max_gl <= 1.0, max_gl  # rounding of GL's interpolator
    assert max_diff <= max_models + 1.0, (max_diff, max_models)


if __name__ == "__main__":
    test_cell_scalars()
    test_point_scalars()
    print("ok")
    sys.exit(0)
