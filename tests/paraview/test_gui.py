"""Run by the ParaView GUI: paraview --script=test_gui.py --exit (under Xvfb).

The plugin comes from PV_PLUGIN_PATH. Writes, to RAYSCOPE_TEST_OUTPUT/gui_filters.txt,
one line per RayScope filter the GUI knows: its proxy name, its menu label
and the Filters menu category of its ShowInMenu hint; then the RayScope view:
its proxy name, label and the class the GUI made for it. test_gui_check.cmake
compares the file with what the plugin's XML declares (the GUI's Python
exceptions do not fail the process, so the check is outside).
"""
import os

from paraview import servermanager as sm

pxm = sm.ProxyManager().SMProxyManager  # the session proxy manager
lines = []
for name in ("RayScopeRayTrace", "RayScopeRayTree", "RayScopeAccelStructure", "RayScopeBVH"):
    proxy = pxm.GetPrototypeProxy("filters", name)
    if proxy is None:
        lines.append(f"{name} missing")
        continue
    category = "-"
    hints = proxy.GetHints()
    menu = hints.FindNestedElementByName("ShowInMenu") if hints else None
    if menu is not None:
        category = menu.GetAttribute("category")
    lines.append(f"{name} | {proxy.GetXMLLabel()} | {category}")
# The RayScope view: offered among the views (the GUI's view-type list is the
# "views" proxy group), and made by the GUI's session as a vtkRayScopeRenderView.
view = pxm.GetPrototypeProxy("views", "RayScopeView")
if view is None:
    lines.append("RayScopeView missing")
else:
    from paraview.simple import CreateView

    made = CreateView("RayScopeView")
    lines.append(f"RayScopeView | {view.GetXMLLabel()} | {made.GetClientSideObject().GetClassName()}")
with open(os.path.join(os.environ.get("RAYSCOPE_TEST_OUTPUT", "."), "gui_filters.txt"), "w") as f:
    f.write("\n".join(lines) + "\n")
