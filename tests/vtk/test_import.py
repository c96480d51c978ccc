"""`import vtk, rayscope` works (from the build tree, or from an install when
PYTHONPATH points there), exposes every class and does not load OpenImageIO."""
import vtk  # noqa: F401
import rayscope

for name in ("vtkRayScopeImageAlgorithm", "vtkRayScopeRayTreeSource", "vtkRayScopeBVHSource",
             "vtkRayScopeRangeQuery", "vtkRayScopeMeshConverter", "vtkRayScopeMeshReader",
             "vtkRayScopeMaterial", "vtkRayScopePass"):
    cls = getattr(rayscope, name)
    obj = cls()
    assert obj.GetClassName() == name, obj.GetClassName()
    assert obj.IsA("vtkObject")

alg = rayscope.vtkRayScopeImageAlgorithm()
assert alg.IsA("vtkImageAlgorithm")
assert rayscope.vtkRayScopeRayTreeSource().IsA("vtkPolyDataAlgorithm")
assert rayscope.vtkRayScopeMeshReader().IsA("vtkDataSetAlgorithm")
assert alg.GetConverter().GetMapper().IsA("vtkMapper")
assert rayscope.vtkRayScopePass().IsA("vtkRenderPass")
assert rayscope.vtkRayScopePass().GetImageAlgorithm().IsA("vtkRayScopeImageAlgorithm")
# The module links the core, which loads OpenImageIO (about 260 libraries)
# only when an image file is read or written (image.h), never here.
with open("/proc/self/maps") as maps:
    assert "libOpenImageIO" not in maps.read(), "import rayscope loaded OpenImageIO"
print("rayscope", rayscope.__file__)
