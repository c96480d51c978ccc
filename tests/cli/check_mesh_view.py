"""A mesh file given as the scene renders with a camera that frames it, a
headlight and the default material (`rayscope render MESH` and `rayscope
inspect MESH`).

Renders MESH at 64x48 and checks the image: it exists, the middle pixel shows
the mesh (lit: brighter than the background), the four corners show the
background, and the mesh covers a fair part of the picture without touching its
top and bottom rows (framed, not cropped). Then `rayscope inspect` of the middle
pixel must hit the mesh (object 0), of a corner must miss.

Usage: check_mesh_view.py RAYSCOPE MESH OUTPUT_FOLDER
"""
import json
import os
import subprocess
import sys

import vtk

W, H = 64, 48

exe, mesh, out = sys.argv[1:4]
png = os.path.join(out, "mesh_view_" + os.path.basename(mesh).replace(".", "_") + ".png")
if os.path.exists(png):
    os.remove(png)
subprocess.run([exe, "render", "-q", mesh, "--size", f"{W}x{H}", "-o", png], check=True)
assert os.path.getsize(png) > 0, png

reader = vtk.vtkPNGReader()
reader.SetFileName(png)
reader.Update()
img = reader.GetOutput()
assert img.GetDimensions()[:2] == (W, H), img.GetDimensions()
scalars = img.GetPointData().GetScalars()


def rgb(x, y):
    """Pixel (x, y) with y from the top, as rayscope counts (VTK's rows go up)."""
    return tuple(int(scalars.GetComponent((H - 1 - y) * W + x, c)) for c in range(3))


background = rgb(0, 0)
for x, y in ((0, 0), (W - 1, 0), (0, H - 1), (W - 1, H - 1)):
    assert rgb(x, y) == background, ("corner", x, y, rgb(x, y), background)
middle = rgb(W // 2, H // 2)
assert sum(middle) > sum(background) + 60, ("middle pixel not lit", middle, background)
covered = [[rgb(x, y) != background for x in range(W)] for y in range(H)]
share = sum(map(sum, covered)) / (W * H)
assert share > 0.05, ("mesh covers too little of the image", share)
assert not any(covered[0]) and not any(covered[-1]), "mesh touches the top or bottom row"

def inspect(x, y):
    r = subprocess.run([exe, "inspect", mesh, "--size", f"{W}x{H}", "--pixel", f"{x},{y}",
                        "--format", "json"], check=True, capture_output=True, text=True)
    return json.loads(r.stdout)["rays"][0]


hit = inspect(W // 2, H // 2)
assert hit["hit"] and hit["object"] == 0, hit
assert not inspect(0, 0)["hit"]
print(f"{mesh}: framed, lit, {share:.0%} of the image")
