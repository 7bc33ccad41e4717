#!/usr/bin/env python3
"""Write the unit-cube deck of shared/BENCHMARKS.md section 1 as an
Abaqus/CalculiX .inp file: [0,1]^3, n x n x n C3D8 or C3D20 elements,
E = 210000, nu = 0.3, bottom (z=0) fixed, top (z=1) uz = -0.01.
The check value is the total z reaction on the top face (NSET TOP).

usage: make_cube_deck.py {C3D8|C3D20} N OUT.inp
"""
import sys

# corner and mid-edge offsets (in units of half an element) in C3D20 = VTK order
CORNERS = [(0, 0, 0), (2, 0, 0), (2, 2, 0), (0, 2, 0), (0, 0, 2), (2, 0, 2), (2, 2, 2), (0, 2, 2)]
EDGES = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4), (0, 4), (1, 5), (2, 6), (3, 7)]


def main():
    etype, n, out = sys.argv[1].upper(), int(sys.argv[2]), sys.argv[3]
    quad = etype == "C3D20"
    p = 2 if quad else 1
    m = p * n + 1
    local = list(CORNERS)
    if quad:
        local += [tuple((CORNERS[a][d] + CORNERS[b][d]) // 2 for d in range(3)) for a, b in EDGES]
    else:
        local = [tuple(c // 2 for c in v) for v in local]
    used = {}
    elems = []
    for k in range(n):
        for j in range(n):
            for i in range(n):
                conn = []
                for (a, b, c) in local:
                    key = (p * i + a, p * j + b, p * k + c)
                    if key not in used:
                        used[key] = len(used) + 1
                    conn.append(used[key])
                elems.append(conn)
    with open(out, "w") as f:
        f.write("*HEADING\nUnit cube %s n=%d (shared/BENCHMARKS.md section 1)\n*NODE, NSET=NALL\n" % (etype, n))
        for key, lab in sorted(used.items(), key=lambda kv: kv[1]):
            f.write("%d, %.17g, %.17g, %.17g\n" % (lab, key[0] / (m - 1), key[1] / (m - 1), key[2] / (m - 1)))
        f.write("*ELEMENT, TYPE=%s, ELSET=EALL\n" % etype)
        for e, conn in enumerate(elems, 1):
            vals = [str(e)] + [str(c) for c in conn]
            # at most 16 entries per line, continuation lines end with a comma
            lines = [", ".join(vals[i:i + 16]) for i in range(0, len(vals), 16)]
            f.write(",\n".join(lines) + "\n")
        for name, z in (("BOTTOM", 0), ("TOP", m - 1)):
            labs = sorted(lab for key, lab in used.items() if key[2] == z)
            f.write("*NSET, NSET=%s\n" % name)
            for i in range(0, len(labs), 16):
                f.write(", ".join(str(x) for x in labs[i:i + 16]) + "\n")
        f.write("*MATERIAL, NAME=STEEL\n*ELASTIC\n210000, 0.3\n*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n")
        f.write("*BOUNDARY\nBOTTOM, 1, 3\n*STEP\n*STATIC\n*BOUNDARY\nTOP, 3, 3, -0.01\n")
        f.write("*NODE PRINT, NSET=TOP, TOTALS=ONLY\nRF\n*END STEP\n")


if __name__ == "__main__":
    main()
