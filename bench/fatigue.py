#!/usr/bin/env python3
"""Fatigue (issue 26): what the cycle jump costs and what it gets right,
on examples/fatigue/dcb_paris.toml (a DCB held at 3 mm opening, the
fatigue_bilinear law with the crack measured on the interface). Whole runs
of the release binary, as a user runs them; medians over --repeat runs.

1. 10 mm of growth: the example held for --cycles cycles (2e5 grows the
   crack past 10 mm): wall time, increments, Newton iterations, cycles
   reached and growth.
2. Cycle by cycle against the cycle jump over the first 1000 cycles: the
   same scene with cycles = 1000 and every fatigue increment one cycle
   (max_increment = initial_increment = 1e-3 of the step; the Paris law
   acts per cycle on the envelope maximum, so one increment per cycle is
   the cycle-by-cycle integration of this law) against the default cycle
   jump (max_damage_increment = 0.05). Compared: the dissipated energy
   (the damage grown, integrated over the interface) and the crack
   length at N = 1000, and the wall time.
3. Speed against accuracy of the cycle jump: max_damage_increment from
   0.4 to 0.0125; for each, the wall time and the error of da/dN over the
   growth windows of the Paris-consistency test (2.5-4.4, 4.4-6.3,
   6.3-8.2 mm), against the finest run (the time-integration error) and
   against the Paris law with G from corrected beam theory (the error a
   user sees, which includes the mesh's).

Writes OUT/fatigue.csv, OUT/fatigue.md and OUT/fatigue_speed_accuracy.svg
(matplotlib), and prints the tables.

Run: python3 bench/fatigue.py [--repeat 3] [--cycles 2e5] [--junta PATH]
     [--out out/fatigue]
The binary defaults to $CARGO_TARGET_DIR/release/junta (else
target/release/junta), built first unless --junta is given.
"""
import argparse
import csv
import json
import os
import re
import statistics
import subprocess
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXAMPLE = os.path.join(ROOT, "examples", "fatigue", "dcb_paris.toml")

# the example's arms and Paris line (mode I)
E1, B, H = 122700.0, 25.4, 1.56
EI = E1 * B * H**3 / 12.0
G_C, C, M = 0.969, 0.0616, 5.4
WINDOWS = [(2.5, 4.4), (4.4, 6.3), (6.3, 8.2)]


def build():
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    subprocess.run(["cargo", "build", "--release", "-q", "-p", "junta-cli"], cwd=ROOT, check=True)
    return os.path.join(target, "release", "junta")


def scene(cycles=None, max_damage=None, one_cycle=False):
    s = open(EXAMPLE).read()
    if cycles is not None:
        s = re.sub(r"^cycles = .*$", f"cycles = {cycles!r}", s, flags=re.M)
    if max_damage is not None:
        s = re.sub(r"^max_damage_increment = .*$", f"max_damage_increment = {max_damage!r}", s, flags=re.M)
    if one_cycle:
        # every increment 1e-3 of its step: 1000 static increments, then
        # one cycle per fatigue increment
        s = s.replace("initial_increment = 0.01", "initial_increment = 0.001")
        s = s.replace("max_increment = 0.01", "max_increment = 0.001")
        s = re.sub(r"^max_damage_increment = .*$", "max_damage_increment = 1.0", s, flags=re.M)
    return s


def run(junta, text, name, repeat, tmp):
    path = os.path.join(tmp, name + ".toml")
    open(path, "w").write(text)
    out = os.path.join(tmp, name)
    walls = []
    for _ in range(repeat):
        t = time.perf_counter()
        r = subprocess.run([junta, "-q", "run", path, "-o", out], capture_output=True, text=True)
        walls.append(time.perf_counter() - t)
        if r.returncode != 0:
            raise SystemExit(f"{name}: {r.stderr}")
    s = json.load(open(os.path.join(out, "summary.json")))
    with open(os.path.join(out, "curve.csv")) as f:
        rows = list(csv.DictReader(f))
    return statistics.median(walls), s, rows


def fatigue_rows(rows):
    return [r for r in rows if r["step"] == "1"]


def num(r, k):
    return float(r[k]) if r[k] else 0.0


def window_rates(rows):
    """da/dN over each window, and beam theory's G / G_c there. The crack
    length is the dissipated energy over G_c B here (continuous in N; the
    `crack_length` column grows by rows of points, which quantises a
    window's rate by a few per cent)."""
    f = fatigue_rows(rows)
    a = [num(r, "dissipated_energy") / (G_C * B) for r in f]
    out = []
    for a0, a1 in WINDOWS:
        i0 = next(i for i, x in enumerate(a) if x >= a0)
        i1 = next(i for i, x in enumerate(a) if x >= a1)
        rate = (a[i1] - a[i0]) / (num(f[i1], "cycles") - num(f[i0], "cycles"))
        gs = []
        for r in f[i0:i1 + 1]:
            p, d = num(r, "reaction"), num(r, "displacement")
            a_eff = (3.0 * EI * d / (2.0 * p)) ** (1.0 / 3.0)
            gs.append(p * p * a_eff * a_eff / (B * EI))
        out.append((rate, statistics.mean(gs) / G_C))
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--cycles", type=float, default=2e5)
    ap.add_argument("--junta")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "fatigue"))
    args = ap.parse_args()
    junta = args.junta or build()
    os.makedirs(args.out, exist_ok=True)
    md = []
    with tempfile.TemporaryDirectory() as tmp:
        # 1. 10 mm of growth
        wall, s, rows = run(junta, scene(cycles=args.cycles), "growth", args.repeat, tmp)
        f = fatigue_rows(rows)
        growth = num(f[-1], "crack_length") - num(fatigue_rows(rows)[0], "crack_length")
        md.append("| case | wall s (median) | increments | Newton iterations | cycles | growth mm |")
        md.append("|---|---|---|---|---|---|")
        md.append(f"| DCB held at 3 mm, {args.cycles:.0e} cycles | {wall:.2f} | {s['increments']} | "
                  f"{s['newton_iterations']['total']} | {num(f[-1], 'cycles'):.4g} | {growth:.2f} |")
        # 2. cycle by cycle over the first 1000 cycles
        md.append("")
        md.append("| first 1000 cycles | wall s | fatigue increments | energy dissipated by fatigue N mm | crack length mm |")
        md.append("|---|---|---|---|---|")
        res = {}
        for name, text in [("cycle_jump", scene(cycles=1000.0)), ("cycle_by_cycle", scene(cycles=1000.0, one_cycle=True))]:
            wall, s, rows = run(junta, text, name, args.repeat, tmp)
            f = fatigue_rows(rows)
            static_end = num(
                [r for r in rows if r["step"] == "0"][-1], "dissipated_energy")
            res[name] = (wall, len(f), num(f[-1], "dissipated_energy") - static_end, num(f[-1], "crack_length"))
            md.append(f"| {name.replace('_', ' ')} | {wall:.2f} | {len(f)} | {res[name][2]:.6f} | {res[name][3]:.4f} |")
        jump, cbc = res["cycle_jump"], res["cycle_by_cycle"]
        md.append("")
        md.append(f"Energy dissipated in the fatigue step by N = 1000: cycle jump {(jump[2] / cbc[2] - 1) * 100:+.3f} % against cycle by "
                  f"cycle; crack length {jump[3]:.4f} against {cbc[3]:.4f} mm; cost ratio "
                  f"{cbc[0] / jump[0]:.1f} (wall), {cbc[1] / jump[1]:.0f} (fatigue increments).")
        # 3. speed against accuracy
        sweep = []
        for dd in [0.4, 0.2, 0.1, 0.05, 0.025, 0.0125]:
            wall, s, rows = run(junta, scene(max_damage=dd), f"dd{dd}", args.repeat, tmp)
            sweep.append((dd, wall, s["increments"], window_rates(rows)))
        finest = sweep[-1][3]
        md.append("")
        md.append("| max_damage_increment | wall s | increments | da/dN error against the finest (3 windows) | "
                  "against Paris with CBT G (3 windows) |")
        md.append("|---|---|---|---|---|")
        table = []
        for dd, wall, inc, rates in sweep:
            vs_fine = [r[0] / f0[0] - 1 for r, f0 in zip(rates, finest)]
            vs_paris = [r[0] / (C * r[1] ** M) - 1 for r in rates]
            table.append((dd, wall, inc, vs_fine, vs_paris))
            md.append(f"| {dd} | {wall:.2f} | {inc} | " + ", ".join(f"{e * 100:+.2f} %" for e in vs_fine) + " | "
                      + ", ".join(f"{e * 100:+.2f} %" for e in vs_paris) + " |")
    text = "\n".join(md)
    print(text)
    open(os.path.join(args.out, "fatigue.md"), "w").write(text + "\n")
    with open(os.path.join(args.out, "fatigue.csv"), "w") as f:
        w = csv.writer(f)
        w.writerow(["max_damage_increment", "wall_s", "increments"]
                   + [f"err_vs_finest_{i}" for i in range(3)] + [f"err_vs_paris_{i}" for i in range(3)])
        for dd, wall, inc, a, b in table:
            w.writerow([dd, wall, inc] + a + b)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    walls = [t[1] for t in table]
    ax.loglog(walls, [max(abs(e) for e in t[3]) or 1e-6 for t in table], "o-",
              label="largest da/dN error against the finest jump")
    ax.loglog(walls, [max(abs(e) for e in t[4]) for t in table], "s--",
              label="largest da/dN error against Paris (CBT G)")
    for t in table:
        ax.annotate(f"{t[0]}", (t[1], max(abs(e) for e in t[4])), textcoords="offset points", xytext=(4, 4),
                    fontsize=8)
    ax.set_xlabel("wall time, s (median)")
    ax.set_ylabel("relative error of da/dN")
    ax.set_title("DCB held at 3 mm: cycle jump, max_damage_increment")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "fatigue_speed_accuracy.svg"))


if __name__ == "__main__":
    main()
