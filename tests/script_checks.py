"""The checks of RayScope's Python test scripts, run by VTK's python3 (tests/vtk)
and by ParaView's pvpython (tests/paraview): check() records and prints what
failed and goes on, so one run reports every failure; finish() ends the script,
non-zero when any check failed.

A script imports it from its parent folder:

    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    from script_checks import check, finish  # noqa: E402
"""
import sys

failures = []


def check(ok, what):
    """Records `what` as failed unless `ok`; returns `ok`."""
    if not ok:
        failures.append(what)
        print("FAIL:", what, file=sys.stderr)
    return ok


def finish(name):
    """Exits non-zero naming how many checks failed, else says all passed."""
    if failures:
        sys.exit(f"{name}: {len(failures)} check(s) failed")
    print(f"{name}: all checks passed")
