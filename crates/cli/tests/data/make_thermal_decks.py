#!/usr/bin/env python3
"""Write the thermal decks of crates/cli/tests/thermal.rs from the
cylindrical-ring decks of make_cyl_decks.py.

thermal_ring_c3d20.inp and thermal_ring_c3d8.inp are cyl_ring_c3d20.inp and
cyl_ring_c3d8.inp (a quarter of a thick tube about a skew axis, strongly
orthotropic, material axes of *ORIENTATION, SYSTEM=CYLINDRICAL at every
integration point, clamped at theta = 0, inner pressure and end loads) with
thermal expansion and a temperature field added:

- *EXPANSION, TYPE=ORTHO on the ENGINEERING CONSTANTS and ORTHO materials
  (alpha_r 3e-5, alpha_theta 1e-6, alpha_z 2e-5: a fibre-like hoop axis),
  TYPE=ANISO with a coupling alpha_12 = 4e-6 on the ANISO material (C3D20
  deck), TYPE=ISO (ZERO=20) on the C3D8 deck's material is ORTHO too;
- *INITIAL CONDITIONS, TYPE=TEMPERATURE: 20 at every node (NALL);
- *TEMPERATURE in the step: on the C3D20 deck T = 20 - 40 + 2 r + 15
  theta + 3 z per node in the ring's own (r, theta, z) (a field linear in
  the elements' natural coordinates: CalculiX's linear approximation of
  the C3D20 temperatures from the corners, `lintemp`, then equals the
  quadratic interpolation Junta makes); on the C3D8 deck a uniform -60
  (CalculiX takes each C3D8's mean nodal temperature at all its points,
  e_c3d.f, where Junta interpolates: the same only for a uniform change).

Reference: CalculiX 2.20 (`ccx -i thermal_ring_c3d20`, `ccx -i
thermal_ring_c3d8`, their .dat, 7 printed digits), values copied into
thermal.rs. Usage: python3 make_thermal_decks.py (writes next to this
script; needs the cyl_ring decks).
"""
import math
import os

# the ring's frame, as in make_cyl_decks.py (which writes its decks when
# imported)
A = (1.0, 2.0, 3.0)
D = (0.3, -0.2, 1.0)


def unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return tuple(x / n for x in v)


def cross(u, v):
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


EZ = unit(D)
EX = unit(cross((0.0, 1.0, 0.0), EZ))
EY = cross(EZ, EX)

HERE = os.path.dirname(os.path.abspath(__file__))


def nodes(lines):
    out = []
    on = False
    for l in lines:
        if l.startswith("*"):
            on = l.upper().startswith("*NODE,") or l.upper() == "*NODE"
            continue
        if on and l.strip():
            f = [x.strip() for x in l.split(",")]
            out.append((int(f[0]), float(f[1]), float(f[2]), float(f[3])))
    return out


def ring_coords(x, y, z):
    """(r, theta, z) of a point in the ring's frame (make_cyl_decks.py)."""
    v = (x - A[0], y - A[1], z - A[2])
    dot = lambda a, b: sum(p * q for p, q in zip(a, b))
    return math.hypot(dot(v, EX), dot(v, EY)), math.atan2(dot(v, EY), dot(v, EX)), dot(v, EZ)


def field(x, y, z):
    r, t, h = ring_coords(x, y, z)
    return 20.0 - 40.0 + 2.0 * r + 15.0 * t + 3.0 * h


def write(src, dst, expansions, uniform=None):
    lines = open(os.path.join(HERE, src)).read().splitlines()
    out = [
        f"** Junta test deck written by make_thermal_decks.py from {src}: {dst} (see the script's docstring).",
        f"** Reference: CalculiX 2.20, ccx -i {dst[:-4]}; values in crates/cli/tests/thermal.rs.",
    ]
    body = [l for l in lines if not l.startswith("** ")]
    i = 0
    while i < len(body):
        l = body[i]
        out.append(l)
        u = l.upper()
        if u.startswith("*ELASTIC"):
            # the data line(s) of *ELASTIC, then the expansion of its material
            mat = [x for x in out if x.upper().startswith("*MATERIAL")][-1].split("=")[1].strip()
            i += 1
            while i < len(body) and not body[i].startswith("*"):
                out.append(body[i])
                i += 1
            out.extend(expansions[mat])
            continue
        if u.startswith("*SOLID SECTION") and not (i + 1 < len(body) and body[i + 1].upper().startswith("*SOLID SECTION")):
            out.append("*INITIAL CONDITIONS, TYPE=TEMPERATURE")
            out.append("NALL, 20.")
        if u == "*STATIC":
            out.append("*TEMPERATURE")
            if uniform is not None:
                out.append(f"NALL, {uniform}")
            else:
                for n, x, y, z in nodes(lines):
                    out.append(f"{n}, {field(x, y, z):.12g}")
        i += 1
    open(os.path.join(HERE, dst), "w").write("\n".join(out) + "\n")


ORTHO = ["*EXPANSION, TYPE=ORTHO", "3.e-5, 1.e-6, 2.e-5"]
write(
    "cyl_ring_c3d20.inp",
    "thermal_ring_c3d20.inp",
    {
        "ENG": ORTHO,
        "ORTHO": ORTHO,
        "ANISO": ["*EXPANSION, TYPE=ANISO", "3.e-5, 1.e-6, 2.e-5, 4.e-6, 0., 0."],
    },
)
write(
    "cyl_ring_c3d8.inp",
    "thermal_ring_c3d8.inp",
    {"ENG": ["*EXPANSION, TYPE=ORTHO, ZERO=20.", "3.e-5, 1.e-6, 2.e-5"]},
    uniform=-60.0,
)
