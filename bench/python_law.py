#!/usr/bin/env python3
"""What a traction law written in Python costs, and what the Python
package costs against the command line, on whole runs of the same scene.

1. the DCB (examples/delamination/dcb.toml: ~500 increments, viscous
   bilinear law) with the compiled `bilinear` law against `py_bilinear`
   (examples/python/bilinear_law.py, the same law in numpy, evaluated once
   per interface block and assembly), both run from Python in memory;
2. the same scene run from Python into a directory
   (`junta.Simulation.from_file(scene).run(output=dir)`) against the
   command line (`target/release/junta run scene -o dir -q`).

Each run is repeated REPEAT times (default 3) one after the other; the
table gives the median wall time and the ratios. Release builds, on a
quiet machine:

    maturin build --release -m python/Cargo.toml -o dist && pip install --force-reinstall dist/junta-*.whl
    cargo build --release -p junta-cli
    python bench/python_law.py [--repeat 3] [--scene examples/delamination/dcb.toml] [--only law|api]

The script says so when the installed package is a debug (dev-profile)
build. `--scene examples/delamination/dcb_coarse.toml` gives a quick run.
"""

import argparse
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "examples" / "python"))

import bilinear_law  # noqa: E402
import junta  # noqa: E402


def median_time(f, repeat):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), times


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--scene", default=str(ROOT / "examples/delamination/dcb.toml"))
    ap.add_argument("--law", default="cz", help="the scene's law table to switch to py_bilinear")
    ap.add_argument("--cli", default=os.environ.get("JUNTA_BIN", str(ROOT / "target/release/junta")))
    ap.add_argument("--only", choices=["law", "api"], help="run one of the two comparisons")
    args = ap.parse_args()
    scene = pathlib.Path(args.scene)
    if junta._junta.debug_build:
        print("warning: the installed junta package is a debug (dev-profile) build; "
              "time a release build (maturin build --release)", file=sys.stderr)
    bilinear_law.register("py_bilinear")
    rows = []

    def in_memory(overrides):
        r = junta.Simulation.from_file(scene, overrides=overrides).run()
        assert r.status == "completed", r.status_line
        return r

    increments = len(in_memory({}).curve["increment"])  # warm-up, and the size
    ratios = []
    if args.only != "api":
        t_rust, all_rust = median_time(lambda: in_memory({}), args.repeat)
        t_py, all_py = median_time(lambda: in_memory({f"laws.{args.law}.type": "py_bilinear"}), args.repeat)
        rows.append(("compiled `bilinear` (Python API, in memory)", t_rust, all_rust))
        rows.append(("`py_bilinear` law in Python (Python API, in memory)", t_py, all_py))
        ratios.append(f"ratio py_bilinear / bilinear: {t_py / t_rust:.2f}")
    if args.only == "law":
        return report(args, scene, increments, rows, ratios)

    with tempfile.TemporaryDirectory() as tmp:
        def api_dir():
            r = junta.Simulation.from_file(scene).run(output=os.path.join(tmp, "api"))
            assert r.status == "completed", r.status_line

        def cli_dir():
            subprocess.run([args.cli, "run", str(scene), "-o", os.path.join(tmp, "cli"), "-q"],
                           check=True, stdout=subprocess.DEVNULL)

        t_api, all_api = median_time(api_dir, args.repeat)
        t_cli, all_cli = median_time(cli_dir, args.repeat)
    rows.append(("Python API into a directory", t_api, all_api))
    rows.append((f"command line ({os.path.relpath(args.cli, ROOT)}) into a directory", t_cli, all_cli))
    ratios.append(f"ratio Python API / command line: {t_api / t_cli:.3f}")
    return report(args, scene, increments, rows, ratios)


def report(args, scene, increments, rows, ratios):
    print(f"{scene.relative_to(ROOT) if scene.is_absolute() and ROOT in scene.parents else scene}: "
          f"{increments} increments, median of {args.repeat} runs, "
          f"{'debug' if junta._junta.debug_build else 'release'} build")
    for name, t, ts in rows:
        print(f"  {name:<58} {t:8.2f} s   ({', '.join(f'{x:.2f}' for x in ts)})")
    for r in ratios:
        print(f"  {r}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
