"""`import vtk, rayscope` works (from the build tree, or from an install when
PYTHONPATH points there), exposes every class (an old name with a deprecation
warning) and does not load OpenImageIO."""
import vtk
import rayscope

for name in ("vtkRayScopeImageAlgorithm", "vtkRayScopeRayTreeSource", "vtkRayScopeAccelSource",
             "vtkRayScopeRangeQuery", "vtkRayScopeMeshConverter", "vtkRayScopeMeshReader",
             "vtkRayScopeMaterial", "vtkRayScopeSceneSettings", "vtkRayScopePass"):
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
# The structure source's old name is the same filter and warns once per
# instance that it is deprecated.
warnings = []
out = vtk.vtkOutputWindow.GetInstance()
tag = out.AddObserver(vtk.vtkCommand.WarningEvent,
                      vtk.calldata_type(vtk.VTK_STRING)(lambda o, e, text: warnings.append(text)))
old = rayscope.vtkRayScopeBVHSource()
out.RemoveObserver(tag)
assert old.IsA("vtkRayScopeAccelSource")
assert any("vtkRayScopeBVHSource is deprecated" in w and "vtkRayScopeAccelSource" in w
           for w in warnings), warnings
# The module links the core, which loads OpenImageIO (about 260 libraries)
# only when an image file is read or written (image.h), never here.
with open("/proc/self/maps") as maps:
    assert "libOpenImageIO" not in maps.read(), "import rayscope loaded OpenImageIO"
print("rayscope", rayscope.__file__)
