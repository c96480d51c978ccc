"""Writes a sphere as .vtp (polydata) and a tetrahedralised sphere as .vtu
(unstructured grid) with VTK's own writers, for the mesh-reader CLI tests."""
import sys

import vtk

out = sys.argv[1]
sphere = vtk.vtkSphereSource()
sphere.Update()
w = vtk.vtkXMLPolyDataWriter()
w.SetFileName(out + "/sphere.vtp")
w.SetInputData(sphere.GetOutput())
assert w.Write() == 1
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
