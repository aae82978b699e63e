#!/usr/bin/env python3
"""Log-log plot of the P1 interpolation error against the vertex count, from
the CSV written by the adaptation_loop example (--csv): uniform isotropic
meshes, every remeshing of the adaptation loop, and the N^(-2/3) slope.
Writes an SVG with no dependency beyond the standard library.

    plot_adaptation.py IN.csv OUT.svg [--norm l2|linf]
"""
import csv
import math
import sys


def main(argv):
    if len(argv) < 3:
        sys.exit(__doc__)
    norm = "l2"
    if "--norm" in argv:
        norm = argv[argv.index("--norm") + 1]
    rows = list(csv.DictReader(open(argv[1])))
    if not rows:
        sys.exit("no rows in " + argv[1])
    domains = sorted({r["domain"] for r in rows}, key=lambda d: [r["domain"] for r in rows].index(d))
    xs = [float(r["vertices"]) for r in rows]
    ys = [float(r[norm]) for r in rows if float(r[norm]) > 0]
    x0, x1 = math.log10(min(xs)) - 0.05, math.log10(max(xs)) + 0.05
    y0, y1 = math.log10(min(ys)) - 0.1, math.log10(max(ys)) + 0.1
    W, H, L, R, T, B = 880, 480, 80, 290, 40, 60
    px = lambda x: L + (math.log10(x) - x0) / (x1 - x0) * (W - L - R)
    py = lambda y: T + (y1 - math.log10(y)) / (y1 - y0) * (H - T - B)
    out = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif" font-size="12">' % (W, H),
           '<rect width="100%" height="100%" fill="white"/>']
    out.append('<rect x="%d" y="%d" width="%d" height="%d" fill="none" stroke="black"/>' % (L, T, W - L - R, H - T - B))
    for e in range(math.floor(x0), math.ceil(x1) + 1):
        for m in range(1, 10):
            v = m * 10 ** e
            if x0 <= math.log10(v) <= x1:
                X = px(v)
                out.append('<line x1="%.1f" y1="%d" x2="%.1f" y2="%d" stroke="#ddd"/>' % (X, T, X, H - B))
                if m in (1, 2, 5):
                    out.append('<text x="%.1f" y="%d" text-anchor="middle">%g</text>' % (X, H - B + 16, v))
    for e in range(math.floor(y0), math.ceil(y1) + 1):
        for m in range(1, 10):
            v = m * 10 ** e
            if y0 <= math.log10(v) <= y1:
                Y = py(v)
                out.append('<line x1="%d" y1="%.1f" x2="%d" y2="%.1f" stroke="#ddd"/>' % (L, Y, W - R, Y))
                if m in (1, 2, 5):
                    out.append('<text x="%d" y="%.1f" text-anchor="end">%g</text>' % (L - 6, Y + 4, v))
    out.append('<text x="%d" y="%d" text-anchor="middle">vertices</text>' % ((L + W - R) / 2, H - 20))
    out.append('<text x="20" y="%d" transform="rotate(-90 20 %d)" text-anchor="middle">%s interpolation error</text>'
               % ((T + H - B) / 2, (T + H - B) / 2, "L2" if norm == "l2" else "L-infinity"))
    colors = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd"]
    legend = []
    for k, d in enumerate(domains):
        c = colors[k % len(colors)]
        uni = sorted((float(r["vertices"]), float(r[norm])) for r in rows if r["domain"] == d and r["mesh"] == "uniform")
        if uni:
            out.append('<polyline fill="none" stroke="%s" stroke-dasharray="6,4" points="%s"/>'
                       % (c, " ".join("%.1f,%.1f" % (px(x), py(y)) for x, y in uni)))
            for x, y in uni:
                out.append('<rect x="%.1f" y="%.1f" width="7" height="7" fill="white" stroke="%s"/>' % (px(x) - 3.5, py(y) - 3.5, c))
            legend.append((c, "6,4", d + ": uniform"))
        targets = sorted({float(r["target"]) for r in rows if r["domain"] == d})
        finals = []
        for t in targets:
            its = [(int(r["iteration"]), float(r["vertices"]), float(r[norm])) for r in rows
                   if r["domain"] == d and r["mesh"] == "adapted" and float(r["target"]) == t]
            for _, x, y in sorted(its):
                out.append('<circle cx="%.1f" cy="%.1f" r="2.5" fill="%s" fill-opacity="0.35"/>' % (px(x), py(y), c))
            if its:
                finals.append(sorted(its)[-1][1:])
        if finals:
            out.append('<polyline fill="none" stroke="%s" stroke-width="2" points="%s"/>'
                       % (c, " ".join("%.1f,%.1f" % (px(x), py(y)) for x, y in sorted(finals))))
            for x, y in finals:
                out.append('<circle cx="%.1f" cy="%.1f" r="4" fill="%s"/>' % (px(x), py(y), c))
            legend.append((c, "", d + ": adapted (last remesh)"))
            if k > 0:
                continue
            # the N^(-2/3) reference through the first domain's first final point
            xa, ya = sorted(finals)[0]
            xb = max(xs)
            out.append('<line x1="%.1f" y1="%.1f" x2="%.1f" y2="%.1f" stroke="black" stroke-dasharray="2,3"/>'
                       % (px(xa), py(ya * 1.4), px(xb), py(ya * 1.4 * (xb / xa) ** (-2 / 3))))
    legend.append(("black", "2,3", "N^(-2/3)"))
    for i, (c, dash, text) in enumerate(legend):
        y = T + 10 + 20 * i
        out.append('<line x1="%d" y1="%d" x2="%d" y2="%d" stroke="%s" stroke-width="2" %s/>'
                   % (W - R + 10, y, W - R + 40, y, c, 'stroke-dasharray="%s"' % dash if dash else ""))
        out.append('<text x="%d" y="%d">%s</text>' % (W - R + 46, y + 4, text))
    out.append('<text x="%d" y="%d" font-size="11">small dots: each remeshing of the loop</text>' % (W - R + 10, T + 20 * len(legend) + 14))
    out.append("</svg>")
    open(argv[2], "w").write("\n".join(out) + "\n")


if __name__ == "__main__":
    main(sys.argv)
