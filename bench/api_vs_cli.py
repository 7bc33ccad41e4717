#!/usr/bin/env python3
"""Whole runs of the same input through the command line, the Rust run API
and the Python package: the API must cost what the CLI costs.

Cases: the DCB of examples/delamination/dcb_arc.toml (arc length to 10 mm,
60 increments, direct LDL^T) and the H20 unit cube n = 20 of shared/BENCHMARKS.md section 1
(107,163 dofs, one linear solve; deck written by bench/make_cube_deck.py).
Each way runs REPEAT times (default 3), the ways in turn (round-robin), release builds, 2 threads; the table gives the median wall time
and its ratio to the CLI's.

- CLI: `target/release/junta run INPUT -o DIR -q`
- Rust API: `target/release/examples/run_file INPUT DIR`
  (crates/junta/examples/run_file.rs: Simulation::from_file + run into DIR)
- Python: `junta.Simulation.from_file(INPUT).run(output=DIR)` in a fresh
  interpreter (skipped when the package is not installed: `pip install ./python`)

usage: bench/api_vs_cli.py [--repeat N] [--cases dcb,cube]
"""
import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def timed(cmd, env):
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, env=env)
    return time.perf_counter() - t0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--cases", default="dcb,cube")
    args = ap.parse_args()
    env = dict(os.environ, RAYON_NUM_THREADS="2")
    subprocess.run(["cargo", "build", "--release", "-q", "-p", "junta-cli",
                    "-p", "junta", "--example", "run_file"], check=True, cwd=ROOT)
    subprocess.run(["cargo", "build", "--release", "-q", "-p", "junta-cli"], check=True, cwd=ROOT)
    junta = os.path.join(ROOT, "target/release/junta")
    run_file = os.path.join(ROOT, "target/release/examples/run_file")
    work = os.path.join(HERE, "work")
    os.makedirs(work, exist_ok=True)
    inputs = {}
    if "dcb" in args.cases:
        inputs["DCB (dcb_arc)"] = os.path.join(ROOT, "examples/delamination/dcb_arc.toml")
    if "cube" in args.cases:
        deck = os.path.join(work, "cube_C3D20_20.inp")
        if not os.path.exists(deck):
            subprocess.run([sys.executable, os.path.join(HERE, "make_cube_deck.py"),
                            "C3D20", "20", deck], check=True)
        inputs["H20 cube n=20"] = deck
    try:
        import junta as _  # noqa: F401
        have_python = True
    except ImportError:
        have_python = False
    print(f"{'case':<16} {'way':<10} {'median s':>9} {'runs':>24} {'ratio':>6}")
    for label, path in inputs.items():
        ways = {
            "CLI": lambda d: [junta, "run", path, "-o", d, "-q"],
            "Rust API": lambda d: [run_file, path, d],
        }
        if have_python:
            ways["Python"] = lambda d: [sys.executable, "-c",
                                        "import junta,sys; junta.Simulation.from_file(sys.argv[1]).run(output=sys.argv[2])",
                                        path, d]
        # round-robin: the ways share whatever else the machine does
        times = {way: [] for way in ways}
        for _ in range(args.repeat):
            for way, cmd in ways.items():
                d = tempfile.mkdtemp(dir=work)
                times[way].append(timed(cmd(d), env))
                shutil.rmtree(d, ignore_errors=True)
        medians = {way: statistics.median(t) for way, t in times.items()}
        for way, t in times.items():
            runs = " ".join(f"{x:.2f}" for x in t)
            print(f"{label:<16} {way:<10} {medians[way]:>9.2f} {runs:>24} "
                  f"{medians[way] / medians['CLI']:>6.3f}")

if __name__ == "__main__":
    main()
