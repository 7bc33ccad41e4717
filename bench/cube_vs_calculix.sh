#!/usr/bin/env bash
# Side-by-side: CalculiX (ccx, SPOOLES) and Junta on the same unit-cube decks
# of shared/BENCHMARKS.md section 1 (H20 n=20: 107,163 dofs; H8 n=40:
# 206,763 dofs), 2 threads each, run one after the other. Checks that the
# top Fz reactions agree to 1e-6 and prints wall time and peak memory
# (/usr/bin/time -v). Junta runs twice: with its default solver settings
# (`auto`: the direct solver or AMG-CG, whichever its cost model predicts
# faster, see crates/junta/src/auto.rs: direct on H20 n=20, AMG on H8 n=40;
# the direct solver's auto precision) and with
# `--solver type=cholesky --solver precision=double` (double-precision
# factor).
# Usage: bench/cube_vs_calculix.sh [CASES...]
# where a case is C3D20:20 or C3D8:40 (default: both).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/.." && pwd)
work="$here/work"
mkdir -p "$work"
export OMP_NUM_THREADS=2 CCX_NPROC_STIFFNESS=2 CCX_NPROC_EQUATION_SOLVER=2 RAYON_NUM_THREADS=2

if ! command -v ccx >/dev/null; then
  echo "installing CalculiX (calculix-ccx)..." >&2
  if [ "$(id -u)" = 0 ]; then apt-get update -qq && apt-get install -y -qq calculix-ccx >/dev/null
  else sudo apt-get update -qq && sudo apt-get install -y -qq calculix-ccx >/dev/null; fi
fi
[ -x /usr/bin/time ] || { echo "installing GNU time..." >&2; apt-get install -y -qq time >/dev/null; }
(cd "$root" && cargo build --release -q -p junta-cli)
junta="$root/target/release/junta"

cases=("$@")
[ ${#cases[@]} -gt 0 ] || cases=(C3D20:20 C3D8:40)

measure() { # label logfile cmd... -> prints "wall_s peak_mb"
  local log=$1; shift
  /usr/bin/time -v "$@" >"$log.out" 2>"$log.time"
  local wall peak
  wall=$(grep "Elapsed (wall clock)" "$log.time" | awk '{print $NF}' | awk -F: '{ if (NF==3) print $1*3600+$2*60+$3; else print $1*60+$2 }')
  peak=$(grep "Maximum resident set size" "$log.time" | awk '{print $NF/1024}')
  echo "$wall $peak"
}

printf '\n| case | dofs | CalculiX wall s | CalculiX peak MB | Junta wall s | Junta peak MB | time ratio | memory ratio | Junta double wall s | Junta double peak MB | double time ratio | double memory ratio | Fz CalculiX | Fz Junta | rel. diff | Fz Junta double | rel. diff |\n'
printf '|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n'
for c in "${cases[@]}"; do
  et=${c%%:*}; n=${c##*:}
  name="cube_${et,,}_n$n"
  python3 "$here/make_cube_deck.py" "$et" "$n" "$work/$name.inp"
  read -r cw cm < <(cd "$work" && measure "$work/$name.ccx" ccx -i "$name")
  read -r jw jm < <(measure "$work/$name.junta" "$junta" run "$work/$name.inp" -o "$work/$name.out" -q)
  read -r dw dm < <(measure "$work/$name.junta_double" "$junta" run "$work/$name.inp" -o "$work/$name.double" -q --solver type=cholesky --solver precision=double)
  # CalculiX prints "total force (fx,fy,fz) for set TOP ..." then the totals line
  fz_c=$(awk '/total force/ {getline; getline; print $3}' "$work/$name.dat" | tail -1)
  fz_j=$(python3 -c "import json;print(json.load(open('$work/$name.out/summary.json'))['reactions']['TOP'][2])")
  fz_d=$(python3 -c "import json;print(json.load(open('$work/$name.double/summary.json'))['reactions']['TOP'][2])")
  dofs=$(python3 -c "import json;print(json.load(open('$work/$name.out/summary.json'))['dofs'])")
  python3 - "$c" "$dofs" "$cw" "$cm" "$jw" "$jm" "$dw" "$dm" "$fz_c" "$fz_j" "$fz_d" <<'PY'
import sys
c, dofs, cw, cm, jw, jm, dw, dm, fc, fj, fd = sys.argv[1:]
cw, cm, jw, jm, dw, dm, fc, fj, fd = map(float, (cw, cm, jw, jm, dw, dm, fc, fj, fd))
rel = abs(fc - fj) / abs(fc)
reld = abs(fc - fd) / abs(fc)
print(f"| {c} | {dofs} | {cw:.1f} | {cm:.0f} | {jw:.1f} | {jm:.0f} | {jw/cw:.3f} | {jm/cm:.3f} | {dw:.1f} | {dm:.0f} | {dw/cw:.3f} | {dm/cm:.3f} | {fc:.3f} | {fj:.7f} | {rel:.1e} | {fd:.7f} | {reld:.1e} |")
if max(rel, reld) > 1e-6:
    print(f"FAIL: reactions differ by {max(rel, reld):.2e} (> 1e-6)", file=sys.stderr)
    sys.exit(1)
PY
done

# ---------------------------------------------------------------- AMG scaling
# Junta with cg + smoothed-aggregation AMG on H8 cubes (AMG_SIZES, default
# "40 60"; 80 and 100 need minutes and several GB), and pyamg's smoothed
# aggregation (default settings, rigid-body modes as B, CG accel. to 1e-10)
# on the matrix Junta exports for the smallest size (--export-matrix).
amg_sizes=(${AMG_SIZES:-40 60})
python3 -c "import pyamg" 2>/dev/null || pip install -q pyamg
printf '\n| H8 n | equations | wall s | peak MB | AMG set-up s | solve s | iterations | levels | wall us/equation |\n|---|---|---|---|---|---|---|---|---|\n'
for n in "${amg_sizes[@]}"; do
  name="cube_c3d8_n$n"
  python3 "$here/make_cube_deck.py" C3D8 "$n" "$work/$name.inp"
  # the matrix for pyamg is exported by a separate, untimed run
  [ "$n" = "${amg_sizes[0]}" ] && "$junta" run "$work/$name.inp" -o "$work/$name.export" -q \
    --solver type=cg --solver preconditioner=amg --export-matrix "$work/$name.mtx" >/dev/null
  read -r aw am < <(measure "$work/$name.amg" "$junta" run "$work/$name.inp" -o "$work/$name.amgout" -q \
    --solver type=cg --solver preconditioner=amg)
  python3 - "$work/$name.amgout/summary.json" "$n" "$aw" "$am" <<'PY'
import json, sys
s = json.load(open(sys.argv[1])); n, aw, am = sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
t, so = s["timings"], s["solver"]
lv = [x for x in so["notes"] if x.startswith("amg:")][0].split(" levels ")[1].split("]")[0] + "]"
print(f"| {n} | {s['dofs']} | {aw:.1f} | {am:.0f} | {t['factor']:.1f} | {t['solve']:.1f} | {so['iterations']} | {lv} | {1e6*aw/s['dofs']:.0f} |")
PY
done
# H20 n=20: AMG against the default direct solver (mixed precision) on the
# same deck; the faster is what `auto` should take there.
name=cube_c3d20_n20
python3 "$here/make_cube_deck.py" C3D20 20 "$work/$name.inp"
read -r hw hm < <(measure "$work/$name.amgh" "$junta" run "$work/$name.inp" -o "$work/$name.amgout" -q \
  --solver type=cg --solver preconditioner=amg)
# the matrix for PETSc GAMG (below) is exported by a separate, untimed run
"$junta" run "$work/$name.inp" -o "$work/$name.export" -q \
  --solver type=cg --solver preconditioner=amg --export-matrix "$work/$name.mtx" >/dev/null
read -r dw dm < <(measure "$work/$name.direct" "$junta" run "$work/$name.inp" -o "$work/$name.directout" -q --solver type=cholesky)
python3 - "$work/$name.amgout/summary.json" "$work/$name.directout/summary.json" "$hw" "$hm" "$dw" "$dm" <<'PY'
import json, sys
a, d = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
hw, hm, dw, dm = map(float, sys.argv[3:])
fa, fd = a["reactions"]["TOP"][2], d["reactions"]["TOP"][2]
print(f"\nH20 n=20 ({a['dofs']} dofs): AMG-CG {hw:.1f} s, {hm:.0f} MB, {a['solver']['iterations']} iterations; "
      f"direct (auto precision) {dw:.1f} s, {dm:.0f} MB; AMG/direct time {hw/dw:.2f}; Fz {fa:.7f} vs {fd:.7f} "
      f"(rel. diff {abs(fa-fd)/abs(fd):.1e})")
PY
python3 - "$work/cube_c3d8_n${amg_sizes[0]}.mtx" <<'PY'
import sys, time, numpy as np, scipy.io, pyamg
d = sys.argv[1]
A = scipy.io.mmread(f"{d}/K.mtx").tocsr(); b = scipy.io.mmread(f"{d}/b.mtx").ravel(); B = scipy.io.mmread(f"{d}/B.mtx")
t = time.time(); ml = pyamg.smoothed_aggregation_solver(A, B=B); ts = time.time() - t
res = []; t = time.time(); x = ml.solve(b, tol=1e-10, accel="cg", residuals=res); tsol = time.time() - t
print(f"\npyamg {pyamg.__version__} smoothed aggregation on {d}: {len(res)-1} CG iterations to "
      f"{np.linalg.norm(b - A @ x) / np.linalg.norm(b):.1e}, levels {[l.A.shape[0] for l in ml.levels]}, "
      f"set-up {ts:.1f} s, solve {tsol:.1f} s")
PY

# ------------------------------------------------------- PETSc as yardstick
# PETSc's GAMG (Debian python3-petsc4py, sequential: one process, one thread)
# with CG to ||b - A x|| / ||b|| <= 1e-10 on the matrices Junta exported above
# (H8 at the first of AMG_SIZES, H20 n=20), against Junta's AMG-CG on the same
# decks: the timed runs above (2 threads) and one more run each with 1 thread.
# Set-up and solve times only (Junta: summary.json timings.factor and
# timings.solve; PETSc: KSPSetUp and KSPSolve, median of 3, default GAMG
# options; see bench/petsc_gamg.py).
if ! dpkg -s python3-petsc4py python3-scipy >/dev/null 2>&1; then
  echo "installing PETSc (python3-petsc4py)..." >&2
  if [ "$(id -u)" = 0 ]; then apt-get update -qq && apt-get install -y -qq python3-petsc4py python3-scipy >/dev/null
  else sudo apt-get update -qq && sudo apt-get install -y -qq python3-petsc4py python3-scipy >/dev/null; fi
fi
printf '\n| deck | equations | Junta AMG set-up s | Junta solve s | Junta its | PETSc GAMG set-up s | PETSc solve s | PETSc its | ratio (Junta set-up+solve)/(PETSc set-up+solve) |\n|---|---|---|---|---|---|---|---|---|\n'
for name in "cube_c3d8_n${amg_sizes[0]}" cube_c3d20_n20; do
  RAYON_NUM_THREADS=1 OMP_NUM_THREADS=1 "$junta" run "$work/$name.inp" -o "$work/$name.amg1t" -q \
    --solver type=cg --solver preconditioner=amg >/dev/null 2>"$work/$name.amg1t.log"
  OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 /usr/bin/python3 "$here/petsc_gamg.py" "$work/$name.mtx" --repeat 3 \
    "$name, Junta 2 threads=$work/$name.amgout/summary.json" "$name, Junta 1 thread=$work/$name.amg1t/summary.json" \
    2>"$work/$name.petsc.log" || { cat "$work/$name.petsc.log" >&2; exit 1; }
done
grep -h '^petsc_gamg: PETSc' "$work/cube_c3d8_n${amg_sizes[0]}.petsc.log" "$work/cube_c3d20_n20.petsc.log"
