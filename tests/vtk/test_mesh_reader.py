"""rayscope.vtkRayScopeMeshReader from Python, where issue 31 met VTK's readers.

Damaged files made here from good ones written by VTK's writers: a truncated
ASCII PLY (vtkPLYReader aborted the interpreter: a bad free() in glibc), a
PLY declaring 1e8 vertices with a tiny body (vtkPLYReader never finished), a
truncated binary STL and one whose header declares more triangles than it
has (vtkSTLReader read part of the triangles without a word), a missing
file. Each gives one error event on the reader whose text names the file and
the problem, a failed update and an empty output, within seconds. The
crashing and hanging files are never given to VTK's plain readers here.

Good files (.stl, .ply, .vtp, .vtu, legacy .vtk, .obj) read back as VTK's
plain reader reads them: same type, points, cells and arrays.
"""
import os
import sys
import tempfile
import time

import vtk
from vtk.util.numpy_support import vtk_to_numpy
import rayscope

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from script_checks import check, finish  # noqa: E402
from damaged_mesh_files import damaged_copies  # noqa: E402

QUICK_SECONDS = 5.0


class Errors:
    def __init__(self, obj):
        self.messages = []
        obj.AddObserver(vtk.vtkCommand.ErrorEvent, self.on_error)

    def on_error(self, obj, event, message=None):
        self.messages.append(str(message))

    on_error.CallDataType = vtk.VTK_STRING


def new_reader():
    reader = rayscope.vtkRayScopeMeshReader()
    errors = Errors(reader)
    Errors(reader.GetExecutive())  # the executive's "returned failure", kept out of the log
    return reader, errors


def sphere():
    s = vtk.vtkSphereSource()
    s.SetThetaResolution(16)
    s.SetPhiResolution(8)
    e = vtk.vtkElevationFilter()
    e.SetInputConnection(s.GetOutputPort())
    t = vtk.vtkTriangleFilter()
    t.SetInputConnection(e.GetOutputPort())
    t.Update()
    return t.GetOutput()


def write(writer, path, data, **settings):
    writer.SetFileName(path)
    writer.SetInputData(data)
    for name, value in settings.items():
        getattr(writer, name)(*value)
    assert writer.Write() == 1, path
    return path


def expect_refused(path, problem):
    reader, errors = new_reader()
    reader.SetFileName(path)
    start = time.monotonic()
    ok = reader.GetExecutive().Update()
    seconds = time.monotonic() - start
    out = reader.GetOutput()
    name = os.path.basename(path)
    check(ok == 0, f"{name}: the update failed")
    check(seconds < QUICK_SECONDS, f"{name}: refused in {seconds:.2f} s")
    check(len(errors.messages) == 1, f"{name}: one error: {errors.messages}")
    text = errors.messages[0] if errors.messages else ""
    check(path + ": " in text and problem in text,
          f"{name}: error names the file and '{problem}': {text}")
    check(out is not None and out.GetNumberOfPoints() == 0 and out.GetNumberOfCells() == 0,
          f"{name}: empty output")
    print(f"{name}: refused in {seconds:.3f} s: {text.strip().splitlines()[-1] if text else ''}")


def ids(id_list):
    return [id_list.GetId(k) for k in range(id_list.GetNumberOfIds())]


def same_dataset(a, b):
    """None when a and b have the same type, points, cells and arrays, else what differs."""
    if a.GetClassName() != b.GetClassName():
        return f"types {a.GetClassName()} != {b.GetClassName()}"
    if (a.GetNumberOfPoints(), a.GetNumberOfCells()) != \
            (b.GetNumberOfPoints(), b.GetNumberOfCells()):
        return "sizes differ"
    if a.GetNumberOfPoints() and \
            (vtk_to_numpy(a.GetPoints().GetData()) != vtk_to_numpy(b.GetPoints().GetData())).any():
        return "points differ"
    ia, ib = vtk.vtkIdList(), vtk.vtkIdList()
    for c in range(a.GetNumberOfCells()):
        a.GetCellPoints(c, ia)
        b.GetCellPoints(c, ib)
        if a.GetCellType(c) != b.GetCellType(c) or ids(ia) != ids(ib):
            return f"cell {c} differs"
    for fa, fb in ((a.GetPointData(), b.GetPointData()), (a.GetCellData(), b.GetCellData())):
        if fa.GetNumberOfArrays() != fb.GetNumberOfArrays():
            return "array counts differ"
        for k in range(fa.GetNumberOfArrays()):
            xa, xb = fa.GetArray(k), fb.GetArray(k)
            if xa.GetName() != xb.GetName() or (vtk_to_numpy(xa) != vtk_to_numpy(xb)).any():
                return f"array {xa.GetName()} differs"
    return None


def expect_same_as_plain(path, plain):
    reader, errors = new_reader()
    reader.SetFileName(path)
    check(reader.GetExecutive().Update() == 1 and not errors.messages,
          f"{path}: read: {errors.messages}")
    plain.SetFileName(path)
    plain.Update()
    diff = same_dataset(reader.GetOutput(), plain.GetOutput())
    check(diff is None, f"{os.path.basename(path)}: same as {plain.GetClassName()}: {diff}")
    print(f"{os.path.basename(path)}: {reader.GetOutput().GetClassName()} with "
          f"{reader.GetOutput().GetNumberOfCells()} cells, as {plain.GetClassName()} reads it")


with tempfile.TemporaryDirectory(prefix="rayscope_mesh_reader_") as tmp:
    pd = sphere()
    stl = write(vtk.vtkSTLWriter(), os.path.join(tmp, "sphere.stl"), pd, SetFileTypeToBinary=())
    ply = write(vtk.vtkPLYWriter(), os.path.join(tmp, "sphere.ply"), pd, SetFileTypeToASCII=())

    # ---- damaged files ----------------------------------------------------
    damaged = damaged_copies(tmp, ply, stl)
    truncated_ply = damaged["truncated_ply"]
    expect_refused(truncated_ply, "truncated PLY")
    expect_refused(damaged["huge_ply"], "the header declares 100000000 vertex elements")
    truncated_stl, over_stl = damaged["truncated_stl"], damaged["overdeclared_stl"]
    declared = damaged["declared"]
    # What issue 31 is about: VTK's own STL reader says nothing and reads part.
    # (The truncated file lacks 1.5 triangles; the over-declared one has all
    # of its body, 5 fewer than its header says.)
    for path, read in ((truncated_stl, pd.GetNumberOfPolys() - 2), (over_stl, declared - 5)):
        plain = vtk.vtkSTLReader()
        plain_errors = Errors(plain)
        plain.SetFileName(path)
        plain.Update()
        check(not plain_errors.messages and plain.GetOutput().GetNumberOfPolys() == read,
              f"{os.path.basename(path)}: vtkSTLReader reads {read} triangles silently")
    expect_refused(truncated_stl, "truncated binary STL")
    expect_refused(over_stl, f"the header declares {declared} triangles")

    expect_refused(os.path.join(tmp, "missing.ply"), "file not found")

    # ---- good files ---------------------------------------------------------
    expect_same_as_plain(stl, vtk.vtkSTLReader())
    expect_same_as_plain(ply, vtk.vtkPLYReader())
    expect_same_as_plain(write(vtk.vtkXMLPolyDataWriter(), os.path.join(tmp, "sphere.vtp"), pd),
                         vtk.vtkXMLPolyDataReader())
    grid = vtk.vtkAppendFilter()  # polydata -> unstructured grid
    grid.AddInputData(pd)
    grid.Update()
    expect_same_as_plain(write(vtk.vtkXMLUnstructuredGridWriter(), os.path.join(tmp, "sphere.vtu"),
                               grid.GetOutput()), vtk.vtkXMLUnstructuredGridReader())
    expect_same_as_plain(write(vtk.vtkDataSetWriter(), os.path.join(tmp, "sphere.vtk"), pd),
                         vtk.vtkDataSetReader())
    expect_same_as_plain(write(vtk.vtkOBJWriter(), os.path.join(tmp, "sphere.obj"), pd),
                         vtk.vtkOBJReader())

    # CanReadFile looks at the name and the kind of file only.
    reader = rayscope.vtkRayScopeMeshReader()
    check(reader.CanReadFile(stl) == 1 and reader.CanReadFile(truncated_ply) == 1,
          "CanReadFile: good and damaged files of a known format")
    check(reader.CanReadFile(os.path.join(tmp, "missing.stl")) == 0 and
          reader.CanReadFile(tmp) == 0,
          "CanReadFile: missing file, folder")

finish("mesh reader")
