#!/usr/bin/env python3
"""Write the cylindrical-orientation decks of crates/cli/tests/decks.rs.

A quarter of a thick tube (inner radius 10, outer 20, height 5; theta from
0 to 90 degrees) about a skew axis through a = (1, 2, 3) along
d = (0.3, -0.2, 1) / |.|, meshed in (r, theta, z) and mapped to global
coordinates. Material axes from *ORIENTATION, SYSTEM=CYLINDRICAL with the
two axis points a and b = a + 7 d: 1 radial, 2 hoop, 3 axial, strongly
orthotropic (E1 = 10000, E2 = 200000, E3 = 50000). The face theta = 0 is
clamped (FIX), the inner face carries a pressure (*DLOAD P6), the face
theta = 90 (END) a *CLOAD along the axis and one across it.

cyl_ring_c3d20.inp: 2 (radial) x 6 (hoop) x 1 (axial) 20-node elements in
three bands of two hoop columns: C3D20R with ENGINEERING CONSTANTS,
C3D20 with ORTHO (nine D_ijkl of the same material), C3D20 with ANISO
(the same with couplings D1112, D2213, D1123).

cyl_ring_c3d8.inp: 3 x 12 x 2 C3D8 elements, ENGINEERING CONSTANTS, and
*EL PRINT of the stresses of one element (PRINTED).

Reference: CalculiX 2.20 (`ccx -i cyl_ring_c3d20`, `ccx -i cyl_ring_c3d8`),
values copied into decks.rs. Usage: python3 make_cyl_decks.py (writes next
to this script).
"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))

RI, RO, H, THETA = 10.0, 20.0, 5.0, math.pi / 2
A = (1.0, 2.0, 3.0)
D = (0.3, -0.2, 1.0)
ENG = (10000.0, 200000.0, 50000.0, 0.02, 0.15, 0.3, 8000.0, 6000.0, 15000.0)


def unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return tuple(x / n for x in v)


def cross(u, v):
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


EZ = unit(D)
EX = unit(cross((0.0, 1.0, 0.0), EZ))
EY = cross(EZ, EX)
B = tuple(A[i] + 7.0 * EZ[i] for i in range(3))


def xyz(r, t, z):
    return tuple(A[i] + r * math.cos(t) * EX[i] + r * math.sin(t) * EY[i] + z * EZ[i] for i in range(3))


def ortho_d(e1, e2, e3, n12, n13, n23, g12, g13, g23):
    """D1111, D1122, D2222, D1133, D2233, D3333, D1212, D1313, D2323."""
    n21, n31, n32 = n12 * e2 / e1, n13 * e3 / e1, n23 * e3 / e2
    det = 1 - n12 * n21 - n23 * n32 - n13 * n31 - 2 * n21 * n32 * n13
    d1111 = e1 * (1 - n23 * n32) / det
    d2222 = e2 * (1 - n13 * n31) / det
    d3333 = e3 * (1 - n12 * n21) / det
    d1122 = e1 * (n21 + n31 * n23) / det
    d1133 = e1 * (n31 + n21 * n32) / det
    d2233 = e2 * (n32 + n12 * n31) / det
    return (d1111, d1122, d2222, d1133, d2233, d3333, g12, g13, g23)


# 20-node hex: corner and mid-side offsets in (r, theta, z) index steps of 1/2
CORNERS = [(0, 0, 0), (2, 0, 0), (2, 2, 0), (0, 2, 0), (0, 0, 2), (2, 0, 2), (2, 2, 2), (0, 2, 2)]
MIDS = [(1, 0, 0), (2, 1, 0), (1, 2, 0), (0, 1, 0), (1, 0, 2), (2, 1, 2), (1, 2, 2), (0, 1, 2),
        (0, 0, 1), (2, 0, 1), (2, 2, 1), (0, 2, 1)]


def mesh(n, quadratic):
    p = 2 if quadratic else 1
    lat = [p * n[a] + 1 for a in range(3)]
    label, nodes = {}, []
    for k in range(lat[2]):
        for j in range(lat[1]):
            for i in range(lat[0]):
                if quadratic and sum(x % 2 for x in (i, j, k)) >= 2:
                    continue
                label[(i, j, k)] = len(nodes) + 1
                r = RI + (RO - RI) * i / (lat[0] - 1)
                t = THETA * j / (lat[1] - 1)
                z = H * k / (lat[2] - 1)
                nodes.append(xyz(r, t, z))
    offs = CORNERS + MIDS if quadratic else [tuple(c // 2 for c in o) for o in CORNERS]
    elems = []
    for k in range(n[2]):
        for j in range(n[1]):
            for i in range(n[0]):
                conn = [label[(p * i + o[0], p * j + o[1], p * k + o[2])] for o in offs]
                elems.append(((i, j, k), conn))
    fix = [l for (i, j, k), l in label.items() if j == 0]
    end = [l for (i, j, k), l in label.items() if j == lat[1] - 1]
    return nodes, elems, sorted(fix), sorted(end)


def lines(vals, per=8):
    out = []
    for s in range(0, len(vals), per):
        out.append(", ".join(str(v) for v in vals[s:s + per]) + ("," if s + per < len(vals) else ""))
    return "\n".join(out)


def deck(name, n, quadratic, bands, el_print=None):
    nodes, elems, fix, end = mesh(n, quadratic)
    out = [f"** Junta test deck written by make_cyl_decks.py: {name} (see the script's docstring).",
           "** Reference: CalculiX 2.20, ccx -i " + name[:-4] + "; values in crates/cli/tests/decks.rs.",
           "*HEADING", "Quarter ring, cylindrical orientation", "*NODE, NSET=NALL"]
    out += [f"{i + 1}, {x!r}, {y!r}, {z!r}" for i, (x, y, z) in enumerate(nodes)]
    nband = n[1] // len(bands)
    sets = {}
    for b, (etype, mat) in enumerate(bands):
        sel = [(e, c) for e, c in enumerate(elems) if c[0][1] // nband == b]
        out.append(f"*ELEMENT, TYPE={etype}, ELSET=B{b + 1}")
        out += [f"{e + 1}, " + lines(conn, 15).replace(",\n", ",\n") for e, (ijk, conn) in sel]
        sets[f"B{b + 1}"] = mat
    inner = [e + 1 for e, (ijk, c) in enumerate(elems) if ijk[0] == 0]
    out += ["*ELSET, ELSET=INNER", lines(inner, 16)]
    out += ["*NSET, NSET=FIX", lines(fix, 16), "*NSET, NSET=END", lines(end, 16)]
    if el_print is not None:
        label = 1 + next(e for e, (ijk, c) in enumerate(elems) if ijk == el_print)
        out += ["*ELSET, ELSET=PRINTED", str(label)]
    out += ["*ORIENTATION, NAME=CYL, SYSTEM=CYLINDRICAL",
            ", ".join(repr(v) for v in A + B)]
    e1, e2, e3, n12, n13, n23, g12, g13, g23 = ENG
    d = ortho_d(*ENG)
    mats = {
        "ENG": ["*ELASTIC, TYPE=ENGINEERING CONSTANTS", lines(ENG, 8)],
        "ORTHO": ["*ELASTIC, TYPE=ORTHO", lines([repr(v) for v in d], 8)],
    }
    d1111, d1122, d2222, d1133, d2233, d3333, d1212, d1313, d2323 = d
    aniso = [d1111, d1122, d2222, d1133, d2233, d3333, 3000.0, 0.0, 0.0, d1212,
             0.0, 2000.0, 0.0, 0.0, d1313, -1500.0, 0.0, 0.0, 0.0, 0.0, d2323]
    mats["ANISO"] = ["*ELASTIC, TYPE=ANISO", lines([repr(v) for v in aniso], 8)]
    for m in sorted(set(sets.values())):
        out += [f"*MATERIAL, NAME={m}"] + mats[m]
    for s, m in sets.items():
        out.append(f"*SOLID SECTION, ELSET={s}, MATERIAL={m}, ORIENTATION=CYL")
    out += ["*BOUNDARY", "FIX, 1, 3", "*STEP", "*STATIC", "*DLOAD", "INNER, P6, 100."]
    # along the axis and across it (global x), spread over the END nodes
    out.append("*CLOAD")
    for l in end:
        out += [f"{l}, {c + 1}, {f!r}" for c, f in enumerate(tuple(40.0 * x + 25.0 * y
                for x, y in zip(EZ, (1.0, 0.0, 0.0)))) if f != 0.0]
    out += ["*NODE PRINT, NSET=END", "U", "*NODE PRINT, NSET=FIX, TOTALS=ONLY", "RF"]
    if el_print is not None:
        out += ["*EL PRINT, ELSET=PRINTED", "S"]
    out.append("*END STEP")
    with open(os.path.join(HERE, name), "w") as f:
        f.write("\n".join(out) + "\n")


deck("cyl_ring_c3d20.inp", (2, 6, 1), True,
     [("C3D20R", "ENG"), ("C3D20", "ORTHO"), ("C3D20", "ANISO")])
deck("cyl_ring_c3d8.inp", (3, 12, 2), False, [("C3D8", "ENG")], el_print=(1, 5, 1))
