#!/usr/bin/env python3
"""Runs over MPI ranks (issue 24): strong scaling on this machine, the
largest cube on 2 ranks, the whole DCB curve against one process, and the
communication of the partition on paper.

Needs the MPI build (`cargo build --release -p junta-cli --features mpi`)
and PETSc/OpenMPI (Debian: petsc-dev libopenmpi-dev openmpi-bin).

Usage:
  python3 bench/distributed.py cube [N]        # H8 cube N^3 (default 60): Junta AMG in
                                               # one process; PETSc GAMG, hypre, MUMPS on 1, 2 ranks
  python3 bench/distributed.py dcb             # bench/dcb_50k.toml, whole curve: ldlt in one
                                               # process; MUMPS on 1, 2 ranks
  python3 bench/distributed.py parity          # examples/delamination/dcb.toml, whole curve, 2 ranks
  python3 bench/distributed.py largest N       # H8 cube N^3 on 2 ranks, GAMG
  python3 bench/distributed.py cut             # partition cut and communication, 2..64 ranks
  python3 bench/distributed.py memory [N]      # H8 cube N^3 (default 60), GAMG on 1, 2, 4 ranks:
                                               # peak RSS per rank, its sum and the ratios to 1 rank

Each run is timed whole (wall clock, `mpirun` included); memory is the
largest resident set of each rank (/usr/bin/time). OpenMP and BLAS get
one thread per rank; rayon gets the cores over the ranks (junta-mpi). A
run in one process (no mpirun) uses both cores. Results go to
out/distributed/*.json and are printed as markdown tables.
"""
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
JUNTA = Path(os.environ.get("JUNTA_MPI_BIN", ROOT / "target/release/junta"))
OUT = ROOT / "out/distributed"
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1", OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")


def run(ranks, args, out):
    """Run junta (in one process when ranks is None); return wall s, per-rank max RSS MB, summary."""
    timed = ["/usr/bin/time", "-f", "maxrss_kB %M", str(JUNTA)] + args + ["-q", "-o", str(out)]
    cmd = timed if ranks is None else ["mpirun", "-np", str(ranks)] + timed
    t = time.perf_counter()
    p = subprocess.run(cmd, env=ENV, capture_output=True, text=True)
    wall = time.perf_counter() - t
    rss = [int(m) / 1024 for m in re.findall(r"maxrss_kB (\d+)", p.stderr)]
    if p.returncode != 0:
        killed = "signal 9" in p.stderr
        print(f"FAILED: {' '.join(cmd)}\n{p.stderr[-1500:]}", file=sys.stderr)
        return wall, rss, {"failed": "killed (out of memory)" if killed else f"exit {p.returncode}"}
    return wall, rss, json.loads((out / "summary.json").read_text())


def cube_scene(n, directory):
    text = (ROOT / "examples/cube.toml").read_text()
    assert "divisions = [2, 2, 2]" in text
    path = Path(directory) / f"cube{n}.toml"
    path.write_text(text.replace("divisions = [2, 2, 2]", f"divisions = [{n}, {n}, {n}]"))
    return path


def table(rows, header):
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for r in rows:
        print("| " + " | ".join(str(x) for x in r) + " |")


def cube(n=60):
    rows, data = [], []
    with tempfile.TemporaryDirectory() as d:
        scene = cube_scene(n, d)
        methods = os.environ.get("METHODS", "gamg,hypre,mumps").split(",")
        cases = [("Junta AMG + CG", None, ["--solver", "type=cg", "--solver", "preconditioner=amg"])]
        if os.environ.get("SKIP_JUNTA"):
            cases = []
        for method in methods:
            for ranks in [1, 2]:
                cases.append((f"PETSc {method}", ranks, ["--solver", "type=petsc", "--solver", f"method={method}",
                                                        "--solver", "tolerance=1e-8"]))
        for label, ranks, extra in cases:
            wall, rss, s = run(ranks, ["run", str(scene)] + extra, Path(d) / "o")
            if "failed" in s:
                rows.append([label, ranks or 1, f"{wall:.1f}", "/".join(f"{m:.0f}" for m in rss), "-", s["failed"]])
                data.append(dict(case=label, ranks=ranks or 1, wall=wall, rss_mb=rss, failed=s["failed"]))
                continue
            top = s["reactions"]["z1"][2]
            its = s["solver"].get("iterations", 0)
            data.append(dict(case=label, ranks=ranks or 1, wall=wall, rss_mb=rss, iterations=its,
                             reaction=top, equations=s["equations"], timings=s["timings"]))
            t = s["timings"]
            rows.append([label, ranks or "1 (2 threads)", f"{wall:.1f}", "/".join(f"{m:.0f}" for m in rss), its,
                         f"{t.get('assemble', 0):.1f}", f"{t.get('factor', 0):.1f}", f"{t.get('solve', 0):.1f}",
                         f"{top:.6f}"])
            print(rows[-1], file=sys.stderr)
    eq = next((x["equations"] for x in data if "equations" in x), "?")
    print(f"\nH8 cube {n}^3, {eq} equations\n")
    table(rows, ["solver", "ranks", "wall s", "max RSS per rank MB", "iterations", "assemble s",
                 "set-up/factor s", "solve s", "top reaction z"])
    return data


def curve(dir_):
    lines = (Path(dir_) / "curve.csv").read_text().splitlines()
    h = lines[0].split(",")
    return h, [l.split(",") for l in lines[1:]]


def curve_difference(a, b):
    ha, ra = curve(a)
    hb, rb = curve(b)
    if len(ra) != len(rb):
        return float("inf"), len(ra), len(rb)
    worst = 0.0
    for col in ["load_factor", "reaction", "displacement", "dissipated_energy"]:
        i = ha.index(col)
        scale = max(abs(float(r[i] or 0)) for r in ra) or 1.0
        worst = max(worst, max(abs(float(x[i] or 0) - float(y[i] or 0)) / scale for x, y in zip(ra, rb)))
    return worst, len(ra), len(rb)


def dcb(scene=ROOT / "bench/dcb_50k.toml", ranks_list=(1, 2)):
    rows, data = [], []
    with tempfile.TemporaryDirectory() as d:
        ref = Path(d) / "seq"
        wall, rss, s = run(None, ["run", str(scene)], ref)
        rows.append(["ldlt, one process (2 threads)", f"{wall:.1f}", "/".join(f"{m:.0f}" for m in rss),
                     s["increments"], s["newton_iterations"]["total"], s["solver"].get("factorizations"), "-"])
        data.append(dict(case="ldlt", ranks=1, wall=wall, rss_mb=rss, timings=s["timings"]))
        print(rows[-1], file=sys.stderr)
        for ranks in ranks_list:
            o = Path(d) / f"np{ranks}"
            wall, rss, s = run(ranks, ["run", str(scene)], o)
            diff, na, nb = curve_difference(ref, o)
            rows.append([f"MUMPS, {ranks} ranks", f"{wall:.1f}", "/".join(f"{m:.0f}" for m in rss), s["increments"],
                         s["newton_iterations"]["total"], s["solver"].get("factorizations"), f"{diff:.1e}"])
            data.append(dict(case="mumps", ranks=ranks, wall=wall, rss_mb=rss, curve_difference=diff,
                             timings=s["timings"]))
            print(rows[-1], file=sys.stderr)
        eq = s["equations"]
    print(f"\n{scene.name}, {eq} equations, whole curve\n")
    table(rows, ["solver", "wall s", "max RSS per rank MB", "increments", "Newton its", "factorisations",
                 "curve vs one process"])
    return data


def largest(n):
    with tempfile.TemporaryDirectory() as d:
        scene = cube_scene(n, d)
        wall, rss, s = run(2, ["run", str(scene), "--solver", "type=petsc", "--solver", "method=gamg",
                               "--solver", "tolerance=1e-8"], Path(d) / "o")
    row = [n, s["equations"], f"{wall:.1f}", "/".join(f"{m:.0f}" for m in rss), s["solver"]["iterations"],
           f"{s['reactions']['z1'][2]:.4f}"]
    table([row], ["n", "equations", "wall s", "max RSS per rank MB", "GAMG iterations", "top reaction z"])
    return dict(n=n, equations=s["equations"], wall=wall, rss_mb=rss, iterations=s["solver"]["iterations"])


def memory(n=60, repeats=3):
    """Peak resident memory of the GAMG cube on 1, 2 and 4 ranks (issue 40's
    goals: the sum over 4 ranks at most 1.15 times the 1-rank peak, the
    largest rank at most 0.30 of it). Memory does not depend on the
    machine's load; the median of `repeats` runs guards against outliers."""
    rows, data = [], []
    with tempfile.TemporaryDirectory() as d:
        scene = cube_scene(n, d)
        args = ["run", str(scene), "--solver", "type=petsc", "--solver", "method=gamg",
                "--solver", "tolerance=1e-8"]
        one = None
        for ranks in [1, 2, 4]:
            sums, largest_, per_rank, summary = [], [], None, None
            for _ in range(repeats):
                wall, rss, s = run(ranks, args, Path(d) / "o")
                if "failed" in s:
                    raise SystemExit(f"{ranks} ranks: {s['failed']}")
                sums.append(sum(rss))
                largest_.append(max(rss))
                per_rank, summary = rss, s
            total, big = statistics.median(sums), statistics.median(largest_)
            one = one or total
            dist = summary["distributed"]
            owned = dist.get("owned_equations", [summary["equations"]])
            ghost = dist.get("ghost_equations", [0])
            rows.append([ranks, summary["equations"], "/".join(f"{m:.0f}" for m in per_rank), f"{total:.0f}",
                         f"{total / one:.3f}", f"{big / one:.3f}",
                         "/".join(str(o) for o in owned), "/".join(str(g) for g in ghost),
                         f"{2**20 * big / max(owned):.0f}"])
            data.append(dict(ranks=ranks, equations=summary["equations"], rss_mb=per_rank, sum_mb=total,
                             largest_mb=big, owned=owned, ghost=ghost))
            print(rows[-1], file=sys.stderr)
    print(f"\nH8 cube {n}^3, GAMG, peak RSS (medians of {repeats})\n")
    table(rows, ["ranks", "equations", "peak RSS per rank MB", "sum MB", "sum / 1 rank", "largest / 1 rank",
                 "owned equations", "ghost equations", "bytes per owned equation (largest rank)"])
    return data


LAMINATE = """
[model]
title = "Laminate plate: 8 plies, 7 interfaces (partition study)"
units = "N, mm, MPa"
[materials.ply]
type = "isotropic"
E = 70000.0
nu = 0.3
[laws.cz]
type = "bilinear"
K = 1.0e5
N = 30.0
S = 60.0
G_Ic = 0.3
G_IIc = 1.0
eta = 2.0
[mesh]
type = "boxes"
{boxes}
{interfaces}
[[boundary]]
set = "p0.z0"
fixed = "all"
[[boundary]]
set = "p7.z1"
displacement = {{ z = 0.01 }}
[analysis]
type = "linear"
"""


def laminate_scene(directory, plies=8, n=60):
    boxes = "".join(
        f'[[mesh.boxes]]\nname = "p{k}"\ngroup = "ply{k}"\norigin = [0.0, 0.0, {0.25 * k}]\nsize = [100.0, 100.0, 0.25]\n'
        f'divisions = [{n}, {n}, 1]\nelement = "h8"\nmaterial = "ply"\n' for k in range(plies))
    interfaces = "".join(
        f'[[interface]]\nname = "i{k}"\nbetween = ["ply{k}", "ply{k + 1}"]\nlaw = "cz"\n' for k in range(plies - 1))
    path = Path(directory) / "laminate.toml"
    path.write_text(LAMINATE.format(boxes=boxes, interfaces=interfaces))
    return path


def cut():
    """Per rank count: the shared nodes of the busiest rank, the bytes it
    exchanges per Newton iteration (PETSc's halo: 3 dofs of each shared node,
    matrix-vector products and the assembled matrix rows; Junta's replicated
    vectors: the force sum, the state copy, the solution gathered), and the
    weak-scaling efficiency these give on a 10 GB/s, 2 us network when each
    rank holds the model's size per rank at 2 ranks."""
    subprocess.run(["cargo", "build", "-q", "--release", "-p", "junta", "--example", "partition_cut"], cwd=ROOT,
                   check=True)
    exe = ROOT / "target/release/examples/partition_cut"
    results = {}
    with tempfile.TemporaryDirectory() as d:
        for label, scene in [("DCB (dcb.toml)", ROOT / "examples/delamination/dcb.toml"),
                             ("DCB 50k (bench/dcb_50k.toml)", ROOT / "bench/dcb_50k.toml"),
                             ("laminate plate, 8 plies, 7 interfaces", laminate_scene(d))]:
            p = subprocess.run([str(exe), str(scene)], capture_output=True, text=True, check=True)
            results[label] = [json.loads(l) for l in p.stdout.splitlines()]
    rows = []
    for label, lines in results.items():
        for r in lines:
            halo = 2 * 3 * 8 * r["shared_nodes_max"]
            rows.append([label, r["ranks"], r["equations"], r["elements_max"], r["shared_nodes_max"],
                         f"{halo / 1e3:.1f}", f"{8 * 3 * r['equations'] / 1e6:.2f}"])
    print("\nPartition cut (recursive coordinate bisection) and bytes per Newton iteration of the busiest rank\n")
    table(rows, ["model", "ranks", "equations", "elements", "shared nodes", "halo kB", "replicated vectors MB"])
    return results


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    what = sys.argv[1] if len(sys.argv) > 1 else "cut"
    if what == "cube":
        data = cube(int(sys.argv[2]) if len(sys.argv) > 2 else 60)
    elif what == "dcb":
        data = dcb()
    elif what == "parity":
        data = dcb(ROOT / "examples/delamination/dcb.toml", ranks_list=(2,))
    elif what == "largest":
        data = largest(int(sys.argv[2]))
    elif what == "cut":
        data = cut()
    elif what == "memory":
        data = memory(int(sys.argv[2]) if len(sys.argv) > 2 else 60)
    else:
        raise SystemExit(__doc__)
    (OUT / f"{what}.json").write_text(json.dumps(data, indent=1))


if __name__ == "__main__":
    main()
