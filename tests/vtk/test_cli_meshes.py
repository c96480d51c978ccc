"""The rayscope command and the VTK module make the same mesh of a file.

1. Smooth normals: a sphere written as .vtp without normals is rendered by
   `rayscope render` (scene file) and by vtkRayScopeImageAlgorithm (the file
   through vtkXMLPolyDataReader) with the same camera, light and material: the
   two images are byte for byte the same, and differ from the flat-shaded
   render ("smooth": false), so both shade the sphere smooth.
2. color_by: a square of two cells with cell values 0 and 1 (and a point array
   that is 0 on the left and 1 on the right), unlit, rendered by the command
   with "color_by" and each color map: the pixels of the two halves have the
   map's end colors.
3. Bad color_by keys and an unknown array name: the command fails with one
   line on stderr that names the scene file and the problem.

Usage: test_cli_meshes.py RAYSCOPE_EXECUTABLE
"""
import json
import os
import subprocess
import sys

import vtk
import rayscope

OUT = os.environ.get("RAYSCOPE_TEST_OUTPUT", ".")
W, H = 64, 48


def write_vtp(data, name):
    path = os.path.join(OUT, name)
    w = vtk.vtkXMLPolyDataWriter()
    w.SetFileName(path)
    w.SetInputData(data)
    assert w.Write() == 1
    return path


def write_scene(name, scene):
    path = os.path.join(OUT, name)
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    return path


def render_cli(exe, scene_file):
    png = scene_file[:-len(".json")] + ".png"
    subprocess.run([exe, "render", "-q", scene_file, "-o", png], check=True)
    r = vtk.vtkPNGReader()  # VTK image rows: row 0 at the bottom, as the module's
    r.SetFileName(png)
    r.Update()
    return r.GetOutput()


def pixel(image, i, j):
    """RGB bytes of pixel (i, j), VTK image coordinates ((0, 0) bottom-left)."""
    a = image.GetPointData().GetScalars()
    return tuple(int(a.GetComponent(j * W + i, k)) for k in range(3))


def same_bytes(a, b):
    ca, cb = a.GetPointData().GetScalars(), b.GetPointData().GetScalars()
    assert ca.GetNumberOfTuples() == cb.GetNumberOfTuples() == W * H
    return all(ca.GetComponent(t, k) == cb.GetComponent(t, k)
               for t in range(W * H) for k in range(3))


def smooth_sphere(exe):
    sphere = vtk.vtkSphereSource()
    sphere.SetThetaResolution(16)
    sphere.SetPhiResolution(8)
    sphere.SetRadius(0.8)
    sphere.Update()
    data = vtk.vtkPolyData()
    data.DeepCopy(sphere.GetOutput())
    data.GetPointData().SetNormals(None)  # a file without normals
    vtp = write_vtp(data, "cli_sphere_no_normals.vtp")

    light = (2.0, 3.0, 4.0)
    scene = {
        "camera": {"eye": [0, 0, 3], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 40},
        "render": {"width": W, "height": H, "samples": 1, "max_depth": 2},
        "background": [0, 0, 1], "ambient_light": [1, 1, 1],
        "materials": {"white": {"color": [1, 1, 1], "ambient": 0, "diffuse": 1,
                                "specular": 0, "model": "blinn-phong"}},
        "lights": [{"type": "point", "position": list(light)}],
        "objects": [{"type": "mesh", "file": vtp, "material": "white"}],
    }
    cli = render_cli(exe, write_scene("cli_sphere_smooth.json", scene))
    scene["objects"][0]["smooth"] = False
    flat = render_cli(exe, write_scene("cli_sphere_flat.json", scene))

    reader = vtk.vtkXMLPolyDataReader()
    reader.SetFileName(vtp)
    alg = rayscope.vtkRayScopeImageAlgorithm()
    alg.AddInputConnection(reader.GetOutputPort())  # default converter and material
    alg.HeadlightOff()
    alg.AddPointLight(*light, 1, 1, 1, 1.0)
    alg.SetPosition(0, 0, 3)
    alg.SetFocalPoint(0, 0, 0)
    alg.SetViewUp(0, 1, 0)
    alg.SetViewAngle(40)
    alg.SetBackground(0, 0, 1)
    alg.SetSize(W, H)
    alg.SetMaxDepth(2)
    alg.Update()
    module = alg.GetOutput()

    assert same_bytes(cli, module), "the command and the module render the sphere differently"
    assert not same_bytes(cli, flat), "smooth and flat shading give the same image"
    print("sphere without normals: `rayscope render` == vtkRayScopeImageAlgorithm, "
          "both smooth (!= flat)")


def two_halves():
    """[-1, 1] x [-1, 1] at z = 0 in four cells of equal width. Cell array
    "Half": 0 on the left half, 1 on the right. Point array "X": 0 for
    x <= -0.5, 1 for x >= 0.5, linear between, so that the outer quarters are
    at the two ends of its range."""
    plane = vtk.vtkPlaneSource()
    plane.SetOrigin(-1, -1, 0)
    plane.SetPoint1(1, -1, 0)
    plane.SetPoint2(-1, 1, 0)
    plane.SetXResolution(4)
    plane.SetYResolution(1)
    plane.Update()
    data = vtk.vtkPolyData()
    data.DeepCopy(plane.GetOutput())
    data.GetPointData().Initialize()  # only the arrays below
    data.GetCellData().Initialize()
    half = vtk.vtkFloatArray()
    half.SetName("Half")
    for c in range(data.GetNumberOfCells()):
        bounds = data.GetCell(c).GetBounds()
        half.InsertNextValue(0.0 if bounds[0] + bounds[1] < 0 else 1.0)
    data.GetCellData().AddArray(half)
    x = vtk.vtkDoubleArray()
    x.SetName("X")
    for p in range(data.GetNumberOfPoints()):
        x.InsertNextValue(min(max(data.GetPoint(p)[0] + 0.5, 0.0), 1.0))
    data.GetPointData().AddArray(x)
    return write_vtp(data, "cli_two_halves.vtp")


def color_scene(vtp, color_by):
    return {
        "camera": {"eye": [0, 0, 2], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 60},
        "render": {"width": W, "height": H, "samples": 1},
        "background": [0, 0, 0], "ambient_light": [1, 1, 1],
        # Unlit: a pixel shows the vertex color as it is (sRGB byte in, byte out).
        "materials": {"unlit": {"color": [1, 1, 1], "ambient": 1, "diffuse": 0, "specular": 0}},
        "lights": [],
        "objects": [{"type": "mesh", "file": vtp, "material": "unlit", "color_by": color_by}],
    }


# The end colors of each map: VTK's lookup tables at the low and high end.
MAPS = {
    "grayscale": ((0, 0, 0), (255, 255, 255)),
    "rainbow": ((0, 0, 255), (255, 0, 0)),
    "cool-warm": ((59, 76, 192), (180, 4, 38)),
}


def check_colors(exe):
    vtp = two_halves()
    # Pixel centers at x = -0.79 and x = 0.79 on the square.
    left, right = (W // 4, H // 2), (3 * W // 4, H // 2)
    checked = 0
    for name, (lo, hi) in MAPS.items():
        for assoc, array in (("cell", "Half"), ("point", "X")):
            scene = color_scene(vtp, {"array": array, "association": assoc, "map": name})
            image = render_cli(exe, write_scene(f"cli_color_{name}_{assoc}.json", scene))
            for where, got, want in (("left", pixel(image, *left), lo),
                                     ("right", pixel(image, *right), hi)):
                assert all(abs(got[k] - want[k]) <= 1 for k in range(3)), \
                    (name, assoc, where, got, want)
            checked += 1
    # An explicit range: X over [0.5, 1] puts the left half at the low end.
    scene = color_scene(vtp, {"array": "X", "map": "grayscale", "range": [0.5, 1]})
    image = render_cli(exe, write_scene("cli_color_range.json", scene))
    assert pixel(image, W // 2 - 4, H // 2) == (0, 0, 0), pixel(image, W // 2 - 4, H // 2)
    assert pixel(image, *right) == (255, 255, 255), pixel(image, *right)
    print(f"color_by: {checked + 1} renders with the maps' end colors at known pixels")


def check_errors(exe):
    vtp = two_halves()
    cases = [
        ({"array": "Half", "association": "cell", "mapp": "rainbow"},
         r"objects[0].color_by: unknown key 'mapp'"),
        ({"array": "Half", "association": "cells"},
         'objects[0].color_by.association: expected "point" or "cell", got "cells"'),
        ({"array": "Half", "association": "cell", "map": "jet"},
         'objects[0].color_by.map: expected one of "cool-warm", "rainbow", "grayscale", '
         'got "jet"'),
        ({"array": "Half", "association": "cell", "range": [1, 0]},
         "objects[0].color_by.range: lo must be less than hi"),
        ({"association": "cell"}, "objects[0].color_by: needs an 'array'"),
        ({"array": "Nope"},
         f"objects[0].color_by.array: {vtp} has no point array 'Nope' (point arrays: X)"),
        ({"array": "X", "association": "cell"},
         f"objects[0].color_by.array: {vtp} has no cell array 'X' (cell arrays: Half)"),
    ]
    for k, (color_by, problem) in enumerate(cases):
        scene = write_scene(f"cli_color_error_{k}.json", color_scene(vtp, color_by))
        out = os.path.join(OUT, f"cli_color_error_{k}.png")
        if os.path.exists(out):
            os.remove(out)
        run = subprocess.run([exe, "render", "-q", scene, "-o", out],
                             capture_output=True, text=True)
        lines = run.stderr.splitlines()
        assert run.returncode != 0 and run.returncode < 128, (color_by, run.returncode)
        assert len(lines) == 1, (color_by, run.stderr)
        assert scene + ": " + problem in lines[0], (color_by, lines[0], problem)
        assert not os.path.exists(out), out
    print(f"color_by: {len(cases)} bad scene files, one error line each naming file and problem")


def main(exe):
    smooth_sphere(exe)
    check_colors(exe)
    check_errors(exe)


if __name__ == "__main__":
    main(sys.argv[1])
