#!/usr/bin/python3
"""Plot the CSV of bench_accuracy: error in ulps against ray distance.

Four panels (99th percentiles of t error, hit point error, distance of the hit
point from the surface, and the rate of hit/miss disagreements with the
reference), one line per primitive and method (naive dashed, RayScope solid),
for one primitive scale and placement of the CSV (default: scale 1, placement
"origin"). Uses VTK's 2D charts and needs an X display:

    build/bench/bench_accuracy --csv accuracy.csv
    xvfb-run -a /usr/bin/python3 bench/plot_accuracy.py accuracy.csv -o accuracy.png

--table prints the same slice as Markdown tables instead of plotting.
"""
import argparse
import csv
import math
import os
import sys

PRIMS = ["plane", "triangle", "sphere"]
METHODS = ["naive", "rayscope"]
COLORS = {"plane": (31, 119, 180), "triangle": (230, 120, 20), "sphere": (40, 160, 60)}
# (quantity, value column, panel title, y axis title, floor for log scale)
PANELS = [
    ("t", "p99_ulps", "(a) ray parameter t", "error of t, p99 [ulps of t]", 0.1),
    ("point", "p99_ulps", "(b) hit point", "distance to exact hit point, p99 [ulps]", 0.1),
    ("surface", "p99_ulps", "(c) hit point off the surface",
     "distance from the surface, p99 [ulps]", 0.1),
    ("t", "miss_rate", "(d) hit/miss disagreements with the reference",
     "rays misclassified [%]", 1e-3),
]
REQUIRED = {"primitive", "method", "quantity", "scale", "distance", "placement", "n",
            "p99_ulps", "median_ulps", "max_ulps", "miss_rate"}


def fail(msg):
    print(f"plot_accuracy: {msg}", file=sys.stderr)
    sys.exit(1)


def load(path, scale, placement):
    """{(prim, method, quantity): [(distance, row), ...]} for the chosen slice."""
    try:
        with open(path, newline="") as f:
            reader = csv.DictReader(f)
            missing = REQUIRED - set(reader.fieldnames or [])
            if missing:
                fail(f"{path}: not a bench_accuracy CSV (missing columns {sorted(missing)})")
            rows = list(reader)
    except OSError as e:
        fail(f"{path}: {e.strerror}")
    series = {}
    try:
        for r in rows:
            if r["placement"] != placement or not math.isclose(float(r["scale"]), scale):
                continue
            key = (r["primitive"], r["method"], r["quantity"])
            series.setdefault(key, []).append((float(r["distance"]), r))
    except ValueError as e:
        fail(f"{path}: bad number ({e})")
    if not series:
        fail(f"{path}: no rows with scale {scale:g} and placement '{placement}'")
    for v in series.values():
        v.sort(key=lambda p: p[0])
    return series


def value(row, column, min_n):
    """The statistic, or NaN when it rests on fewer than min_n hits; percent for rates."""
    if column == "miss_rate":
        return 100.0 * float(row[column])
    if not row[column] or int(row["n"]) < min_n:
        return math.nan
    return float(row[column])


def print_tables(series, scale, placement, min_n):
    def f(x):
        return "–" if math.isnan(x) else f"{x:.3g}"
    print(f"Scale {scale:g}, placement {placement}; entries naive / rayscope; "
          f"errors are 99th percentiles in ulps ('–': fewer than {min_n} hits).\n")
    for prim in PRIMS:
        print(f"**{prim}**\n")
        print("| distance | t p99 | point p99 | surface p99 | t median | miss % |")
        print("|---:|---:|---:|---:|---:|---:|")
        distances = [d for d, _ in series[(prim, "naive", "t")]]
        for i, d in enumerate(distances):
            cells = []
            for q, col in [("t", "p99_ulps"), ("point", "p99_ulps"), ("surface", "p99_ulps"),
                           ("t", "median_ulps"), ("t", "miss_rate")]:
                a, b = (value(series[(prim, m, q)][i][1], col, min_n) for m in METHODS)
                cells.append(f"{f(a)} / {f(b)}")
            print(f"| {d:g} | " + " | ".join(cells) + " |")
        print()


def decade_label(e):
    return {-2: "0.01", -1: "0.1", 0: "1", 1: "10", 2: "100"}.get(e, f"1e{e}")


def set_decade_ticks(axis, lo, hi, step):
    """Log axis ticks at every `step`-th decade in [lo, hi], labelled 1e-6, 0.01, 1, 1e4..."""
    from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkStringArray
    positions, labels = vtkDoubleArray(), vtkStringArray()
    for e in range(math.ceil(math.log10(lo) - 1e-9), math.floor(math.log10(hi) + 1e-9) + 1):
        if e % step == 0:
            positions.InsertNextValue(float(e))  # log axes place ticks in log10 units
            labels.InsertNextValue(decade_label(e))
    axis.SetCustomTickPositions(positions, labels)
    return positions, labels


def plot(series, scale, placement, min_n, out, width, height):
    from vtkmodules.vtkChartsCore import vtkAxis, vtkChart, vtkChartMatrix
    from vtkmodules.vtkCommonCore import vtkFloatArray
    from vtkmodules.vtkCommonDataModel import vtkTable, vtkVector2f, vtkVector2i
    from vtkmodules.vtkIOImage import vtkPNGWriter
    from vtkmodules.vtkRenderingContext2D import vtkPen
    from vtkmodules.vtkRenderingCore import vtkTextActor, vtkWindowToImageFilter
    from vtkmodules.vtkViewsContext2D import vtkContextView
    import vtkmodules.vtkRenderingContextOpenGL2  # noqa: F401 (context device)
    import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
    import vtkmodules.vtkRenderingFreeType  # noqa: F401 (text)

    view = vtkContextView()
    view.GetRenderer().SetBackground(1.0, 1.0, 1.0)
    window = view.GetRenderWindow()
    window.SetSize(width, height)
    window.SetOffScreenRendering(1)

    matrix = vtkChartMatrix()
    matrix.SetSize(vtkVector2i(2, 2))
    matrix.SetGutter(vtkVector2f(90.0, 110.0))
    matrix.SetBorders(100, 60, 30, 100)  # left, bottom, right, top (pixels)
    view.GetScene().AddItem(matrix)

    tables = []  # keep the tables alive until rendering
    for k, (quantity, column, title, ytitle, floor) in enumerate(PANELS):
        chart = matrix.GetChart(vtkVector2i(k % 2, 1 - k // 2))
        chart.SetTitle(title)
        chart.GetTitleProperties().SetFontSize(20)
        chart.GetTitleProperties().SetBold(True)
        for axis_id, text in [(vtkAxis.BOTTOM, f"ray origin distance d (primitive size {scale:g})"),
                              (vtkAxis.LEFT, ytitle)]:
            axis = chart.GetAxis(axis_id)
            axis.SetTitle(text)
            axis.SetLogScale(True)
            axis.GetTitleProperties().SetFontSize(16)
            axis.GetLabelProperties().SetFontSize(14)
        bottom = chart.GetAxis(vtkAxis.BOTTOM)
        bottom.SetBehavior(vtkAxis.FIXED)
        bottom.SetRange(0.3e-6, 3e6)
        tables.append(set_decade_ticks(bottom, 1e-6, 1e6, 2))
        top = 1.0
        for prim in PRIMS:
            for method in METHODS:
                pts = series.get((prim, method, quantity), [])
                table = vtkTable()
                xs, ys = vtkFloatArray(), vtkFloatArray()
                xs.SetName("distance")
                ys.SetName(f"{prim}, {'RayScope' if method == 'rayscope' else 'naive'}")
                for d, row in pts:
                    y = value(row, column, min_n)
                    if not math.isnan(y):
                        y = max(y, floor)
                        top = max(top, y)
                    xs.InsertNextValue(d)
                    ys.InsertNextValue(y)
                table.AddColumn(xs)
                table.AddColumn(ys)
                tables.append(table)
                line = chart.AddPlot(vtkChart.LINE)
                line.SetInputData(table, 0, 1)
                line.SetColor(*COLORS[prim], 255)
                line.SetWidth(3.0 if method == "rayscope" else 2.5)
                line.SetMarkerStyle(4 if method == "rayscope" else 2)  # circle / plus
                line.SetMarkerSize(9.0)
                if method == "naive":
                    line.GetPen().SetLineType(vtkPen.DASH_LINE)
        left = chart.GetAxis(vtkAxis.LEFT)
        left.SetBehavior(vtkAxis.FIXED)
        ytop = 300.0 if column == "miss_rate" else 10 ** math.ceil(math.log10(top) + 0.3)
        left.SetRange(floor, ytop)
        decades = math.log10(ytop / floor)
        tables.append(set_decade_ticks(left, floor, ytop, 1 if decades <= 8 else 2))
        # Legends where the panels are empty (upper left of (b) and (c)).
        chart.SetShowLegend(k in (1, 2))
        chart.GetLegend().GetLabelProperties().SetFontSize(15)
        chart.GetLegend().SetHorizontalAlignment(chart.GetLegend().LEFT)
        chart.GetLegend().SetVerticalAlignment(chart.GetLegend().TOP)

    title = vtkTextActor()
    title.SetInput(
        "Intersection accuracy against a __float128 reference: naive textbook formulas (dashed) "
        f"vs RayScope (solid)\nfloat rays, primitive size {scale:g}, placement '{placement}'; "
        "99th percentiles over random rays; values below the axis floor are drawn at it")
    prop = title.GetTextProperty()
    prop.SetFontSize(22)
    prop.SetColor(0.0, 0.0, 0.0)
    prop.SetJustificationToCentered()
    prop.SetVerticalJustificationToTop()
    title.SetPosition(width / 2, height - 12)
    view.GetRenderer().AddActor2D(title)

    window.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.ReadFrontBufferOff()
    grab.Update()
    tmp = os.path.join(os.path.dirname(os.path.abspath(out)),
                       f".{os.path.basename(out)}.tmp{os.getpid()}.png")
    writer = vtkPNGWriter()
    writer.SetFileName(tmp)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()
    if writer.GetErrorCode() or not os.path.exists(tmp):
        if os.path.exists(tmp):
            os.remove(tmp)
        fail(f"{out}: cannot write PNG")
    os.replace(tmp, out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv", help="CSV written by bench_accuracy --csv")
    ap.add_argument("-o", "--output", default="accuracy.png", help="PNG to write")
    ap.add_argument("--scale", type=float, default=1.0, help="primitive size to plot (default 1)")
    ap.add_argument("--placement", default="origin", choices=["origin", "far"])
    ap.add_argument("--min-hits", type=int, default=100,
                    help="leave out statistics over fewer hits (default 100)")
    ap.add_argument("--size", default="1600x1200", help="image size WxH")
    ap.add_argument("--table", action="store_true", help="print Markdown tables, do not plot")
    args = ap.parse_args()
    series = load(args.csv, args.scale, args.placement)
    if args.table:
        print_tables(series, args.scale, args.placement, args.min_hits)
        return
    try:
        width, height = (int(v) for v in args.size.lower().split("x"))
        if width < 400 or height < 300:
            raise ValueError
    except ValueError:
        fail(f"--size {args.size}: expected WxH with W >= 400, H >= 300")
    out_dir = os.path.dirname(os.path.abspath(args.output))
    if not os.path.isdir(out_dir):
        fail(f"{args.output}: directory does not exist")
    plot(series, args.scale, args.placement, args.min_hits, args.output, width, height)


if __name__ == "__main__":
    main()
