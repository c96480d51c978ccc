"""The ray tree of one pixel as polydata (vtkRayScopeRayTreeSource, or
ParaView's Ray Tree filter) against `rayscope inspect --format json` of that
pixel: shared by tests/vtk/test_inspect_cli.py (system VTK) and
tests/paraview/test_inspect.py (pvpython). Plain Python: it only calls the
polydata's methods, so it runs in either interpreter.
"""
import json
import subprocess


def inspect(exe, scene, pixels):
    """`rayscope inspect --format json` of several pixels (x, y from the top)."""
    cmd = [exe, "inspect", scene, "--format", "json"]
    for x, y in pixels:
        cmd += ["--pixel", f"{x},{y}"]
    data = json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)
    records = data["pixels"] if isinstance(data, dict) and "pixels" in data else [data]
    assert len(records) == len(pixels), len(records)
    for rec, (x, y) in zip(records, pixels):
        assert tuple(rec["pixel"]) == (x, y), (rec["pixel"], x, y)
    return records


def assert_same_tree(pd, rec, pixel):
    """Asserts that polydata `pd` (hit-point verts first, then one line per ray)
    holds exactly the rays of inspect record `rec`: kinds, depths, parents,
    samples, walk counters, colors, origins, hit flags, hit points and
    objects, and the pixel's color. Returns the set of ray kinds seen."""
    cd = pd.GetCellData()
    rays = rec["rays"]
    nverts = pd.GetNumberOfVerts()
    lines = list(range(nverts, pd.GetNumberOfCells()))
    assert len(lines) == len(rays), (pixel, len(lines), len(rays))
    assert tuple(rec["color"]) == pd.GetFieldData().GetArray("PixelColor").GetTuple3(0), \
        (pixel, rec["color"])
    kinds = set()
    hits = 0
    for c, ray in zip(lines, rays):
        where = f"pixel {pixel} ray {ray['id']}"
        assert cd.GetAbstractArray("KindName").GetValue(c) == ray["kind"], where
        assert cd.GetArray("Depth").GetValue(c) == ray["depth"], where
        assert cd.GetArray("ParentId").GetValue(c) == ray["parent"], where
        assert cd.GetArray("Sample").GetValue(c) == ray["sample"], where
        assert cd.GetArray("BoxesTested").GetValue(c) == ray["bvh"]["boxes_tested"], where
        assert cd.GetArray("PrimitivesTested").GetValue(c) == \
            ray["bvh"]["primitives_tested"], where
        assert cd.GetArray("NodesVisited").GetValue(c) == len(ray["bvh"]["nodes"]), where
        assert cd.GetArray("Color").GetTuple3(c) == tuple(ray["color"]), where
        start = pd.GetPoint(pd.GetCell(c).GetPointId(0))
        assert start == tuple(ray["origin"]), (where, start, ray["origin"])
        kinds.add(ray["kind"])
        if ray["kind"] == "shadow":
            assert cd.GetArray("Occluded").GetValue(c) == ray["occluded"], where
            if ray["occluded"]:
                assert cd.GetArray("ObjectId").GetValue(c) == ray["occluder"], where
            continue
        assert cd.GetArray("Hit").GetValue(c) == ray["hit"], where
        if ray["hit"]:
            hits += 1
            end = pd.GetPoint(pd.GetCell(c).GetPointId(1))
            assert end == tuple(ray["point"]), (where, end, ray["point"])
            assert cd.GetArray("ObjectId").GetValue(c) == ray["object"], where
    assert nverts == hits, (pixel, nverts, hits)
    return kinds
