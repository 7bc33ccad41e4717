#!/usr/bin/env python3
"""Is the paper's quadratic element worth it? Peak-load error of the DCB
(examples/delamination/dcb.toml) against corrected beam theory versus wall
time, for H8+INTER8, H8I+INTER8, H20+INTER16 and H27+INTER18 over a series
of meshes (element length along the bonded part; H8 gets 2 elements through
each arm, the others 1).

Usage: python3 bench/dcb_mesh_sweep.py [--junta target/release/junta] [--out out/dcb_mesh_sweep]
Writes OUT/sweep.csv and OUT/sweep.svg. Each run goes to delta = 4.8 mm,
past the peak (viscous regularisation of the example), so a run costs
50-100 increments. Reference: corrected beam theory peak 138.51 N
(BENCHMARKS.md section 4, beam_theory.py).
"""
import argparse
import csv
import json
import os
import re
import subprocess
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
P_CBT = 138.51
FAMILIES = [("h8", 2), ("h8i", 1), ("h20", 1), ("h27", 1)]
LENGTHS = [1.0, 0.5, 0.33, 0.25]  # element length along the bonded part (mm)


def scene(template, element, nz, nx_bond):
    s = template.replace('element = "h20"', f'element = "{element}"')
    s = s.replace("divisions = [11, 1, 1]", f"divisions = [11, 1, {nz}]")
    s = re.sub(r"divisions = \[\d+, 1, 1\]", f"divisions = [{nx_bond}, 1, {nz}]", s)
    s = s.replace("steps = [10.0]", "steps = [4.8]")
    s = s.replace('file = "dcb_beam_theory.csv"',
                  'file = "' + os.path.join(REPO, "examples/delamination/dcb_beam_theory.csv") + '"')
    s = re.sub(r"every = \d+", "every = 100000", s)
    return s


def svg(rows, path):
    import math
    w, h, m = 640, 420, 60
    xs = [math.log10(r["seconds"]) for r in rows]
    ys = [math.log10(max(abs(r["error"]), 1e-4)) for r in rows]
    x0, x1 = min(xs) - 0.1, max(xs) + 0.1
    y0, y1 = min(ys) - 0.1, max(ys) + 0.1
    X = lambda v: m + (v - x0) / (x1 - x0) * (w - 2 * m)
    Y = lambda v: h - m - (v - y0) / (y1 - y0) * (h - 2 * m)
    colors = {"h8": "#d62728", "h8i": "#ff7f0e", "h20": "#1f77b4", "h27": "#2ca02c"}
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}">',
           f'<rect width="{w}" height="{h}" fill="white"/>',
           f'<text x="{w/2}" y="20" text-anchor="middle" font-size="14">DCB peak-load error against corrected beam theory vs wall time</text>',
           f'<text x="{w/2}" y="{h-15}" text-anchor="middle" font-size="12">wall time (s, log)</text>',
           f'<text x="15" y="{h/2}" font-size="12" transform="rotate(-90 15 {h/2})" text-anchor="middle">|peak error| (log)</text>',
           f'<line x1="{m}" y1="{h-m}" x2="{w-m}" y2="{h-m}" stroke="black"/>',
           f'<line x1="{m}" y1="{m}" x2="{m}" y2="{h-m}" stroke="black"/>']
    for e in (0.01, 0.02, 0.05, 0.1):
        if y0 <= math.log10(e) <= y1:
            out.append(f'<line x1="{m}" y1="{Y(math.log10(e))}" x2="{w-m}" y2="{Y(math.log10(e))}" stroke="#ccc"/>')
            out.append(f'<text x="{m-5}" y="{Y(math.log10(e))+4}" font-size="10" text-anchor="end">{e:g}</text>')
    for t in (1, 3, 10, 30, 100, 300):
        if x0 <= math.log10(t) <= x1:
            out.append(f'<text x="{X(math.log10(t))}" y="{h-m+15}" font-size="10" text-anchor="middle">{t}</text>')
    for i, (fam, _) in enumerate(FAMILIES):
        pts = [(X(math.log10(r["seconds"])), Y(math.log10(max(abs(r["error"]), 1e-4)))) for r in rows if r["family"] == fam]
        if not pts:
            continue
        out.append('<polyline fill="none" stroke="%s" stroke-width="2" points="%s"/>' % (
            colors[fam], " ".join(f"{x:.1f},{y:.1f}" for x, y in pts)))
        for x, y in pts:
            out.append(f'<circle cx="{x:.1f}" cy="{y:.1f}" r="3" fill="{colors[fam]}"/>')
        out.append(f'<text x="{w-m-80}" y="{m+15*i}" font-size="12" fill="{colors[fam]}">{fam}</text>')
    out.append("</svg>")
    open(path, "w").write("\n".join(out))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--junta", default=os.path.join(REPO, "target/release/junta"))
    ap.add_argument("--out", default=os.path.join(REPO, "out/dcb_mesh_sweep"))
    ap.add_argument("--lengths", default=",".join(map(str, LENGTHS)))
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    template = open(os.path.join(REPO, "examples/delamination/dcb.toml")).read()
    rows = []
    for fam, nz in FAMILIES:
        for le in map(float, a.lengths.split(",")):
            nx = max(1, round(69.1 / le))
            d = os.path.join(a.out, f"{fam}_{nx}")
            os.makedirs(d, exist_ok=True)
            path = os.path.join(d, "scene.toml")
            open(path, "w").write(scene(template, fam, nz, nx))
            t = time.time()
            r = subprocess.run([a.junta, "run", path, "-o", d, "-q"], capture_output=True, text=True)
            wall = time.time() - t
            s = json.load(open(os.path.join(d, "summary.json")))
            with open(os.path.join(d, "curve.csv")) as f:
                peak = max(float(x["reaction"]) for x in csv.DictReader(f))
            row = {"family": fam, "element_length": 69.1 / nx, "through_thickness": nz,
                   "equations": s["equations"], "peak": peak, "error": peak / P_CBT - 1.0,
                   "seconds": wall, "increments": s["increments"], "status": s["status"][:60]}
            rows.append(row)
            print(f"{fam:4} l_e={69.1/nx:.3f} eq={s['equations']:6} peak={peak:7.2f} N "
                  f"error={100*row['error']:+6.2f} % wall={wall:6.1f} s  {row['status']}", flush=True)
    with open(os.path.join(a.out, "sweep.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    svg(rows, os.path.join(a.out, "sweep.svg"))
    print("wrote", os.path.join(a.out, "sweep.csv"), "and sweep.svg")


if __name__ == "__main__":
    main()
