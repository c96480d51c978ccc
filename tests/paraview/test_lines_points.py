"""Lines as tubes and points as spheres through the plugin in pvpython:
ParaView's Stream Tracer output (polylines) and a Point Source (vertices) are
drawn by "Ray Trace", each alone, with no error: the tubes and spheres cover
pixels of their own objects, and a larger Line Radius covers more.
"""
import os
import sys

from paraview.simple import *
from paraview import servermanager as sm

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from script_checks import check, finish  # noqa: E402

W, H = 80, 60


def object_pixels(image, obj):
    ids = image.GetPointData().GetArray("ObjectId")
    return sum(1 for i in range(ids.GetNumberOfValues()) if ids.GetValue(i) == obj)


wavelet = Wavelet(WholeExtent=[-8, 8, -8, 8, -8, 8])
gradient = Gradient(Input=wavelet)
gradient.ScalarArray = ["POINTS", "RTData"]
streams = StreamTracer(Input=gradient, SeedType="Point Cloud")
streams.Vectors = ["POINTS", "Gradient"]
streams.SeedType.Radius = 3.0
streams.SeedType.NumberOfPoints = 20
streams.MaximumStreamlineLength = 20.0
check(sm.Fetch(streams).GetNumberOfLines() > 5, "the stream tracer made streamlines")

thin = sm.Fetch(RayTrace(Input=streams, ImageSize=[W, H], LineRadius=0.1))
thick = sm.Fetch(RayTrace(Input=streams, ImageSize=[W, H], LineRadius=0.3))
# Object 0: the stream tracer's (empty) mesh; object 1: its tubes.
check(object_pixels(thin, 1) > 50, f"streamlines drawn as tubes ({object_pixels(thin, 1)} pixels)")
check(object_pixels(thick, 1) > object_pixels(thin, 1), "a larger Line Radius covers more pixels")

cloud = PointSource(NumberOfPoints=100, Radius=1.0)
spheres = sm.Fetch(RayTrace(Input=cloud, ImageSize=[W, H], PointRadius=0.08))
check(object_pixels(spheres, 1) > 50, f"a point cloud drawn as spheres ({object_pixels(spheres, 1)} pixels)")

finish("paraview.lines_points")
