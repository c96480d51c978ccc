/**
 * @file plain_obj.h
 * @brief The common OBJ file (vertices and faces only) read in one pass.
 *
 * Scanners and many converters write OBJ files of nothing but vertices
 * ("v x y z", an optional w) and faces of plain vertex indices ("f 1 2 3",
 * 1-based or negative), with comments and blank lines: the Stanford bunny is
 * one. For those, VTK's OBJ reader was the largest single cost of loading a
 * scene (about 110 ms of a 0.7 s `rayscope render` of the bunny, more than
 * the BVH), and check_obj_file() had to read the file once more before it.
 * read_plain_obj_file() reads such a file once, checks it as it goes, and
 * builds what vtkOBJReader (VTK 9.1) would: float points, the faces as
 * polygons, a float cell array "GroupIds" of zeros. test_vtk_plain_obj checks
 * that equality, point for point and id for id, on the bunny and on files
 * built to differ.
 *
 * Anything else (texture coordinates, normals, groups, materials, lines,
 * points, corners with slashes, a face of fewer than three corners, an index
 * out of range, a number it does not read whole or that is outside a float's
 * range) returns null: the caller then
 * checks the file and reads it with vtkOBJReader, which reports the problem
 * in the one place that words it (check_obj_file()).
 */
#pragma once

#include <filesystem>

#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

namespace rayscope_vtkio {

/// The file as vtkOBJReader would read it, or null if it is not a plain
/// vertices-and-faces OBJ file (see above) or cannot be opened.
vtkSmartPointer<vtkPolyData> read_plain_obj_file(const std::filesystem::path& path);

}  // namespace rayscope_vtkio
