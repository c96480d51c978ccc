"""RayScope for VTK: ray-traced images of VTK datasets, ray trees and BVHs as VTK data.

    import vtk, rayscope
    tracer = rayscope.vtkRayScopeImageAlgorithm()

Every class of the wrapped C++ modules RayScopeVTK (algorithms and sources)
and RayScopeRendering (vtkRayScopePass, a vtkRenderPass) is available here.
"""
from .RayScopeVTK import *  # noqa: F401,F403
from .RayScopeRendering import *  # noqa: F401,F403
