"""The Ray Trace filter on 1 and 2 MPI ranks (issue: 2 ranks against 1 on this
2-core machine), in the same run: the trace's speedup, what gathering the
pieces and building the scene on every rank add, and the tiles handed out by
estimated cost (Balance Tiles, the default) against interleaved.

Run with a plain python3 from the checkout, the plugin built:

    python3 bench/paraview_mpi_ranks.py [--size 800x600] [--samples 3] [--runs 5]

It runs `mpiexec -n N build/paraview/pvbatch` on this script (--worker) for N
= 1, N = 2 with interleaved tiles and N = 2 balanced, in turn, --runs times
each. A worker reads the Stanford bunny
(glmark2-data) through the plugin's mesh reader on rank 0 only (ParaView's
readers of one file give the other ranks nothing, so the gather moves the
whole mesh), adds a floor and a sphere, and traces them with the Ray Trace
filter (one thread per rank, reflective surfaces, shadows): a first update
(gather, build, trace, assemble) and then three traces with other seeds
(trace and assemble only; nothing to gather). It prints the filter's
"Seconds" field (gather, build, trace, assemble on rank 0) and the wall time
of each update. The report gives medians over the runs and the ratios.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def worker(args):
    from paraview.simple import RayScopeMeshReader, Plane, Sphere, RayTrace
    from paraview import servermanager as sm
    W, H = (int(v) for v in args.size.split("x"))
    bunny = RayScopeMeshReader(FileName=args.mesh)
    floor = Plane(Origin=[-6.0, -0.065, -6.0], Point1=[6.0, -0.065, -6.0], Point2=[-6.0, -0.065, 6.0])
    ball = Sphere(Center=[1.3, 0.7, 1.0], Radius=0.7, ThetaResolution=64, PhiResolution=32)
    rt = RayTrace(Input=[bunny, floor, ball], ImageSize=[W, H], Samples=args.samples, Threads=1,
                  BalanceTiles=args.balance,
                  Reflectivity=0.25, AutoCamera=0, Position=[0.0, 2.0, 7.0], FocalPoint=[0.0, 0.9, 0.0],
                  ViewUp=[0.0, 1.0, 0.0], ViewAngle=35.0)
    updates = []
    for seed in (0, 1, 2, 3):
        rt.Seed = seed
        start = time.perf_counter()
        image = sm.Fetch(rt, 0)
        wall = time.perf_counter() - start
        seconds = image.GetFieldData().GetArray("Seconds")
        if seconds is None or image.GetNumberOfPoints() != W * H:
            sys.exit("paraview_mpi_ranks: the Ray Trace image is empty")
        updates.append({"wall": wall, "steps": list(seconds.GetTuple(0))})
    print("RESULT " + json.dumps(updates))


def run(ranks, balance, args):
    cmd = ["mpiexec", "--allow-run-as-root", "--oversubscribe", "-n", str(ranks),
           os.path.join(ROOT, "build", "paraview", "pvbatch"), os.path.abspath(__file__), "--worker",
           "--size", args.size, "--samples", str(args.samples), "--mesh", args.mesh,
           "--balance", str(balance)]
    env = dict(os.environ, PV_PLUGIN_PATH=os.path.join(
        ROOT, "build", "paraview", "install", "lib", "paraview-5.11", "plugins", "RayScope"))
    out = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=900)
    line = next((l for l in out.stdout.splitlines() if l.startswith("RESULT ")), None)
    if out.returncode != 0 or line is None:
        sys.exit(f"{ranks} ranks failed ({out.returncode}):\n{out.stdout[-2000:]}{out.stderr[-2000:]}")
    return json.loads(line[len("RESULT "):])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", default="800x600")
    ap.add_argument("--samples", type=int, default=3)
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--mesh", default="/usr/share/glmark2/models/bunny.obj")
    ap.add_argument("--worker", action="store_true")
    ap.add_argument("--balance", type=int, default=1)
    args = ap.parse_args()
    if args.worker:
        return worker(args)
    configs = {"1": (1, 1), "2 interleaved": (2, 0), "2 balanced": (2, 1)}
    results = {name: [] for name in configs}
    for _ in range(args.runs):
        for name, (ranks, balance) in configs.items():
            results[name].append(run(ranks, balance, args))
    med = {}
    for ranks, runs in results.items():
        first = [r[0] for r in runs]
        again = [u for r in runs for u in r[1:]]
        med[ranks] = {
            "first wall": statistics.median(u["wall"] for u in first),
            "gather": statistics.median(u["steps"][0] for u in first),
            "build": statistics.median(u["steps"][1] for u in first),
            "first trace": statistics.median(u["steps"][2] for u in first),
            "trace wall": statistics.median(u["wall"] for u in again),
            "trace": statistics.median(u["steps"][2] for u in again),
            "assemble": statistics.median(u["steps"][3] for u in again),
            # Rank 0 traces its share, then waits in the gather for the slower
            # rank: its trace and assemble steps are the parallel trace's time.
            "traced": statistics.median(u["steps"][2] + u["steps"][3] for u in again),
        }
    print(f"Ray Trace filter, bunny + floor + sphere, {args.size}, {args.samples}x{args.samples} samples, "
          f"1 thread per rank; medians of {args.runs} runs (re-traces: 3 per run)\n")
    print("| ranks | first update (s) | gather | build | trace | re-trace update (s) | trace | assemble |")
    print("| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for ranks, m in med.items():
        print(f"| {ranks} | {m['first wall']:.3f} | {m['gather']:.3f} | {m['build']:.3f} | {m['first trace']:.3f} "
              f"| {m['trace wall']:.3f} | {m['trace']:.3f} | {m['assemble']:.3f} |")
    for two in ("2 interleaved", "2 balanced"):
        print(f"\nspeedup, {two} against 1: trace (trace + assemble on rank 0) "
              f"{med['1']['traced'] / med[two]['traced']:.2f}x; whole re-trace update "
              f"{med['1']['trace wall'] / med[two]['trace wall']:.2f}x; first update "
              f"{med['1']['first wall'] / med[two]['first wall']:.2f}x")


if __name__ == "__main__":
    main()
