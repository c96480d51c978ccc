"""Every way VTK's writers write a mesh is read by `rayscope render`, to the
same picture.

RayScope checks .vtp, .vtu and legacy .vtk files before VTK's readers see
them (vtkplugin/vtkio: vtk_xml_checks.cpp, legacy_vtk_checks.cpp). The
checks must refuse damaged files without refusing any file VTK writes. So
the same datasets are written with every writer option:

- XML (.vtp, .vtu): ascii, inline binary, appended raw and appended base64
  data; no compression, zlib, LZ4 and LZMA (with a small block size, so that
  arrays span several compressed blocks); UInt32 and UInt64 headers;
- legacy (.vtk): ASCII and binary; the current format (offsets and
  connectivity) and the old one (version 4.2: counts and ids);

and each file is rendered by the rayscope command. Every variant of a
dataset must give the image of its first variant, byte for byte (the same
points and cells make the same triangles). The datasets carry point normals,
scalars, texture coordinates and field data (all of which the checks walk),
and the unstructured grid has a tetrahedron, a hexahedron and a polyhedron
(its face stream is checked); a structured-points volume is written as legacy
.vtk.

Usage: test_writer_variants.py RAYSCOPE_EXECUTABLE
"""
import os
import subprocess
import sys

import vtk

OUT = os.path.join(os.environ.get("RAYSCOPE_TEST_OUTPUT", "."), "writer_variants")
RAYSCOPE = sys.argv[1]
W, H = 48, 36


def sphere():
    s = vtk.vtkSphereSource()
    s.SetThetaResolution(12)
    s.SetPhiResolution(8)
    e = vtk.vtkElevationFilter()  # point scalars
    e.SetInputConnection(s.GetOutputPort())
    t = vtk.vtkTextureMapToSphere()  # texture coordinates
    t.SetInputConnection(e.GetOutputPort())
    t.Update()
    pd = vtk.vtkPolyData()
    pd.DeepCopy(t.GetOutput())
    ids = vtk.vtkIntArray()
    ids.SetName("cell_ids")
    for c in range(pd.GetNumberOfCells()):
        ids.InsertNextValue(c)
    pd.GetCellData().AddArray(ids)
    note = vtk.vtkDoubleArray()
    note.SetName("field_values")
    for v in (1.0, 2.0, 3.0):
        note.InsertNextValue(v)
    pd.GetFieldData().AddArray(note)
    return pd


def grid():
    pts = vtk.vtkPoints()
    coords = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1),  # tetrahedron
              (2, 0, 0), (3, 0, 0), (3, 1, 0), (2, 1, 0),  # hexahedron
              (2, 0, 1), (3, 0, 1), (3, 1, 1), (2, 1, 1),
              (0, 2, 0), (1, 2, 0), (1, 3, 0), (0, 3, 0),  # polyhedron (a cube)
              (0, 2, 1), (1, 2, 1), (1, 3, 1), (0, 3, 1)]
    for p in coords:
        pts.InsertNextPoint(p)
    ug = vtk.vtkUnstructuredGrid()
    ug.SetPoints(pts)
    ug.InsertNextCell(vtk.VTK_TETRA, 4, [0, 1, 2, 3])
    ug.InsertNextCell(vtk.VTK_HEXAHEDRON, 8, list(range(4, 12)))
    faces = [[12, 15, 14, 13], [16, 17, 18, 19], [12, 13, 17, 16],
             [13, 14, 18, 17], [14, 15, 19, 18], [15, 12, 16, 19]]
    stream = vtk.vtkIdList()
    stream.InsertNextId(len(faces))
    for f in faces:
        stream.InsertNextId(len(f))
        for i in f:
            stream.InsertNextId(i)
    ug.InsertNextCell(vtk.VTK_POLYHEDRON, stream)
    temp = vtk.vtkFloatArray()
    temp.SetName("temperature")
    for i in range(len(coords)):
        temp.InsertNextValue(float(i))
    ug.GetPointData().SetScalars(temp)
    return ug


def volume():
    img = vtk.vtkImageData()
    img.SetDimensions(4, 3, 2)
    img.SetSpacing(0.5, 0.5, 0.5)
    img.SetOrigin(-1, -0.5, 0)
    img.AllocateScalars(vtk.VTK_FLOAT, 1)
    return img


def xml_variants(data, ext, writer_class):
    modes = [("ascii", lambda w: w.SetDataModeToAscii())]
    modes += [("binary", lambda w: w.SetDataModeToBinary())]
    modes += [("appended_raw", lambda w: (w.SetDataModeToAppended(), w.EncodeAppendedDataOff()))]
    modes += [("appended_b64", lambda w: (w.SetDataModeToAppended(), w.EncodeAppendedDataOn()))]
    compressors = [("none", lambda w: w.SetCompressorTypeToNone()),
                   ("zlib", lambda w: w.SetCompressorTypeToZLib()),
                   ("lz4", lambda w: w.SetCompressorTypeToLZ4()),
                   ("lzma", lambda w: w.SetCompressorTypeToLZMA())]
    headers = [("h32", lambda w: w.SetHeaderTypeToUInt32()),
               ("h64", lambda w: w.SetHeaderTypeToUInt64())]
    for mode, set_mode in modes:
        for comp, set_comp in compressors:
            if mode == "ascii" and comp != "none":
                continue  # ascii data is never compressed
            for header, set_header in headers:
                name = "%s_%s_%s%s" % (mode, comp, header, ext)
                w = writer_class()
                w.SetInputData(data)
                set_mode(w)
                set_comp(w)
                set_header(w)
                w.SetBlockSize(256)  # several compressed blocks per array
                w.SetFileName(os.path.join(OUT, name))
                assert w.Write() == 1, name
                yield name


def legacy_variants(data, prefix):
    for binary in (False, True):
        for version, set_version in (("v51", lambda w: None),
                                     ("v42", lambda w: w.SetFileVersion(42))):
            name = "%s_%s_%s.vtk" % (prefix, "binary" if binary else "ascii", version)
            w = vtk.vtkDataSetWriter()
            w.SetInputData(data)
            w.SetFileTypeToBinary() if binary else w.SetFileTypeToASCII()
            set_version(w)
            w.SetFileName(os.path.join(OUT, name))
            assert w.Write() == 1, name
            yield name


def render(name):
    png = os.path.join(OUT, name + ".png")
    r = subprocess.run([RAYSCOPE, "render", os.path.join(OUT, name), "-o", png,
                        "--width", str(W), "--height", str(H)],
                       capture_output=True, text=True)
    if r.returncode != 0:
        return None, r.stderr.strip()
    with open(png, "rb") as f:
        return f.read(), ""


def not_blank(name):
    reader = vtk.vtkPNGReader()
    reader.SetFileName(os.path.join(OUT, name + ".png"))
    reader.Update()
    lo, hi = reader.GetOutput().GetPointData().GetScalars().GetRange(-1)
    return hi > lo


def main():
    os.makedirs(OUT, exist_ok=True)
    groups = {
        "sphere.vtp": list(xml_variants(sphere(), ".vtp", vtk.vtkXMLPolyDataWriter)),
        "grid.vtu": list(xml_variants(grid(), ".vtu", vtk.vtkXMLUnstructuredGridWriter)),
        "sphere.vtk": list(legacy_variants(sphere(), "sphere")),
        "grid.vtk": list(legacy_variants(grid(), "grid")),
        "volume.vtk": list(legacy_variants(volume(), "volume")),
    }
    failures = []
    total = 0
    for group, names in groups.items():
        reference = None
        for name in names:
            total += 1
            png, error = render(name)
            if png is None:
                failures.append("%s: refused: %s" % (name, error))
                continue
            # The same pixels make the same PNG file (one encoder, no time stamps).
            if reference is None:
                reference = (name, png)
                # The picture is not empty: the mesh covers some pixels.
                assert not_blank(name), name + ": blank image"
            elif png != reference[1]:
                failures.append("%s: image differs from %s" % (name, reference[0]))
    for f in failures:
        print("FAIL", f)
    print("%d files of %d datasets, %d failures" % (total, len(groups), len(failures)))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
