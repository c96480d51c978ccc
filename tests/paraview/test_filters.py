"""The plugin's four filters in pvpython, on ParaView's own sources.

The plugin is not loaded by this script: ParaView finds it through
PV_PLUGIN_PATH, the folder it is installed in (ctest sets it), so the filters
must already be in paraview.simple. Then:

- "Ray Trace" of a Sphere: the image's size and AOV arrays; ObjectId 0 on the
  sphere and -1 around it; Depth = the camera's distance to the sphere at the
  image's center; the auto camera sees the whole sphere (background on every
  border pixel).
- "Ray Trace" of the Wavelet contoured by value, colored by an array through a
  ParaView lookup table: the colors are the table's colors, and they differ
  from the solid-color render.
- "Ray Tree" of a pixel: line cells per ray with the documented arrays, one
  primary ray, a reflection ray when the material reflects.
- "Acceleration Structure": boxes with Level, NodeId, PrimitiveCount, SAHCost,
  VisitCount; the leaves hold every triangle once; the level range limits the
  levels. Its old name, "BVH", makes the same boxes and warns that it is
  deprecated.
- "Range Query": a box query through the kD-tree (and the BSP tree with split
  storage, the bounding spheres, the loose median-split kD-tree, a 3 x 7 x 5
  grid) finds the same triangles as through no structure, testing fewer; the
  range output is the box; the k nearest come nearest first.
- bad parameters (a pixel outside the image, samples 0): an empty output and
  an error in ParaView's output.
- one settings proxy, "RayScopeScene" (Edit > Settings): its camera and
  samples reach every filter, which renders from them; a filter whose own
  value was set keeps it.
"""
import math
import sys

from paraview.simple import *
from paraview import servermanager as sm
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.vtkConstants import VTK_STRING
from vtkmodules.vtkCommonCore import vtkCommand, vtkOutputWindow

for name in ("RayTrace", "RayTree", "AccelerationStructure", "RangeQuery"):
    assert name in globals(), f"{name} is missing: the plugin was not loaded from PV_PLUGIN_PATH"

W, H = 120, 90


def fetch(proxy):
    return sm.Fetch(proxy)


def watch(event):
    """The texts of the output window's messages of `event` (vtkCommand.ErrorEvent,
    WarningEvent) from now on, as a list that fills as they come; and the
    observer's tag."""
    texts = []

    @calldata_type(VTK_STRING)
    def on_message(obj, ev, text):
        texts.append(text)

    return texts, vtkOutputWindow.GetInstance().AddObserver(event, on_message)


# ---- Ray Trace of a sphere -----------------------------------------------
sphere = Sphere(Radius=0.5, ThetaResolution=48, PhiResolution=24)
rt = RayTrace(Input=[sphere], ImageSize=[W, H])
image = fetch(rt)
assert image.GetDimensions() == (W, H, 1), image.GetDimensions()
pd = image.GetPointData()
names = sorted(pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays()))
assert names == ["Color", "Cost", "CostBoxes", "CostPrimitives", "CostRays", "Depth",
                 "LinearColor", "Normal", "ObjectId"], names
ids = pd.GetArray("ObjectId")
assert ids.GetRange() == (-1.0, 0.0), ids.GetRange()
center = (H // 2) * W + W // 2
assert ids.GetValue(center) == 0
# The auto camera fits the sphere's bounds as a render view's Reset Camera
# does: along +z at distance r / sin(15 deg) from their center, where r is the
# bounds' half diagonal; the center ray meets the sphere near its pole (the
# pixel's center is half a pixel off the axis, where the polygons are flat).
b = fetch(sphere).GetBounds()
r = 0.5 * math.sqrt(sum((b[2 * k + 1] - b[2 * k]) ** 2 for k in range(3)))
expect_depth = r / math.sin(math.radians(15.0)) + 0.5 * (b[4] + b[5]) - b[5]
depth = pd.GetArray("Depth").GetValue(center)
assert abs(depth - expect_depth) < 1e-3, (depth, expect_depth)
border = [j * W + i for j in (0, H - 1) for i in range(W)] + \
         [j * W + i for j in range(H) for i in (0, W - 1)]
assert all(ids.GetValue(k) == -1 for k in border), "the fitted camera cuts the sphere off"
solid = pd.GetArray("Color").GetTuple3(center)
print(f"ray trace: {W}x{H}, center depth {depth:.4f} (expected {expect_depth:.4f}), color {solid}")

# ---- colored by an array through a lookup table ---------------------------
wavelet = Wavelet()
contour = Contour(Input=wavelet, ContourBy=["POINTS", "RTData"], Isosurfaces=[157.0],
                  ComputeScalars=0)
elevation = Elevation(Input=contour, LowPoint=[-10, -10, -10], HighPoint=[10, 10, 10])
lut = GetColorTransferFunction("Elevation")
lut.ApplyPreset("Cool to Warm", True)
lut.RescaleTransferFunction(0.0, 1.0)
colored = RayTrace(Input=[elevation], ImageSize=[W, H], Coloring="Color Array",
                   ColorArray=["POINTS", "Elevation"], LookupTable=lut, Headlight=1,
                   AmbientLight=[1, 1, 1], Ambient=1.0, Diffuse=0.0, Shadows=0)
img = fetch(colored)
cpd = img.GetPointData()
cids = cpd.GetArray("ObjectId")
hits = [k for k in range(W * H) if cids.GetValue(k) == 0]
assert len(hits) > W * H // 10, len(hits)
# Ambient 1, diffuse 0: each pixel is the surface color, which is the lookup
# table's color of an elevation in [0, 1]: blue-ish to red-ish, not grey.
lin = cpd.GetArray("LinearColor")
table = lut.GetClientSideObject()
lo, hi = [0.0] * 3, [0.0] * 3
table.GetColor(0.0, lo)
table.GetColor(1.0, hi)
spread = max(abs(lin.GetTuple3(k)[0] - lin.GetTuple3(k)[2]) for k in hits)
assert spread > 0.2, f"the surface is not colored by the table (max |r-b| {spread})"
solid_img = fetch(RayTrace(Input=[elevation], ImageSize=[W, H], AmbientLight=[1, 1, 1],
                           Ambient=1.0, Diffuse=0.0, Shadows=0))
slin = solid_img.GetPointData().GetArray("LinearColor")
assert all(slin.GetTuple3(k) == (1.0, 1.0, 1.0) for k in hits), "solid color is not white"
print(f"colored by Elevation through the table: {len(hits)} pixels, max |r-b| {spread:.3f} "
      f"(table ends {[round(v, 3) for v in lo]} .. {[round(v, 3) for v in hi]})")

# ---- Ray Tree --------------------------------------------------------------
tree = RayTree(Input=[sphere], ImageSize=[W, H], Pixel=[W // 2, H // 2], Reflectivity=0.5)
pdt = fetch(tree)
cd = pdt.GetCellData()
for a in ("RayId", "ParentId", "Kind", "KindName", "Depth", "Hit", "Occluded", "Weight",
          "Color", "NodesVisited", "BoxesTested", "PrimitivesTested", "Skipped"):
    assert cd.GetAbstractArray(a) is not None, a
kinds = [int(cd.GetArray("Kind").GetValue(c)) for c in range(pdt.GetNumberOfVerts(),
                                                               pdt.GetNumberOfCells())]
assert kinds.count(0) == 1, kinds            # one primary ray (1 sample)
assert 1 in kinds and 2 in kinds, kinds      # a shadow ray, a reflection ray
assert pdt.GetNumberOfVerts() >= 1           # the primary ray's hit point
print(f"ray tree of pixel ({W // 2}, {H // 2}): {len(kinds)} rays, kinds {sorted(set(kinds))}")

# ---- Acceleration Structure (the BVH by default) -------------------------------
bvh = AccelerationStructure(Input=[sphere])
boxes = fetch(bvh)
bcd = boxes.GetCellData()
for a in ("Level", "NodeId", "ParentId", "IsLeaf", "PrimitiveCount", "SAHCost", "VisitCount"):
    assert bcd.GetArray(a) is not None, a
triangles = fetch(sphere).GetNumberOfPolys()
leaf_prims = 0
seen = set()
for c in range(boxes.GetNumberOfCells()):
    node = int(bcd.GetArray("NodeId").GetValue(c))
    if node in seen:
        continue
    seen.add(node)
    if bcd.GetArray("IsLeaf").GetValue(c):
        leaf_prims += int(bcd.GetArray("PrimitiveCount").GetValue(c))
assert leaf_prims == triangles, (leaf_prims, triangles)
assert boxes.GetNumberOfCells() == 12 * len(seen), "12 edges per box"
levels = bcd.GetArray("Level").GetRange()
bvh.LevelRange = [1, 2]
part = fetch(bvh).GetCellData().GetArray("Level").GetRange()
assert part == (1.0, 2.0), part
# Visits are counted on the walk renders do: the 8-wide walk enters the binary
# nodes at the top of each wide node and the leaves, and the root's wide node
# swallows levels 1 and 2, so count over every level.
bvh.LevelRange = [0, 64]
bvh.VisitMode = "Every ray of the image"
visits = fetch(bvh).GetCellData().GetArray("VisitCount").GetRange()
assert visits[1] > 0, visits
print(f"Acceleration Structure (BVH): {len(seen)} nodes, levels {levels}, leaves hold "
      f"{leaf_prims} triangles; visit counts {visits}")

# The filter's old name still makes it, for this release, with a warning.
warnings, tag = watch(vtkCommand.WarningEvent)
old = fetch(BVH(Input=[sphere]))
vtkOutputWindow.GetInstance().RemoveObserver(tag)
assert old.GetNumberOfCells() == boxes.GetNumberOfCells(), (old.GetNumberOfCells(),
                                                            boxes.GetNumberOfCells())
deprecated = [w for w in warnings if "vtkRayScopeBVHSource is deprecated" in w]
assert deprecated, warnings
print(f"BVH (the old name): the same {old.GetNumberOfCells()} cells, warning: "
      f"{deprecated[0].strip().splitlines()[-1]}")

# ---- Range Query -------------------------------------------------------------
query = RangeQuery(Input=[sphere], QueryType="Box", Box=[0.1, 0.6, -0.2, 0.2, -0.6, 0.6])


def found_ids(proxy):
    out = fetch(proxy)
    ids = out.GetCellData().GetArray("PrimitiveId")
    return [int(ids.GetValue(c)) for c in range(out.GetNumberOfCells())], out


query.Accel = "None (test every primitive)"
brute, out_none = found_ids(query)
query.Accel = "kD-tree (SAH)"
walked, out_kd = found_ids(query)
assert brute and walked == brute, (len(brute), len(walked))
tested = [int(o.GetFieldData().GetArray("PrimitivesTested").GetValue(0)) for o in (out_none, out_kd)]
assert tested[0] == triangles and tested[1] < tested[0], tested
# Every other structure of the lecture, and the loose kD-tree (smallest-cell,
# loose factor 0.25, median splits): the same triangles, fewer tested.
others = {}
for accel, storage in (("BSP tree (planes through the triangles)", "Split (BSP fragments)"),
                       ("Bounding spheres", "Every cell (store multiple times)"),
                       ("kD-tree (SAH)", "Smallest cell (loose octree, BSP node lists)"),
                       ("Uniform grid", "Every cell (store multiple times)")):
    query.Accel, query.Storage = accel, storage
    if accel == "kD-tree (SAH)":
        query.LooseFactor, query.KdSplit = 0.25, "Median"
    if accel == "Uniform grid":
        query.GridResolution = [3, 7, 5]
    ids, out = found_ids(query)
    assert ids == brute, (accel, len(ids), len(brute))
    others[accel] = int(out.GetFieldData().GetArray("PrimitivesTested").GetValue(0))
    assert others[accel] < tested[0], (accel, others[accel])
query.Accel, query.Storage = "kD-tree (SAH)", "Every cell (store multiple times)"
query.LooseFactor, query.KdSplit = 0.1, "Surface area heuristic"
query.GridResolution = [0, 0, 0]
print(f"Range Query, primitives tested by BSP (split), spheres, loose median kD-tree, "
      f"3 x 7 x 5 grid: {others}")
range_box = sm.Fetch(query, idx=1).GetBounds()
assert [round(v, 6) for v in range_box] == [0.1, 0.6, -0.2, 0.2, -0.6, 0.6], range_box
query.QueryType = "Nearest"
query.Center = [0.0, 0.0, 0.9]
query.NumberOfNeighbors = 5
near = fetch(query)
dist = [near.GetCellData().GetArray("Distance").GetValue(c) for c in range(near.GetNumberOfCells())]
assert len(dist) == 5 and dist == sorted(dist) and dist[0] > 0.3, dist
print(f"Range Query: box finds {len(brute)} triangles, testing {tested[1]} through the kD-tree "
      f"against {tested[0]} without; 5 nearest at {dist[0]:.3f} .. {dist[-1]:.3f}")

# ---- bad parameters ------------------------------------------------------------
messages, _ = watch(vtkCommand.ErrorEvent)


def expect_error(proxy, words, what):
    del messages[:]
    out = fetch(proxy)
    size = out.GetNumberOfPoints() + out.GetNumberOfCells()
    assert size == 0, f"{what}: the output is not empty"
    assert any(all(w in m for w in words) for m in messages), (what, messages)
    text = [m for m in messages if all(w in m for w in words)][0]
    print(f"{what}: empty output, error: {text.strip().splitlines()[-1]}")


tree.Pixel = [W + 5, 0]
expect_error(tree, ["pixel (", "outside the"], "a pixel outside the image")
tree.Pixel = [W // 2, H // 2]
rt.Samples = 0
expect_error(rt, ["samples"], "0 samples per pixel")
rt.Samples = 1
rt.ViewAngle = 200.0
expect_error(rt, ["ViewAngle"], "a view angle of 200 degrees")
query.QueryType = "Box"
query.Box = [1, -1, 0, 1, 0, 1]
expect_error(query, ["range query"], "a box with xmin > xmax")

# ---- Adaptive sampling and the filtered checker, as properties ------------
rt.ViewAngle = 30.0
rt.TargetError = 0.02
expect_error(rt, ["target_error", "max_samples"], "a target error without adaptive sampling")
rt.Samples = 2
rt.MaxSamples = 6
rt.TextureFilter = 1
apd = fetch(rt).GetPointData()
counts = apd.GetArray("Samples")
assert counts is not None, "no Samples array with adaptive sampling"
taken = [int(counts.GetValue(k)) for k in range(counts.GetNumberOfTuples())]
# Batches of 2x2 from a 6x6 grid, at least two of them; the flat background
# at the image's border stops after two, the sphere's outline takes more.
assert all(v % 4 == 0 and 8 <= v <= 36 for v in taken), sorted(set(taken))
assert all(taken[k] == 8 for k in border), "the flat background took more than two batches"
assert max(taken) > 8, "no pixel took more than two batches"
print(f"adaptive: {sum(taken) / len(taken):.2f} samples per pixel on average, "
      f"{min(taken)} to {max(taken)} of 36")

# ---- One settings proxy for every filter ----------------------------------------
scene = GetSettingsProxy("RayScopeScene")
assert scene is not None, "no RayScopeScene settings proxy"
trace, raytree, structure = (RayTrace(Input=[sphere]), RayTree(Input=[sphere]),
                             AccelerationStructure(Input=[sphere]))
ranges = RangeQuery(Input=[sphere])  # shows the structure settings only
scene.AutoCamera = 0
scene.FocalPoint = [0, 0, 0]
scene.ImageSize = [40, 30]
for z in (4.0, 6.0):
    scene.Position = [0, 0, z]
    for f in (trace, raytree, structure):
        assert list(f.Position) == [0, 0, z] and f.AutoCamera == 0, list(f.Position)
    # The center pixel's depth and the primary ray's origin follow the camera.
    depth = fetch(trace).GetPointData().GetArray("Depth").GetValue(15 * 40 + 20)
    assert abs(depth - (z - 0.5)) < 0.02, (z, depth)
    raytree.Pixel = [20, 15]
    rays = fetch(raytree)
    gap = min(max(abs(a - b) for a, b in zip(rays.GetPoint(p), (0, 0, z)))
              for p in range(rays.GetNumberOfPoints()))
    assert gap < 1e-6, (z, gap)  # a ray starts at the eye
scene.Accel = "kD-tree (SAH)"
accels = [f.GetProperty("Accel").GetData() for f in (trace, raytree, structure, ranges)]
assert accels == ["kD-tree (SAH)"] * 4, accels
assert fetch(structure).GetFieldData().GetAbstractArray("Structure").GetValue(0) == "kdtree"
# A filter's own value unlinks that property from the settings.
raytree.Samples = 2
scene.Samples = 3
assert [f.Samples for f in (trace, raytree, structure)] == [3, 2, 3], [f.Samples for f in (trace, raytree, structure)]
print("RayScopeScene settings: the camera and the structure reached every filter (depth "
      f"{depth:.3f} at distance 6); a filter's own Samples stays")
print("OK")
