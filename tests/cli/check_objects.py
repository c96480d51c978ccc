#!/usr/bin/python3
"""The objects a scene's pixels show: renders SCENE (a scene or mesh file) at
32x24 with `rayscope inspect --rect` over every pixel and passes when the
primary rays hit exactly the objects 0..N-1, object I named as NAME_I says
(a regular expression matched in full), so that the blocks of a composite
file are told apart by their object ids.

Usage: check_objects.py RAYSCOPE SCENE NAME_0 [NAME_1 ...]
"""
import json
import re
import subprocess
import sys

W, H = 32, 24
exe, scene, *names = sys.argv[1:]
run = subprocess.run([exe, "inspect", scene, "--size", f"{W}x{H}", "--rect", f"0,0,{W},{H}",
                      "--max-depth", "0", "--format", "json"],
                     capture_output=True, text=True, check=False)
if run.returncode != 0:
    sys.exit(f"rayscope inspect failed ({run.returncode}): {run.stderr}")
seen = {}
for pixel in json.loads(run.stdout)["pixels"]:
    for ray in pixel["rays"]:
        if ray["kind"] == "primary" and ray["hit"]:
            seen.setdefault(ray["object"], set()).add(ray["object_name"])
if sorted(seen) != list(range(len(names))):
    sys.exit(f"{scene}: the pixels show objects {sorted(seen)}, expected 0..{len(names) - 1}")
for i, pattern in enumerate(names):
    for name in seen[i]:
        if not re.fullmatch(pattern, name):
            sys.exit(f"{scene}: object {i} is named '{name}', expected /{pattern}/")
print(f"{scene}: objects " + ", ".join(f"{i} '{sorted(seen[i])[0]}'" for i in sorted(seen)))
