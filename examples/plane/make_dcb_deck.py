#!/usr/bin/env python3
"""Write `dcb_cpe4i.inp`: the DCB of ../delamination/dcb_abaqus.inp as an
Abaqus user writes it in 2D. Plane-strain CPE4I arms (two elements
through each arm's thickness), COH2D4 cohesive elements of zero thickness
on the bonded part, listed counter-clockwise as Abaqus wants them (1-2 on
the lower arm, 3-4 above them), `*COHESIVE SECTION` with the constitutive
thickness 1 and the out-of-plane thickness 25.4 (the width), the same
QUADS onset and BK energy softening, the same mesh along x (1 mm on the
precrack, 0.5 mm on the first 35 mm of the bond, 2 mm beyond).

Run from anywhere:  python3 examples/plane/make_dcb_deck.py
(standard library only; rewrites the deck next to this script).
"""

from pathlib import Path

HERE = Path(__file__).resolve().parent
L, B, H, A0 = 102.0, 25.4, 1.56, 32.9
X_PARTS = [(0.0, A0, 33), (A0, 35.0, 70), (A0 + 35.0, L - A0 - 35.0, 17)]
NY = 2  # elements through each arm


def xs():
    out = [0.0]
    for x0, length, n in X_PARTS:
        out += [x0 + length * (i + 1) / n for i in range(n)]
    return out


def main():
    x = xs()
    nx = len(x) - 1
    rows = []  # (label, x, y): lower arm rows 0..NY, upper arm rows NY..2NY (own nodes)
    label = {}
    nid = 0
    for arm in range(2):
        for j in range(NY + 1):
            y = arm * H + H * j / NY
            for i, xi in enumerate(x):
                nid += 1
                label[(arm, j, i)] = nid
                rows.append(f"{nid}, {xi:.10g}, {y:.10g}")
    elems = {0: [], 1: []}
    eid = 0
    for arm in range(2):
        for j in range(NY):
            for i in range(nx):
                eid += 1
                n = [label[(arm, j, i)], label[(arm, j, i + 1)], label[(arm, j + 1, i + 1)], label[(arm, j + 1, i)]]
                elems[arm].append(f"{eid}, " + ", ".join(map(str, n)))
    bond = []
    first = next(i for i, xi in enumerate(x) if abs(xi - A0) < 1e-9)
    for i in range(first, nx):
        eid += 1
        # counter-clockwise: 1-2 on the lower arm's top, 3-4 on the upper arm's bottom
        n = [label[(0, NY, i)], label[(0, NY, i + 1)], label[(1, 0, i + 1)], label[(1, 0, i)]]
        bond.append(f"{eid}, " + ", ".join(map(str, n)))
    load_up = [label[(1, j, 0)] for j in range(NY + 1)]
    load_low = [label[(0, j, 0)] for j in range(NY + 1)]
    clamp = [label[(arm, j, nx)] for arm in range(2) for j in range(NY + 1)]
    text = f"""*HEADING
DCB, AS4/PEEK, mode I, plane strain: CPE4I arms + COH2D4 bond (written by make_dcb_deck.py)
** The DCB of ../delamination/dcb_abaqus.inp (Camanho, Davila & de Moura 2003) in 2D, as an
** Abaqus user writes it. Units: N, mm, MPa. Arms 102 x 1.56 mm in the x-y plane, width
** 25.4 mm out of the plane (the *SOLID SECTION and *COHESIVE SECTION thicknesses), precrack
** a0 = 32.9 mm from the loaded end x = 0, far end clamped; the loaded ends move apart by
** +-delta/2 up to delta = 10 mm over the step.
** junta: curve reaction_set=LOAD_UP reaction_component=y point_set=LOAD_UP point_component=y relative_to=LOAD_LOW
** junta: output every=50
*NODE
""" + "\n".join(rows) + """
*ELEMENT, TYPE=CPE4I, ELSET=LOWER
""" + "\n".join(elems[0]) + """
*ELEMENT, TYPE=CPE4I, ELSET=UPPER
""" + "\n".join(elems[1]) + """
*ELEMENT, TYPE=COH2D4, ELSET=BOND
""" + "\n".join(bond) + f"""
*NSET, NSET=LOAD_UP
{", ".join(map(str, load_up))}
*NSET, NSET=LOAD_LOW
{", ".join(map(str, load_low))}
*NSET, NSET=CLAMP
""" + "\n".join(", ".join(map(str, clamp[k:k + 8])) for k in range(0, len(clamp), 8)) + f"""
*ELSET, ELSET=ARMS
LOWER, UPPER
*MATERIAL, NAME=AS4PEEK
*ELASTIC, TYPE=ENGINEERING CONSTANTS
122700.0, 10100.0, 10100.0, 0.25, 0.25, 0.45, 5500.0, 5500.0,
3700.0
*MATERIAL, NAME=CZ
*ELASTIC, TYPE=TRACTION
1000000.0, 1000000.0, 1000000.0
*DAMAGE INITIATION, CRITERION=QUADS
80.0, 100.0, 100.0
*DAMAGE EVOLUTION, TYPE=ENERGY, SOFTENING=LINEAR, MIXED MODE BEHAVIOR=BK, POWER=2.284
0.969, 1.719, 1.719
*SOLID SECTION, ELSET=ARMS, MATERIAL=AS4PEEK
{B}
*COHESIVE SECTION, ELSET=BOND, MATERIAL=CZ, RESPONSE=TRACTION SEPARATION
1.0, {B}
*BOUNDARY
CLAMP, ENCASTRE
*STEP, NAME=OPEN, NLGEOM=NO, INC=1000
*STATIC
0.01, 1.0, 1e-06, 0.01
*BOUNDARY
LOAD_UP, 2, 2, 5.0
LOAD_LOW, 2, 2, -5.0
*NODE PRINT, NSET=LOAD_UP
U, RF
*END STEP
"""
    (HERE / "dcb_cpe4i.inp").write_text(text)


if __name__ == "__main__":
    main()
