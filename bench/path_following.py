#!/usr/bin/env python3
"""Cost of path following (issue: snap-back): whole runs of the arc-length
examples against the displacement-controlled DCB of the fracture-law
examples, with the release binary.

For each scene: wall time (median of --repeat runs), increments, Newton
iterations, linear solves per iteration (2 under path following: one
factorisation, two right-hand sides; 1 under load control), and the cost
per increment and per iteration. The displacement-controlled DCB
(examples/delamination/dcb.toml, 0.45 mm H20, viscous regularisation) runs
its first --dcb-increments increments only (the full curve takes ~5 min).

Run: python3 bench/path_following.py [--repeat 3] [--dcb-increments 80]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EX = os.path.join(ROOT, "examples", "delamination")


def build():
    subprocess.run(["cargo", "build", "--release", "-q", "-p", "junta-cli"], cwd=ROOT, check=True)
    return os.path.join(ROOT, "target", "release", "junta")


def run(junta, scene, extra, repeat):
    walls, summary = [], None
    for _ in range(repeat):
        with tempfile.TemporaryDirectory() as out:
            t = time.perf_counter()
            p = subprocess.run([junta, "-q", "run", scene, "-o", out] + extra,
                               capture_output=True, text=True)
            walls.append(time.perf_counter() - t)
            with open(os.path.join(out, "summary.json")) as f:
                summary = json.load(f)
            if p.returncode != 0:
                summary["status"] = "failed: " + p.stderr.strip().splitlines()[-1][:80]
    return statistics.median(walls), summary


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--dcb-increments", type=int, default=80)
    args = ap.parse_args()
    junta = build()
    cases = [
        ("enf_snapback.toml (arc length)", os.path.join(EX, "enf_snapback.toml"), []),
        ("dcb_coarse.toml (arc length)", os.path.join(EX, "dcb_coarse.toml"), []),
        ("mmb50.toml (arc length)", os.path.join(EX, "mmb50.toml"), []),
        (f"dcb.toml (displacement control, first {args.dcb_increments} increments)",
         os.path.join(EX, "dcb.toml"), ["--max-increments", str(args.dcb_increments)]),
    ]
    print(f"{'scene':<58} {'equations':>9} {'wall s':>7} {'incr':>5} {'iter':>5} {'all':>5} "
          f"{'solves/iter':>11} {'ms/incr':>8} {'ms/iter':>8}  status")
    print("(iter: of the converged increments; all: with the failed attempts; "
          "solves/iter and ms/iter over all)")
    for name, scene, extra in cases:
        wall, s = run(junta, scene, extra, args.repeat)
        inc = s.get("increments", 0) - (s.get("restarted_from_increment") or 0)
        it = s["newton_iterations"]["total"]
        it_all = s["driver"]["newton_iterations_with_failed_attempts"]
        solves = s["driver"]["linear_solves"]
        print(f"{name:<58} {s['equations']:>9} {wall:>7.2f} {inc:>5} {it:>5} {it_all:>5} "
              f"{solves / max(it_all, 1):>11.2f} {1e3 * wall / max(inc, 1):>8.1f} "
              f"{1e3 * wall / max(it_all, 1):>8.1f}  {s['status'][:60]}")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
