#!/usr/bin/python3
"""Two scenes render the same picture: renders SCENE_A and SCENE_B (scene or
mesh files) at 64x48 into OUT_PREFIX.a.png and OUT_PREFIX.b.png and passes
when both exit 0 and the pictures have the same pixels, and not all the same
(something is drawn).

Usage: same_pixels.py RAYSCOPE SCENE_A SCENE_B OUT_PREFIX
"""
import os
import subprocess
import sys

import vtk

exe, a, b, prefix = sys.argv[1:5]


def pixels(scene, png):
    if os.path.exists(png):
        os.remove(png)
    subprocess.run([exe, "render", "-q", scene, "--size", "64x48", "-o", png], check=True)
    reader = vtk.vtkPNGReader()
    reader.SetFileName(png)
    reader.Update()
    scalars = reader.GetOutput().GetPointData().GetScalars()
    return [scalars.GetTuple(i) for i in range(scalars.GetNumberOfTuples())]


pa, pb = pixels(a, prefix + ".a.png"), pixels(b, prefix + ".b.png")
if len(set(pa)) < 2:
    sys.exit(f"{a}: a blank picture")
differ = sum(x != y for x, y in zip(pa, pb))
if len(pa) != len(pb) or differ:
    sys.exit(f"{a} and {b} render differently: {differ} of {len(pa)} pixels differ")
print(f"{a} renders as {b}: {len(pa)} pixels, {len(set(pa))} colors")
