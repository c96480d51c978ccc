#!/usr/bin/python3
"""Plots of bench_quality's CSV files with VTK's charts (rendered offscreen).

    /usr/bin/python3 bench/plot_quality.py OUT_DIR [--images DIR]

Reads OUT_DIR/quality.csv and OUT_DIR/rays_vs_depth.csv and writes
  time_vs_error.png   render time against error (linear RMSE, and 1 - SSIM),
                      every configuration as a point, the Pareto front of each
                      scene as a line;
  rays_vs_depth.png   rays per primary ray against the maximum depth r for each
                      cutoff, with the lecture's worst case 2^(r+1) - 1 (a full
                      binary ray tree), and the 1 spp render time;
into --images (default OUT_DIR). VTK needs a display: run under xvfb-run when
there is none (bench/run_quality does).
"""
import argparse
import csv
import math
import os
import sys
import tempfile

import vtk

# One color per scene (Okabe-Ito, distinguishable with color-blindness).
COLORS = [(0, 114, 178), (213, 94, 0), (0, 158, 115), (204, 121, 167), (230, 159, 0),
          (86, 180, 233)]
PANEL = (720, 540)


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def scenes_in(rows):
    seen = []
    for r in rows:
        if r["scene"] not in seen:
            seen.append(r["scene"])
    return seen


def table(columns):
    """vtkTable from [(name, values)]."""
    t = vtk.vtkTable()
    for name, values in columns:
        a = vtk.vtkDoubleArray()
        a.SetName(name)
        for v in values:
            a.InsertNextValue(v)
        t.AddColumn(a)
    return t


def integer_ticks(chart, values):
    """Ticks at the given integers on the bottom axis."""
    axis = chart.GetAxis(vtk.vtkAxis.BOTTOM)
    pos = vtk.vtkDoubleArray()
    for v in values:
        pos.InsertNextValue(v)
    axis.SetCustomTickPositions(pos)
    axis.SetBehavior(vtk.vtkAxis.FIXED)
    axis.SetRange(min(values) - 0.2, max(values) + 0.2)


def legend_room(chart, lo, hi, top_fraction=0.4):
    """Log y range from lo to above hi, leaving the top of the plot to the legend."""
    axis = chart.GetAxis(vtk.vtkAxis.LEFT)
    lo, hi = math.log10(lo), math.log10(hi)
    span = max(hi - lo, 0.5)
    axis.SetBehavior(vtk.vtkAxis.FIXED)
    axis.SetUnscaledRange(10 ** (lo - 0.05 * span), 10 ** (hi + span * top_fraction / (1 - top_fraction)))


def place_legend(chart, horizontal, vertical):
    legend = chart.GetLegend()
    legend.SetHorizontalAlignment(horizontal)
    legend.SetVerticalAlignment(vertical)


def new_chart(title, xtitle, ytitle, xlog, ylog):
    view = vtk.vtkContextView()
    win = view.GetRenderWindow()
    win.SetOffScreenRendering(1)
    win.SetSize(*PANEL)
    view.GetRenderer().SetBackground(1, 1, 1)
    chart = vtk.vtkChartXY()
    view.GetScene().AddItem(chart)
    chart.SetTitle(title)
    chart.GetTitleProperties().SetFontSize(17)
    chart.GetTitleProperties().SetBold(True)
    chart.SetShowLegend(True)
    legend = chart.GetLegend()
    legend.GetLabelProperties().SetFontSize(12)
    for axis_id, text, log in ((vtk.vtkAxis.BOTTOM, xtitle, xlog), (vtk.vtkAxis.LEFT, ytitle, ylog)):
        axis = chart.GetAxis(axis_id)
        axis.SetTitle(text)
        axis.GetTitleProperties().SetFontSize(15)
        axis.GetLabelProperties().SetFontSize(13)
        axis.SetLogScale(log)
        axis.GetGridPen().SetColor(220, 220, 220, 255)
    return view, chart


def add_points(chart, t, x, y, color, label, size=6.0, alpha=110):
    p = chart.AddPlot(vtk.vtkChart.POINTS)
    p.SetInputData(t, x, y)
    p.SetColor(color[0], color[1], color[2], alpha)
    p.SetMarkerStyle(vtk.vtkPlotPoints.CIRCLE)
    p.SetMarkerSize(size)
    p.SetLabel(label)
    if not label:
        p.SetLegendVisibility(False)
    return p


def add_line(chart, t, x, y, color, label, width=2.5, style=vtk.vtkPen.SOLID_LINE, marker=True):
    p = chart.AddPlot(vtk.vtkChart.LINE)
    p.SetInputData(t, x, y)
    p.SetColor(color[0], color[1], color[2], 255)
    p.SetWidth(width)
    p.GetPen().SetLineType(style)
    if marker:
        p.SetMarkerStyle(vtk.vtkPlotPoints.CIRCLE)
        p.SetMarkerSize(7.0)
    p.SetLabel(label)
    return p


def snapshot(view):
    """The pixels of a chart view (or any object with a render window)."""
    return snapshot_window(view.GetRenderWindow())


def snapshot_window(win):
    """Renders the window and copies its back buffer into a new image."""
    win.Render()
    w2i = vtk.vtkWindowToImageFilter()
    w2i.SetInput(win)
    w2i.ReadFrontBufferOff()
    w2i.Update()
    img = vtk.vtkImageData()
    img.DeepCopy(w2i.GetOutput())
    return img


def write_png(images, path):
    """Writes the panels side by side, atomically (temporary file + rename)."""
    append = vtk.vtkImageAppend()
    append.SetAppendAxis(0)
    for img in images:
        append.AddInputData(img)
    append.Update()
    fd, tmp = tempfile.mkstemp(suffix=".png", dir=os.path.dirname(os.path.abspath(path)))
    os.close(fd)
    w = vtk.vtkPNGWriter()
    w.SetFileName(tmp)
    w.SetInputData(append.GetOutput())
    w.Write()
    if w.GetErrorCode() != 0 or os.path.getsize(tmp) == 0:
        os.remove(tmp)
        raise RuntimeError(f"{path}: cannot write PNG")
    os.chmod(tmp, 0o644)
    os.replace(tmp, path)


def save_window(win, path):
    """Renders the window and writes it to `path` as a PNG, atomically."""
    write_png([snapshot_window(win)], path)


def time_vs_error(rows, path):
    scenes = scenes_in(rows)
    r0 = rows[0]
    where = f"{r0['width']}x{r0['height']}, {r0['threads']} threads"
    panels = []
    for metric, label, pareto_col in (
            ("rmse_linear", "RMSE (linear RGB)", "pareto_rmse"),
            ("ssim_srgb_luma", "1 - SSIM (sRGB luma)", "pareto_ssim")):
        view, chart = new_chart(f"Render time against {label.split(' (')[0]} ({where})",
                                "render time (s), median", label + " against reference",
                                True, True)

        def err(r):
            v = float(r[metric])
            return max(1.0 - v, 1e-7) if metric.startswith("ssim") else v

        for i, s in enumerate(scenes):
            c = COLORS[i % len(COLORS)]
            rs = [r for r in rows if r["scene"] == s]
            t = table([("time", [float(r["time_s"]) for r in rs]), ("err", [err(r) for r in rs])])
            add_points(chart, t, 0, 1, c, "")
            front = sorted((r for r in rs if r[pareto_col] == "1"), key=lambda r: float(r["time_s"]))
            tf = table([("time", [float(r["time_s"]) for r in front]),
                        ("err", [err(r) for r in front])])
            add_line(chart, tf, 0, 1, c, f"{s}: Pareto front")
        place_legend(chart, vtk.vtkChartLegend.LEFT, vtk.vtkChartLegend.BOTTOM)
        panels.append(snapshot(view))
    write_png(panels, path)


def rays_vs_depth(rows, path):
    scenes = scenes_in(rows)
    cutoffs = []
    for r in rows:
        if r["min_contribution"] not in cutoffs:
            cutoffs.append(r["min_contribution"])
    styles = [vtk.vtkPen.SOLID_LINE, vtk.vtkPen.DASH_LINE, vtk.vtkPen.DOT_LINE,
              vtk.vtkPen.DASH_DOT_LINE]
    r0 = rows[0]
    panels = []
    for what in ("rays", "time"):
        ys_all = []
        if what == "rays":
            view, chart = new_chart(
                "Rays per primary ray against maximum depth r (1 spp)",
                "maximum depth r", "primary + reflection + refraction rays per primary ray",
                False, True)
            depths = sorted({int(r["max_depth"]) for r in rows})
            tb = table([("depth", depths), ("bound", [2.0 ** (d + 1) - 1 for d in depths])])
            add_line(chart, tb, 0, 1, (0, 0, 0), "worst case 2^(r+1) - 1 (lecture: O(n m 2^r))",
                     width=2.0, style=vtk.vtkPen.DASH_LINE, marker=False)
        else:
            view, chart = new_chart(
                f"Render time against maximum depth r (1 spp, {r0['width']}x{r0['height']})",
                "maximum depth r", "render time (ms)", False, True)
        for i, s in enumerate(scenes):
            c = COLORS[i % len(COLORS)]
            for j, cut in enumerate(cutoffs):
                rs = sorted((r for r in rows if r["scene"] == s and r["min_contribution"] == cut),
                            key=lambda r: int(r["max_depth"]))
                ys = ([float(r["tree_rays_per_primary"]) for r in rs] if what == "rays"
                      else [1e3 * float(r["time_s"]) for r in rs])
                t = table([("depth", [int(r["max_depth"]) for r in rs]), ("y", ys)])
                add_line(chart, t, 0, 1, c, f"{s}, cutoff {cut}", width=2.0,
                         style=styles[j % len(styles)], marker=(j == 0))
                ys_all.extend(ys)
        depths = sorted({int(r["max_depth"]) for r in rows})
        integer_ticks(chart, depths)
        if what == "rays":
            ys_all.extend(2.0 ** (d + 1) - 1 for d in depths)
        legend_room(chart, min(ys_all), max(ys_all))
        place_legend(chart, vtk.vtkChartLegend.LEFT, vtk.vtkChartLegend.TOP)
        panels.append(snapshot(view))
    write_png(panels, path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", help="bench_quality's output folder")
    ap.add_argument("--images", help="where to write the PNGs (default: the output folder)")
    a = ap.parse_args()
    images = a.images or a.out
    os.makedirs(images, exist_ok=True)
    try:
        q = read_csv(os.path.join(a.out, "quality.csv"))
        r = read_csv(os.path.join(a.out, "rays_vs_depth.csv"))
    except OSError as e:
        sys.exit(f"plot_quality: {e.filename}: {e.strerror}")
    if not q or not r:
        sys.exit(f"plot_quality: {a.out}: empty CSV")
    time_vs_error(q, os.path.join(images, "time_vs_error.png"))
    rays_vs_depth(r, os.path.join(images, "rays_vs_depth.png"))
    print(f"wrote {os.path.join(images, 'time_vs_error.png')}, "
          f"{os.path.join(images, 'rays_vs_depth.png')}")


if __name__ == "__main__":
    main()
