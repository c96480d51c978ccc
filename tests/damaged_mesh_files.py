"""Damaged copies of good mesh files, made from their bytes (no VTK needed, so
that the system python3 and ParaView's pvpython both import it): the files
issue 31 found VTK's own readers crash, hang or read in part on.

damaged_copies(folder, ascii_ply, binary_stl) writes them into `folder` and
returns their paths by name:
  truncated_ply     the ASCII PLY cut after two thirds (vtkPLYReader aborts)
  huge_ply          an ASCII PLY declaring 1e8 vertices with a body of three
                    (vtkPLYReader loops for minutes, or aborts in ParaView's VTK)
  truncated_stl     the binary STL without its last 75 bytes (vtkSTLReader
                    reads 1.5 triangles fewer without a word)
  overdeclared_stl  the binary STL whose header declares 5 triangles more than
                    its body holds (likewise read in part)
and `declared`, the triangle count the over-declared header claims.
"""
import os
import struct


def damaged_copies(folder, ascii_ply, binary_stl):
    out = {}
    body = open(ascii_ply, "rb").read()
    out["truncated_ply"] = os.path.join(folder, "truncated.ply")
    with open(out["truncated_ply"], "wb") as f:
        f.write(body[: len(body) * 2 // 3])

    out["huge_ply"] = os.path.join(folder, "huge.ply")
    with open(out["huge_ply"], "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex 100000000\nproperty float x\n"
                "property float y\nproperty float z\nelement face 1\n"
                "property list uchar int vertex_indices\nend_header\n"
                "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")

    stl = open(binary_stl, "rb").read()
    out["truncated_stl"] = os.path.join(folder, "truncated.stl")
    with open(out["truncated_stl"], "wb") as f:
        f.write(stl[:-75])
    out["declared"] = struct.unpack("<I", stl[80:84])[0] + 5
    out["overdeclared_stl"] = os.path.join(folder, "overdeclared.stl")
    with open(out["overdeclared_stl"], "wb") as f:
        f.write(stl[:80] + struct.pack("<I", out["declared"]) + stl[84:])
    return out
