"""The ray-tree polydata of a pixel matches `rayscope inspect` of that pixel.

The same scene is built twice: once in VTK (sources into
vtkRayScopeImageAlgorithm) and once as a scene file for the command-line tool,
whose meshes are the module's own converted triangles written as binary .vtk
files (float points and normals, read back bit for bit). Materials, lights and the
camera use values that both sides turn into the same floats. Then for several
pixels the ray tree of vtkRayScopeRayTreeSource and the JSON of
`rayscope inspect --format json` must agree exactly: number of rays, kinds,
depths, parents, hit flags, hit points, BVH counters and the pixel's color.

Usage: test_inspect_cli.py RAYSCOPE_EXECUTABLE
"""
import json
import os
import sys

import vtk
import rayscope

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from raytree_compare import assert_same_tree, inspect  # noqa: E402

OUT = os.environ.get("RAYSCOPE_TEST_OUTPUT", ".")
W, H, SPP, DEPTH = 48, 36, 2, 4


def sources():
    floor = vtk.vtkPlaneSource()
    floor.SetOrigin(-3, -0.5, 3)
    floor.SetPoint1(3, -0.5, 3)
    floor.SetPoint2(-3, -0.5, -3)
    floor.SetResolution(3, 3)
    glass = vtk.vtkSphereSource()
    glass.SetCenter(-0.4, 0.0, 0.25)
    glass.SetRadius(0.5)
    glass.SetThetaResolution(32)
    glass.SetPhiResolution(16)
    mirror = vtk.vtkSphereSource()
    mirror.SetCenter(0.75, 0.0, -0.5)
    mirror.SetRadius(0.45)
    mirror.SetThetaResolution(24)
    mirror.SetPhiResolution(12)
    return [("floor", floor), ("glass", glass), ("mirror", mirror)]


# Colors 0 and 1 decode from sRGB to the same linear values exactly.
MATERIALS = {
    "floor": dict(color=(1, 1, 1), ambient=0.1, diffuse=0.75, reflectivity=0.25),
    "glass": dict(color=(1, 1, 1), ambient=0.0, diffuse=0.1, transparency=0.9, ior=1.5),
    "mirror": dict(color=(1, 0, 0), ambient=0.05, diffuse=0.35, specular=0.5, shininess=40,
                   reflectivity=0.6),
}
LIGHT = dict(position=(2.0, 4.0, 3.0), intensity=0.75)
CAMERA = dict(eye=(0.0, 1.0, 4.0), look_at=(0.0, -0.1, 0.0), up=(0.0, 1.0, 0.0), fov=30.0)


def build_vtk_scene(named_sources):
    alg = rayscope.vtkRayScopeImageAlgorithm()
    for k, (name, src) in enumerate(named_sources):
        alg.AddInputConnection(src.GetOutputPort())
        v = MATERIALS[name]
        m = rayscope.vtkRayScopeMaterial()
        m.SetColor(*v["color"])
        m.SetAmbient(v["ambient"])
        m.SetDiffuse(v["diffuse"])
        m.SetSpecular(v.get("specular", 0.0))
        m.SetSpecularPower(v.get("shininess", 1.0))
        m.SetReflectivity(v.get("reflectivity", 0.0))
        m.SetTransparency(v.get("transparency", 0.0))
        m.SetIndexOfRefraction(v.get("ior", 1.5))
        alg.SetInputMaterial(k, m)
    alg.HeadlightOff()
    alg.AddPointLight(*LIGHT["position"], 1, 1, 1, LIGHT["intensity"])
    alg.SetPosition(*CAMERA["eye"])
    alg.SetFocalPoint(*CAMERA["look_at"])
    alg.SetViewUp(*CAMERA["up"])
    alg.SetViewAngle(CAMERA["fov"])
    alg.SetBackground(0, 0, 1)
    alg.SetSize(W, H)
    alg.SetSamples(SPP)
    alg.SetMaxDepth(DEPTH)
    return alg


def write_scene_file(named_sources):
    conv = rayscope.vtkRayScopeMeshConverter()  # the module's default conversion
    objects = []
    for name, src in named_sources:
        src.Update()
        tri = vtk.vtkPolyData()
        assert conv.Convert(src.GetOutput(), tri) == 1
        # Legacy binary .vtk: float points and normals, read back bit for bit.
        path = os.path.join(OUT, f"inspect_{name}.vtk")
        w = vtk.vtkPolyDataWriter()
        w.SetFileName(path)
        w.SetInputData(tri)
        w.SetFileTypeToBinary()
        assert w.Write() == 1
        objects.append({"type": "mesh", "name": name, "file": path, "material": name})
    materials = {}
    for name, v in MATERIALS.items():
        materials[name] = {"color": list(v["color"]), "ambient": v["ambient"],
                           "diffuse": v["diffuse"], "specular": v.get("specular", 0.0),
                           "shininess": v.get("shininess", 1.0),
                           "reflectivity": v.get("reflectivity", 0.0),
                           "transparency": v.get("transparency", 0.0), "ior": v.get("ior", 1.5),
                           "model": "blinn-phong"}
    scene = {
        "camera": {k: list(v) if isinstance(v, tuple) else v for k, v in CAMERA.items()},
        "render": {"width": W, "height": H, "samples": SPP, "max_depth": DEPTH},
        "background": [0, 0, 1],
        "ambient_light": [1, 1, 1],
        "materials": materials,
        "lights": [{"type": "point", "position": list(LIGHT["position"]),
                    "intensity": LIGHT["intensity"]}],
        "objects": objects,
    }
    path = os.path.join(OUT, "inspect_scene.json")
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    return path


def main(exe):
    named = sources()
    alg = build_vtk_scene(named)
    scene_file = write_scene_file(named)
    alg.Update()
    image = alg.GetOutput()
    ids = image.GetPointData().GetArray("ObjectId")

    tree = rayscope.vtkRayScopeRayTreeSource()
    tree.SetSceneSource(alg)
    pixels = [(i, j) for j in range(3, H, 8) for i in range(2, W, 7)]
    records = inspect(exe, scene_file, [(i, H - 1 - j) for i, j in pixels])  # rows from the top
    kinds_seen = set()
    compared = 0
    for (i, j), rec in zip(pixels, records):
        tree.SetPixel(i, j)
        tree.Update()
        kinds_seen |= assert_same_tree(tree.GetOutput(), rec, (i, j))
        rays = rec["rays"]
        oid = ids.GetValue(j * W + i)
        assert oid == (rays[0]["object"] if rays[0]["hit"] else -1), (i, j, oid)
        compared += 1
    print(f"{compared} pixels: ray trees identical to `rayscope inspect` "
          f"(kinds seen: {', '.join(sorted(kinds_seen))})")
    assert kinds_seen == {"primary", "shadow", "reflection", "refraction"}, kinds_seen


if __name__ == "__main__":
    main(sys.argv[1])
