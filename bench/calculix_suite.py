#!/usr/bin/env python3
"""Run CalculiX's own test suite (Debian package calculix-ccx-test) through
`junta run` and compare with the shipped reference output (*.dat.ref).

In scope: decks with a *STATIC step, only solid elements (C3D4, C3D10, C3D8,
C3D8R, C3D8I, C3D20, C3D20R, C3D6, C3D15) and no keyword outside linear
elasticity (see classify_decks.py for the filter and the reasons). Each
in-scope deck runs with `junta run`; the displacement ("displacements") and
reaction ("forces", "total force") blocks of its .dat.ref are compared with
Junta's node_print.csv (the deck's *NODE PRINT requests), and the stress
blocks ("stresses", per element and integration point) with its
el_print.csv (*EL PRINT requests). The error of a block is max |junta -
ref| / max |ref| over the block (the .dat prints 7 significant digits, so
1e-5 is the tolerance); the table gives the worst nodal block and the worst
stress block.

Usage: bench/calculix_suite.py [--junta target/debug/junta] [--keep DIR]
"""
import argparse, csv, gzip, os, re, shutil, subprocess, sys, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from classify_decks import classify, SOLID  # noqa: E402

SUITE = "/usr/share/doc/calculix-ccx-test/examples/test"
TOL = 1e-5


def ensure_suite():
    if os.path.isdir(SUITE):
        return
    print("installing calculix-ccx-test ...", file=sys.stderr)
    subprocess.run(["apt-get", "install", "-y", "calculix-ccx-test"], check=True)


def ref_blocks(path):
    """{(kind, set): {node or 'total': [x, y, z]}} of the last time of a .dat."""
    opener = gzip.open if path.endswith(".gz") else open
    blocks, cur = {}, None
    with opener(path, "rt", errors="replace") as f:
        for line in f:
            s = line.strip()
            m = re.match(r"(displacements|forces|total force|stresses)\s*\(.*\)\s*for set\s+(\S+)", s)
            if m:
                kind = {"displacements": "U", "forces": "RF", "total force": "RFT",
                        "stresses": "S"}[m.group(1)]
                cur = {}
                blocks[(kind, m.group(2).upper())] = cur
                continue
            if not s:
                continue
            if cur is None:
                continue
            f_ = s.split()
            try:
                vals = [float(x.replace("D", "E")) for x in f_]
            except ValueError:
                cur = None
                continue
            if len(vals) == 3:
                cur["total"] = vals
            elif len(vals) == 4:
                cur[int(vals[0])] = vals[1:]
            elif len(vals) == 8:
                cur[(int(vals[0]), int(vals[1]))] = vals[2:]
            else:
                cur = None
    return blocks


def junta_el_rows(path):
    rows = {}
    if not os.path.exists(path):
        return rows
    with open(path) as f:
        for r in csv.DictReader(f):
            key = (int(r["element"]), int(r["point"]))
            rows.setdefault((r["variable"], r["set"].upper()), {})[key] = [float(r[c]) for c in "123456"]
    return rows


def junta_rows(path):
    rows = {}
    with open(path) as f:
        for r in csv.DictReader(f):
            kind = r["variable"] if r["node"] != "total" else r["variable"] + "T"
            key = "total" if r["node"] == "total" else int(r["node"])
            rows.setdefault((kind, r["set"].upper()), {})[key] = [float(r[c]) for c in "123"]
    return rows


def compare(ref, got):
    """Worst relative error over the blocks. CalculiX keeps the labels of a
    `*NSET, GENERATE` range that name no node and prints them with zeros;
    Junta's sets hold defined nodes only, so an all-zero reference row of a
    node Junta does not print is skipped (and counted)."""
    worst, n, skipped = 0.0, 0, 0
    for key, blk in ref.items():
        if key not in got:
            return None, f"no Junta rows for {key[0]} of set {key[1]}"
        g = got[key]
        scale = max((abs(v) for vals in blk.values() for v in vals), default=0.0) or 1.0
        for node, vals in blk.items():
            if node not in g and node != "total" and all(v == 0.0 for v in vals):
                skipped += 1
                continue
            if node not in g:
                return None, f"node {node} missing in {key}"
            for a, b in zip(g[node], vals):
                worst = max(worst, abs(a - b) / scale)
                n += 1
    note = f"{n} values" + (f" ({skipped} zero rows of undefined labels skipped)" if skipped else "")
    return worst, note


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--junta", default=os.path.join(HERE, "..", "target", "debug", "junta"))
    ap.add_argument("--keep", default=None)
    a = ap.parse_args()
    ensure_suite()
    work = a.keep or tempfile.mkdtemp(prefix="junta_ccx_")
    rows, out_of_scope = [], []
    for f in sorted(os.listdir(SUITE)):
        if not f.endswith(".inp"):
            continue
        deck = f[:-4]
        ref = os.path.join(SUITE, deck + ".dat.ref.gz")
        if not os.path.exists(ref):
            ref = os.path.join(SUITE, deck + ".dat.ref")
            if not os.path.exists(ref):
                continue
        et, kws, reasons = classify(os.path.join(SUITE, f))
        if "STATIC" in kws and et and et <= SOLID and reasons:
            out_of_scope.append((deck, "; ".join(reasons)))
        if reasons or not et:
            continue
        d = os.path.join(work, deck)
        p = subprocess.run([a.junta, "run", os.path.join(SUITE, f), "-o", d, "-q"],
                           capture_output=True, text=True)
        if p.returncode != 0:
            err = p.stderr.strip().splitlines()[0] if p.stderr.strip() else "?"
            err = re.sub(r"; supported keywords:.*", "", err.replace(SUITE + "/", ""))
            rows.append((deck, "refused", "", err))
            continue
        csvp = os.path.join(d, "node_print.csv")
        if not os.path.exists(csvp):
            rows.append((deck, "ran", "", "no *NODE PRINT to compare"))
            continue
        blocks = ref_blocks(ref)
        nodal = {k: v for k, v in blocks.items() if k[0] != "S"}
        stress = {k: v for k, v in blocks.items() if k[0] == "S"}
        err, why = compare(nodal, junta_rows(csvp))
        if err is not None and stress:
            serr, swhy = compare(stress, junta_el_rows(os.path.join(d, "el_print.csv")))
            if serr is None:
                err, why = None, swhy
            else:
                why = f"nodal {err:.1e} ({why}); stresses {serr:.1e} ({swhy.replace('values', 'point values')})"
                err = max(err, serr)
        if err is None:
            rows.append((deck, "ran", "", why))
        else:
            rows.append((deck, "match" if err <= TOL else "DIFFERS", f"{err:.2e}", why))
    w = max(len(r[0]) for r in rows + out_of_scope) if rows else 10
    print(f"{'deck':<{w}}  {'status':<8}  {'max rel err':<11}  note")
    for r in rows:
        print(f"{r[0]:<{w}}  {r[1]:<8}  {r[2]:<11}  {r[3]}")
    for deck, why in out_of_scope:
        print(f"{deck:<{w}}  {'out':<8}  {'':<11}  {why}")
    n_match = sum(1 for r in rows if r[1] == "match")
    print(f"\n{len(rows)} in scope: {n_match} match to {TOL:g}, "
          f"{sum(1 for r in rows if r[1] == 'refused')} refused; "
          f"{len(out_of_scope)} static solid decks out of scope", file=sys.stderr)
    if not a.keep:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
