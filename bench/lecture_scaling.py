#!/usr/bin/env python3
"""The lecture's cost figures, measured with `rayscope render` on this machine
(docs/lecture/07-worst-case-cost.md and 16-coherence.md quote its output).

1. Brute force against the BVH as the object count grows: N random small
   triangles in a unit cube (N = 10 .. 10^6, seeded), rendered by one thread
   at one sample per pixel with `--accel none` and `--accel bvh`; rays per
   second from `--stats` (primary and shadow rays), median of --runs.
   Brute force tests every triangle for every ray, so it is run only up to
   --brute-max triangles.
2. The lecture's "in practice" slide: on the largest mesh, triangle-ray
   intersection tests per second (`--stats`' primitives tested over the
   render time) of the lecture's simple kD-tree (alternating axes, median
   cut, one ray at a time), of the SAH kD-tree, and of the 8-wide BVH with
   and without packets.

    bench/lecture_scaling.py build/debugger/rayscope [--runs 3] [--size 160x120]
                             [--max 1000000] [--brute-max 100000]
"""
import argparse
import os
import random
import re
import statistics
import subprocess
import sys
import tempfile


def write_triangles(path, n, seed=1):
    """n random triangles in the unit cube, each about as large as the space
    per triangle (edge 1 / cbrt(n)), so that they fill the cube about equally
    densely at every n."""
    rng = random.Random(seed)
    size = 1.0 / max(n, 1) ** (1.0 / 3.0)
    with open(path, "w") as f:
        for _ in range(n):
            c = [rng.random() for _ in range(3)]
            for _ in range(3):
                f.write("v %.6f %.6f %.6f\n" % tuple(x + size * (rng.random() - 0.5) for x in c))
        for t in range(n):
            f.write("f %d %d %d\n" % (3 * t + 1, 3 * t + 2, 3 * t + 3))


def render_stats(rayscope, mesh, size, accel, extra=()):
    """(Mrays/s, rays, primitives tested, render seconds) of one render (the
    rate from the counts and the time, which --stats prints to 1 ms)."""
    out = subprocess.run(
        [rayscope, "render", mesh, "--size", size, "--spp", "1", "--threads", "1", "--accel",
         accel, "--stats", "-o", os.path.join(os.path.dirname(mesh), "out.png"), *extra],
        capture_output=True, text=True, check=True).stdout
    seconds = float(re.search(r"([\d.]+) s render", out).group(1))
    rays = int(re.search(r"^  total +(\d+)", out, re.M).group(1))
    prims = int(re.search(r"^  primitives tested +(\d+)", out, re.M).group(1))
    return rays / max(seconds, 1e-3) / 1e6, rays, prims, seconds


def median_of(runs, f):
    results = [f() for _ in range(runs)]
    rates = [r[0] for r in results]
    m = statistics.median(rates)
    return results[rates.index(m)] if m in rates else results[0]


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("rayscope")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--size", default="160x120")
    ap.add_argument("--max", type=int, default=1000000)
    ap.add_argument("--brute-max", type=int, default=100000)
    a = ap.parse_args(argv)
    counts = [n for n in (10, 100, 1000, 10000, 100000, 1000000) if n <= a.max]
    with tempfile.TemporaryDirectory() as work:
        print(f"Rays per second, one thread, {a.size}, 1 sample per pixel, median of {a.runs}")
        print(f"{'triangles':>10} {'none Mrays/s':>13} {'bvh Mrays/s':>12} {'bvh / none':>11}")
        mesh = None
        for n in counts:
            mesh = os.path.join(work, f"tris{n}.obj")
            write_triangles(mesh, n)
            bvh = median_of(a.runs, lambda: render_stats(a.rayscope, mesh, a.size, "bvh"))
            if n <= a.brute_max:
                none = median_of(a.runs, lambda: render_stats(a.rayscope, mesh, a.size, "none"))
                print(f"{n:>10} {none[0]:>13.3g} {bvh[0]:>12.3g} {bvh[0] / none[0]:>11.3g}")
            else:
                print(f"{n:>10} {'(not run)':>13} {bvh[0]:>12.3g} {'':>11}")
            sys.stdout.flush()
        n = counts[-1]
        print(f"\nTriangle-ray intersection tests per second on {n} triangles, one thread")
        print(f"{'walk':<40} {'tests':>12} {'seconds':>8} {'M tests/s':>10} {'Mrays/s':>8}")
        walks = [
            ("kdtree, alternating-median, single rays", "kdtree",
             ["--kd-split", "alternating-median", "--single-rays"]),
            ("kdtree, sah, single rays", "kdtree", ["--kd-split", "sah", "--single-rays"]),
            ("bvh, single rays", "bvh", ["--single-rays"]),
            ("bvh, packets", "bvh", []),
        ]
        for name, accel, extra in walks:
            r = median_of(a.runs, lambda: render_stats(a.rayscope, mesh, a.size, accel, extra))
            print(f"{name:<40} {r[2]:>12} {r[3]:>8.3f} {r[2] / r[3] / 1e6:>10.2f} {r[0]:>8.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
