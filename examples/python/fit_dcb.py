#!/usr/bin/env python3
"""Fit the mode I toughness G_Ic of the DCB to a target load-opening curve.

The target is the corrected-beam-theory (LEFM) curve of the DCB,
``examples/delamination/dcb_beam_theory.csv`` (shared/BENCHMARKS.md
section 4; written by beam_theory.py with G_Ic = 0.969 N/mm, AS4/PEEK):
an outside reference, not a Junta run. Each evaluation runs the coarse DCB
(``examples/delamination/dcb_coarse.toml``: 2 mm elements, arc length,
about 100 increments) in memory with ``overrides={"laws.cz.G_Ic": g}``;
the misfit is the RMS difference between the computed load and the target
load at the computed openings on the propagation branch (opening past
5 mm: the initial slope does not depend on G_Ic, the propagation load goes
as G_Ic^(3/4)). ``scipy.optimize.minimize_scalar`` (bounded) finds the
minimum.

Units: N, mm, N/mm. Needs scipy, and matplotlib for the chart: install
the package with its ``examples`` extra (``pip install "./python[examples]"``).
Run from the repository root:

    python examples/python/fit_dcb.py            # writes out/fit_dcb.png
    python examples/python/fit_dcb.py --quick    # G_Ic to 0.02 N/mm (CI)

Prints the fitted G_Ic, the number of runs and the wall time; without
matplotlib it says how to get the chart instead of drawing it.
"""

import argparse
import pathlib
import sys
import time

import numpy as np
try:
    from scipy.optimize import minimize_scalar
except ImportError:
    sys.exit('fit_dcb.py needs scipy: pip install "./python[examples]" (or pip install scipy)')

import junta

HERE = pathlib.Path(__file__).resolve().parent
SCENE = HERE.parent / "delamination" / "dcb_coarse.toml"
TARGET = HERE.parent / "delamination" / "dcb_beam_theory.csv"
PROPAGATION = 5.0  # mm: fit the curve past this opening


def target_curve():
    """(opening, load) of the corrected beam theory."""
    d = np.loadtxt(TARGET, delimiter=",", comments="#")
    return d[:, 0], d[:, 1]


def run(g_ic, end):
    """The coarse DCB with G_Ic = g_ic: (opening, load) of every increment.

    Arc length can turn back at the first peak of the coarse mesh's
    saw-tooth for some G_Ic (the load factor falls back to zero: the run
    "completes" without opening the DCB to ``end``); such a run is done
    again with a first increment half as long."""
    overrides = {"laws.cz.G_Ic": float(g_ic)}
    for retry in (None, {"analysis.newton.initial_increment": 0.05}):
        r = junta.Simulation.from_file(SCENE, overrides=dict(overrides, **(retry or {}))).run()
        delta = r.curve["displacement"]
        if r.status == "completed" and np.max(delta) >= 0.99 * end:
            return delta, r.curve["reaction"]
        print(f"    G_Ic = {g_ic:.5f}: {r.status_line} at opening {np.max(delta):.3f} mm; "
              + ("again with initial_increment = 0.05" if retry is None else "given up"))
    raise RuntimeError(f"G_Ic = {g_ic}: {r.status_line}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="a coarse fit (G_Ic to 0.02 N/mm): fewer runs")
    args = ap.parse_args(argv)
    xatol = 2e-2 if args.quick else 1e-3
    delta_t, load_t = target_curve()
    runs = []

    def misfit(g_ic):
        delta, load = run(g_ic, delta_t[-1])
        past = delta > PROPAGATION
        r = load[past] - np.interp(delta[past], delta_t, load_t)
        m = float(np.sqrt(np.mean(r**2)))
        runs.append((g_ic, m))
        print(f"  run {len(runs):2d}: G_Ic = {g_ic:.5f} N/mm, RMS misfit {m:.4f} N", flush=True)
        return m

    t0 = time.perf_counter()
    res = minimize_scalar(misfit, bounds=(0.5, 1.5), method="bounded", options={"xatol": xatol})
    wall = time.perf_counter() - t0
    g = float(res.x)
    print(f"fitted G_Ic = {g:.4f} N/mm (the target curve's G_Ic: 0.969 N/mm, "
          f"{100 * (g - 0.969) / 0.969:+.2f} %), RMS misfit {res.fun:.4f} N")
    print(f"{len(runs)} runs of {SCENE.name} in {wall:.1f} s ({wall / len(runs):.2f} s per run)")

    try:
        import matplotlib
    except ImportError:
        print('no chart: matplotlib is not installed (pip install "./python[examples]" '
              "or pip install matplotlib, then run this script again for out/fit_dcb.png)")
        return 0
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    delta, load = run(g, delta_t[-1])
    out = pathlib.Path("out")
    out.mkdir(exist_ok=True)
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.plot(delta_t, load_t, "k--", label="target: corrected beam theory (G_Ic = 0.969 N/mm)")
    ax.plot(delta, load, "C0-", lw=1.2, label=f"Junta, coarse DCB, fitted G_Ic = {g:.4f} N/mm")
    ax.axvline(PROPAGATION, color="0.7", lw=0.8)
    ax.set_xlabel("opening delta (mm)")
    ax.set_ylabel("load P (N)")
    ax.set_title(f"DCB: G_Ic fitted in {len(runs)} runs ({wall:.0f} s)")
    ax.legend(loc="lower right", fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    png = out / "fit_dcb.png"
    fig.savefig(png, dpi=120)
    print(f"wrote {png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
