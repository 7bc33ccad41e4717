#!/usr/bin/env python3
"""Write the wedge decks of crates/cli/tests/decks.rs and cohesive_deck.rs.

wedge_dload_c3d6.inp / wedge_dload_c3d15.inp: the unit cube, 2 x 2 x 2
cells each cut along its (x-, y-) to (x+, y+) diagonal into two wedges
(Junta's box generator's cut: wedge A on the cell's corners 0-1-2, wedge B
on 0-2-3), clamped at x = 0 (FIX), with pressures on every wedge face
label: *DLOAD P1 (bottom triangles of the lower layer), P2 (top triangles of
the upper layer), P3 (A's side on y = 0), P4 (A's side on x = 1), P5 (A's
cut face in the cell at the origin: an internal face), and P4 of B (the
side on y = 1) through *SURFACE S4 + *DSLOAD. Reference: CalculiX 2.20
(`ccx -i wedge_dload_c3d6` etc.), values copied into decks.rs.

coh3d6_stack.inp: two C3D6 layers (the unit square, one cell cut into two
wedges, 0.5 thick each) bonded by two COH3D6 elements, every node held in
x and y (uniaxial strain), bottom fixed, top pulled 0.01 in z.

Usage: python3 make_wedge_decks.py (writes next to this script).
"""
import os

HERE = os.path.dirname(os.path.abspath(__file__))

# H27 local ids of the two wedges of a cell (Wedge15 order; first 6: Wedge6)
WEDGE_A = [0, 1, 2, 4, 5, 6, 8, 9, 24, 12, 13, 25, 16, 17, 18]
WEDGE_B = [0, 2, 3, 4, 6, 7, 24, 10, 11, 25, 14, 15, 16, 18, 19]
# natural coordinates of the H27 nodes (Junta's HEX27_NODES)
HEX27 = [
    (-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1),
    (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1),
    (0, -1, -1), (1, 0, -1), (0, 1, -1), (-1, 0, -1),
    (0, -1, 1), (1, 0, 1), (0, 1, 1), (-1, 0, 1),
    (-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0),
    (-1, 0, 0), (1, 0, 0), (0, -1, 0), (0, 1, 0),
    (0, 0, -1), (0, 0, 1), (0, 0, 0),
]


def wedge_box(n, size, quadratic):
    """Nodes {label: xyz}, elements [(label, kind, conn, (i, j, k))]."""
    p = 2 if quadratic else 1
    npe = 15 if quadratic else 6
    lat = [p * n[a] + 1 for a in range(3)]
    lid = lambda i, j, k: (k * lat[1] + j) * lat[0] + i
    elems = []
    used = set()
    for k in range(n[2]):
        for j in range(n[1]):
            for i in range(n[0]):
                cell = []
                for xi in HEX27:
                    a = p * i + int((xi[0] + 1) * p // 2)
                    b = p * j + int((xi[1] + 1) * p // 2)
                    c = p * k + int((xi[2] + 1) * p // 2)
                    cell.append(lid(a, b, c))
                for kind, local in (("A", WEDGE_A), ("B", WEDGE_B)):
                    conn = [cell[a] for a in local[:npe]]
                    used.update(conn)
                    elems.append((kind, conn, (i, j, k)))
    label = {}
    nodes = {}
    for k in range(lat[2]):
        for j in range(lat[1]):
            for i in range(lat[0]):
                l = lid(i, j, k)
                if l in used:
                    label[l] = len(label) + 1
                    nodes[label[l]] = tuple(
                        size[a] * [i, j, k][a] / (lat[a] - 1) for a in range(3)
                    )
    out = [(e + 1, kind, [label[c] for c in conn], ijk)
           for e, (kind, conn, ijk) in enumerate(elems)]
    return nodes, out


def lines16(values):
    values = [str(v) for v in values]
    return "\n".join(", ".join(values[i:i + 16]) for i in range(0, len(values), 16))


def dload_deck(quadratic):
    typ = "C3D15" if quadratic else "C3D6"
    n = (2, 2, 2)
    nodes, elems = wedge_box(n, (1.0, 1.0, 1.0), quadratic)
    sel = lambda f: [e for e, kind, _, ijk in elems if f(kind, *ijk)]
    fix = [l for l, x in nodes.items() if x[0] == 0.0]
    tip = [l for l, x in nodes.items() if x[0] == 1.0]
    out = [
        f"** Wedge pressures, {typ}: written by make_wedge_decks.py (see there);",
        f"** reference CalculiX 2.20 (ccx -i wedge_dload_{typ.lower()}), crates/cli/tests/decks.rs.",
        "*HEADING",
        f"Unit cube of {typ} wedges with P1..P5 pressures",
        "*NODE, NSET=NALL",
    ]
    out += [f"{l}, {x[0]:.6g}, {x[1]:.6g}, {x[2]:.6g}" for l, x in nodes.items()]
    out.append(f"*ELEMENT, TYPE={typ}, ELSET=EALL")
    for e, _, conn, _ in elems:
        out.append(f"{e}, " + ", ".join(map(str, conn[:10])) + ("," if len(conn) > 10 else ""))
        if len(conn) > 10:
            out.append(", ".join(map(str, conn[10:])))
    sets = {
        "BOT": sel(lambda kind, i, j, k: k == 0),
        "TOPL": sel(lambda kind, i, j, k: k == n[2] - 1),
        "YLO": sel(lambda kind, i, j, k: kind == "A" and j == 0),
        "XHI": sel(lambda kind, i, j, k: kind == "A" and i == n[0] - 1),
        "YHI": sel(lambda kind, i, j, k: kind == "B" and j == n[1] - 1),
        "CUT": sel(lambda kind, i, j, k: kind == "A" and i == 0 and j == 0),
    }
    for name, members in sets.items():
        out += [f"*ELSET, ELSET={name}", lines16(members)]
    out += ["*NSET, NSET=FIX", lines16(fix), "*NSET, NSET=TIP", lines16(tip)]
    out += [
        "*MATERIAL, NAME=STEEL",
        "*ELASTIC",
        "210000, 0.3",
        "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL",
        "*BOUNDARY",
        "FIX, 1, 3",
        "*SURFACE, NAME=YHIS, TYPE=ELEMENT",
        "YHI, S4",
        "*STEP",
        "*STATIC",
        "*DLOAD",
        "BOT, P1, 5.",
        "TOPL, P2, 10.",
        "YLO, P3, 3.",
        "XHI, P4, 4.",
        "CUT, P5, 1.5",
        "*DSLOAD",
        "YHIS, P, 2.",
        "*NODE PRINT, NSET=TIP",
        "U",
        "*NODE PRINT, NSET=FIX, TOTALS=ONLY",
        "RF",
        "*END STEP",
    ]
    path = os.path.join(HERE, f"wedge_dload_{typ.lower()}.inp")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def coh3d6_deck():
    # lower layer z 0..0.5 (nodes 1-8), upper layer z 0.5..1 (9-16), the
    # upper's bottom nodes 9-12 on top of the lower's top nodes 5-8
    sq = [(0, 0), (1, 0), (1, 1), (0, 1)]
    nodes = []
    for z in (0.0, 0.5, 0.5, 1.0):
        nodes += [(x, y, z) for x, y in sq]
    tri = [(0, 1, 2), (0, 2, 3)]
    wedge = lambda base, top: [[base + a + 1 for a in t] + [top + a + 1 for a in t] for t in tri]
    out = [
        "** Two C3D6 layers (0.5 thick) bonded by two COH3D6 (written by make_wedge_decks.py).",
        "** Every node held in x and y (uniaxial strain); bottom fixed, top pulled 0.01 in z.",
        "** Closed form (series of the layers and the penalty): sigma = delta / (2 h / M + 1 / K),",
        "** M = E (1 - nu) / ((1 + nu)(1 - 2 nu)), h = 0.5, K = K_nn / T0: crates/cli/tests/cohesive_deck.rs.",
        "*HEADING",
        "COH3D6 stack",
        "*NODE, NSET=NALL",
    ]
    out += [f"{i + 1}, {x:g}, {y:g}, {z:g}" for i, (x, y, z) in enumerate(nodes)]
    out.append("*ELEMENT, TYPE=C3D6, ELSET=LOWER")
    out += [f"{e + 1}, " + ", ".join(map(str, c)) for e, c in enumerate(wedge(0, 4))]
    out.append("*ELEMENT, TYPE=C3D6, ELSET=UPPER")
    out += [f"{e + 3}, " + ", ".join(map(str, c)) for e, c in enumerate(wedge(8, 12))]
    out.append("*ELEMENT, TYPE=COH3D6, ELSET=GLUE")
    out += [f"{e + 5}, " + ", ".join(map(str, c)) for e, c in enumerate(wedge(4, 8))]
    out += [
        "*NSET, NSET=BOTTOM", "1, 2, 3, 4",
        "*NSET, NSET=TOP", "13, 14, 15, 16",
        "*MATERIAL, NAME=STEEL", "*ELASTIC", "210000, 0.3",
        "*MATERIAL, NAME=GLUE", "*ELASTIC, TYPE=TRACTION", "1.0E5, 1.0E5, 1.0E5",
        "*SOLID SECTION, ELSET=LOWER, MATERIAL=STEEL",
        "*SOLID SECTION, ELSET=UPPER, MATERIAL=STEEL",
        "*COHESIVE SECTION, ELSET=GLUE, MATERIAL=GLUE, RESPONSE=TRACTION SEPARATION",
        "1.0",
        "*BOUNDARY", "NALL, 1, 2", "BOTTOM, 3, 3",
        "*STEP", "*STATIC",
        "*BOUNDARY", "TOP, 3, 3, 0.01",
        "*END STEP",
    ]
    with open(os.path.join(HERE, "coh3d6_stack.inp"), "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    dload_deck(False)
    dload_deck(True)
    coh3d6_deck()
