#!/usr/bin/env python3
"""Performance of the fracture-laws issue: the DCB at 50,000 dofs or more,
full curve to a 10 mm opening (bench/dcb_50k.toml: 50,736 dofs), with the
release binary, next to the 12k-equation DCB of the examples
(examples/delamination/dcb_arc.toml).

For each scene: wall time (median of --repeat runs), increments, Newton
iterations, the split between assembly, factorisation and solve (from the
run's summary.json), symbolic analyses (one per run), numeric
factorisations and how many of them were partial (only the panels of the
factor reached by the entries that changed, see crates/solvers/src/ldlt.rs)
with the mean share of the work they redid; and the accuracy: the peak load
and the load at 6, 8 and 10 mm against corrected beam theory
(examples/delamination/dcb_beam_theory.csv).

`--solver KEY=VALUE` passes solver overrides to every run (e.g.
`--solver partial_refactor=false` for the complete refactorisation each
iteration, `--solver ordering=amd`).

Run: python3 bench/dcb_performance.py [--repeat 3] [--solver KEY=VALUE ...]
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = [
    ("dcb_arc (12k eq)", os.path.join(ROOT, "examples", "delamination", "dcb_arc.toml")),
    ("dcb_50k (51k dofs)", os.path.join(ROOT, "bench", "dcb_50k.toml")),
]
BEAM = os.path.join(ROOT, "examples", "delamination", "dcb_beam_theory.csv")


def build():
    subprocess.run(["cargo", "build", "--release", "-q", "-p", "junta-cli"], cwd=ROOT, check=True)
    return os.path.join(ROOT, "target", "release", "junta")


def read_curve(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return [(float(r["displacement"]), float(r["reaction"])) for r in rows]


def read_beam():
    pts = []
    with open(BEAM) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            d, p = line.split(",")[:2]
            pts.append((float(d), float(p)))
    return pts


def at(curve, x):
    """Load at opening x on the last branch through x (linear interpolation)."""
    best = None
    for (d0, p0), (d1, p1) in zip(curve, curve[1:]):
        if min(d0, d1) <= x <= max(d0, d1) and d1 != d0:
            best = p0 + (p1 - p0) * (x - d0) / (d1 - d0)
    return best


def run(junta, scene, extra, repeat):
    walls, summary, curve = [], None, None
    for _ in range(repeat):
        with tempfile.TemporaryDirectory() as out:
            t = time.perf_counter()
            p = subprocess.run([junta, "-q", "run", scene, "-o", out] + extra,
                               capture_output=True, text=True)
            walls.append(time.perf_counter() - t)
            with open(os.path.join(out, "summary.json")) as f:
                summary = json.load(f)
            curve = read_curve(os.path.join(out, "curve.csv"))
            if p.returncode != 0:
                summary["status"] = "failed: " + p.stderr.strip().splitlines()[-1][:80]
    return statistics.median(walls), summary, curve


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--solver", action="append", default=[])
    args = ap.parse_args()
    junta = build()
    extra = [a for kv in args.solver for a in ("--solver", kv)]
    beam = read_beam()
    peak_bt = max(p for _, p in beam)
    print(f"# {args.repeat} run(s) each, median wall time; solver overrides: {args.solver or 'none'}")
    print("| scene | dofs | wall s | increments | Newton it. | assemble s | factor s | solve s "
          "| analyses | factorisations (partial, mean share) | peak N (beam theory) | P(6), P(8), P(10) vs beam theory |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name, scene in SCENES:
        wall, s, curve = run(junta, scene, extra, args.repeat)
        t = s["timings"]
        sol = s["solver"]
        share = sol.get("partial_work_mean")
        part = f"{sol.get('factorizations')} ({sol.get('partial_factorizations')}, " + (
            f"{100 * share:.1f} %)" if share is not None else "-)")
        peak = max(p for _, p in curve)
        errs = []
        for x in (6.0, 8.0, 10.0):
            pj, pb = at(curve, x), at(beam, x)
            errs.append("-" if pj is None or pb is None else f"{100 * (pj - pb) / pb:+.1f} %")
        print(f"| {name} | {s['dofs']} | {wall:.1f} | {s['increments']} | "
              f"{s['newton_iterations']['total']} | {t['assemble']:.1f} | {t['factor']:.1f} | "
              f"{t['solve']:.1f} | {s.get('symbolic_analyses')} | {part} | "
              f"{peak:.1f} ({peak_bt:.1f}) | {', '.join(errs)} |")
        if s.get("status") != "completed":
            print(f"  status: {s.get('status')}")


if __name__ == "__main__":
    main()
