#!/usr/bin/env python3
"""Model no more than a scene needs: the DCB as a 2D plane-strain model
(examples/plane/dcb_plane_strain.toml: CPE8 + LINE_INTER6, the width out
of the plane) against the one-element-wide 3D slab of the same in-plane
mesh (examples/delamination/dcb_arc.toml: H20 + INTER16), both traced by
arc length to a 10 mm opening, on a series of meshes along the bond.

For each model and mesh: equations, wall time (median of --repeat runs of
the release binary), increments, Newton iterations, and the accuracy: the
peak load and the mean load over the propagation (5.5 to 9.5 mm) against
corrected beam theory (plane strain for the 2D model, E11 / (1 - nu13
nu31); the slab's beam theory is the same within 0.13 %, BENCHMARKS.md
section 7). Writes OUT/plane_vs_slab.csv and OUT/plane_vs_slab.svg (wall
time against the peak error, one line per model).

With --full, also the full-width 3D model (the slab's scene with four H20
across the 25.4 mm width, its sides free): the third line of the chart.

Run: python3 bench/plane_vs_slab.py [--repeat 3] [--full] [--junta target/release/junta] [--out out/plane_vs_slab]
"""
import argparse
import csv
import json
import math
import os
import re
import statistics
import subprocess
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PLANE = os.path.join(ROOT, "examples", "plane", "dcb_plane_strain.toml")
SLAB = os.path.join(ROOT, "examples", "delamination", "dcb_arc.toml")
BOND_DIVISIONS = [70, 155, 280]  # elements along the 69.1 mm bond: 0.99, 0.45, 0.25 mm


def beam_theory():
    """(peak load, load on the propagation branch as a function of delta),
    corrected beam theory in plane strain (crates/cli/tests/plane_dcb.rs)."""
    e11, e22, e33, g13, nu13 = 122700.0, 10100.0, 10100.0, 5500.0, 0.25
    e = e11 / (1.0 - nu13 * nu13 * e33 / e11)
    b, h, a0, gc = 25.4, 1.56, 32.9, 0.969
    gamma = 1.18 * math.sqrt(e * e22) / g13
    chi = math.sqrt(e / (11.0 * g13) * (3.0 - 2.0 * (gamma / (1.0 + gamma)) ** 2))
    ei, a_e = e * b * h ** 3 / 12.0, a0 + chi * h
    peak = math.sqrt(gc * b * ei) / a_e
    return peak, lambda d: (gc * b) ** 0.75 * ei ** 0.25 * math.sqrt(2.0 / (3.0 * d))


def scene(path, n, across=1):
    """The scene of `path` with `n` elements along the bond and, for the 3D
    scenes, `across` elements across the width."""
    text = open(path).read()
    text = re.sub(r"divisions = \[155, 1(, 1)?\]", lambda m: f"divisions = [{n}, 1{m.group(1) or ''}]", text)
    text = re.sub(r"divisions = \[(\d+), 1, 1\]", lambda m: f"divisions = [{m.group(1)}, {across}, 1]", text)
    if across > 1:
        # the curved front's snap-backs stop the arc length alone; the
        # default control passes them
        text = text.replace('control = "arc_length"\n', "")
    ref = os.path.join(ROOT, "examples", "delamination", "dcb_beam_theory.csv")
    text = re.sub(r'file = "[^"]*dcb_beam_theory.csv"', f'file = "{ref}"', text)
    return re.sub(r"every = \d+", "every = 100000", text)


def curve(path):
    with open(path) as f:
        return [(float(r["displacement"]), float(r["reaction"])) for r in csv.DictReader(f)]


def load_at(c, d):
    for (d0, p0), (d1, p1) in zip(c, c[1:]):
        if d0 <= d <= d1 and d1 > d0:
            return p0 + (p1 - p0) * (d - d0) / (d1 - d0)
    return float("nan")


def run(junta, text, repeat):
    times, summary, rows = [], None, None
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "dcb.toml")
        with open(path, "w") as f:
            f.write(text)
        for _ in range(repeat):
            out = os.path.join(tmp, "out")
            t0 = time.perf_counter()
            # a run that stops (a snap-back it cannot follow) still has
            # its curve up to there: the chart shows how far it got
            subprocess.run([junta, "run", path, "-o", out, "-q"], check=False)
            times.append(time.perf_counter() - t0)
            summary = json.load(open(os.path.join(out, "summary.json")))
            rows = curve(os.path.join(out, "curve.csv"))
    return statistics.median(times), summary, rows


def svg(rows, path):
    w, h, m = 560, 360, 60
    xs = [r["seconds"] for r in rows]
    ys = [abs(r["peak_error_pct"]) for r in rows]
    lx = lambda v: m + (math.log10(v) - math.log10(min(xs) / 1.5)) / (math.log10(max(xs) * 1.5) - math.log10(min(xs) / 1.5)) * (w - 2 * m)
    ly = lambda v: h - m - v / (max(ys) * 1.2) * (h - 2 * m)
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="12">',
           f'<text x="{w/2}" y="20" text-anchor="middle">DCB: peak error against wall time (2D plane strain, 3D slab, full-width 3D)</text>',
           f'<line x1="{m}" y1="{h-m}" x2="{w-m}" y2="{h-m}" stroke="black"/><line x1="{m}" y1="{m}" x2="{m}" y2="{h-m}" stroke="black"/>',
           f'<text x="{w/2}" y="{h-20}" text-anchor="middle">wall time (s, log)</text>',
           f'<text x="15" y="{h/2}" transform="rotate(-90 15 {h/2})" text-anchor="middle">|peak - beam theory| (%)</text>']
    for model, colour in [("2D CPE8", "#1f77b4"), ("3D H20 slab", "#d62728"), ("3D H20, 4 across", "#2ca02c")]:
        pts = [(lx(r["seconds"]), ly(abs(r["peak_error_pct"])), r) for r in rows if r["model"] == model]
        out.append('<polyline fill="none" stroke="%s" points="%s"/>' % (colour, " ".join(f"{x:.1f},{y:.1f}" for x, y, _ in pts)))
        for x, y, r in pts:
            out.append(f'<circle cx="{x:.1f}" cy="{y:.1f}" r="3" fill="{colour}"/><text x="{x+5:.1f}" y="{y-5:.1f}">{r["element_mm"]:.2f} mm</text>')
        k = ["#1f77b4", "#d62728", "#2ca02c"].index(colour)
        out.append(f'<text x="{w-m-120}" y="{m + 20 * k}" fill="{colour}">{model}</text>')
    out.append("</svg>")
    open(path, "w").write("\n".join(out))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--junta", default=None)
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "plane_vs_slab"))
    ap.add_argument("--full", action="store_true",
                    help="also the full-width 3D model: four H20 across the 25.4 mm width, free sides")
    a = ap.parse_args()
    junta = a.junta
    if junta is None:
        subprocess.run(["cargo", "build", "--release", "-q", "-p", "junta-cli"], cwd=ROOT, check=True)
        junta = os.path.join(ROOT, "target", "release", "junta")
    os.makedirs(a.out, exist_ok=True)
    peak_cbt, prop = beam_theory()
    mean_cbt = statistics.mean(prop(5.5 + 0.1 * k) for k in range(41))
    rows = []
    for n in BOND_DIVISIONS:
        models = [("2D CPE8", PLANE, 1), ("3D H20 slab", SLAB, 1)]
        if a.full:
            models.append(("3D H20, 4 across", SLAB, 4))
        for model, path, across in models:
            secs, s, c = run(junta, scene(path, n, across), a.repeat)
            peak = max(p for _, p in c)
            mean = statistics.mean(load_at(c, 5.5 + 0.1 * k) for k in range(41))
            rows.append({
                "model": model, "element_mm": 69.1 / n, "equations": s["equations"],
                "seconds": secs, "increments": s["increments"],
                "status": s.get("status", "")[:60],
                "newton_iterations": s["newton_iterations"]["total"],
                "peak_N": peak, "peak_error_pct": 100.0 * (peak / peak_cbt - 1.0),
                "mean_propagation_N": mean, "mean_error_pct": 100.0 * (mean / mean_cbt - 1.0),
            })
            print(" | ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}" for k, v in rows[-1].items()), flush=True)
    with open(os.path.join(a.out, "plane_vs_slab.csv"), "w", newline="") as f:
        wr = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        wr.writeheader()
        wr.writerows(rows)
    svg(rows, os.path.join(a.out, "plane_vs_slab.svg"))
    for n in BOND_DIVISIONS:
        two = next(r for r in rows if r["model"] == "2D CPE8" and abs(r["element_mm"] - 69.1 / n) < 1e-9)
        three = next(r for r in rows if r["model"] == "3D H20 slab" and abs(r["element_mm"] - 69.1 / n) < 1e-9)
        print(f"{69.1 / n:.2f} mm: slab / 2D wall time = {three['seconds'] / two['seconds']:.2f}, "
              f"equations {three['equations']} / {two['equations']}")
        full = [r for r in rows if r["model"] == "3D H20, 4 across" and abs(r["element_mm"] - 69.1 / n) < 1e-9]
        if full:
            print(f"{69.1 / n:.2f} mm: full-width 3D / 2D wall time = {full[0]['seconds'] / two['seconds']:.2f}, "
                  f"equations {full[0]['equations']} / {two['equations']}")


if __name__ == "__main__":
    main()
