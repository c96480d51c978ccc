// Color conventions of the module (private header).
//
// VTK colors are display values: vtkProperty colors, background colors, lookup
// table entries and the unsigned char colors a mapper produces are sRGB-encoded
// (the framebuffer shows them as they are). The core works in linear RGB. Every
// color entering the core is decoded with the sRGB transfer function, every
// color leaving it (the "Color" image array) is encoded back and rounded as
// RayScope's PNG writer rounds: lround(255 * linear_to_srgb(c)). An unlit color
// (ambient 1, diffuse 0, white ambient light) therefore comes out as the very
// byte VTK shows, up to one rounding step.
#pragma once

#include "rayscope/vtk_polydata.h"

namespace rayscope_vtk {

using rayscope::srgb_byte_table;
using rayscope::srgb_to_linear;

}  // namespace rayscope_vtk
