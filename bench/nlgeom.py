#!/usr/bin/env python3
"""Large deformation (issue 25): what NLGEOM costs against small strain,
and where small strain stops being good enough on a DCB. Whole runs of the
release binary, as a user runs them; medians over --repeat runs.

1. Cost: the same scene run with small strain and with `[analysis] nlgeom
   = true`, wall time (median) and Newton iterations (issue 41's targets:
   nlgeom at most 2 times small strain before the DCB's peak, 2.5 times
   through propagation):
   - examples/delamination/dcb_h8.toml (H8 + INTER8, 0.5 mm along the
     bond, as the scene runs it: load control, path following past the
     peak) opened to 4 mm (before the peak at 4.2 mm) and to 10 mm;
   - examples/cube.toml (the unit cube, uz = -0.01 on the top face) as it
     is (2 x 2 x 2 H8) and refined to --cube-n (H8 n^3): small strain
     linear (one solve, as the scene runs), small strain incremental
     (`type = "static"`, one step) and nlgeom (incremental: a scene with
     nlgeom runs incrementally);
   - examples/delamination/dcb.toml (H20 + INTER16, 0.5 mm along the
     bond, displacement control with viscosity 1e-4), pin-loaded (the
     opening prescribed on the mid-thickness line of each arm's end face,
     see dcb_scene), opened to --opening mm (increments of 0.1 mm, as the
     example; about 3 and 11 minutes to 14 mm), small strain and nlgeom
     (the nlgeom interface tangent is nonsymmetric: `auto` picks `lu`).
     dcb_plain.toml's default control (path following past the peak) is
     not used: under nlgeom its arc length turns back along elastic
     unloading branches (to an opening of about 1 mm, then reloads) three
     times before 11 mm, measured 2026-11-26.
2. Accuracy: the DCB's load-opening curve, small strain and nlgeom,
   against small-strain corrected beam theory (beam_theory.py, a_e = a +
   chi h) with and without the large-displacement correction of ASTM
   D5528 for a pin-loaded DCB without load blocks (t = 0, L' = 0):
     G = 3 P delta F / (2 b a_e N),   F = 1 - (3/10)(delta/a_e)^2,
     N = 1 - (9/35)(delta/a_e)^2      (N's large-displacement term)
   With the beam compliance delta = N 2 P a_e^3 / (3 E I) this is
   G = F P^2 a_e^2 / (b E I): at G = G_Ic the load rises by 1/sqrt(F) and
   the opening shrinks by N against linear theory at the same crack
   length. Two corrected curves: F alone (the standard's F factor on G,
   the compliance kept linear) and F with N (the full correction).

Writes OUT/nlgeom_cost.csv, OUT/nlgeom_cost.md, OUT/dcb_curves.csv and
OUT/dcb_nlgeom.svg (+ .png; matplotlib if available), and prints the
tables.

Run: python3 bench/nlgeom.py [--repeat 3] [--dcb-repeat 1] [--opening 14]
     [--cube-n 12] [--junta PATH] [--out out/nlgeom] [--skip-dcb] [--skip-cube]
The binary defaults to $CARGO_TARGET_DIR/release/junta (else
target/release/junta), built first unless --junta is given.
"""
import argparse
import csv
import json
import math
import os
import platform
import re
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EX = os.path.join(ROOT, "examples")
DEL = os.path.join(EX, "delamination")
sys.path.insert(0, DEL)
import beam_theory as bt  # noqa: E402

B, H = 25.4, 1.56
EI = bt.E11 * B * H**3 / 12.0


def build():
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    subprocess.run(["cargo", "build", "--release", "-q", "-p", "junta-cli"], cwd=ROOT, check=True)
    return os.path.join(target, "release", "junta")


def with_nlgeom(text):
    return text.replace("[analysis]\n", "[analysis]\nnlgeom = true\n", 1)


def cube_scene(n, kind, nlgeom):
    s = open(os.path.join(EX, "cube.toml")).read()
    s = s.replace("divisions = [2, 2, 2]", f"divisions = [{n}, {n}, {n}]")
    s = s.replace('type = "cholesky"', 'type = "auto"')
    s += "\n[output]\nvtu = false\n"
    if kind == "static" or nlgeom:
        s += f'\n[analysis]\ntype = "{kind}"\nsteps = [1.0]\n'
        if nlgeom:
            s = with_nlgeom(s)
    return s


def dcb_scene(opening, nlgeom):
    s = open(os.path.join(DEL, "dcb.toml")).read()
    s = s.replace("steps = [10.0]", f"steps = [{opening}]")
    # the same 0.1 mm largest increment of the opening as the example's
    s = s.replace("max_increment = 0.01", f"max_increment = {0.1 / opening:.6g}")
    s = s.replace("initial_increment = 0.01", f"initial_increment = {0.1 / opening:.6g}")
    s = s.replace('file = "dcb_beam_theory.csv"', 'file = "' + os.path.join(DEL, "dcb_beam_theory.csv") + '"')
    # pin loading (ASTM D5528 without blocks, t = 0): the opening is
    # prescribed on the mid-thickness line of each arm's end face, about
    # which the face turns freely. Prescribing it on the whole end face
    # (as dcb.toml does) holds the face's nodes at one uz, which under
    # nlgeom resists the face's rotation (uz = z'(cos theta - 1)): a
    # partial clamp that stiffens the arm beyond any large-displacement
    # theory (measured: +0.6 % at 2 mm, +2.2 % at 4 mm against small strain).
    s = s.replace('set = "upper_crack.x0"\ndisplacement', 'set = "upper_pin"\ndisplacement')
    s = s.replace('set = "lower_crack.x0"\ndisplacement', 'set = "lower_pin"\ndisplacement')
    s = s.replace('reaction_set = "upper_crack.x0"', 'reaction_set = "upper_pin"')
    s = s.replace('point_set = "upper_crack.x0"', 'point_set = "upper_pin"')
    s = s.replace('relative_to = "lower_crack.x0"', 'relative_to = "lower_pin"')
    s += ("\n[[node_set]]\nname = \"upper_pin\"\nwithin = [[-0.01, -1.0, 2.33], [0.01, 26.4, 2.35]]\n"
          "\n[[node_set]]\nname = \"lower_pin\"\nwithin = [[-0.01, -1.0, 0.77], [0.01, 26.4, 0.79]]\n")
    s = re.sub(r"every = \d+", "every = 100000", s)
    s = s.replace("[output]\n", "[output]\nvtu = false\n", 1)
    return with_nlgeom(s) if nlgeom else s


def h8_scene(opening, nlgeom):
    """examples/delamination/dcb_h8.toml (H8 + INTER8, 0.5 mm along the
    bond, the increments of the scene, its default control) opened to
    `opening` mm, frames off."""
    s = open(os.path.join(DEL, "dcb_h8.toml")).read()
    s = s.replace("steps = [10.0]", f"steps = [{opening}]")
    s = re.sub(r"every = \d+", "every = 100000", s)
    return with_nlgeom(s) if nlgeom else s


def run(junta, text, name, repeat, tmp):
    path = os.path.join(tmp, name + ".toml")
    open(path, "w").write(text)
    walls = []
    for _ in range(repeat):
        out = os.path.join(tmp, name)
        t = time.perf_counter()
        r = subprocess.run([junta, "-q", "run", path, "-o", out], capture_output=True, text=True)
        walls.append(time.perf_counter() - t)
        if r.returncode != 0:
            raise SystemExit(f"{name}: {r.stderr}")
    s = json.load(open(os.path.join(out, "summary.json")))
    rows = []
    if os.path.exists(os.path.join(out, "curve.csv")):
        with open(os.path.join(out, "curve.csv")) as f:
            rows = [(float(r["displacement"]), float(r["reaction"])) for r in csv.DictReader(f)
                    if r["displacement"]]
    return statistics.median(walls), s, rows


def corrected_curve(with_n, delta_max, n=300):
    """(delta, P) of corrected beam theory with ASTM D5528's large-
    displacement factors (t = 0): the linear branch at a0 up to G_Ic, then
    propagation, parametrised by the load (linear branch) and by a_e."""
    ae0 = 32.9 + bt.chi() * H

    def point(ae, p=None):
        x = 0.0
        for _ in range(100):
            f = 1.0 - 0.3 * x * x
            nn = 1.0 - 9.0 / 35.0 * x * x if with_n else 1.0
            pp = p if p is not None else math.sqrt(bt.GIC * B * EI / f) / ae
            if p is not None:  # linear branch: stop at G = G_Ic
                pp = min(p, math.sqrt(bt.GIC * B * EI / f) / ae)
            d = nn * 2.0 * pp * ae**3 / (3.0 * EI)
            x = d / ae
        return d, pp

    pc = math.sqrt(bt.GIC * B * EI) / ae0 * 1.05
    pts = [point(ae0, pc * i / 40.0) for i in range(41)]
    pts = [q for k, q in enumerate(pts) if k == 0 or q[1] > pts[k - 1][1]]
    ae = ae0
    while True:
        ae += 0.25
        d, p = point(ae)
        if d > 1.1 * delta_max:
            break
        pts.append((d, p))
    return pts


def interp(curve, d):
    for (d0, p0), (d1, p1) in zip(curve, curve[1:]):
        if d0 <= d <= d1 and d1 > d0:
            return p0 + (p1 - p0) * (d - d0) / (d1 - d0)
    return float("nan")


def windowed(a, b, d, half=0.5, n=41):
    """Mean of a(x) / b(x) - 1 over x in [d - half, d + half]."""
    xs = [d - half + 2.0 * half * k / (n - 1) for k in range(n)]
    vals = [interp(a, x) / interp(b, x) - 1.0 for x in xs]
    vals = [v for v in vals if v == v]
    return sum(vals) / len(vals) if vals else float("nan")


def chart(out, small, large, cbt, cbt_f, cbt_fn):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not available: no chart")
        return
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(7.5, 8.5), sharex=True,
                                 gridspec_kw={"height_ratios": [3, 2]})
    for c, lab, st in [(cbt, "corrected beam theory (small strain)", "k--"),
                       (cbt_f, "CBT with D5528 F", "C2:"),
                       (cbt_fn, "CBT with D5528 F and N", "C2-")]:
        ax.plot([d for d, _ in c], [p for _, p in c], st, lw=1.2, label=lab)
    ax.plot([d for d, _ in small], [p for _, p in small], "C0-", lw=1.5, label="Junta, small strain")
    ax.plot([d for d, _ in large], [p for _, p in large], "C3-", lw=1.5, label="Junta, nlgeom")
    ax.set_ylabel("load P on one arm (N)")
    ax.set_title("DCB (AS4/PEEK, dcb.toml pin-loaded, viscosity 1e-4) at large opening")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    ds = [d for d, _ in large if d > 1.0]
    rel = lambda a, b: [100.0 * (interp(a, d) / interp(b, d) - 1.0) for d in ds]
    bx.plot(ds, rel(large, small), "C3-", lw=0.5, alpha=0.4, label="Junta: nlgeom / small strain - 1")
    dm = [0.1 * k for k in range(10, int(10 * ds[-1]) - 4)]
    bx.plot(dm, [100.0 * windowed(large, small, d) for d in dm], "C3-", lw=2,
            label="the same, mean over 1 mm (the element saw-tooth averaged out)")
    bx.plot(ds, rel(cbt_f, cbt), "C2:", label="beam theory: F / linear - 1")
    bx.plot(ds, rel(cbt_fn, cbt), "C2-", label="beam theory: F and N / linear - 1")
    bx.axhline(1.0, color="grey", lw=0.8)
    bx.axhline(-1.0, color="grey", lw=0.8)
    bx.set_xlabel("opening delta (mm)")
    bx.set_ylabel("large-displacement effect on P (%)")
    bx.legend(fontsize=8)
    bx.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "dcb_nlgeom.svg"))
    fig.savefig(os.path.join(out, "dcb_nlgeom.png"), dpi=110)
    print("wrote", os.path.join(out, "dcb_nlgeom.svg"), "and .png")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--opening", type=float, default=14.0)
    ap.add_argument("--cube-n", type=int, default=12)
    ap.add_argument("--junta")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "nlgeom"))
    ap.add_argument("--dcb-repeat", type=int, default=1, help="repeats of the DCB runs (minutes each)")
    ap.add_argument("--skip-dcb", action="store_true")
    ap.add_argument("--skip-cube", action="store_true")
    ap.add_argument("--skip-h8", action="store_true", help="no dcb_h8.toml rows (to 4 mm, before the peak; to 10 mm)")
    a = ap.parse_args()
    junta = a.junta or build()
    os.makedirs(a.out, exist_ok=True)
    print(f"{time.strftime('%Y-%m-%d')}, {platform.node()}, {os.cpu_count()} cores, {platform.processor() or platform.machine()}")
    cost = []
    curves = {}
    with tempfile.TemporaryDirectory() as tmp:
        cases = []
        for n in ([] if a.skip_cube else sorted({2, a.cube_n})):
            cases += [(f"cube H8 n={n}", f"cube{n}_linear", cube_scene(n, "linear", False), "small strain, linear"),
                      (f"cube H8 n={n}", f"cube{n}_static", cube_scene(n, "static", False), "small strain, incremental"),
                      (f"cube H8 n={n}", f"cube{n}_nlgeom", cube_scene(n, "static", True), "nlgeom")]
        for opening in ([] if a.skip_h8 else [4.0, 10.0]):
            cases += [(f"DCB H8 to {opening:g} mm", f"h8_{opening:g}_small", h8_scene(opening, False), "small strain"),
                      (f"DCB H8 to {opening:g} mm", f"h8_{opening:g}_nlgeom", h8_scene(opening, True), "nlgeom")]
        if not a.skip_dcb:
            cases += [(f"DCB to {a.opening:g} mm", "dcb_small", dcb_scene(a.opening, False), "small strain"),
                      (f"DCB to {a.opening:g} mm", "dcb_nlgeom", dcb_scene(a.opening, True), "nlgeom")]
        for case, name, text, kin in cases:
            repeat = a.dcb_repeat if name.startswith("dcb") else a.repeat
            wall, s, rows = run(junta, text, name, repeat, tmp)
            newton = s.get("newton_iterations", {}).get("total", 1)
            rot = s.get("largest_rotation") or {}
            row = {"case": case, "kinematics": kin, "equations": s["equations"], "wall_s": wall,
                   "increments": s.get("increments", 1), "newton_iterations": newton,
                   "solver": s["solver"]["name"], "status": s.get("status", "completed")[:40],
                   "largest_rotation_deg": rot.get("degrees"), "rotation_ratio": rot.get("ratio")}
            if name.startswith("cube"):
                row["reaction_z"] = s["reactions"]["z1"][2]
            cost.append(row)
            if rows:
                curves[name] = rows
            print(f"{case:18} {kin:26} eq={s['equations']:7} wall={wall:7.2f} s "
                  f"increments={row['increments']:4} newton={newton:5} solver={row['solver']}", flush=True)
    base = {}
    for r in cost:
        key = r["case"]
        if r["kinematics"].startswith("small strain"):
            base.setdefault(key, r)
        r["ratio_to_first_small_strain"] = r["wall_s"] / base[key]["wall_s"]
    fields = list(dict.fromkeys(k for r in cost for k in r))
    with open(os.path.join(a.out, "nlgeom_cost.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields)
        w.writeheader()
        w.writerows(cost)
    md = ["| case | kinematics | equations | wall (s, median) | ratio | increments | Newton iterations | solver | largest rotation |",
          "|---|---|---|---|---|---|---|---|---|"]
    for r in cost:
        rot = "-" if r["largest_rotation_deg"] is None else f"{r['largest_rotation_deg']:.1f} deg" + (
            f" (ratio {r['rotation_ratio']:.2f})" if r["rotation_ratio"] is not None else "")
        md.append(f"| {r['case']} | {r['kinematics']} | {r['equations']} | {r['wall_s']:.2f} | "
                  f"{r['ratio_to_first_small_strain']:.2f} | {r['increments']} | {r['newton_iterations']} | "
                  f"{r['solver']} | {rot} |")
    open(os.path.join(a.out, "nlgeom_cost.md"), "w").write("\n".join(md) + "\n")
    print("\n".join(md))
    if "dcb_small" not in curves:
        return
    small, large = curves["dcb_small"], curves["dcb_nlgeom"]
    _, _, cbt = bt.dcb(delta_max=a.opening, n=400)
    cbt_f = corrected_curve(False, a.opening)
    cbt_fn = corrected_curve(True, a.opening)
    with open(os.path.join(a.out, "dcb_curves.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["delta", "junta_small", "junta_nlgeom", "cbt", "cbt_F", "cbt_FN"])
        for d in [0.5 * k for k in range(1, int(2 * a.opening) + 1)]:
            w.writerow([d] + [f"{interp(c, d):.4f}" for c in (small, large, cbt, cbt_f, cbt_fn)])
    print("\n| delta (mm) | small strain (N) | nlgeom (N) | nlgeom/small - 1 (mean over 1 mm) | CBT (N) | F/CBT - 1 | F,N/CBT - 1 |")
    print("|---|---|---|---|---|---|---|")
    for d in [1.0, 2.0, 3.0, 4.0, 6.0, 8.0, 10.0, 12.0, 14.0, 16.0, 18.0, 20.0, 25.0, 30.0]:
        if d > a.opening:
            break
        ps, pl, pc, pf, pfn = (interp(c, d) for c in (small, large, cbt, cbt_f, cbt_fn))
        mean = windowed(large, small, min(d, a.opening - 0.5))
        print(f"| {d:g} | {ps:.2f} | {pl:.2f} | {100 * (pl / ps - 1):+.2f} % ({100 * mean:+.2f} %) | {pc:.2f} | "
              f"{100 * (pf / pc - 1):+.2f} % | {100 * (pfn / pc - 1):+.2f} % |")
    chart(a.out, small, large, cbt, cbt_f, cbt_fn)


if __name__ == "__main__":
    main()
