# Generator of the unit-cube fixtures cube_h8_n2.inp and cube_h20_n2.inp
# (BENCHMARKS.md section 1). Node order of C3D8/C3D20 = VTK.
import itertools
H27 = [(-1,-1,-1),(1,-1,-1),(1,1,-1),(-1,1,-1),(-1,-1,1),(1,-1,1),(1,1,1),(-1,1,1),
       (0,-1,-1),(1,0,-1),(0,1,-1),(-1,0,-1),(0,-1,1),(1,0,1),(0,1,1),(-1,0,1),
       (-1,-1,0),(1,-1,0),(1,1,0),(-1,1,0)]
def deck(p, n, etype, npe, title):
    m = p * n
    lab = {}
    nodes = []
    for k, j, i in itertools.product(range(m + 1), repeat=3):
        if p == 2 and (i % 2) + (j % 2) + (k % 2) >= 2:
            continue
        lab[(i, j, k)] = len(nodes) + 1
        nodes.append((i / m, j / m, k / m))
    out = ["*HEADING", title,
           "** nodes: 0-based lattice labels 1..N, elements in VTK = Abaqus order",
           "*NODE, NSET=NALL"]
    for (i, j, k), l in sorted(lab.items(), key=lambda t: t[1]):
        x = nodes[l - 1]
        out.append(f"{l}, {x[0]:.6g}, {x[1]:.6g}, {x[2]:.6g}")
    out.append(f"*ELEMENT, TYPE={etype}, ELSET=EALL")
    e = 0
    for ez, ey, ex in itertools.product(range(n), repeat=3):
        e += 1
        conn = []
        for xi in H27[:npe]:
            conn.append(lab[(p * ex + (xi[0] + 1) * p // 2, p * ey + (xi[1] + 1) * p // 2, p * ez + (xi[2] + 1) * p // 2)])
        vals = [e] + conn
        if len(vals) > 16:
            out.append(", ".join(map(str, vals[:16])) + ",")
            out.append(", ".join(map(str, vals[16:])))
        else:
            out.append(", ".join(map(str, vals)))
    for name, kk in (("BOTTOM", 0), ("TOP", m)):
        out.append(f"*NSET, NSET={name}")
        ls = sorted(l for (i, j, k), l in lab.items() if k == kk)
        for c in range(0, len(ls), 8):
            out.append(", ".join(map(str, ls[c:c + 8])))
    out += ["*MATERIAL, NAME=STEEL", "*ELASTIC", "210000., 0.3",
            "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL",
            "** bottom face fully fixed",
            "*BOUNDARY", "BOTTOM, 1, 3",
            "*STEP", "*STATIC",
            "** top face: uz = -0.01 prescribed, ux and uy free",
            "*BOUNDARY", "TOP, 3, 3, -0.01",
            "*NODE PRINT, NSET=TOP, TOTALS=ONLY", "RF",
            "*END STEP"]
    return "\n".join(out) + "\n"
open("cube_h8_n2.inp", "w").write(deck(1, 2, "C3D8", 8, "Unit cube [0,1]^3, 2x2x2 C3D8, E=210000 nu=0.3 (BENCHMARKS.md section 1, Fz = -2224.553)"))
open("cube_h20_n2.inp", "w").write(deck(2, 2, "C3D20", 20, "Unit cube [0,1]^3, 2x2x2 C3D20, E=210000 nu=0.3 (BENCHMARKS.md section 1, Fz = -2183.070)"))
