#!/usr/bin/env python3
"""Area against max error of every module in out/hw/summary.json, as SVG.

    python3 hw/plot_pareto.py SUMMARY.json OUT.svg

One column per kind of error (texture coordinates in texels; t_w as a
fraction of the span; a window's texel positions in texels), since the
modules of different kinds compute different things; two rows of area:
the technology-independent transistor estimate (Yosys + ABC, `stat -tech
cmos`) and the iCE40's logic cells of the module itself (`ice40_lc_module`:
the out-of-context wrapper's LCs subtracted, also for a module that does not
fit the UP5K) plus each SB_MAC16 counted as the SB_LUT4s of a 16 x 16
multiply built from logic (`ice40_dsp_lut4_equivalent`, measured by
scripts/hw.sh). Each panel's Pareto front (no other module both smaller
and more accurate) is the line. Both axes are logarithmic. Standard library
only; modules missing a number are listed under the plot, not drawn.
"""
import html
import json
import math
import sys

GROUPS = [
    ("texels", "texture coordinates: max error (texels)"),
    ("t_w", "t_w along a span: max |error|"),
    ("texel position", "window texels: max position error (texels)"),
]
PW, PH = 330, 250          # panel
ML, MR, MT, MB = 70, 20, 40, 45
COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf",
           "#7f7f7f", "#bcbd22"]


def error_of(r):
    """(unit, value): the module's max error in its own unit."""
    unit = r.get("error_unit")
    if unit:
        return unit, r.get("max_error")
    return "texels", r.get("max_error_texels")


def areas(r, dspeq):
    """The two areas, None where the summary lacks a number."""
    cmos = r.get("cmos_transistors")
    lc = r.get("ice40_lc_module")
    ice = None
    if lc is not None and dspeq is not None:
        ice = lc + (r.get("ice40_dsp_module") or 0) * dspeq
    return cmos, ice


def pareto(points):
    """The non-dominated points (area, error), sorted by error."""
    front = []
    for p in sorted(points, key=lambda q: (q[1], q[0])):
        if not front or p[0] < front[-1][0]:
            front.append(p)
    return front


def log_range(vals):
    lo, hi = min(vals), max(vals)
    a, b = math.floor(math.log10(lo)), math.ceil(math.log10(hi))
    if a == b:
        b += 1
    return a, b


def panel(out, x0, y0, title, ylabel, pts, colour_of):
    """pts: [(module, error, area)]."""
    out.append('<g transform="translate(%d,%d)">' % (x0, y0))
    out.append('<rect x="0" y="0" width="%d" height="%d" fill="none" stroke="#444"/>' % (PW, PH))
    out.append('<text x="%d" y="-8" font-size="12" text-anchor="middle">%s</text>' % (PW // 2, html.escape(title)))
    if not pts:
        out.append('<text x="%d" y="%d" font-size="11" text-anchor="middle" fill="#777">no module</text>'
                   % (PW // 2, PH // 2))
        out.append("</g>")
        return
    ex0, ex1 = log_range([p[1] for p in pts])
    ay0, ay1 = log_range([p[2] for p in pts])

    def X(e):
        return (math.log10(e) - ex0) / (ex1 - ex0) * PW

    def Y(a):
        return PH - (math.log10(a) - ay0) / (ay1 - ay0) * PH

    for d in range(ex0, ex1 + 1):
        x = X(10.0 ** d)
        out.append('<line x1="%.1f" y1="0" x2="%.1f" y2="%d" stroke="#ddd"/>' % (x, x, PH))
        out.append('<text x="%.1f" y="%d" font-size="10" text-anchor="middle">1e%d</text>' % (x, PH + 14, d))
    for d in range(ay0, ay1 + 1):
        y = Y(10.0 ** d)
        out.append('<line x1="0" y1="%.1f" x2="%d" y2="%.1f" stroke="#ddd"/>' % (y, PW, y))
        out.append('<text x="-5" y="%.1f" font-size="10" text-anchor="end">1e%d</text>' % (y + 3, d))
    out.append('<text x="%d" y="%d" font-size="11" text-anchor="middle">max error</text>' % (PW // 2, PH + 32))
    out.append('<text transform="translate(-52,%d) rotate(-90)" font-size="11" text-anchor="middle">%s</text>'
               % (PH // 2, html.escape(ylabel)))
    front = pareto([(a, e) for _, e, a in pts])
    if len(front) > 1:
        path = []
        for k, (a, e) in enumerate(front):
            if k:
                path.append("L%.1f,%.1f" % (X(e), Y(front[k - 1][0])))
            path.append(("M" if not k else "L") + "%.1f,%.1f" % (X(e), Y(a)))
        out.append('<path d="%s" fill="none" stroke="#000" stroke-dasharray="4,3"/>' % " ".join(path))
    for m, e, a in pts:
        on = (a, e) in front
        out.append('<circle cx="%.1f" cy="%.1f" r="%d" fill="%s" stroke="#000" stroke-width="%s">'
                   '<title>%s: error %g, area %g</title></circle>'
                   % (X(e), Y(a), 5 if on else 4, colour_of(m), "1.5" if on else "0.5", html.escape(m), e, a))
        out.append('<text x="%.1f" y="%.1f" font-size="10">%s</text>' % (X(e) + 6, Y(a) - 5, html.escape(m)))
    out.append("</g>")


def main():
    if len(sys.argv) != 3:
        sys.stderr.write("usage: plot_pareto.py SUMMARY.json OUT.svg\n")
        return 2
    summary = json.load(open(sys.argv[1]))
    rows = summary.get("modules", [])
    dspeq = summary.get("ice40_dsp_lut4_equivalent")
    names = [r["module"] for r in rows]
    colour_of = lambda m: COLOURS[names.index(m) % len(COLOURS)]
    groups = [(u, t) for u, t in GROUPS if any(error_of(r)[0] == u for r in rows)] or GROUPS[:1]
    skipped = []
    data = {}
    for r in rows:
        unit, err = error_of(r)
        cmos, ice = areas(r, dspeq)
        for row, area in enumerate((cmos, ice)):
            if err is None or not err > 0 or area is None or not area > 0:
                skipped.append("%s (%s)" % (r["module"], "no error" if err is None or not err > 0 else
                                            ("no transistor estimate", "no iCE40 area")[row]))
                continue
            data.setdefault((unit, row), []).append((r["module"], float(err), float(area)))
    width = ML + len(groups) * (PW + ML + MR)
    height = MT + 30 + 2 * (PH + MT + MB) + 40
    out = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif">' % (width, height),
           '<rect width="100%" height="100%" fill="#fff"/>',
           '<text x="%d" y="22" font-size="15" text-anchor="middle">Area against max error of the RTL modules '
           '(Pareto front dashed)</text>' % (width // 2)]
    ylabels = ("CMOS transistors (Yosys + ABC)", "iCE40 LCs + %s LUT4 per SB_MAC16" % (dspeq if dspeq else "?"))
    for c, (unit, title) in enumerate(groups):
        for row in range(2):
            panel(out, ML + c * (PW + ML + MR), MT + 30 + row * (PH + MT + MB), title, ylabels[row],
                  data.get((unit, row), []), colour_of)
    notes = "iCE40 area: the module's logic cells, the out-of-context wrapper's subtracted; block RAM not counted."
    out.append('<text x="10" y="%d" font-size="10">%s</text>' % (height - 24, html.escape(notes)))
    if skipped:
        out.append('<text x="10" y="%d" font-size="10">not drawn: %s</text>'
                   % (height - 10, html.escape(", ".join(sorted(set(skipped))))))
    out.append("</svg>")
    with open(sys.argv[2], "w") as f:
        f.write("\n".join(out) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
