"""paraview.example.*: runs an example script with -o PNG, then checks the
picture: written, at the example's size (960x480), and not blank (hundreds of
distinct colors).

Usage: pvpython check_screenshot.py EXAMPLE.py OUT.png
"""
import os
import runpy
import sys

from vtkmodules.vtkIOImage import vtkPNGReader

example, out = sys.argv[1], sys.argv[2]
if os.path.exists(out):
    os.remove(out)
sys.argv = [example, "-o", out]
runpy.run_path(example, run_name="__main__")
assert os.path.exists(out), f"{example} wrote no {out}"
reader = vtkPNGReader()
reader.SetFileName(out)
reader.Update()
img = reader.GetOutput()
w, h, _ = img.GetDimensions()
assert (w, h) == (960, 480), (w, h)
colors = img.GetPointData().GetScalars()
seen = set()
for k in range(0, w * h, 7):
    seen.add(tuple(int(colors.GetComponent(k, c)) for c in range(3)))
assert len(seen) > 500, f"{out} looks blank: {len(seen)} colors"
print(f"{out}: {w}x{h}, {len(seen)} distinct colors (every 7th pixel)")
