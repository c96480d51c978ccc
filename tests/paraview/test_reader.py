"""The plugin's reader, "RayScope Mesh Reader" (vtkRayScopeMeshReader), in pvpython.

The plugin comes from PV_PLUGIN_PATH, as in test_filters.py. Then:

- ParaView's reader factory offers it for .ply, .stl, .vtu files (and upper-case
  .PLY), beside ParaView's own readers: the ReaderFactory hint and CanReadFile
  through the client-server layer;
- good files read as ParaView's own readers read them (same type, points, cells);
- damaged files made here (a truncated ASCII PLY and a PLY declaring 1e8
  vertices with a tiny body: ParaView's PLY reader aborts the process, an
  assertion in vtkPLY::ascii_get_element; a truncated binary STL: its STL
  reader shows part of it without a word) and a missing file give an error in ParaView's output naming the file
  and the problem, an empty output, within seconds, and the session goes on.
  The crashing and hanging files are never given to ParaView's own readers.
"""
import os
import sys
import tempfile
import time

from paraview.simple import *
from paraview import servermanager as sm
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.vtkConstants import VTK_STRING
from vtkmodules.vtkCommonCore import vtkCommand, vtkOutputWindow
from vtkmodules.vtkFiltersCore import vtkAppendFilter, vtkTriangleFilter
from vtkmodules.vtkFiltersSources import vtkSphereSource
from vtkmodules.vtkIOGeometry import vtkSTLWriter
from vtkmodules.vtkIOPLY import vtkPLYWriter
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from damaged_mesh_files import damaged_copies  # noqa: E402

assert "RayScopeMeshReader" in globals(), \
    "RayScopeMeshReader is missing: the plugin was not loaded from PV_PLUGIN_PATH"
QUICK_SECONDS = 5.0

messages = []


@calldata_type(VTK_STRING)
def on_error(obj, event, text):
    messages.append(text)


vtkOutputWindow.GetInstance().AddObserver(vtkCommand.ErrorEvent, on_error)


def write(writer, path, data, *settings):
    writer.SetFileName(path)
    writer.SetInputData(data)
    for name in settings:
        getattr(writer, name)()
    assert writer.Write() == 1, path
    return path


def offered(path):
    """Whether ParaView's reader factory lists the RayScope reader for `path`."""
    factory = sm.vtkSMProxyManager.GetProxyManager().GetReaderFactory()
    if factory.GetNumberOfRegisteredPrototypes() == 0:  # filled on first use, as OpenDataFile does
        factory.UpdateAvailableReaders()
    readers = factory.GetReaders(path, sm.ActiveConnection.Session)
    entries = [readers.GetString(k) for k in range(readers.GetLength())]
    # (group, proxy name, label) per reader
    return any(entries[k:k + 2] == ["sources", "RayScopeMeshReader"]
               for k in range(0, len(entries), 3))


def expect_refused(path, problem):
    del messages[:]
    start = time.monotonic()  # the proxy's creation reads the file (RequestDataObject)
    reader = RayScopeMeshReader(FileName=path)
    out = sm.Fetch(reader)
    seconds = time.monotonic() - start
    name = os.path.basename(path)
    assert out.GetNumberOfPoints() == 0 and out.GetNumberOfCells() == 0, f"{name}: output not empty"
    mine = [m for m in messages if path + ": " in m and problem in m]
    assert mine, (name, problem, messages)
    assert seconds < QUICK_SECONDS, (name, seconds)
    print(f"{name}: refused in {seconds:.3f} s: {mine[0].strip().splitlines()[-1]}")
    Delete(reader)


def expect_same(path, plain_proxy, file_property):
    """`file_property`: FileName, or FileNames for ParaView's file-series readers."""
    del messages[:]
    reader = RayScopeMeshReader(FileName=path)
    ours = sm.Fetch(reader)
    plain = plain_proxy(**{file_property: [path] if file_property == "FileNames" else path})
    theirs = sm.Fetch(plain)
    name = os.path.basename(path)
    assert not messages, (name, messages)
    assert ours.GetClassName() == theirs.GetClassName(), (name, ours.GetClassName())
    assert ours.GetNumberOfCells() > 0
    assert (ours.GetNumberOfPoints(), ours.GetNumberOfCells()) == \
        (theirs.GetNumberOfPoints(), theirs.GetNumberOfCells()), name
    for i in range(0, ours.GetNumberOfPoints(), 7):
        assert ours.GetPoint(i) == theirs.GetPoint(i), (name, i)
    print(f"{name}: {ours.GetClassName()} with {ours.GetNumberOfCells()} cells, "
          f"as ParaView's {plain_proxy.__name__} reads it")
    Delete(reader)
    Delete(plain)


with tempfile.TemporaryDirectory(prefix="rayscope_pv_reader_") as tmp:
    s = vtkSphereSource()
    s.SetThetaResolution(16)
    s.SetPhiResolution(8)
    t = vtkTriangleFilter()
    t.SetInputConnection(s.GetOutputPort())
    t.Update()
    sphere = t.GetOutput()
    stl = write(vtkSTLWriter(), os.path.join(tmp, "sphere.stl"), sphere, "SetFileTypeToBinary")
    ply = write(vtkPLYWriter(), os.path.join(tmp, "sphere.ply"), sphere, "SetFileTypeToASCII")
    append = vtkAppendFilter()
    append.AddInputData(sphere)
    append.Update()
    vtu = write(vtkXMLUnstructuredGridWriter(), os.path.join(tmp, "sphere.vtu"), append.GetOutput())
    upper = os.path.join(tmp, "SPHERE.PLY")
    with open(ply, "rb") as f, open(upper, "wb") as g:
        g.write(f.read())

    for path in (stl, ply, vtu, upper):
        assert offered(path), f"the reader factory does not offer RayScopeMeshReader for {path}"
    assert not offered(os.path.join(tmp, "missing.ply")), "offered for a missing file"
    print("reader factory: offered for .stl, .ply, .vtu and .PLY files")

    expect_same(stl, STLReader, "FileNames")
    expect_same(ply, PLYReader, "FileNames")
    expect_same(vtu, XMLUnstructuredGridReader, "FileName")

    damaged = damaged_copies(tmp, ply, stl)
    truncated_ply, truncated_stl = damaged["truncated_ply"], damaged["truncated_stl"]
    expect_refused(truncated_ply, "truncated PLY")
    expect_refused(damaged["huge_ply"], "the header declares 100000000 vertex elements")
    expect_refused(truncated_stl, "truncated binary STL")

    expect_refused(os.path.join(tmp, "missing.stl"), "file not found")

    # The session goes on: a good file after the damaged ones.
    expect_same(stl, STLReader, "FileNames")

print("paraview reader: all checks passed")
sys.exit(0)
