"""`import vtk, rayscope` works from the build tree and exposes every class."""
import vtk  # noqa: F401
import rayscope

for name in ("vtkRayScopeImageAlgorithm", "vtkRayScopeRayTreeSource", "vtkRayScopeBVHSource",
             "vtkRayScopeMeshConverter", "vtkRayScopeMaterial"):
    cls = getattr(rayscope, name)
    obj = cls()
    assert obj.GetClassName() == name, obj.GetClassName()
    assert obj.IsA("vtkObject")

alg = rayscope.vtkRayScopeImageAlgorithm()
assert alg.IsA("vtkImageAlgorithm")
assert rayscope.vtkRayScopeRayTreeSource().IsA("vtkPolyDataAlgorithm")
assert alg.GetConverter().GetMapper().IsA("vtkMapper")
print("rayscope", rayscope.__file__)
