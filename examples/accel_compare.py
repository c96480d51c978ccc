#!/usr/bin/python3
"""The acceleration structures side by side, as a picture.

Runs `rayscope accel compare` on a scene (every structure built and rendered
in the same run), reads its CSV, and draws three bar charts with VTK's charts:
rays per second, primitives tested per ray (what a structure saves), and the
memory it holds beside its build time.

    xvfb-run -a /usr/bin/python3 examples/accel_compare.py RAYSCOPE -o compare.png \
        [--scene SCENE] [--size WxH] [--runs N] [--structures bvh,kdtree,...]

RAYSCOPE is the rayscope executable (build/debugger/rayscope). Without
--scene: the built-in default scene.
"""
import argparse
import csv
import math
import os
import subprocess
import sys
import tempfile

import vtk

# The panel snapshot and the atomic PNG writer of the benchmark plots.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "bench"))
from plot_quality import snapshot, write_png  # noqa: E402

PANEL = (520, 420)
BAR = (0, 114, 178)
BAR2 = (213, 94, 0)


def run_compare(args):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "compare.csv")
        cmd = [args.rayscope, "accel", "compare", "--csv", out, "--runs", str(args.runs)]
        if args.scene:
            cmd.append(args.scene)
        if args.size:
            cmd += ["--size", args.size]
        if args.structures:
            cmd += ["--structures", args.structures]
        run = subprocess.run(cmd, capture_output=True, text=True)
        if run.returncode != 0:
            sys.exit(f"accel_compare.py: {' '.join(cmd)} failed: {run.stderr.strip()}")
        print(run.stdout, end="")
        with open(out, newline="") as f:
            return list(csv.DictReader(f)), run.stdout.splitlines()[0]


LOG_FLOOR = 0.1  # the bottom of a logarithmic panel


def bar_chart(rows, columns, title, ytitle, log=False):
    """One panel: a bar per structure for each (column, label, color); with
    `log`, bars of log10(value / LOG_FLOOR) on an axis labelled in decades
    (VTK's bar plots have no logarithmic axis), values below LOG_FLOOR at 0."""
    view = vtk.vtkContextView()
    view.GetRenderWindow().SetOffScreenRendering(1)
    view.GetRenderWindow().SetSize(*PANEL)
    view.GetRenderer().SetBackground(1, 1, 1)
    chart = vtk.vtkChartXY()
    view.GetScene().AddItem(chart)
    chart.SetTitle(title)
    chart.GetTitleProperties().SetFontSize(15)
    chart.GetTitleProperties().SetBold(True)
    chart.SetShowLegend(len(columns) > 1)
    t = vtk.vtkTable()
    x = vtk.vtkDoubleArray()
    x.SetName("structure")
    for i in range(len(rows)):
        x.InsertNextValue(i)
    t.AddColumn(x)
    for name, label, _ in columns:
        a = vtk.vtkDoubleArray()
        a.SetName(label)
        for r in rows:
            v = float(r[name])
            a.InsertNextValue(math.log10(max(v, LOG_FLOOR) / LOG_FLOOR) if log else v)
        t.AddColumn(a)
    for k, (_, label, color) in enumerate(columns):
        bar = chart.AddPlot(vtk.vtkChart.BAR)
        bar.SetInputData(t, 0, k + 1)
        bar.SetColor(color[0], color[1], color[2], 255)
        bar.SetLabel(label)
    bottom = chart.GetAxis(vtk.vtkAxis.BOTTOM)
    pos = vtk.vtkDoubleArray()
    labels = vtk.vtkStringArray()
    for i, r in enumerate(rows):
        pos.InsertNextValue(i)
        labels.InsertNextValue(r["structure"])
    bottom.SetCustomTickPositions(pos, labels)
    bottom.SetBehavior(vtk.vtkAxis.FIXED)
    bottom.SetRange(-0.6, len(rows) - 0.4)
    bottom.SetTitle("")
    bottom.GetLabelProperties().SetFontSize(14)
    left = chart.GetAxis(vtk.vtkAxis.LEFT)
    left.SetTitle(ytitle)
    left.GetTitleProperties().SetFontSize(13)
    left.GetLabelProperties().SetFontSize(12)
    if log:
        top = max(math.log10(max(float(r[n]), LOG_FLOOR) / LOG_FLOOR) for r in rows
                  for n, _, _ in columns)
        ticks = vtk.vtkDoubleArray()
        names = vtk.vtkStringArray()
        for d in range(int(math.ceil(top)) + 1):
            ticks.InsertNextValue(d)
            names.InsertNextValue(f"{LOG_FLOOR * 10 ** d:g}")
        left.SetCustomTickPositions(ticks, names)
        left.SetBehavior(vtk.vtkAxis.FIXED)
        left.SetRange(0.0, math.ceil(top) + 0.3)
    else:
        left.SetMinimum(0.0)
        left.SetBehavior(vtk.vtkAxis.AUTO)
    return snapshot(view)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("rayscope")
    p.add_argument("-o", "--output", required=True)
    p.add_argument("--scene")
    p.add_argument("--size")
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--structures")
    args = p.parse_args()
    rows, header = run_compare(args)
    for r in rows:
        r["memory_mib"] = float(r["memory_bytes"]) / 1048576.0
    panels = [
        bar_chart(rows, [("mrays_per_s", "Mrays/s", BAR)], "Rays per second (median)",
                  "million rays per second"),
        bar_chart(rows, [("prims_per_ray", "primitives tested", BAR),
                         ("nodes_per_ray", "nodes or cells visited", BAR2)],
                  "Work per ray (log scale)", "per ray", log=True),
        bar_chart(rows, [("memory_mib", "memory (MiB)", BAR), ("build_ms", "build (ms)", BAR2)],
                  "What it costs to hold and build", "MiB, ms"),
    ]
    write_png(panels, args.output)
    print(f"wrote {args.output} ({header})")


if __name__ == "__main__":
    main()
