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

`--sweep-target 5,8,12,16` charts speed against accuracy instead: the 50k
scene with `[analysis.arc_length] target_iterations` set to each value
(longer path steps for larger values), its wall time, increments and
Newton iterations next to the load at 3, 4, ..., 10 mm against the run
with the first value (the finest path steps) and against beam theory.

Run: python3 bench/dcb_performance.py [--repeat 3] [--solver KEY=VALUE ...]
     python3 bench/dcb_performance.py --sweep-target 5,8,12,16 [--repeat 3]
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


def with_target(scene, target):
    """A copy of `scene` (beside it, so that its relative paths hold) with
    `target_iterations = target` in `[analysis.arc_length]`."""
    lines, out, placed = open(scene).read().splitlines(), [], False
    for line in lines:
        if line.strip().startswith("target_iterations"):
            continue
        out.append(line)
        if line.strip() == "[analysis.arc_length]":
            out.append(f"target_iterations = {target}")
            placed = True
    if not placed:
        out += ["[analysis.arc_length]", f"target_iterations = {target}"]
    fd, path = tempfile.mkstemp(suffix=".toml", prefix="_target", dir=os.path.dirname(scene))
    with os.fdopen(fd, "w") as f:
        f.write("\n".join(out) + "\n")
    return path


def sweep_target(junta, targets, extra, repeat, beam):
    scene = SCENES[1][1]
    xs = [3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0]
    print(f"# {os.path.relpath(scene, ROOT)}: path step target, {repeat} run(s) each, median wall time")
    print("| target_iterations | wall s | increments | Newton it. | peak N | max |dP| vs finest, 3-10 mm "
          "| max |dP| vs beam theory, 5-10 mm |")
    print("|---|---|---|---|---|---|---|")
    finest = None
    for t in targets:
        path = with_target(scene, t)
        try:
            wall, s, curve = run(junta, path, extra, repeat)
        finally:
            os.remove(path)
        if finest is None:
            finest = curve
        d_fine = max(abs(at(curve, x) - at(finest, x)) / at(finest, x) for x in xs)
        d_beam = max(abs(at(curve, x) - at(beam, x)) / at(beam, x) for x in xs if x >= 5.0)
        print(f"| {t} | {wall:.1f} | {s['increments']} | {s['newton_iterations']['total']} | "
              f"{max(p for _, p in curve):.1f} | {100 * d_fine:.3f} % | {100 * d_beam:.2f} % |")
        if s.get("status") != "completed":
            print(f"  status: {s.get('status')}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--solver", action="append", default=[])
    ap.add_argument("--sweep-target", default=None,
                    help="comma-separated target_iterations values for the 50k scene")
    args = ap.parse_args()
    junta = build()
    extra = [a for kv in args.solver for a in ("--solver", kv)]
    beam = read_beam()
    if args.sweep_target:
        targets = [int(v) for v in args.sweep_target.split(",")]
        sweep_target(junta, targets, extra, args.repeat, beam)
        return
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
