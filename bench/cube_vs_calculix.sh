#!/usr/bin/env bash
# Side-by-side: CalculiX (ccx, SPOOLES) and Junta on the same unit-cube decks
# of shared/BENCHMARKS.md section 1 (H20 n=20: 107,163 dofs; H8 n=40:
# 206,763 dofs), 2 threads each, run one after the other. Checks that the
# top Fz reactions agree to 1e-6 and prints wall time and peak memory
# (/usr/bin/time -v). Junta runs twice: with its default solver settings
# (auto precision: a single-precision factor refined to double-precision
# residuals on these well-conditioned matrices) and with
# `--solver precision=double` (double-precision factor).
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
  read -r dw dm < <(measure "$work/$name.junta_double" "$junta" run "$work/$name.inp" -o "$work/$name.double" -q --solver precision=double)
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
