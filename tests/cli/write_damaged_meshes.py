#!/usr/bin/python3
"""Writes damaged mesh files for the rayscope command's bad-input tests.

Usage: write_damaged_meshes.py OUT_DIR

Each file starts as a valid file written by VTK's own writers (a sphere, or a
single triangle) and is then damaged the way real files get damaged:
truncated copies, corrupt element counts, out-of-range point ids, a NaN
coordinate, and a sparse 2 GB file whose header says it holds nothing; OBJ
files with NaN or infinite vertices, random bytes named .obj, and a loop of
symbolic links. Also
makes a folder named like a mesh file and a folder to give as the output
image. tests/cli/CMakeLists.txt runs the command on each (cli.damaged.*).
"""
import math
import os
import random
import re
import struct
import sys

import vtk


def sphere():
    s = vtk.vtkSphereSource()
    s.SetThetaResolution(24)
    s.SetPhiResolution(12)
    s.Update()
    return s.GetOutput()


def triangle():
    pts = vtk.vtkPoints()
    for p in ((0, 0, 0), (1, 0, 0), (0, 1, 0)):
        pts.InsertNextPoint(p)
    polys = vtk.vtkCellArray()
    polys.InsertNextCell(3, (0, 1, 2))
    pd = vtk.vtkPolyData()
    pd.SetPoints(pts)
    pd.SetPolys(polys)
    return pd


def write(writer, data, path, binary=None):
    writer.SetInputData(data)
    writer.SetFileName(path)
    if binary is True:
        writer.SetFileTypeToBinary()
    elif binary is False:
        writer.SetFileTypeToASCII()
    if not writer.Write():
        sys.exit(f"could not write {path}")


def truncate_copy(src, dst, fraction):
    with open(src, "rb") as f:
        data = f.read()
    with open(dst, "wb") as f:
        f.write(data[: int(len(data) * fraction)])


def replace_once(src, dst, old, new):
    """Copies src to dst with the first match of the regex old replaced."""
    with open(src, "rb") as f:
        data = f.read()
    damaged, n = re.subn(old, new, data, count=1)
    if n != 1:
        sys.exit(f"{src}: {old!r} not found")
    with open(dst, "wb") as f:
        f.write(damaged)


def main(out):
    os.makedirs(out, exist_ok=True)
    p = lambda name: os.path.join(out, name)  # noqa: E731
    ball = sphere()

    # Binary STL: 80-byte header, triangle count, 50 bytes per triangle.
    write(vtk.vtkSTLWriter(), ball, p("valid.stl"), binary=True)
    truncate_copy(p("valid.stl"), p("truncated.stl"), 0.5)
    # A NaN in the first corner of the first triangle (after the header and
    # the triangle's normal): the renderer skips that triangle with a warning.
    with open(p("valid.stl"), "rb") as f:
        data = bytearray(f.read())
    data[84 + 12 : 84 + 16] = struct.pack("<f", math.nan)
    with open(p("nan.stl"), "wb") as f:
        f.write(data)
    # 2 GB of nothing (sparse): the header declares 0 triangles.
    with open(p("sparse.stl"), "wb") as f:
        f.truncate(2 << 30)

    # PLY, ASCII and binary, cut off in the faces; a face naming vertex 999 of
    # a 3-vertex file; a vertex count far beyond what the file holds.
    write(vtk.vtkPLYWriter(), ball, p("valid_ascii.ply"), binary=False)
    truncate_copy(p("valid_ascii.ply"), p("truncated_ascii.ply"), 0.8)
    write(vtk.vtkPLYWriter(), ball, p("valid_binary.ply"), binary=True)
    truncate_copy(p("valid_binary.ply"), p("truncated_binary.ply"), 0.8)
    write(vtk.vtkPLYWriter(), triangle(), p("triangle.ply"), binary=False)
    replace_once(p("triangle.ply"), p("bad_index.ply"), b"3 0 1 2", b"3 0 1 999")
    replace_once(p("valid_ascii.ply"), p("huge_count.ply"), rb"element vertex \d+",
                 b"element vertex 2000000000")

    # Legacy VTK: cut off in the points; a point count larger than the data;
    # a triangle naming point 7 of 3.
    write(vtk.vtkPolyDataWriter(), ball, p("valid.vtk"), binary=False)
    truncate_copy(p("valid.vtk"), p("truncated.vtk"), 0.3)
    replace_once(p("valid.vtk"), p("bad_count.vtk"), rb"POINTS (\d+)", rb"POINTS 9\1")
    write(vtk.vtkPolyDataWriter(), triangle(), p("triangle.vtk"), binary=False)
    replace_once(p("triangle.vtk"), p("bad_id.vtk"), b"\n0 1 2", b"\n0 1 7")
    # An unknown value type (VTK's reader went on with a null array: SEGV).
    replace_once(p("valid.vtk"), p("bad_type.vtk"), rb"POINTS (\d+) float", rb"POINTS \1 floa")

    # VTK XML polydata cut off in the middle.
    w = vtk.vtkXMLPolyDataWriter()
    w.SetDataModeToAscii()
    write(w, ball, p("valid.vtp"))
    truncate_copy(p("valid.vtp"), p("truncated.vtp"), 0.5)
    # Binary, zlib-compressed: a point count 9 times the data, and a
    # compression header whose block count 1 became 4093640705 (VTK's parser
    # allocated 16 GB for it).
    w = vtk.vtkXMLPolyDataWriter()
    w.SetDataModeToBinary()
    w.SetCompressorTypeToZLib()
    write(w, ball, p("valid_zlib.vtp"))
    replace_once(p("valid_zlib.vtp"), p("bad_count.vtp"), rb'NumberOfPoints="(\d+)"',
                 rb'NumberOfPoints="9\1"')
    replace_once(p("valid_zlib.vtp"), p("bad_blocks.vtp"), rb"AQAAAACAAAA", b"AQAA9ACAAAA")

    # Every vertex NaN or infinite (an all-NaN mesh rendered a blank image);
    # one infinite corner in an OBJ otherwise valid.
    with open(p("all_nan.obj"), "w") as f:
        f.write("v nan nan nan\nv inf 0 0\nv 0 -inf nan\nf 1 2 3\n")
    with open(p("inf_vertex.obj"), "w") as f:
        f.write("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 inf\nf 1 2 3\nf 2 4 3\n")
    # Random bytes named .obj (VTK's reader said "Line longer than 262144" of
    # a 4096-byte file and quoted its control characters); the same seed
    # gives the same file, whose first control byte is 0x10 at column 3.
    data = bytearray(random.Random(31).randbytes(4096))
    data[0:3] = b"v \x10"
    with open(p("random.obj"), "wb") as f:
        f.write(bytes(data))
    # A loop of symbolic links (reported as "file not found").
    for a, b in (("loop_a.obj", "loop_b.obj"), ("loop_b.obj", "loop_a.obj")):
        if os.path.lexists(p(a)):
            os.remove(p(a))
        os.symlink(b, p(a))

    os.makedirs(p("folder.stl"), exist_ok=True)
    os.makedirs(p("output_folder.png"), exist_ok=True)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
