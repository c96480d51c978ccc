"""The "Ray Tree" filter in ParaView gives the tree `rayscope inspect` prints.

The scene is built twice from ParaView's own sources (a Plane as the floor,
two Spheres): once as the Ray Tree filter's inputs and properties, once as a
scene file for the rayscope command, whose meshes are those very datasets
written by ParaView as binary legacy .vtk files (float points and normals,
read back bit for bit). Camera, light and material use values both sides turn
into the same floats. For a grid of pixels the ray tree of the filter and the
JSON of `rayscope inspect --format json` must agree exactly: number of rays,
kinds, depths, parents, samples, hit flags, origins, hit points, objects, BVH
counters, ray colors and the pixel's color.

Usage: pvpython test_inspect.py RAYSCOPE_EXECUTABLE (the plugin on PV_PLUGIN_PATH)
"""
import json
import os
import sys

from paraview.simple import *
from paraview import servermanager as sm

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from raytree_compare import assert_same_tree, inspect  # noqa: E402

OUT = os.environ.get("RAYSCOPE_TEST_OUTPUT", ".")
W, H, SPP, DEPTH = 48, 36, 2, 4
CAMERA = dict(eye=[0.0, 1.0, 4.0], look_at=[0.0, -0.1, 0.0], up=[0.0, 1.0, 0.0], fov=30.0)
LIGHT = dict(position=[2.0, 4.0, 3.0], intensity=0.75)
# One material for every input (the filter has one): reflective and
# refractive, so that every ray kind appears.
MATERIAL = dict(color=[1, 1, 1], ambient=0.1, diffuse=0.5, specular=0.25, shininess=20.0,
                reflectivity=0.25, transparency=0.5, ior=1.5)


def sources():
    floor = Plane(Origin=[-3, -0.5, 3], Point1=[3, -0.5, 3], Point2=[-3, -0.5, -3],
                  XResolution=3, YResolution=3)
    glass = Sphere(Center=[-0.4, 0.0, 0.25], Radius=0.5, ThetaResolution=32, PhiResolution=16)
    mirror = Sphere(Center=[0.75, 0.0, -0.5], Radius=0.45, ThetaResolution=24, PhiResolution=12)
    return [("floor", floor), ("glass", glass), ("mirror", mirror)]


def write_scene_file(named):
    objects = []
    for name, src in named:
        path = os.path.join(OUT, f"pv_inspect_{name}.vtk")
        SaveData(path, proxy=src, FileType="Binary")
        objects.append({"type": "mesh", "name": name, "file": path, "material": "m"})
    m = MATERIAL
    scene = {
        "camera": CAMERA,
        "render": {"width": W, "height": H, "samples": SPP, "max_depth": DEPTH},
        "background": [0, 0, 1],
        "ambient_light": [1, 1, 1],
        "materials": {"m": {"color": m["color"], "ambient": m["ambient"], "diffuse": m["diffuse"],
                            "specular": m["specular"], "shininess": m["shininess"],
                            "reflectivity": m["reflectivity"],
                            "transparency": m["transparency"], "ior": m["ior"],
                            "model": "blinn-phong"}},
        "lights": [{"type": "point", "position": LIGHT["position"],
                    "intensity": LIGHT["intensity"]}],
        "objects": objects,
    }
    path = os.path.join(OUT, "pv_inspect_scene.json")
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    return path


def main(exe):
    named = sources()
    scene_file = write_scene_file(named)
    m = MATERIAL
    tree = RayTree(Input=[src for _, src in named], ImageSize=[W, H], Samples=SPP, MaxDepth=DEPTH,
                   AutoCamera=0, Position=CAMERA["eye"], FocalPoint=CAMERA["look_at"],
                   ViewUp=CAMERA["up"], ViewAngle=CAMERA["fov"], Background=[0, 0, 1],
                   AmbientLight=[1, 1, 1], Headlight=0,
                   Lights=[0, *LIGHT["position"], 1, 1, 1, LIGHT["intensity"]],
                   MaterialColor=m["color"], Ambient=m["ambient"], Diffuse=m["diffuse"],
                   Specular=m["specular"], SpecularPower=m["shininess"],
                   Reflectivity=m["reflectivity"], Transparency=m["transparency"],
                   IndexOfRefraction=m["ior"])
    pixels = [(i, j) for j in range(3, H, 8) for i in range(2, W, 7)]
    records = inspect(exe, scene_file, [(i, H - 1 - j) for i, j in pixels])
    kinds_seen = set()
    rays_compared = 0
    for (i, j), rec in zip(pixels, records):
        tree.Pixel = [i, j]
        kinds_seen |= assert_same_tree(sm.Fetch(tree), rec, (i, j))
        rays_compared += len(rec["rays"])
    print(f"{len(pixels)} pixels, {rays_compared} rays: the Ray Tree filter's trees are identical "
          f"to `rayscope inspect` (kinds seen: {', '.join(sorted(kinds_seen))})")
    assert kinds_seen == {"primary", "shadow", "reflection", "refraction"}, kinds_seen


if __name__ == "__main__":
    main(sys.argv[1])
