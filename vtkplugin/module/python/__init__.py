"""RayScope for VTK: ray-traced images of VTK datasets, ray trees and BVHs as VTK data.

    import vtk, rayscope
    tracer = rayscope.vtkRayScopeImageAlgorithm()

Every class of the wrapped C++ module RayScopeVTK is available here.
"""
from .RayScopeVTK import *  # noqa: F401,F403
