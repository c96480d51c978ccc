"""The RayScope view and the Ray Trace filter on 1, 2 and 3 MPI ranks
(`mpiexec -n N pvbatch tests/paraview/mpi_render.py`): the same images, bit for
bit, and a bad parameter ends every rank with one error.

mpi_render.py reads a two-piece .pvtp (a sphere; a floor and a wall), which
ParaView hands out piece by piece: on 2 ranks each rank holds one piece, on 3
one rank holds nothing. The sphere's shadow and its reflections fall on the
other piece, so an image traced from each rank's own piece (as compositing
per-rank images does) differs from the serial one; the ranks' gathered scene
gives the serial image exactly, the tiles handed out by estimated cost with
every rank tracing some, and the view refines progressively on the ranks into
the same image. The same again with pvpython as the client of
a pvserver on 2 ranks, rendering on the server. Run by a plain python3:

    test_mpi.py PVBATCH PVPYTHON PVSERVER MPIEXEC OUT_DIR
"""
import os
import socket
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from script_checks import check, finish  # noqa: E402

pvbatch, pvpython, pvserver, mpiexec, out = sys.argv[1:6]
script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "mpi_render.py")
TIMEOUT = 300  # seconds for one run; a hang fails the test instead of ctest's timeout


def run(ranks, mode):
    """Runs mpi_render.py on `ranks` ranks; returns (exit code, output, seconds, folder)."""
    folder = os.path.join(out, f"mpi_{mode}_{ranks}")
    os.makedirs(folder, exist_ok=True)
    start = time.monotonic()
    try:
        p = subprocess.run([mpiexec, "--allow-run-as-root", "--oversubscribe", "-n", str(ranks), pvbatch,
                            script, folder, mode], capture_output=True, text=True, timeout=TIMEOUT)
        code, text = p.returncode, p.stdout + p.stderr
    except subprocess.TimeoutExpired as e:
        code, text = None, f"timed out after {TIMEOUT} s: {e}"
    return code, text, time.monotonic() - start, folder


def run_client_server(ranks):
    """pvserver on `ranks` ranks and pvpython as its client running mpi_render.py;
    returns (client's exit code, output, seconds, folder)."""
    folder = os.path.join(out, f"mpi_client_server_{ranks}")
    os.makedirs(folder, exist_ok=True)
    with socket.socket() as s:  # a free port
        s.bind(("localhost", 0))
        port = s.getsockname()[1]
    log_path = os.path.join(folder, "server.log")
    start = time.monotonic()
    with open(log_path, "w") as log:
        server = subprocess.Popen([mpiexec, "--allow-run-as-root", "--oversubscribe", "-n", str(ranks), pvserver,
                                   f"--server-port={port}"], stdout=log, stderr=subprocess.STDOUT)
    try:
        while "Accepting connection" not in open(log_path).read():
            if server.poll() is not None or time.monotonic() - start > 60:
                return None, "pvserver did not start:\n" + open(log_path).read(), 0.0, folder
            time.sleep(0.2)
        try:
            p = subprocess.run([pvpython, "--dr", script, folder, "image", f"localhost:{port}"],
                               capture_output=True, text=True, timeout=TIMEOUT)
            code, text = p.returncode, p.stdout + p.stderr
        except subprocess.TimeoutExpired as e:
            code, text = None, f"timed out after {TIMEOUT} s: {e}"
        server.wait(timeout=60)  # it ends when its client disconnects
    except subprocess.TimeoutExpired:
        code, text = None, "pvserver did not end after its client left"
    finally:
        if server.poll() is None:
            server.kill()
    return code, text + open(log_path).read(), time.monotonic() - start, folder


def read(folder, name):
    with open(os.path.join(folder, name), "rb") as f:
        return f.read()


images = {}
for ranks in (1, 2, 3):
    code, text, seconds, folder = run(ranks, "image")
    ok = check(code == 0 and f"{ranks} ranks: images written" in text,
               f"{ranks} ranks: the run succeeds (exit {code}, {seconds:.1f} s)\n{text[-3000:]}")
    if ok:
        images[ranks] = {name: read(folder, name) for name in ("ray_trace.raw", "view.raw", "tree.raw",
                                                                "process.txt", "passes.txt")}
        print(f"{ranks} ranks: {seconds:.1f} s")

code, text, seconds, folder = run_client_server(2)
if check(code == 0 and "2 ranks: images written" in text,
         f"pvserver on 2 ranks, pvpython its client: the run succeeds (exit {code}, {seconds:.1f} s)\n{text[-3000:]}"):
    images["client-server"] = {name: read(folder, name) for name in ("ray_trace.raw", "view.raw", "tree.raw",
                                                                "process.txt", "passes.txt")}
    print(f"pvserver on 2 ranks: {seconds:.1f} s")

if 1 in images:
    view = images[1]["view.raw"]
    colors = {view[i:i + 3] for i in range(0, len(view), 3)}
    check(len(colors) > 50, f"the serial view's image is not blank ({len(colors)} colors)")
    check(len(images[1]["tree.raw"]) > 200, f"the serial ray tree has rays ({len(images[1]['tree.raw'])} bytes)")
    for ranks in (2, 3, "client-server"):
        if ranks not in images:
            continue
        for name, what in (("ray_trace.raw", "Ray Trace filter's image"), ("view.raw", "RayScope view's image"),
                           ("tree.raw", "View Ray Tree's ray tree")):
            a, b = images[1][name], images[ranks][name]
            differ = sum(1 for i in range(min(len(a), len(b))) if a[i] != b[i])
            check(len(a) == len(b) and differ == 0,
                  f"{ranks}: the {what} is the serial one bit for bit "
                  f"({differ} of {len(a)} bytes differ)")
for ranks, files in images.items():
    check(files["passes.txt"] == b"[[1, 4], [2, 4], [3, 4], [4, 4]]",
          f"{ranks}: the view refines one sample per pixel per still render: {files['passes.txt'].decode()}")
    if ranks == 1:
        continue
    counts = eval(files["process.txt"].decode())
    n = 2 if ranks == "client-server" else ranks
    check(len(counts) == n and sum(counts) == 160 * 120 and min(counts) > 0,
          f"{ranks}: every rank traces tiles, the one with no data too (pixels per rank: {counts})")

# A bad parameter (MaxDepth -1): one error, from one rank, and every rank ends
# with a non-zero exit (the script exits 1 on the empty image; mpiexec then
# ends the other ranks), well within the timeout.
code, text, seconds, _ = run(2, "bad")
errors = text.count("max_depth must be in 0..64, got -1")
check(code not in (0, None), f"a bad parameter on 2 ranks: non-zero exit ({code}) in {seconds:.1f} s")
check(errors == 1, f"a bad parameter on 2 ranks: the error is shown once ({errors} times)\n{text[-3000:]}")
check("the Ray Trace image is empty" in text, "a bad parameter on 2 ranks: the image is empty")
finish("paraview.mpi")
