"""paraview.gui.view: ParaView's GUI opens the RayScope view from its view
types and refines its image on its own. Run by a plain python3:

    test_gui_view.py PARAVIEW OUT_DIR

Plays gui_open_view.xml in `paraview --test-script` (on ctest's X display, or
under xvfb-run without one): closes the Render View, clicks "RayScope" among
the empty frame's view types, applies a Sphere from the Sources menu, and runs
gui_view_checks.py in the Python shell, which asks for 3 x 3 samples, renders
once and notes the image passes the view shows at each of the following shell
commands. Checks here: the view is a vtkRayScopeRenderView showing the sphere
at the view's size, the image is not complete after the script's one render,
and its passes grow to 9 of 9 with no further render asked for by the script (the plugin's
behavior renders again while the image refines).
"""
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from script_checks import check, finish  # noqa: E402

paraview, out = sys.argv[1:3]
here = os.path.dirname(os.path.abspath(__file__))
result_path = os.path.join(out, "gui_view.json")
if os.path.exists(result_path):
    os.remove(result_path)
command = [paraview, "--dr", "--test-script=" + os.path.join(here, "gui_open_view.xml"), "--exit"]
if not os.environ.get("DISPLAY"):
    command = ["xvfb-run", "-a"] + command
env = dict(os.environ, RAYSCOPE_GUI_CHECKS=os.path.join(here, "gui_view_checks.py"), RAYSCOPE_TEST_OUTPUT=out)
run = subprocess.run(command, env=env, capture_output=True, text=True, timeout=300)
log = "\n".join(line for line in (run.stdout + run.stderr).splitlines() if "Available widget" not in line)
check(run.returncode == 0 and "Success =  true" in log, f"the GUI plays the test (exit {run.returncode})\n{log[-3000:]}")
if check(os.path.exists(result_path), f"the Python shell wrote {result_path}\n{log[-3000:]}"):
    with open(result_path) as f:
        got = json.load(f)
    check(not got["errors"], "the shell's checks ran:\n" + "".join(got["errors"]))
    check(got.get("view") == "RayScopeView" and got.get("class") == "vtkRayScopeRenderView",
          f"the frame's RayScope button made a RayScope view ({got.get('view')}, {got.get('class')})")
    check(got.get("visible") == [1], f"the applied sphere is shown in it ({got.get('visible')})")
    check(got.get("traced_size") == got.get("view_size") and got.get("view_size", [0])[0] > 100,
          f"a still render traces the view's size ({got.get('traced_size')}, view {got.get('view_size')})")
    passes = got.get("passes", [])
    check(bool(passes) and passes[0][0] < 9 and passes[0][1] == 9,
          f"after the script's one render the image is not yet complete ({passes[:1]} of 3 x 3)")
    check(passes[-1:] == [[9, 9]], f"the GUI refines the image to 9 of 9 passes on its own ({passes})")
    check(all(a[0] <= b[0] for a, b in zip(passes, passes[1:])), f"passes only grow ({passes})")
finish("paraview.gui.view")
