#!/usr/bin/env python3
"""Write the NLGEOM decks of crates/cli/tests/large_deformation.rs and, with
--reference, run CalculiX on them to write their reference .dat files.

nlgeom_cantilever_c3d20r.inp: a cantilever 10 x 1 x 1 (E = 10000, nu = 0.3)
of 10 x 2 x 2 C3D20R (one element through the depth would not do: under
NLGEOM the reduced-integration modes of a single layer take the compressive
stress and neither CalculiX nor Junta converges), clamped at x = 0 (FIX), a dead end load P = 25
(P L^2 / EI = 3, a tip rotation of 56 degrees) downwards and P/5 sideways
as *CLOADs on the end face (END) with the consistent weights of a uniform
traction (8-node face: corners -1/12, mid-sides 1/3).

nlgeom_cantilever_c3d8i.inp: the same beam of 20 x 2 x 2 C3D8I (4-node
faces: corners 1/16, edges 1/8, centre 1/4 of the load).

nlgeom_twist_c3d20r.inp: a block 1 x 1 x 3 of 2 x 2 x 6 C3D20R, the base
z = 0 clamped (FIX), every node of the top face z = 3 (TOP) moved as the
top face of a rigid rotation by 60 degrees about the block's axis with an
axial stretch of 0.3, by *BOUNDARY displacements (ramped linearly over
the step, as Junta and CalculiX both do). The reactions include the
Poynting effect (an axial force from the twist alone).

Every deck has *STEP, NLGEOM, *STATIC 0.1, 1 and *CONTROLS, PARAMETERS=FIELD
with CalculiX's residual and correction criteria tightened to 1e-9 (its
defaults, 5e-3 and 1e-2, would stop its Newton iterations well before the
1e-5 agreement the test asks; Junta notes *CONTROLS and applies its own
criteria). *NODE PRINT writes U of END / TOP / MID and the FIX reaction
totals.

Reference: CalculiX 2.20 (Debian calculix-ccx), `ccx -i NAME`; the .dat
files are checked in next to the decks. Usage:
python3 make_nlgeom_decks.py [--reference]   (writes next to this script)
"""
import math
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))

CORNERS = [(0, 0, 0), (2, 0, 0), (2, 2, 0), (0, 2, 0), (0, 0, 2), (2, 0, 2), (2, 2, 2), (0, 2, 2)]
MIDS = [(1, 0, 0), (2, 1, 0), (1, 2, 0), (0, 1, 0), (1, 0, 2), (2, 1, 2), (1, 2, 2), (0, 1, 2),
        (0, 0, 1), (2, 0, 1), (2, 2, 1), (0, 2, 1)]


def box(size, n, quadratic):
    """Nodes {(i, j, k): (label, xyz)} on the half-step lattice and the
    connectivities of an n[0] x n[1] x n[2] box."""
    p = 2 if quadratic else 1
    lat = [p * n[a] + 1 for a in range(3)]
    nodes = {}
    for k in range(lat[2]):
        for j in range(lat[1]):
            for i in range(lat[0]):
                if quadratic and sum(x % 2 for x in (i, j, k)) >= 2:
                    continue
                xyz = tuple(size[a] * (i, j, k)[a] / (lat[a] - 1) for a in range(3))
                nodes[(i, j, k)] = (len(nodes) + 1, xyz)
    offs = CORNERS + MIDS if quadratic else [tuple(c // 2 for c in o) for o in CORNERS]
    elems = []
    for k in range(n[2]):
        for j in range(n[1]):
            for i in range(n[0]):
                elems.append([nodes[(p * i + o[0], p * j + o[1], p * k + o[2])][0] for o in offs])
    return nodes, elems, lat


def lines(vals, per=16):
    return "\n".join(", ".join(str(v) for v in vals[s:s + per]) + ("," if s + per < len(vals) else "")
                     for s in range(0, len(vals), per))


def head(name, title, nodes):
    out = [f"** Junta test deck written by make_nlgeom_decks.py: {name} (see the script's docstring).",
           f"** Reference: CalculiX 2.20, ccx -i {name[:-4]}; output {name[:-4]}.dat next to this deck.",
           "*HEADING", title, "*NODE, NSET=NALL"]
    out += [f"{l}, {x!r}, {y!r}, {z!r}" for (l, (x, y, z)) in sorted(nodes.values())]
    return out


def step(loads, prints):
    return (["*STEP, NLGEOM, INC=1000", "*STATIC", "0.1, 1.0",
             "*CONTROLS, PARAMETERS=FIELD", "1e-9, 1e-9"]
            + loads + prints + ["*END STEP"])


def face_weights(lat, quadratic, fixed_axis, at):
    """Consistent nodal shares of a uniform traction on the face
    lattice[fixed_axis] == at: {(i, j, k): share}, summing to 1."""
    shares = {}
    other = [a for a in range(3) if a != fixed_axis]
    ne = [(lat[a] - 1) // (2 if quadratic else 1) for a in other]
    w8 = {(0, 0): -1 / 12, (2, 0): -1 / 12, (2, 2): -1 / 12, (0, 2): -1 / 12,
          (1, 0): 1 / 3, (2, 1): 1 / 3, (1, 2): 1 / 3, (0, 1): 1 / 3}
    p = 2 if quadratic else 1
    for e0 in range(ne[0]):
        for e1 in range(ne[1]):
            local = w8 if quadratic else {(0, 0): .25, (1, 0): .25, (1, 1): .25, (0, 1): .25}
            for (a, b), w in local.items():
                ijk = [0, 0, 0]
                ijk[fixed_axis] = at
                ijk[other[0]] = p * e0 + a
                ijk[other[1]] = p * e1 + b
                key = tuple(ijk)
                shares[key] = shares.get(key, 0.0) + w / (ne[0] * ne[1])
    return shares


def cantilever(name, etype, n, quadratic):
    nodes, elems, lat = box((10.0, 1.0, 1.0), n, quadratic)
    out = head(name, f"Cantilever under a dead end load, {etype}, NLGEOM", nodes)
    out += [f"*ELEMENT, TYPE={etype}, ELSET=BEAM"]
    out += [f"{e + 1}, " + lines(c, 10) for e, c in enumerate(elems)]
    fix = sorted(l for ijk, (l, x) in nodes.items() if ijk[0] == 0)
    end = sorted(l for ijk, (l, x) in nodes.items() if ijk[0] == lat[0] - 1)
    mid = sorted(l for ijk, (l, x) in nodes.items() if ijk[0] == (lat[0] - 1) // 2)
    out += ["*NSET, NSET=FIX", lines(fix), "*NSET, NSET=END", lines(end), "*NSET, NSET=MID", lines(mid)]
    out += ["*MATERIAL, NAME=M", "*ELASTIC", "10000.0, 0.3", "*SOLID SECTION, ELSET=BEAM, MATERIAL=M",
            "*BOUNDARY", "FIX, 1, 3"]
    p = 25.0  # P L^2 / EI = 25 * 100 / (10000 / 12) = 3
    loads = ["*CLOAD"]
    for ijk, w in sorted(face_weights(lat, quadratic, 0, lat[0] - 1).items()):
        l = nodes[ijk][0]
        loads += [f"{l}, 3, {-p * w!r}", f"{l}, 2, {0.2 * p * w!r}"]
    prints = ["*NODE PRINT, NSET=END", "U", "*NODE PRINT, NSET=MID", "U",
              "*NODE PRINT, NSET=FIX, TOTALS=ONLY", "RF"]
    return out + step(loads, prints)


def twist(name):
    nodes, elems, lat = box((1.0, 1.0, 3.0), (2, 2, 6), True)
    out = head(name, "Block twisted by 60 degrees and stretched, C3D20R, NLGEOM", nodes)
    out += ["*ELEMENT, TYPE=C3D20R, ELSET=BLOCK"]
    out += [f"{e + 1}, " + lines(c, 10) for e, c in enumerate(elems)]
    fix = sorted(l for ijk, (l, x) in nodes.items() if ijk[2] == 0)
    top = [(l, x) for ijk, (l, x) in sorted(nodes.items()) if ijk[2] == lat[2] - 1]
    mid = sorted(l for ijk, (l, x) in nodes.items() if ijk[2] == (lat[2] - 1) // 2)
    out += ["*NSET, NSET=FIX", lines(fix), "*NSET, NSET=TOP", lines(sorted(l for l, x in top)),
            "*NSET, NSET=MID", lines(mid)]
    out += ["*MATERIAL, NAME=M", "*ELASTIC", "10000.0, 0.3", "*SOLID SECTION, ELSET=BLOCK, MATERIAL=M",
            "*BOUNDARY", "FIX, 1, 3"]
    t = math.radians(60.0)
    loads = ["*BOUNDARY"]
    for l, (x, y, z) in top:
        dx, dy = x - 0.5, y - 0.5
        u = (0.5 + math.cos(t) * dx - math.sin(t) * dy - x, 0.5 + math.sin(t) * dx + math.cos(t) * dy - y, 0.3)
        loads += [f"{l}, {c + 1}, {c + 1}, {v!r}" for c, v in enumerate(u)]
    prints = ["*NODE PRINT, NSET=MID", "U", "*NODE PRINT, NSET=FIX, TOTALS=ONLY", "RF"]
    return out + step(loads, prints)


DECKS = {
    "nlgeom_cantilever_c3d20r.inp": lambda n: cantilever(n, "C3D20R", (10, 2, 2), True),
    "nlgeom_cantilever_c3d8i.inp": lambda n: cantilever(n, "C3D8I", (20, 2, 2), False),
    "nlgeom_twist_c3d20r.inp": twist,
}

for name, make in DECKS.items():
    with open(os.path.join(HERE, name), "w") as f:
        f.write("\n".join(make(name)) + "\n")
    if "--reference" in sys.argv:
        with tempfile.TemporaryDirectory() as tmp:
            shutil.copy(os.path.join(HERE, name), tmp)
            subprocess.run(["ccx", "-i", name[:-4]], cwd=tmp, check=True, stdout=subprocess.DEVNULL)
            shutil.copy(os.path.join(tmp, name[:-4] + ".dat"), HERE)
