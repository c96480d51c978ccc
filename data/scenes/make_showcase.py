#!/usr/bin/env python3
"""Writes the acceleration-structure showcase scenes (docs/acceleration.md).

Each scene shows where some structure wins and another loses:

- teapot_in_stadium.json: the classic "teapot in a stadium" (Haines). A small,
  detailed object (the Stanford bunny plays the teapot: 69,666 triangles in
  a 1.5-unit box) in the middle of a big, sparse stadium (stadium.obj: tiers
  of seats 40 to 70 units away, a few thousand large triangles). A uniform
  grid sized from the object count spreads its cells over the whole stadium,
  so the bunny falls into a handful of crowded cells; hierarchies adapt.
- many_spheres.json: many equal objects, evenly spread on a plane (24 x 24
  spheres of one size): the uniform grid's best case, every cell about as
  full as the next.
- thin_triangles.json: long thin triangles that straddle every split
  (slivers.obj: 1,200 straws, each about 6 to 9 units long and 0.05 wide, in
  every direction across a 10-unit box). Every-cell storage stores each one
  in very many cells; smallest-cell storage keeps them high in the tree; the
  BVH's boxes overlap.

The meshes are made here (no download, nothing third-party) from a fixed
seed, so the files are the same on every run. `--check` writes nothing and
exits non-zero when a committed file differs from what this script makes
(the test data.showcase.current runs it).

Usage: make_showcase.py [--check]
"""

import json
import math
import pathlib
import random
import sys

HERE = pathlib.Path(__file__).resolve().parent
MESHES = HERE.parent / "meshes"
BUNNY = "/usr/share/glmark2/models/bunny.obj"


def fmt(x):
    """A coordinate with 4 decimals and no negative zero."""
    s = f"{x:.4f}"
    return "0.0000" if s == "-0.0000" else s


def obj_text(header, vertices, faces):
    lines = [f"# {line}" if line else "#" for line in header.splitlines()]
    lines += [f"v {fmt(x)} {fmt(y)} {fmt(z)}" for x, y, z in vertices]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces]
    return "\n".join(lines) + "\n"


def stadium():
    """Tiers of seats around the origin: each tier a step (tread and riser)
    of a ring, SEGMENTS quads around, plus the outer wall."""
    segments, tiers = 64, 12
    r0, r1 = 40.0, 70.0
    rise = 1.5
    vertices, faces = [], []

    def ring(r, y):
        first = len(vertices)
        for k in range(segments):
            a = 2.0 * math.pi * k / segments
            vertices.append((r * math.cos(a), y, r * math.sin(a)))
        return first

    def band(lo, hi):  # quads between two rings of equal size
        for k in range(segments):
            k1 = (k + 1) % segments
            faces.append((lo + k, lo + k1, hi + k1))
            faces.append((lo + k, hi + k1, hi + k))

    depth = (r1 - r0) / tiers
    for t in range(tiers):
        r, y = r0 + t * depth, t * rise
        riser_lo = ring(r, y)
        riser_hi = ring(r, y + rise)
        tread_out = ring(r + depth, y + rise)
        band(riser_lo, riser_hi)
        band(riser_hi, tread_out)
    wall_top = ring(r1, tiers * rise + 4.0)
    band(len(vertices) - 2 * segments, wall_top)
    header = (
        "Stadium for data/scenes/teapot_in_stadium.json, made by data/scenes/make_showcase.py:\n"
        f"{tiers} tiers of seats from r = {r0:g} to {r1:g} around the origin, {segments} segments."
    )
    return obj_text(header, vertices, faces)


def slivers(rng):
    """Long thin triangles ("straws") in every direction across a 10-unit box."""
    count = 1200
    vertices, faces = [], []
    for _ in range(count):
        center = (rng.uniform(-5, 5), rng.uniform(0.5, 6.5), rng.uniform(-5, 5))
        # A uniform direction, a length of 6 to 9 units, a width of 0.05.
        z = rng.uniform(-1, 1)
        phi = rng.uniform(0, 2 * math.pi)
        s = math.sqrt(1 - z * z)
        d = (s * math.cos(phi), z, s * math.sin(phi))
        half = 0.5 * rng.uniform(6, 9)
        # Any unit vector across d gives the width.
        helper = (0.0, 1.0, 0.0) if abs(d[1]) < 0.9 else (1.0, 0.0, 0.0)
        w = (d[1] * helper[2] - d[2] * helper[1], d[2] * helper[0] - d[0] * helper[2],
             d[0] * helper[1] - d[1] * helper[0])
        wl = math.sqrt(sum(c * c for c in w))
        w = tuple(0.025 * c / wl for c in w)
        first = len(vertices)
        vertices.append(tuple(center[i] - half * d[i] for i in range(3)))
        vertices.append(tuple(center[i] + half * d[i] - w[i] for i in range(3)))
        vertices.append(tuple(center[i] + half * d[i] + w[i] for i in range(3)))
        faces.append((first, first + 1, first + 2))
    header = (
        "Slivers for data/scenes/thin_triangles.json, made by data/scenes/make_showcase.py:\n"
        f"{count} triangles 6 to 9 units long and 0.05 wide, uniform directions."
    )
    return obj_text(header, vertices, faces)


CHECKER = {"color": [0.9, 0.9, 0.9], "ambient": 0.15, "diffuse": 0.85, "reflectivity": 0.2,
           "checker": {"color": [0.15, 0.15, 0.18], "size": 1.0}}
LIGHTS = [
    {"type": "point", "name": "key", "position": [-6, 12, 9], "intensity": 0.8},
    {"type": "directional", "name": "fill", "direction": [0.6, -1, -0.3], "intensity": 0.35},
]


def scene(camera, materials, objects):
    return {
        "camera": camera,
        "render": {"width": 640, "height": 480, "samples": 1, "max_depth": 4},
        "background": [0.55, 0.7, 0.9],
        "materials": materials,
        "lights": LIGHTS,
        "objects": objects,
    }


def teapot_in_stadium():
    return scene(
        {"eye": [0.0, 2.2, 6.5], "look_at": [0.0, 1.2, 0.0], "up": [0, 1, 0], "fov": 40},
        {"checker": CHECKER,
         "clay": {"color": [0.85, 0.6, 0.45], "ambient": 0.15, "diffuse": 0.8, "specular": 0.3,
                  "shininess": 40},
         "concrete": {"color": [0.6, 0.62, 0.66], "ambient": 0.2, "diffuse": 0.8}},
        [
            {"type": "plane", "name": "field", "point": [0, 0, 0], "normal": [0, 1, 0],
             "material": "checker"},
            {"type": "mesh", "name": "stadium", "file": "../meshes/stadium.obj",
             "material": "concrete"},
            {"type": "mesh", "name": "teapot (the bunny)", "file": BUNNY,
             "transform": {"translate": [0.0, 1.1, 0.0], "rotate": [0, 20, 0], "scale": 1.1},
             "material": "clay"},
        ]
    )


def many_spheres():
    objects = [{"type": "plane", "name": "floor", "point": [0, 0, 0], "normal": [0, 1, 0],
                "material": "checker"}]
    n, spacing, radius = 24, 1.0, 0.35
    for i in range(n):
        for k in range(n):
            x = (i - (n - 1) / 2) * spacing
            z = (k - (n - 1) / 2) * spacing
            objects.append({"type": "sphere", "center": [x, radius, z], "radius": radius,
                            "material": "red" if (i + k) % 2 else "blue"})
    return scene(
        {"eye": [0.0, 9.0, 19.0], "look_at": [0.0, 0.0, 1.0], "up": [0, 1, 0], "fov": 45},
        {"checker": CHECKER,
         "red": {"color": [0.8, 0.15, 0.1], "ambient": 0.15, "diffuse": 0.8, "specular": 0.4,
                 "shininess": 60},
         "blue": {"color": [0.15, 0.3, 0.8], "ambient": 0.15, "diffuse": 0.8, "specular": 0.4,
                  "shininess": 60}},
        objects
    )


def thin_triangles():
    return scene(
        {"eye": [0.0, 6.0, 17.0], "look_at": [0.0, 3.2, 0.0], "up": [0, 1, 0], "fov": 45},
        {"checker": CHECKER,
         "straw": {"color": [0.9, 0.75, 0.3], "ambient": 0.2, "diffuse": 0.8, "specular": 0.2,
                   "shininess": 20}},
        [
            {"type": "plane", "name": "floor", "point": [0, 0, 0], "normal": [0, 1, 0],
             "material": "checker"},
            {"type": "mesh", "name": "straws", "file": "../meshes/slivers.obj",
             "material": "straw"},
        ]
    )


def scene_text(s):
    """JSON with one line per top-level key, material, light and object."""
    def one(v):
        return json.dumps(v)

    parts = []
    for key, value in s.items():
        if isinstance(value, list) and isinstance(value[0], dict):
            body = ",\n".join(f"    {one(v)}" for v in value)
            parts.append(f'  "{key}": [\n{body}\n  ]')
        elif key == "materials":
            body = ",\n".join(f'    "{k}": {one(v)}' for k, v in value.items())
            parts.append(f'  "{key}": {{\n{body}\n  }}')
        else:
            parts.append(f'  "{key}": {one(value)}')
    return "{\n" + ",\n".join(parts) + "\n}\n"


def outputs():
    rng = random.Random(14)
    files = {
        MESHES / "stadium.obj": stadium(),
        MESHES / "slivers.obj": slivers(rng),
    }
    for name, make in (("teapot_in_stadium", teapot_in_stadium), ("many_spheres", many_spheres),
                       ("thin_triangles", thin_triangles)):
        files[HERE / f"{name}.json"] = scene_text(make())
    return files


def main(argv):
    if argv not in ([], ["--check"]):
        print("usage: make_showcase.py [--check]", file=sys.stderr)
        return 2
    stale = []
    for path, text in outputs().items():
        if argv:
            if not path.exists() or path.read_text() != text:
                stale.append(path)
        else:
            path.write_text(text)
    for path in stale:
        print(f"{path}: differs from what data/scenes/make_showcase.py makes; run it",
              file=sys.stderr)
    return 1 if stale else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
