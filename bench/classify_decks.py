#!/usr/bin/env python3
"""Classify CalculiX test-suite decks: linear-static solid-element ones (in scope) vs the rest, with the reason."""
import os, re, sys
D = sys.argv[1] if len(sys.argv) > 1 else "/usr/share/doc/calculix-ccx-test/examples/test"
SOLID = {"C3D4", "C3D10", "C3D8", "C3D8R", "C3D8I", "C3D20", "C3D20R", "C3D6", "C3D15"}
PROC_OUT = {"FREQUENCY", "BUCKLE", "DYNAMIC", "HEAT TRANSFER", "COUPLED TEMPERATURE-DISPLACEMENT",
            "MODAL DYNAMIC", "STEADY STATE DYNAMICS", "COMPLEX FREQUENCY", "VISCO", "UNCOUPLED TEMPERATURE-DISPLACEMENT",
            "CFD", "ELECTROMAGNETICS", "SENSITIVITY", "GREEN", "CRACK PROPAGATION", "SUBSTRUCTURE GENERATE"}
NONLIN = {"PLASTIC", "HYPERELASTIC", "HYPERFOAM", "CREEP", "USER MATERIAL", "DEFORMATION PLASTICITY",
          "CONTACT PAIR", "GAP", "TIE", "EXPANSION", "INITIAL CONDITIONS", "TEMPERATURE", "RIGID BODY",
          "DISTRIBUTING COUPLING", "COUPLING", "MPC", "SPRING", "DASHPOT", "MASS", "TRANSFORM", "CYCLIC SYMMETRY MODEL",
          "PRE-TENSION SECTION", "SUBMODEL", "CHANGE SOLID SECTION", "BEAM SECTION", "SHELL SECTION", "MEMBRANE SECTION",
          "DFLUX", "CFLUX", "FILM", "RADIATE", "NO ANALYSIS", "RESTART", "DLOAD GRAV", "CENTRIF", "MODEL CHANGE",
          "FRICTION", "SURFACE INTERACTION", "USER ELEMENT", "CONDUCTIVITY", "SPECIFIC HEAT", "FLUID SECTION", "CONTROLS"}
def lines(path, seen=None):
    seen = seen or set()
    try:
        txt = open(path, errors="replace").read().splitlines()
    except OSError:
        return
    for l in txt:
        s = l.strip()
        if s.upper().startswith("*INCLUDE"):
            m = re.search(r"INPUT\s*=\s*([^,\s]+)", s, re.I)
            if m:
                p = os.path.join(os.path.dirname(path), m.group(1))
                if p not in seen:
                    seen.add(p)
                    yield from lines(p, seen)
            continue
        yield s
def classify(path):
    kws, etypes, reasons = set(), set(), []
    nl = False
    for s in lines(path):
        if not s.startswith("*") or s.startswith("**"):
            continue
        parts = [p.strip() for p in s[1:].split(",")]
        kw = re.sub(r"\s+", " ", parts[0].upper())
        kws.add(kw)
        params = {p.split("=")[0].strip().upper(): (p.split("=", 1)[1].strip().upper() if "=" in p else None) for p in parts[1:] if p}
        if kw == "ELEMENT":
            etypes.add(params.get("TYPE", "?"))
        if kw == "STEP" and ("NLGEOM" in params and params["NLGEOM"] != "NO"):
            nl = True
        if kw == "DLOAD":
            pass
        if kw == "ELASTIC" and params.get("TYPE") not in (None, "ISO", "ISOTROPIC", "ORTHO", "ANISO", "ENGINEERING CONSTANTS"):
            reasons.append("*ELASTIC TYPE=" + str(params.get("TYPE")))
    if "STATIC" not in kws:
        reasons.append("no *STATIC (" + ",".join(sorted(kws & PROC_OUT)) + ")")
    bad_proc = kws & PROC_OUT
    if bad_proc:
        reasons.append("procedure " + ",".join(sorted(bad_proc)))
    bad_el = etypes - SOLID
    if bad_el:
        reasons.append("elements " + ",".join(sorted(bad_el)))
    bad_kw = kws & NONLIN
    if bad_kw:
        reasons.append("keywords " + ",".join(sorted(bad_kw)))
    if nl:
        reasons.append("NLGEOM")
    return etypes, kws, reasons
if __name__ == "__main__":
    ins = []
    for f in sorted(os.listdir(D)):
        if not f.endswith(".inp"):
            continue
        if not os.path.exists(os.path.join(D, f[:-4] + ".dat.ref.gz")) and not os.path.exists(os.path.join(D, f[:-4] + ".dat.ref")):
            continue
        et, kws, r = classify(os.path.join(D, f))
        if not r:
            ins.append(f[:-4])
            print("IN ", f[:-4], ",".join(sorted(et)), "|", ",".join(sorted(kws)))
        elif "-v" in sys.argv:
            print("OUT", f[:-4], "; ".join(r))
    print(len(ins), "in scope", file=sys.stderr)
