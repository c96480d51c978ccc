"""Writes test meshes with VTK's own writers: a sphere as .vtp (polydata),
.vtk (legacy), .stl and .ply, a tetrahedralised sphere as .vtu (unstructured
grid), and for .vtp and .vtu a scene file that uses the mesh. Usage:
write_vtk_meshes.py OUTPUT_FOLDER"""
import sys

import vtk

out = sys.argv[1]
sphere = vtk.vtkSphereSource()
sphere.Update()
for ext, writer in (("vtp", vtk.vtkXMLPolyDataWriter), ("vtk", vtk.vtkPolyDataWriter),
                    ("stl", vtk.vtkSTLWriter), ("ply", vtk.vtkPLYWriter)):
    w = writer()
    w.SetFileName(f"{out}/sphere.{ext}")
    w.SetInputData(sphere.GetOutput())
    assert w.Write() == 1, ext
tets = vtk.vtkDelaunay3D()
tets.SetInputData(sphere.GetOutput())
tets.Update()
w = vtk.vtkXMLUnstructuredGridWriter()
w.SetFileName(out + "/sphere.vtu")
w.SetInputData(tets.GetOutput())
assert w.Write() == 1
for ext in ("vtp", "vtu"):
    with open(f"{out}/sphere_{ext}.json", "w") as f:
        f.write('{"objects": [{"type": "mesh", "file": "sphere.%s"}],'
                ' "lights": [{"position": [2, 2, 5]}]}' % ext)
