"""Pixel coordinates of the command line and of the VTK module, converted.

`rayscope` counts pixels from the top-left corner (rows go down, as in the
image file); the VTK classes count from the bottom-left (rows go up, as in
vtkImageData). So pixel (X, Y) of `rayscope inspect` is pixel (X, H-1-Y) of
vtkRayScopeRayTreeSource.

One sphere sits in the upper left of the view. The same scene is built in VTK
(a vtkSphereSource into vtkRayScopeImageAlgorithm) and as a scene file for the
command (the module's converted triangles written as binary .vtk, read back bit
for bit; values both sides turn into the same floats). Checked:
- the command's pixel where the sphere's center projects, counted from the
  top-left, hits the sphere, and the command's (0, 0) is the top-left corner;
- for every pixel of a grid, `rayscope inspect --pixel X,Y --format json`
  equals the ray tree of vtkRayScopeRayTreeSource at (X, H-1-Y): the same rays
  (kind, depth, parent, hit, object, start and end points, returned color) and
  the same pixel color;
- the conversion matters: at (X, Y) unconverted the VTK trees differ.

Usage: test_pixel_origin.py RAYSCOPE_EXECUTABLE
"""
import json
import math
import os
import subprocess
import sys

import vtk
import rayscope

OUT = os.environ.get("RAYSCOPE_TEST_OUTPUT", ".")
W, H = 40, 30
CENTER, RADIUS = (-0.6, 0.45, 0.0), 0.4
EYE, FOV = (0.0, 0.0, 4.0), 30.0
LIGHT, INTENSITY = (1.0, 3.0, 4.0), 0.75


def sphere_source():
    s = vtk.vtkSphereSource()
    s.SetCenter(*CENTER)
    s.SetRadius(RADIUS)
    s.SetThetaResolution(24)
    s.SetPhiResolution(12)
    return s


def vtk_scene(src):
    alg = rayscope.vtkRayScopeImageAlgorithm()
    alg.AddInputConnection(src.GetOutputPort())
    m = rayscope.vtkRayScopeMaterial()
    m.SetColor(1, 1, 1)
    m.SetAmbient(0.25)
    m.SetDiffuse(0.75)
    m.SetSpecular(0.0)
    m.SetSpecularPower(1.0)
    alg.SetInputMaterial(0, m)
    alg.HeadlightOff()
    alg.AddPointLight(*LIGHT, 1, 1, 1, INTENSITY)
    alg.SetPosition(*EYE)
    alg.SetFocalPoint(0, 0, 0)
    alg.SetViewUp(0, 1, 0)
    alg.SetViewAngle(FOV)
    alg.SetBackground(0, 0, 1)
    alg.SetSize(W, H)
    alg.SetSamples(1)
    alg.SetMaxDepth(2)
    return alg


def scene_file(src):
    src.Update()
    tri = vtk.vtkPolyData()
    assert rayscope.vtkRayScopeMeshConverter().Convert(src.GetOutput(), tri) == 1
    mesh = os.path.join(OUT, "pixel_origin_sphere.vtk")
    w = vtk.vtkPolyDataWriter()
    w.SetFileName(mesh)
    w.SetInputData(tri)
    w.SetFileTypeToBinary()
    assert w.Write() == 1
    scene = {
        "camera": {"eye": list(EYE), "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": FOV},
        "render": {"width": W, "height": H, "samples": 1, "max_depth": 2},
        "background": [0, 0, 1],
        "ambient_light": [1, 1, 1],
        "materials": {"m": {"color": [1, 1, 1], "ambient": 0.25, "diffuse": 0.75,
                            "specular": 0.0, "shininess": 1.0, "model": "blinn-phong"}},
        "lights": [{"type": "point", "position": list(LIGHT), "intensity": INTENSITY}],
        "objects": [{"type": "mesh", "name": "sphere", "file": mesh, "material": "m"}],
    }
    path = os.path.join(OUT, "pixel_origin.json")
    with open(path, "w") as f:
        json.dump(scene, f)
    return path


def cli_trees(exe, scene, pixels):
    """`rayscope inspect --format json`, command-line pixel coordinates."""
    cmd = [exe, "inspect", scene, "--format", "json"]
    for x, y in pixels:
        cmd += ["--pixel", f"{x},{y}"]
    records = json.loads(subprocess.run(cmd, check=True, capture_output=True,
                                        text=True).stdout)["pixels"]
    trees = {}
    for rec in records:
        rays = [(r["kind"], r["depth"], r["parent"],
                 r["occluded"] if r["kind"] == "shadow" else r["hit"],
                 r.get("object", r.get("occluder", -1)) if r.get("hit") or r.get("occluded") else -1,
                 tuple(r["origin"]),
                 tuple(r["point"]) if r["kind"] != "shadow" and r["hit"] else None,
                 tuple(r["color"]))
                for r in rec["rays"]]
        trees[tuple(rec["pixel"])] = (tuple(rec["color"]), rays)
    return trees


def vtk_tree(source, i, j):
    """vtkRayScopeRayTreeSource's tree of pixel (i, j), VTK image coordinates."""
    source.SetPixel(i, j)
    source.Update()
    pd = source.GetOutput()
    cd = pd.GetCellData()
    rays = []
    for c in range(pd.GetNumberOfVerts(), pd.GetNumberOfCells()):
        kind = cd.GetAbstractArray("KindName").GetValue(c)
        hit = cd.GetArray("Occluded" if kind == "shadow" else "Hit").GetValue(c)
        cell = pd.GetCell(c)
        rays.append((kind, cd.GetArray("Depth").GetValue(c), cd.GetArray("ParentId").GetValue(c),
                     bool(hit), cd.GetArray("ObjectId").GetValue(c) if hit else -1,
                     pd.GetPoint(cell.GetPointId(0)),
                     pd.GetPoint(cell.GetPointId(1)) if kind != "shadow" and hit else None,
                     cd.GetArray("Color").GetTuple3(c)))
    return pd.GetFieldData().GetArray("PixelColor").GetTuple3(0), rays


def main(exe):
    src = sphere_source()
    alg = vtk_scene(src)
    scene = scene_file(src)

    # Where the sphere's center lands, counted from the top-left corner.
    t = math.tan(math.radians(FOV) / 2)
    ndc_x = CENTER[0] / (EYE[2] - CENTER[2]) / (t * W / H)
    ndc_y = CENTER[1] / (EYE[2] - CENTER[2]) / t
    top_left = (int((1 + ndc_x) / 2 * W), int((1 - ndc_y) / 2 * H))
    assert top_left[0] < W // 2 and top_left[1] < H // 2, top_left
    pixels = [top_left, (0, 0), (W - 1, H - 1)]
    pixels += [(x, y) for y in range(1, H, 4) for x in range(2, W, 5)]
    cli = cli_trees(exe, scene, pixels)
    assert cli[top_left][1][0][3] and cli[top_left][1][0][4] == 0, \
        ("the sphere is not at the top-left pixel", top_left, cli[top_left][1][0])
    assert not cli[(0, 0)][1][0][3], "pixel (0, 0) hit something"

    source = rayscope.vtkRayScopeRayTreeSource()
    source.SetSceneSource(alg)
    differs = 0
    for (x, y), tree in cli.items():
        assert vtk_tree(source, x, H - 1 - y) == tree, \
            (f"rayscope pixel ({x}, {y}) != VTK pixel ({x}, {H - 1 - y})", tree,
             vtk_tree(source, x, H - 1 - y))
        differs += vtk_tree(source, x, y) != tree
    assert differs > 0, "the VTK trees at unconverted (X, Y) are the same: the test shows nothing"
    print(f"{len(cli)} pixels: rayscope (X, Y) == VTK (X, {H}-1-Y); "
          f"{differs} of them differ at VTK (X, Y)")


if __name__ == "__main__":
    main(sys.argv[1])
