#!/usr/bin/env python3
"""Speed against accuracy of the default control (issue: runs that reach
their end by themselves): whole runs with the release binary, as a user
runs them, against the controls a user had to choose before.

DCB (AS4/PEEK, BENCHMARKS.md section 4), accuracy against corrected beam
theory (CBT: peak 138.5 N; P(delta) on the propagation branch):
  - dcb_plain.toml: no control, no viscosity (`auto`: path following from
    the peak on);
  - dcb_arc.toml: `control = "arc_length"` throughout;
  - dcb.toml: displacement control with `viscosity = 1e-4` (--viscous: the
    full curve takes about two minutes);
  - dcb_abaqus.inp as it is (`auto`), and with --solver control=arc_length.
  - dcb_plain.toml without its increment lines (the defaults a user who
    writes nothing gets), auto against arc length;
ENF with a0 = 0.5 L (enf_snapback.toml, snap-back) without its `control`
line, against the example as it is (arc length throughout).
Mixed mode (mmb80_short.toml, G_II/G_T = 0.8): the default tangent (the
switch to the exact tangent when Newton stalls) against `tangent =
"exact"` from the start; accuracy: the first peak and the end point.

For each: median wall time of --repeat runs, increments, Newton
iterations, the switches the driver made, the peak, and the worst and mean
deviation from CBT past 5.5 mm (DCB).

The ratio the issue targets (auto / path following, at most 1.3) is
printed under the table.

Run: python3 bench/auto_control.py [--repeat 3] [--viscous] [--junta BINARY]
(--junta: another build, e.g. an older commit's, for a before/after table)
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
EX = os.path.join(ROOT, "examples", "delamination")


def cbt(delta):
    gic, b, e11, h = 0.969, 25.4, 122700.0, 1.56
    return (gic * b) ** 0.75 * (e11 * b * h**3 / 12.0) ** 0.25 * (2.0 / (3.0 * delta)) ** 0.5


def build():
    subprocess.run(["cargo", "build", "--release", "-q", "-p", "junta-cli"], cwd=ROOT, check=True)
    return os.path.join(ROOT, "target", "release", "junta")


def run(junta, scene, extra, repeat):
    walls = []
    for _ in range(repeat):
        with tempfile.TemporaryDirectory() as out:
            t = time.perf_counter()
            subprocess.run([junta, "-q", "run", scene, "-o", out] + extra,
                           capture_output=True, text=True, check=False)
            walls.append(time.perf_counter() - t)
            with open(os.path.join(out, "summary.json")) as f:
                summary = json.load(f)
            with open(os.path.join(out, "curve.csv")) as f:
                rows = [(float(r["displacement"]), float(r["reaction"])) for r in csv.DictReader(f)]
    return statistics.median(walls), summary, rows


def first_peak(rows):
    best = (0.0, 0.0)
    for d, p in rows:
        if p < 0.9 * best[1]:
            break
        if p > best[1]:
            best = (d, p)
    return best


def exact_tangent_copy(tmp):
    src = os.path.join(EX, "mmb80_short.toml")
    plain = [l for l in open(src) if not l.startswith("tangent =")]
    default = os.path.join(tmp, "mmb80_short_default.toml")
    open(default, "w").writelines(plain)
    return default, src


def stripped_copy(tmp, name, drop):
    """examples/delamination/`name` without the lines starting with any of
    `drop`, its reference curves linked beside it."""
    lines = [l for l in open(os.path.join(EX, name)) if not l.startswith(drop)]
    out = os.path.join(tmp, name.replace(".toml", "_auto.toml"))
    open(out, "w").writelines(lines)
    for f in os.listdir(EX):
        if f.endswith(".csv") and not os.path.exists(os.path.join(tmp, f)):
            os.symlink(os.path.join(EX, f), os.path.join(tmp, f))
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--viscous", action="store_true")
    ap.add_argument("--junta", help="the binary to time (default: this tree's release build)")
    a = ap.parse_args()
    junta = a.junta or build()
    with tempfile.TemporaryDirectory() as tmp:
        dcb_default = stripped_copy(tmp, "dcb_plain.toml", ("initial_increment", "max_increment"))
        enf_auto = stripped_copy(tmp, "enf_snapback.toml", ("control =",))
        mmb_default, mmb_exact = exact_tangent_copy(tmp)
        cases = [
            ("dcb_plain.toml (auto)", os.path.join(EX, "dcb_plain.toml"), [], "dcb"),
            ("dcb_arc.toml (arc_length)", os.path.join(EX, "dcb_arc.toml"), [], "dcb"),
            ("dcb_abaqus.inp (auto)", os.path.join(EX, "dcb_abaqus.inp"), [], "dcb"),
            ("dcb_abaqus.inp (arc_length)", os.path.join(EX, "dcb_abaqus.inp"),
             ["--solver", "control=arc_length"], "dcb"),
            ("dcb_plain.toml, default increments (auto)", dcb_default, [], "dcb"),
            ("dcb_plain.toml, default increments (arc_length)", dcb_default,
             ["--solver", "control=arc_length"], "dcb"),
            ("enf_snapback.toml without control (auto)", enf_auto, [], "enf"),
            ("enf_snapback.toml (arc_length)", os.path.join(EX, "enf_snapback.toml"), [], "enf"),
            ("mmb80_short (default tangent)", mmb_default, [], "mmb"),
            ("mmb80_short (tangent = exact)", mmb_exact, [], "mmb"),
        ]
        if a.viscous:
            cases.insert(2, ("dcb.toml (viscous, displacement)", os.path.join(EX, "dcb.toml"), [], "dcb"))
        print("| run | wall (s, median) | increments | Newton iterations | switches | peak (N) | CBT past 5.5 mm: worst / mean | end |")
        print("|---|---|---|---|---|---|---|---|")
        walls = {}
        for label, scene, extra, kind in cases:
            wall, s, rows = run(junta, scene, extra, a.repeat)
            walls[label] = wall
            # deck displacements are load factors x 10 mm: the curve is in mm
            dpk, ppk = first_peak(rows)
            switches = ", ".join(f"{w['to']}@{w['increment']}" for w in s.get("path_switches", [])) or "-"
            if kind == "dcb":
                errs = [p / cbt(d) - 1.0 for d, p in rows if d > 5.5]
                dev = f"{100 * max(errs, key=abs):+.1f} % / {100 * statistics.mean(errs):+.1f} %" if errs else "-"
            else:
                dev = "-"
            end = f"{rows[-1][1]:.1f} N at {rows[-1][0]:.2f} mm"
            print(f"| {label} | {wall:.2f} | {s['increments']} | {s['newton_iterations']['total']} | "
                  f"{switches} | {ppk:.1f} at {dpk:.2f} mm | {dev} | {end} |")
        pairs = [
            ("dcb_plain.toml (auto)", "dcb_arc.toml (arc_length)"),
            ("dcb_abaqus.inp (auto)", "dcb_abaqus.inp (arc_length)"),
            ("dcb_plain.toml, default increments (auto)",
             "dcb_plain.toml, default increments (arc_length)"),
            ("enf_snapback.toml without control (auto)", "enf_snapback.toml (arc_length)"),
        ]
        print()
        for auto, arc in pairs:
            print(f"auto / path following: {auto}: {walls[auto] / walls[arc]:.2f}")


if __name__ == "__main__":
    main()
