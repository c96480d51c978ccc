#!/usr/bin/python3
"""Writes the seed corpus of fuzz_mesh_loader: small valid files of every
format the mesh loader reads, made by VTK's own writers.

Usage: make_mesh_corpus.py OUT_DIR   (tests/fuzz/corpus/mesh_loader)

Each corpus file is one byte choosing the format (its index in
fuzz_mesh_loader.cpp's kFormats: obj, stl, ply, vtk, vtp, vtu, vti, pvtp,
pvtu, pvti, vtm, vtpc, ex2) followed by the file, then, for files that name
other files (parallel pieces, composite blocks), each of those after a line
"%%file NAME" (the fuzzer writes them beside the input file; block files
move from the writer's subfolder to beside it). The meshes are a tetrahedron
(with normals, colors and a scalar array in the formats that store them), a
quad of two triangles and small images; every corpus file is well under 10
KB.
"""
import os
import sys
import tempfile

import vtk

FORMATS = [".obj", ".stl", ".ply", ".vtk", ".vtp", ".vtu", ".vti", ".pvtp", ".pvtu", ".pvti",
           ".vtm", ".vtpc", ".ex2"]
FILE_MARK = b"\n%%file "


def tetra(decorated):
    pts = vtk.vtkPoints()
    for p in ((0, 1, 0), (-1, -1, 1), (1, -1, 1), (0, -1, -1)):
        pts.InsertNextPoint(p)
    polys = vtk.vtkCellArray()
    for t in ((0, 1, 2), (0, 2, 3), (0, 3, 1), (1, 3, 2)):
        polys.InsertNextCell(3, t)
    pd = vtk.vtkPolyData()
    pd.SetPoints(pts)
    pd.SetPolys(polys)
    if decorated:
        normals = vtk.vtkFloatArray()
        normals.SetName("Normals")
        normals.SetNumberOfComponents(3)
        colors = vtk.vtkUnsignedCharArray()
        colors.SetName("Colors")
        colors.SetNumberOfComponents(3)
        values = vtk.vtkFloatArray()
        values.SetName("temperature")
        for i in range(4):
            p = pts.GetPoint(i)
            n = sum(c * c for c in p) ** 0.5
            normals.InsertNextTuple3(*(c / n for c in p))
            colors.InsertNextTuple3(40 * i, 200, 255 - 40 * i)
            values.InsertNextValue(float(i))
        pd.GetPointData().SetNormals(normals)
        pd.GetPointData().SetScalars(colors)
        pd.GetPointData().AddArray(values)
    return pd


def quad():
    q = vtk.vtkPlaneSource()
    q.Update()
    return q.GetOutput()


def volume():
    ug = vtk.vtkUnstructuredGrid()
    ug.SetPoints(tetra(False).GetPoints())
    ug.InsertNextCell(vtk.VTK_TETRA, 4, (0, 1, 2, 3))
    return ug


def polyhedron():
    """A unit cube as one polyhedron cell (its faces listed in the cell)."""
    pts = vtk.vtkPoints()
    for p in ((0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0),
              (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)):
        pts.InsertNextPoint(p)
    ug = vtk.vtkUnstructuredGrid()
    ug.SetPoints(pts)
    faces = ((0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7))
    stream = vtk.vtkIdList()
    stream.InsertNextId(len(faces))
    for f in faces:
        stream.InsertNextId(len(f))
        for i in f:
            stream.InsertNextId(i)
    ug.InsertNextCell(vtk.VTK_POLYHEDRON, stream)
    return ug


def image():
    img = vtk.vtkImageData()
    img.SetDimensions(3, 2, 2)
    img.AllocateScalars(vtk.VTK_UNSIGNED_CHAR, 1)
    return img


def lz4_appended_raw():
    """Appended raw data, LZ4 blocks, 64-bit headers."""
    w = vtk.vtkXMLPolyDataWriter()
    w.SetCompressorTypeToLZ4()
    w.SetHeaderTypeToUInt64()
    w.EncodeAppendedDataOff()
    return w


def old_legacy():
    """A legacy writer of the pre-5 format (cells as counts and ids)."""
    w = vtk.vtkPolyDataWriter()
    w.SetFileVersion(42)
    return w


def two_blocks(kind):
    """The tetrahedron and the quad as two blocks (a multiblock dataset, the
    second named), or as two partitioned datasets of one partition each."""
    if kind == "vtm":
        mb = vtk.vtkMultiBlockDataSet()
        mb.SetNumberOfBlocks(2)
        mb.SetBlock(0, tetra(True))
        mb.SetBlock(1, quad())
        mb.GetMetaData(1).Set(vtk.vtkCompositeDataSet.NAME(), "quad")
        return mb
    pc = vtk.vtkPartitionedDataSetCollection()
    pc.SetNumberOfPartitionedDataSets(2)
    for i, block in enumerate((tetra(False), quad())):
        pd = vtk.vtkPartitionedDataSet()
        pd.SetPartition(0, block)
        pc.SetPartitionedDataSet(i, pd)
    return pc


def exodus_blocks():
    """Two element blocks: a tetrahedron and a hexahedron beside it."""
    hexa = vtk.vtkUnstructuredGrid()
    pts = vtk.vtkPoints()
    for p in ((2, 0, 0), (3, 0, 0), (3, 1, 0), (2, 1, 0), (2, 0, 1), (3, 0, 1), (3, 1, 1), (2, 1, 1)):
        pts.InsertNextPoint(p)
    hexa.SetPoints(pts)
    hexa.InsertNextCell(vtk.VTK_HEXAHEDRON, 8, range(8))
    mb = vtk.vtkMultiBlockDataSet()
    mb.SetNumberOfBlocks(2)
    mb.SetBlock(0, volume())
    mb.SetBlock(1, hexa)
    return mb


def parallel(writer):
    """A parallel writer of two pieces."""
    writer.SetNumberOfPieces(2)
    writer.SetStartPiece(0)
    writer.SetEndPiece(1)
    return writer


def with_named_files(path, body):
    """The file's bytes followed by every file it names (pieces, blocks), as
    the fuzzer takes them; block files are moved beside it."""
    folder, name = os.path.split(path)
    stem = os.path.splitext(name)[0]
    files = sorted(f for f in os.listdir(folder) if f.startswith(stem + "_"))
    sub = os.path.join(folder, stem)
    if os.path.isdir(sub):
        files += sorted(os.path.join(stem, f) for f in os.listdir(sub))
        body = body.replace((stem + "/").encode(), b"")
    for f in files:
        with open(os.path.join(folder, f), "rb") as named:
            body += FILE_MARK + os.path.basename(f).encode() + b"\n" + named.read()
    return body


def write(writer, data, path, mode=None):
    writer.SetInputData(data)
    writer.SetFileName(path)
    if mode == "ascii":
        writer.SetFileTypeToASCII()
    elif mode == "binary":
        writer.SetFileTypeToBinary()
    elif mode in ("xml-ascii", "xml-binary", "xml-appended"):
        {"xml-ascii": writer.SetDataModeToAscii, "xml-binary": writer.SetDataModeToBinary,
         "xml-appended": writer.SetDataModeToAppended}[mode]()
    if not writer.Write():
        sys.exit(f"could not write {path}")


def main(out):
    os.makedirs(out, exist_ok=True)
    cases = []
    for name, data in (("tetra", tetra(True)), ("quad", quad())):
        cases += [
            (f"{name}.obj", vtk.vtkOBJWriter(), data, None),
            (f"{name}_ascii.stl", vtk.vtkSTLWriter(), data, "ascii"),
            (f"{name}_binary.stl", vtk.vtkSTLWriter(), data, "binary"),
            (f"{name}_ascii.ply", vtk.vtkPLYWriter(), data, "ascii"),
            (f"{name}_binary.ply", vtk.vtkPLYWriter(), data, "binary"),
            (f"{name}_ascii.vtk", vtk.vtkPolyDataWriter(), data, "ascii"),
            (f"{name}_binary.vtk", vtk.vtkPolyDataWriter(), data, "binary"),
            (f"{name}_ascii.vtp", vtk.vtkXMLPolyDataWriter(), data, "xml-ascii"),
            (f"{name}_appended.vtp", vtk.vtkXMLPolyDataWriter(), data, "xml-appended"),
        ]
    cases += [
        ("tetra_volume_ascii.vtu", vtk.vtkXMLUnstructuredGridWriter(), volume(), "xml-ascii"),
        ("tetra_volume_binary.vtu", vtk.vtkXMLUnstructuredGridWriter(), volume(), "xml-binary"),
        ("tetra_volume_ascii.vtk", vtk.vtkUnstructuredGridWriter(), volume(), "ascii"),
        ("quad_v42_ascii.vtk", old_legacy(), quad(), "ascii"),
        ("quad_v42_binary.vtk", old_legacy(), quad(), "binary"),
        ("cube_polyhedron_ascii.vtu", vtk.vtkXMLUnstructuredGridWriter(), polyhedron(), "xml-ascii"),
        ("cube_polyhedron_binary.vtu", vtk.vtkXMLUnstructuredGridWriter(), polyhedron(),
         "xml-binary"),
        ("tetra_lz4_raw.vtp", lz4_appended_raw(), tetra(False), "xml-appended"),
        ("image_ascii.vtk", vtk.vtkStructuredPointsWriter(), image(), "ascii"),
        ("image_binary.vtk", vtk.vtkStructuredPointsWriter(), image(), "binary"),
        ("tetra_volume_binary.vtk", vtk.vtkUnstructuredGridWriter(), volume(), "binary"),
        ("image_ascii.vti", vtk.vtkXMLImageDataWriter(), image(), "xml-ascii"),
        ("image_appended.vti", vtk.vtkXMLImageDataWriter(), image(), "xml-appended"),
        ("tetra_pieces.pvtp", parallel(vtk.vtkXMLPPolyDataWriter()), tetra(True), "xml-ascii"),
        ("tetra_volume_pieces.pvtu", parallel(vtk.vtkXMLPUnstructuredGridWriter()), volume(),
         "xml-binary"),
        ("image_pieces.pvti", parallel(vtk.vtkXMLPImageDataWriter()), image(), "xml-ascii"),
        ("blocks.vtm", vtk.vtkXMLMultiBlockDataWriter(), two_blocks("vtm"), "xml-ascii"),
        ("blocks.vtpc", vtk.vtkXMLPartitionedDataSetCollectionWriter(), two_blocks("vtpc"),
         "xml-ascii"),
        ("blocks.ex2", vtk.vtkExodusIIWriter(), exodus_blocks(), None),
    ]
    with tempfile.TemporaryDirectory() as top:
        for name, writer, data, mode in cases:
            tmp = os.path.join(top, os.path.splitext(name)[0] + "_" + name.split(".")[1])
            os.makedirs(tmp)
            ext = os.path.splitext(name)[1]
            path = os.path.join(tmp, "input" + ext)
            write(writer, data, path, mode)
            with open(path, "rb") as f:
                body = with_named_files(path, f.read())
            if len(body) >= 10000:
                sys.exit(f"{name}: {len(body)} bytes, too large for the seed corpus")
            with open(os.path.join(out, name), "wb") as f:
                f.write(bytes([FORMATS.index(ext)]) + body)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
