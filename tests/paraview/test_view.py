"""The RayScope render view in pvpython (CreateView('RayScopeView')): ParaView's
Render View ray-traced by RayScope through vtkRayScopePass.

A sphere in a solid red and a Wavelet contour colored by elevation through a
lookup table are shown. The view's screenshot shows the red sphere and the
contour in several colors of the map; a still render traces the view's
Samples, an interactive one 1 sample per 2 x 2 block; moving the camera changes the image; the
Cost, Normals, Depth and Object Ids display modes show other images. The ray tree of a pixel
of the view (View Ray Tree) replays the view's own scene: its pixel
color is the color the view shows there; the structure its rays walk (View
Acceleration Structure) counts that pixel's node visits. A representation's Metallic and Base
IOR are its reflectivity and index of refraction; categorical colors are the
table's indexed colors. With the same camera, lights and lookup table, the
view's image and the Ray Trace filter's are the same pixels.
"""
import os
import sys

from paraview.simple import *
from paraview import servermanager as sm
from paraview.vtk.vtkIOImage import vtkPNGReader

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from script_checks import check, finish  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rayscope_views import new_view  # noqa: E402

W, H = 120, 90
OUT = os.environ.get("RAYSCOPE_TEST_OUTPUT", ".")


def screenshot(name):
    """The view's pixels as a list of (r, g, b)."""
    path = os.path.join(OUT, name)
    SaveScreenshot(path, view, ImageResolution=[W, H])
    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    a = reader.GetOutput().GetPointData().GetScalars()
    return [tuple(int(a.GetComponent(i, k)) for k in range(3)) for i in range(a.GetNumberOfTuples())]


def traced_samples():
    view.UpdatePropertyInformation()
    return view.GetPropertyValue("TracedSamples")


def traced_size():
    view.UpdatePropertyInformation()
    return list(view.GetPropertyValue("TracedSize"))


view = new_view((W, H), (0.0, 0.0, 0.0))

sphere = Sphere(Center=[-15.0, 0.0, 0.0], Radius=4.0, ThetaResolution=32, PhiResolution=32)
sphere_display = Show(sphere, view)
sphere_display.ColorArrayName = ["POINTS", ""]
sphere_display.DiffuseColor = [1.0, 0.0, 0.0]
sphere_display.AmbientColor = [1.0, 0.0, 0.0]

wavelet = Wavelet(WholeExtent=[-8, 8, -8, 8, -8, 8])
contour = Contour(Input=wavelet, ContourBy=["POINTS", "RTData"], Isosurfaces=[150.0])
elevation = Elevation(Input=contour, LowPoint=[0, -8, 0], HighPoint=[0, 8, 0])
contour_display = Show(elevation, view)
ColorBy(contour_display, ("POINTS", "Elevation"))
GetColorTransferFunction("Elevation").ApplyPreset("Rainbow Uniform", True)

view.ResetCamera()
Render(view)
check(traced_samples() == 2, f"a still render traces the view's Samples ({traced_samples()})")
first = screenshot("rayscope_view.png")
red = sum(1 for r, g, b in first if r > 60 and r > 2 * g and r > 2 * b)
check(red > W * H // 20, f"the sphere is drawn in its solid red ({red} pixels)")
others = {(r // 48, g // 48, b // 48) for r, g, b in first if max(r, g, b) > 30 and not (r > 2 * g and r > 2 * b)}
check(len(others) > 4, f"the contour is colored through its lookup table ({len(others)} color bins)")

# The ray tree of a pixel of the view (View Ray Tree): the view's
# own scene, camera and settings. Its pixel color is the pixel the view shows
# (linear color, sRGB-encoded as the image is), on a surface and on the
# background.
def srgb(c):
    c = min(max(c, 0.0), 1.0)
    return 255.0 * (12.92 * c if c <= 0.0031308 else 1.055 * c ** (1 / 2.4) - 0.055)


def lit(k):
    return max(first[k]) > 30


# A pixel inside a surface (it and its four neighbors show one), and the
# corner, which shows the background.
inside = next(k for k in range(W + 1, W * H - W - 1) if all(lit(n) for n in (k, k - 1, k + 1, k - W, k + W)))
for k in (inside, 0):
    i, j = k % W, k // W  # the PNG's rows run from the bottom, as VTK images do
    tree = ViewRayTree(View=view, Pixel=[i, j])
    rays = sm.Fetch(tree)
    kinds = rays.GetCellData().GetArray("Kind")
    hits = rays.GetCellData().GetArray("Hit")
    primary = [c for c in range(rays.GetNumberOfCells()) if kinds.GetValue(c) == 0 and rays.GetCellType(c) == 3]
    check(len(primary) == 4, f"pixel ({i}, {j}): one primary ray per sample, 2 x 2 ({len(primary)})")
    hit = sum(hits.GetValue(c) for c in primary)
    check(hit > 0 if k == inside else hit == 0, f"pixel ({i}, {j}): {hit} of its primary rays hit")
    color = rays.GetFieldData().GetArray("PixelColor").GetTuple3(0)
    shown = first[k]
    check(all(abs(srgb(color[c]) - shown[c]) <= 1.5 for c in range(3)),
          f"pixel ({i}, {j}): the tree's pixel color {[round(srgb(v), 1) for v in color]} is the view's {shown}")
    Delete(tree)

# The structure the view's rays walk (View Acceleration Structure): the visits
# of a pixel's rays, node by node, add up to the nodes its ray tree's rays
# visited: the same scene, structure and camera as the view.
i, j = inside % W, inside // W
walked = sm.Fetch(ViewRayTree(View=view, Pixel=[i, j]))
visited = walked.GetCellData().GetArray("NodesVisited")
tree_nodes = sum(visited.GetValue(c) for c in range(walked.GetNumberOfCells()) if walked.GetCellType(c) == 3)
boxes = sm.Fetch(ViewAccelerationStructure(View=view, Pixel=[i, j]))
node_ids, counts = boxes.GetCellData().GetArray("NodeId"), boxes.GetCellData().GetArray("VisitCount")
per_node = {node_ids.GetValue(c): counts.GetValue(c) for c in range(boxes.GetNumberOfCells())}
check(len(per_node) > 10, f"View Acceleration Structure: the view's structure ({len(per_node)} nodes)")
check(tree_nodes > 0 and sum(per_node.values()) == tree_nodes,
      f"pixel ({i}, {j}): node visits {sum(per_node.values())} == its ray tree's {tree_nodes}")

# The structure the view walks (Accel, the filters' property): the kD-tree
# gives the same image, other boxes (View Acceleration Structure), another
# cost heat map.
def structure_nodes():
    boxes = sm.Fetch(ViewAccelerationStructure(View=view, Pixel=[i, j]))
    return len({boxes.GetCellData().GetArray("NodeId").GetValue(c) for c in range(boxes.GetNumberOfCells())})


bvh_nodes = structure_nodes()
view.DisplayMode = "Cost"
bvh_cost = screenshot("rayscope_view_bvh_cost.png")
view.Accel = "kD-tree (SAH)"
kd_cost = screenshot("rayscope_view_kd_cost.png")
view.DisplayMode = "Color"
check(screenshot("rayscope_view_kd.png") == first, "the kD-tree gives the view the BVH's image")
kd_nodes = structure_nodes()
check(kd_nodes != bvh_nodes, f"View Acceleration Structure shows the kD-tree ({kd_nodes} nodes, BVH {bvh_nodes})")
check(sum(1 for a, b in zip(bvh_cost, kd_cost) if a != b) > W * H // 50, "and the cost heat map changes")
view.Accel = "BVH (8-wide walk)"

# An interactive render (the camera moving) traces 1 sample per pixel; the
# next still render the view's Samples again.
view.SMProxy.InteractiveRender()
check(traced_samples() == 1, f"an interactive render traces 1 sample ({traced_samples()})")
check(traced_size() == [(W + 1) // 2, (H + 1) // 2],
      f"an interactive render traces one pixel per 2 x 2 block ({traced_size()})")
Render(view)
check(traced_samples() == 2, "the next still render traces the view's Samples again")
check(traced_size() == [W, H], f"and every pixel ({traced_size()})")

# Progressive refinement (Refine Progressively, on by default): while the
# camera rests, each still render adds one sample per pixel to the image
# (ParaView's GUI renders again until ImagePasses says it is complete; here the
# script does), and the complete image is the one-render image bit for bit. A
# screenshot completes the image at once; an interactive render starts again.
def image_passes():
    view.UpdatePropertyInformation()
    return list(view.GetPropertyValue("ImagePasses"))


GetActiveCamera().Elevation(15.0)
Render(view)
passes = [image_passes()]
while passes[-1][0] < passes[-1][1] and len(passes) < 10:
    Render(view)
    passes.append(image_passes())
check([p[0] for p in passes] == [1, 2, 3, 4] and all(p[1] == 4 for p in passes),
      f"still renders refine the image one sample per pixel at a time: {passes}")
refined = screenshot("rayscope_view_refined.png")
check(image_passes() == [4, 4], f"a complete image stays as it is ({image_passes()})")
view.RefineProgressively = 0
one_render = screenshot("rayscope_view_one_render.png")
check(image_passes() == [1, 1], f"without Refine Progressively one render traces all ({image_passes()})")
differ = sum(1 for a, b in zip(refined, one_render) if a != b)
check(differ == 0, f"the refined image is the one-render image ({differ} pixels differ)")
view.RefineProgressively = 1
GetActiveCamera().Elevation(-15.0)
screenshot("rayscope_view_progressive.png")
check(image_passes() == [4, 4], f"a screenshot completes the image at once ({image_passes()})")
view.SMProxy.InteractiveRender()
check(image_passes() == [1, 1], f"an interactive render is one pass ({image_passes()})")
Render(view)
check(image_passes() == [1, 4], f"and the next still render starts again ({image_passes()})")

# The image follows the camera.
GetActiveCamera().Azimuth(40.0)
moved = screenshot("rayscope_view_moved.png")
changed = sum(1 for a, b in zip(first, moved) if a != b)
check(changed > W * H // 20, f"the image follows the camera ({changed} pixels changed)")

# The cost heat map is another image.
view.DisplayMode = "Cost"
cost = screenshot("rayscope_view_cost.png")
changed = sum(1 for a, b in zip(moved, cost) if a != b)
check(changed > W * H // 20, f"the Cost display mode shows the heat map ({changed} pixels differ)")

# Normals, Depth and Object Ids: three more images, and Object Ids shows
# one color per object (the sphere, the contour) and black misses.
modes = {}
for mode in ("Normals", "Depth", "Object Ids"):
    view.DisplayMode = mode
    modes[mode] = screenshot("rayscope_view_" + mode.replace(" ", "_").lower() + ".png")
    changed = sum(1 for a, b in zip(moved, modes[mode]) if a != b)
    check(changed > W * H // 20, f"the {mode} display mode shows another image ({changed} pixels differ)")
check(modes["Normals"] != modes["Depth"], "Normals and Depth are different images")
ids = {p for p in modes["Object Ids"]}
check(3 <= len(ids) <= 4, f"Object Ids: one color per object and black ({len(ids)} colors)")
check((0, 0, 0) in ids, "Object Ids: misses are black")

# Reflectivity and index of refraction per representation: ParaView's Metallic
# and Base IOR (Surface's advanced properties). The ray tree of a pixel on the
# sphere has reflection rays only once the sphere is metallic, refraction rays
# once it is also translucent.
view.DisplayMode = "Color"
Hide(elevation, view)  # the contour's colors include red: find the sphere alone
alone = screenshot("rayscope_view_sphere.png")
Show(elevation, view)
red_pixels = [k for k, (r, g, b) in enumerate(alone) if r > 60 and r > 2 * g and r > 2 * b]
check(len(red_pixels) > 0, "the sphere is in view after the camera moved")


def kinds_at(k):
    Render(view)
    tree = ViewRayTree(View=view, Pixel=[k % W, k // W])
    rays = sm.Fetch(tree)
    kinds = rays.GetCellData().GetArray("Kind")
    found = {kinds.GetValue(c) for c in range(rays.GetNumberOfCells())}
    Delete(tree)
    return found


if red_pixels:
    k = red_pixels[len(red_pixels) // 2]
    check(2 not in kinds_at(k), "a sphere pixel has no reflection ray while Metallic is 0")
    sphere_display.Metallic = 0.4
    check(2 in kinds_at(k), "Metallic 0.4: the sphere's pixel has reflection rays")
    sphere_display.Opacity = 0.5
    sphere_display.BaseIOR = 1.3
    check(3 in kinds_at(k), "Opacity 0.5, Base IOR 1.3: the sphere's pixel has refraction rays")

# Categorical colors (Interpret Values As Categories): a value's indexed color
# from the table, as in the OpenGL view (a copied table lost them once: every
# surface came out in one dark red).
Hide(sphere, view)
Hide(elevation, view)
ids = ProcessIdScalars(Input=sphere)  # ProcessId 0 on one process
ids_display = Show(ids, view)
ColorBy(ids_display, ("POINTS", "ProcessId"))
categories = GetColorTransferFunction("ProcessId")
categories.InterpretValuesAsCategories = 1
categories.Annotations = ["0", "zero", "1", "one"]
categories.IndexedColors = [0.1, 0.3, 0.9, 0.9, 0.9, 0.1]
ids_display.LookupTable = categories
Render(view)
blue = sum(1 for r, g, b in screenshot("rayscope_view_categories.png") if b > 60 and b > 2 * r)
check(blue > W * H // 40, f"categorical coloring: the sphere in its category's blue ({blue} pixels)")

# One settings owner: a new view follows the RayScope Scene settings (as the
# filters do) until its own value is set.
scene_settings = GetSettingsProxy("RayScopeScene")
scene_settings.MaxDepth = 3
follower = CreateView("RayScopeView")
check(follower.MaxDepth == 3, f"a new view takes MaxDepth from RayScope Scene ({follower.MaxDepth})")
scene_settings.MaxDepth = 4
check(follower.MaxDepth == 4, f"and follows it ({follower.MaxDepth})")
follower.MaxDepth = 2
scene_settings.MaxDepth = 5
check(follower.MaxDepth == 2, f"until set on the view ({follower.MaxDepth})")
Delete(follower)

# The view and the Ray Trace filter see the same scene alike: with the same
# camera, lights (a headlight only: the light kit off) and coloring (both
# shapes colored by Elevation through one lookup table), the filter's Color
# array and the view's screenshot are the same pixels, byte for byte.
same = new_view((W, H), (0.1, 0.1, 0.2))
same.UseLight = 0
AddLight(view=same).Coords = "Headlight"
shapes = [Elevation(Input=s, LowPoint=[0, -8, 0], HighPoint=[0, 8, 0]) for s in (sphere, contour)]
heights = GetColorTransferFunction("Height")
heights.ApplyPreset("Rainbow Uniform", True)
heights.RescaleTransferFunction(0.0, 1.0)
for shape in shapes:
    shown = Show(shape, same)
    ColorBy(shown, ("POINTS", "Elevation"))
    shown.LookupTable = heights
same.ResetCamera()
Render(same)
SaveScreenshot(os.path.join(OUT, "rayscope_view_same.png"), same, ImageResolution=[W, H])
reader = vtkPNGReader()
reader.SetFileName(os.path.join(OUT, "rayscope_view_same.png"))
reader.Update()
shown_pixels = reader.GetOutput().GetPointData().GetScalars()
camera = same.GetActiveCamera()
traced = sm.Fetch(RayTrace(Input=shapes, ImageSize=[W, H], Samples=2, AutoCamera=0,
                           Position=camera.GetPosition(), FocalPoint=camera.GetFocalPoint(),
                           ViewUp=camera.GetViewUp(), ViewAngle=camera.GetViewAngle(),
                           Background=[0.1, 0.1, 0.2], Coloring="Color Array",
                           ColorArray=["POINTS", "Elevation"], LookupTable=heights, Headlight=1,
                           AmbientLight=[1, 1, 1]))
traced_pixels = traced.GetPointData().GetArray("Color")
differ = sum(1 for i in range(W * H)
             if any(shown_pixels.GetComponent(i, c) != traced_pixels.GetComponent(i, c) for c in range(3)))
lit_pixels = sum(1 for i in range(W * H) if max(traced_pixels.GetTuple3(i)) > 60)
check(lit_pixels > W * H // 10, f"the Ray Trace image shows the shapes ({lit_pixels} lit pixels)")
check(differ == 0, f"the view and the Ray Trace filter, same camera and lights: {differ} pixels differ")

# And a pixel's ray tree from the view (View Ray Tree) is the Ray Tree filter's
# of the same scene, camera and lights, ray for ray (their rays, hits and
# kinds; the filter's solid color aside), the filter whose trees
# paraview.inspect finds identical to `rayscope inspect`'s.
def tree_arrays(tree):
    return [bytes(memoryview(tree.GetPoints().GetData()))] + [
        bytes(memoryview(tree.GetCellData().GetArray(name))) for name in ("Kind", "Depth", "Hit", "Occluded")]


lit = [k for k in range(W * H) if max(traced_pixels.GetTuple3(k)) > 60]
for k in (lit[len(lit) // 3], lit[2 * len(lit) // 3]) if lit else ():
    pixel = [k % W, k // W]
    from_view = sm.Fetch(ViewRayTree(View=same, Pixel=pixel))
    from_filter = sm.Fetch(RayTree(Input=shapes, ImageSize=[W, H], Samples=2, AutoCamera=0,
                                   Position=camera.GetPosition(), FocalPoint=camera.GetFocalPoint(),
                                   ViewUp=camera.GetViewUp(), ViewAngle=camera.GetViewAngle(),
                                   Background=[0.1, 0.1, 0.2], Headlight=1, AmbientLight=[1, 1, 1],
                                   Pixel=pixel))
    check(from_view.GetNumberOfCells() > 4 and tree_arrays(from_view) == tree_arrays(from_filter),
          f"pixel {pixel}: View Ray Tree == the Ray Tree filter's tree "
          f"({from_view.GetNumberOfCells()} and {from_filter.GetNumberOfCells()} cells)")

finish("paraview.view")
