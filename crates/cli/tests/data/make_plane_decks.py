"""Decks derived from CalculiX's 2D test decks (ccx_suite/), for
crates/cli/tests/plane_decks.rs:

- axial_cax8.inp: ccx_suite/axial.inp with CAX8R -> CAX8 (full
  integration); its reference axial_cax8.dat is `ccx -i axial_cax8`
  (CalculiX 2.20). With CAX8R, CalculiX integrates the centrifugal load
  (rho omega^2 r, times the ring's 2 pi r: quadratic in r) with the
  element's 2x2 rule, which is not exact; with CAX8 both codes integrate it
  exactly.
- planestress3_c3d8.inp: ccx_suite/planestress3.inp expanded as CalculiX
  expands CPS4 (one layer of C3D8 of the section's thickness 0.1, the plane
  node n at mid-thickness becoming n+1000 at z = -0.05 and n+2000 at z =
  +0.05, each load shared between them; one z fixed). Its displacements are
  those of planestress3.dat.ref.

Run: python3 make_plane_decks.py (from this folder).
"""

SUITE = "ccx_suite/"


def axial_cax8():
    text = open(SUITE + "axial.inp").read().replace("TYPE=CAX8R", "TYPE=CAX8")
    open("axial_cax8.inp", "w").write(text)


def planestress3_c3d8():
    out, mode = [], None
    for l in open(SUITE + "planestress3.inp").read().splitlines():
        u = l.strip().upper()
        if u.startswith("*"):
            mode = u.split(",")[0]
            if mode == "*ELEMENT":
                l = l.replace("CPS4", "C3D8")
            if mode == "*SOLID SECTION":
                out.append(l)
                continue
            out.append(l)
            continue
        if mode == "*NODE":
            f = [x.strip() for x in l.split(",")]
            lab = int(f[0])
            x = [float(v) if v else 0.0 for v in f[1:]] + [0.0, 0.0]
            out.append(f"{lab + 1000},{x[0]},{x[1]},-0.05")
            out.append(f"{lab + 2000},{x[0]},{x[1]},0.05")
        elif mode == "*ELEMENT":
            f = [int(v) for v in l.split(",")]
            bot = ",".join(str(a + 1000) for a in f[1:])
            top = ",".join(str(a + 2000) for a in f[1:])
            out.append(f"{f[0]},{bot},{top}")
        elif mode == "*NSET" and l.strip()[0].isdigit():
            ids = [int(v) for v in l.split(",") if v.strip()]
            out.append(",".join(str(v) for v in [i + 1000 for i in ids] + [i + 2000 for i in ids]))
        elif mode == "*SOLID SECTION":
            continue  # the thickness line: the layer has it
        elif mode == "*BOUNDARY":
            out.append(l)
            out.append("1001,3,3")
        elif mode == "*CLOAD":
            n, d, v = l.split(",")
            out.append(f"{int(n) + 1000},{d},{float(v) / 2}")
            out.append(f"{int(n) + 2000},{d},{float(v) / 2}")
        else:
            out.append(l)
    open("planestress3_c3d8.inp", "w").write("\n".join(out) + "\n")


if __name__ == "__main__":
    axial_cax8()
    planestress3_c3d8()
