#!/usr/bin/python3
"""Writes the files of the rayscope command's tests of the formats beyond
single datasets: composite files (.vtm, .vtpc, Exodus II), parallel files
(.pvtp, .pvti) and images (.vti), each with a file it must render like, and
damaged or incomplete ones.

Usage: write_mesh_formats.py OUT_DIR

- two.vtm, two.vtpc: two spheres as two blocks (the second named "small");
  two_pieces.pvtp: the same two spheres as the two pieces of one polydata;
  merged.vtp: the two appended into one polydata (vtkAppendPolyData).
- image.vti: an image of 5x4x3 points; image_pieces.pvti: the same image
  written in two pieces; image_surface.vtp: its outer surface as VTK's dataset
  mapper makes it (vtkDataSetSurfaceFilter).
- two.ex2: two element blocks of one hexahedron each (vtkExodusIIWriter).
- lines.vtm: a sphere, a block of a line only (no surface triangles) and a
  block of points without cells (nothing to draw).
- curves.vtp: lines and vertices only, no surface: a polyline of 40 segments
  (a helix, as streamlines are) and a cloud of 50 vertices.
- Damaged: missing_piece.pvtp and missing_block.vtm name a file that does not
  exist, bad_piece.pvtp names a truncated piece, no_points_array.pvtp misspells
  the element declaring its points array, bad_index.vtm gives a block
  index beyond its blocks, loose_dataset.vtpc has a DataSet outside any
  Partitions (VTK 9.1's reader crashes on it), truncated.ex2 is half of
  two.ex2, bad_node.ex2 is two.ex2 with a hexahedron naming node 999 of 16,
  not_netcdf.ex2 is text, damaged_hdf5.ex2 starts as a netCDF-4 (HDF5) file
  does and goes on with bytes that are not HDF5.
"""
import math
import os
import sys

import vtk

out = sys.argv[1]
os.makedirs(out, exist_ok=True)


def path(name):
    return os.path.join(out, name)


def sphere(center, radius):
    s = vtk.vtkSphereSource()
    s.SetCenter(center)
    s.SetRadius(radius)
    s.SetThetaResolution(16)
    s.SetPhiResolution(10)
    s.Update()
    return s.GetOutput()


def write(writer, data, name):
    writer.SetInputData(data)
    writer.SetFileName(path(name))
    if not writer.Write():
        sys.exit(f"could not write {name}")


big = sphere((0, 0, 0), 1.0)
small = sphere((1.2, 0.4, 0.8), 0.45)
for name, data in (("big.vtp", big), ("small.vtp", small)):
    write(vtk.vtkXMLPolyDataWriter(), data, name)

blocks = vtk.vtkMultiBlockDataSet()
blocks.SetNumberOfBlocks(2)
blocks.SetBlock(0, big)
blocks.SetBlock(1, small)
blocks.GetMetaData(1).Set(vtk.vtkCompositeDataSet.NAME(), "small")
write(vtk.vtkXMLMultiBlockDataWriter(), blocks, "two.vtm")

collection = vtk.vtkPartitionedDataSetCollection()
collection.SetNumberOfPartitionedDataSets(2)
for i, data in enumerate((big, small)):
    partitions = vtk.vtkPartitionedDataSet()
    partitions.SetPartition(0, data)
    collection.SetPartitionedDataSet(i, partitions)
write(vtk.vtkXMLPartitionedDataSetCollectionWriter(), collection, "two.vtpc")

append = vtk.vtkAppendPolyData()
append.AddInputData(big)
append.AddInputData(small)
append.Update()
write(vtk.vtkXMLPolyDataWriter(), append.GetOutput(), "merged.vtp")


def parallel_polydata(name, sources):
    """A .pvtp whose pieces are the given files (points and normals Float32,
    as vtkSphereSource makes them)."""
    pieces = "".join(f'    <Piece Source="{s}"/>\n' for s in sources)
    with open(path(name), "w") as f:
        f.write('<?xml version="1.0"?>\n'
                '<VTKFile type="PPolyData" version="0.1" byte_order="LittleEndian">\n'
                '  <PPolyData GhostLevel="0">\n'
                '    <PPointData Normals="Normals">\n'
                '      <PDataArray type="Float32" Name="Normals" NumberOfComponents="3"/>\n'
                '    </PPointData>\n'
                '    <PPoints>\n'
                '      <PDataArray type="Float32" Name="Points" NumberOfComponents="3"/>\n'
                '    </PPoints>\n'
                f'{pieces}'
                '  </PPolyData>\n'
                '</VTKFile>\n')


parallel_polydata("two_pieces.pvtp", ("big.vtp", "small.vtp"))
parallel_polydata("missing_piece.pvtp", ("big.vtp", "gone.vtp"))
with open(path("small.vtp"), "rb") as f:
    small_bytes = f.read()
with open(path("truncated_piece.vtp"), "wb") as f:
    f.write(small_bytes[: len(small_bytes) // 2])
parallel_polydata("bad_piece.pvtp", ("big.vtp", "truncated_piece.vtp"))
with open(path("two_pieces.pvtp")) as f:
    two_pieces_text = f.read()
points_array = '<PDataArray type="Float32" Name="Points" NumberOfComponents="3"/>'
assert two_pieces_text.count(points_array) == 1
with open(path("no_points_array.pvtp"), "w") as f:
    f.write(two_pieces_text.replace(points_array, points_array.replace("PDataArray", "PDataArrey")))

image = vtk.vtkRTAnalyticSource()
image.SetWholeExtent(0, 4, 0, 3, 0, 2)
image.Update()
whole = vtk.vtkImageData()  # the source's output changes as the pieces are written
whole.DeepCopy(image.GetOutput())
write(vtk.vtkXMLImageDataWriter(), whole, "image.vti")
pieces = vtk.vtkXMLPImageDataWriter()
pieces.SetInputConnection(image.GetOutputPort())  # a source that splits its extent
pieces.SetNumberOfPieces(2)
pieces.SetStartPiece(0)
pieces.SetEndPiece(1)
pieces.SetFileName(path("image_pieces.pvti"))
if not pieces.Write():
    sys.exit("could not write image_pieces.pvti")
surface = vtk.vtkDataSetSurfaceFilter()
surface.SetInputData(whole)
surface.Update()
write(vtk.vtkXMLPolyDataWriter(), surface.GetOutput(), "image_surface.vtp")


def hexahedron(x):
    pts = vtk.vtkPoints()
    for p in ((0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0),
              (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)):
        pts.InsertNextPoint(p[0] + x, p[1], p[2])
    grid = vtk.vtkUnstructuredGrid()
    grid.SetPoints(pts)
    grid.InsertNextCell(vtk.VTK_HEXAHEDRON, 8, range(8))
    return grid


exodus = vtk.vtkMultiBlockDataSet()
exodus.SetNumberOfBlocks(2)
exodus.SetBlock(0, hexahedron(0.0))
exodus.SetBlock(1, hexahedron(1.5))
write(vtk.vtkExodusIIWriter(), exodus, "two.ex2")
with open(path("two.ex2"), "rb") as f:
    exodus_bytes = f.read()
with open(path("truncated.ex2"), "wb") as f:
    f.write(exodus_bytes[: len(exodus_bytes) // 2])
# Block 1's connectivity, nodes 1..8 as big-endian 32-bit integers, with its
# last node made 999 of the 16 the file has.
nodes = b"".join(i.to_bytes(4, "big") for i in range(1, 9))
assert exodus_bytes.count(nodes) == 1, "block 1's connectivity not found"
with open(path("bad_node.ex2"), "wb") as f:
    f.write(exodus_bytes.replace(nodes, nodes[:-4] + (999).to_bytes(4, "big")))
with open(path("not_netcdf.ex2"), "w") as f:
    f.write("This is not an Exodus file.\n")
with open(path("damaged_hdf5.ex2"), "wb") as f:
    f.write(b"\x89HDF\r\n\x1a\n" + bytes(range(256)) * 8)

lines = vtk.vtkLineSource()
lines.Update()
with_lines = vtk.vtkMultiBlockDataSet()
with_lines.SetNumberOfBlocks(3)
with_lines.SetBlock(0, big)
with_lines.SetBlock(1, lines.GetOutput())
with_lines.GetMetaData(1).Set(vtk.vtkCompositeDataSet.NAME(), "lines")
nothing = vtk.vtkPolyData()  # points without cells
nothing.SetPoints(big.GetPoints())
with_lines.SetBlock(2, nothing)
with_lines.GetMetaData(2).Set(vtk.vtkCompositeDataSet.NAME(), "empty")
write(vtk.vtkXMLMultiBlockDataWriter(), with_lines, "lines.vtm")

helix = vtk.vtkPolyLineSource()
helix.SetNumberOfPoints(41)
for i in range(41):
    a = 0.3 * i
    helix.SetPoint(i, math.cos(a), math.sin(a), 0.05 * i)
cloud = vtk.vtkPointSource()
cloud.SetNumberOfPoints(50)
cloud.SetCenter(0.0, 0.0, 1.0)
cloud.SetRadius(0.5)
curves = vtk.vtkAppendPolyData()
curves.AddInputConnection(helix.GetOutputPort())
curves.AddInputConnection(cloud.GetOutputPort())
curves.Update()
write(vtk.vtkXMLPolyDataWriter(), curves.GetOutput(), "curves.vtp")

# Composite files written by hand around the blocks written above.
with open(path("missing_block.vtm"), "w") as f:
    f.write('<?xml version="1.0"?>\n<VTKFile type="vtkMultiBlockDataSet" version="1.0">\n'
            '  <vtkMultiBlockDataSet>\n    <DataSet index="0" file="big.vtp"/>\n'
            '    <DataSet index="1" file="gone.vtp"/>\n  </vtkMultiBlockDataSet>\n</VTKFile>\n')
with open(path("bad_index.vtm"), "w") as f:
    f.write('<?xml version="1.0"?>\n<VTKFile type="vtkMultiBlockDataSet" version="1.0">\n'
            '  <vtkMultiBlockDataSet>\n    <DataSet index="0" file="big.vtp"/>\n'
            '    <DataSet index="1000000000" file="small.vtp"/>\n'
            '  </vtkMultiBlockDataSet>\n</VTKFile>\n')
with open(path("loose_dataset.vtpc"), "w") as f:
    f.write('<?xml version="1.0"?>\n'
            '<VTKFile type="vtkPartitionedDataSetCollection" version="1.0">\n'
            '  <vtkPartitionedDataSetCollection>\n    <DataSet index="0" file="big.vtp"/>\n'
            '  </vtkPartitionedDataSetCollection>\n</VTKFile>\n')
