"""Run in ParaView's Python shell by gui_open_view.xml (paraview.gui.view),
after the GUI opened a RayScope view from its view types and showed a sphere:
records what the GUI made, asks the view for 3 x 3 samples and renders it once;
record() then notes the image passes the view shows, while the GUI renders it
again on its own (the plugin's refinement behavior), and finish() writes
everything, with any Python error, to $RAYSCOPE_TEST_OUTPUT/gui_view.json for
test_gui_view.cmake to check (the GUI's Python errors do not fail the process).
"""
import json
import os
import traceback

from paraview.simple import GetActiveView, GetDisplayProperties, GetSources, Render

rs_result = {"errors": []}
rs_seen = []


def rs_guard(f):
    def run():
        try:
            f()
        except Exception:
            rs_result["errors"].append(traceback.format_exc())
    return run


@rs_guard
def rs_start():
    view = GetActiveView()
    rs_result["view"] = view.GetXMLName()
    rs_result["class"] = view.GetClientSideObject().GetClassName()
    rs_result["visible"] = [GetDisplayProperties(s, view).Visibility for s in GetSources().values()]
    view.Samples = 3
    Render(view)
    view.UpdatePropertyInformation()
    rs_result["traced_size"] = [int(v) for v in view.GetPropertyValue("TracedSize")]
    rs_result["view_size"] = [int(v) for v in view.ViewSize]
    rs_record()


@rs_guard
def rs_record():
    view = GetActiveView()
    view.UpdatePropertyInformation()
    rs_seen.append([int(v) for v in view.GetPropertyValue("ImagePasses")])


def rs_finish():
    rs_record()
    rs_result["passes"] = rs_seen
    path = os.path.join(os.environ.get("RAYSCOPE_TEST_OUTPUT", "."), "gui_view.json")
    with open(path, "w") as f:
        json.dump(rs_result, f)


rs_start()
