#!/usr/bin/env python3
"""Write the Abaqus DCB deck `dcb_abaqus.inp` and its twin TOML scene
`dcb_h8.toml` (same mesh, same law, same load program).

The double cantilever beam of `dcb.toml` (AS4/PEEK, Camanho, Davila & de
Moura 2003; BENCHMARKS.md section 4), meshed for a deck: Abaqus' cohesive
brick COH3D8 has 8 nodes and matches C3D8 faces, so the arms are C3D8 (two
elements through each arm's thickness so that bending is not locked too
much) and the bonded part is COH3D8, where `dcb.toml` uses H20 + INTER16.
`dcb_h8.toml` builds the identical mesh with the box generator (H8 +
INTER8, same divisions, same coordinates), so `junta run` gives the same
curve.csv for both (crates/cli/tests/cli.rs checks it).

Run from anywhere:  python3 examples/delamination/make_dcb_deck.py
(standard library only; rewrites both files next to this script).
"""

from pathlib import Path

HERE = Path(__file__).resolve().parent

# geometry (mm): arms 102 long (x), 25.4 wide (y), h = 1.56 thick (z)
L, B, H, A0 = 102.0, 25.4, 1.56, 32.9
# x parts of each arm: precrack, fine bonded part (0.5 mm: the cohesive zone
# is ~1.4-3 mm long, see dcb.toml), coarse bonded far end (2 mm: the crack
# tip stays short of it up to delta = 10 mm, a ~ 55 mm by beam theory)
X_PARTS = [  # (name, x origin, length, divisions)
    ("crack", 0.0, A0, 33),
    ("near", A0, 35.0, 70),
    ("far", A0 + 35.0, L - A0 - 35.0, 17),
]
NY, NZ = 1, 2  # elements across the width, through each arm
DELTA_END = 10.0  # total opening at the end of the step (mm)

# AS4/PEEK (fibres along x), Camanho, Davila & de Moura 2003
E = dict(E1=122700.0, E2=10100.0, E3=10100.0, nu12=0.25, nu13=0.25, nu23=0.45,
         G12=5500.0, G13=5500.0, G23=3700.0)
# interface: the bilinear law of dcb.toml
K, N, S, GIC, GIIC, ETA = 1.0e6, 80.0, 100.0, 0.969, 1.719, 2.284
# increments: 0.01 of the step (0.1 mm of opening), as dcb.toml
DT0, DTMIN, DTMAX = 0.01, 1.0e-6, 0.01


def ticks(origin, length, n):
    """Node coordinates along an axis, as Junta's box generator computes
    them (origin + length * i / n, the last one exactly origin + length)."""
    x = [origin + length * i / n for i in range(n)]
    return x + [origin + length]


def arm_xs():
    xs = []
    for k, (_, x0, lx, nx) in enumerate(X_PARTS):
        t = ticks(x0, lx, nx)
        xs.extend(t if k == 0 else t[1:])
    return xs


def deck():
    xs = arm_xs()
    ys = ticks(0.0, B, NY)
    nodes = {}  # (arm, i, j, k) -> label
    lines = []
    out = lines.append
    out("*HEADING")
    out("DCB, AS4/PEEK, mode I: C3D8 arms + COH3D8 bonded part (written by make_dcb_deck.py)")
    out("** Double cantilever beam of Camanho, Davila & de Moura (2003), BENCHMARKS.md section 4.")
    out("** Units: N, mm, MPa. Arms 102 x 25.4 x 1.56 mm, precrack a0 = 32.9 mm from the loaded")
    out("** end x = 0, far end x = 102 clamped; the end faces move apart by +-delta/2 up to")
    out(f"** delta = {DELTA_END} mm over the step (Abaqus ramps the *BOUNDARY values: load factor 1 at")
    out("** the end of the period). Cohesive material: *ELASTIC, TYPE=TRACTION (K per unit")
    out("** area, constitutive thickness 1 on the *COHESIVE SECTION data line), QUADS onset,")
    out("** energy-based linear softening with the BK rule (POWER = eta): Junta's `bilinear` law.")
    out("** Twin TOML scene: dcb_h8.toml (same mesh); generator: make_dcb_deck.py.")
    out("** Run: junta run examples/delamination/dcb_abaqus.inp (an incremental run: the")
    out("** softening law makes it one). Measured with --solver type=cholesky: 100.7 N at")
    out("** delta = 3 mm (corrected beam theory 98.6 N), peak 142.5 N at delta = 4.45 mm")
    out("** (corrected beam theory 138.5 N at 4.21 mm, Akantu hex8 142.7 N at 4.49 mm); the")
    out("** propagation branch needs the `ldlt` back end (solver auto).")
    out('** Advice (`junta check`):')
    out('** - the mesh advice says too coarse (2.7 elements in the cohesive zone where')
    out("**   the crack runs, 3 wanted): kept, because 0.5 mm elements (2.7 in Rice's")
    out('**   zone, just under 3) keep the run short and the loads above are measured')
    out('**   on this mesh.')
    out("** - the law warns that its shear strength S breaks Turon's 2010 consistency")
    out('**   condition S = N sqrt(G_IIc/G_Ic) for one penalty K (mixed-mode onset and')
    out('**   propagation disagree): kept, because the material data above are used as')
    out("**   published and the example's numbers are measured with them")
    out('**   (shear_penalty = "turon2018" would change them).')
    out('** - the H8 locking warning (C3D8 arms, two elements through each) is this')
    out("**   deck's twin dcb_h8.toml's point: h8 against h8i.")
    out("** The `** junta:` lines are comments for Abaqus and directives for Junta:")
    out("** junta: curve reaction_set=LOAD_UP reaction_component=z point_set=LOAD_UP point_component=z relative_to=LOAD_LOW")
    out("** junta: output every=50")
    out("*NODE")
    label = 0
    for arm in (0, 1):
        for k in range(NZ + 1):
            z = ticks(0.0 if arm == 0 else H, H, NZ)[k]
            for j, y in enumerate(ys):
                for i, x in enumerate(xs):
                    label += 1
                    nodes[(arm, i, j, k)] = label
                    out(f"{label}, {x!r}, {y!r}, {z!r}")
    # solids
    e = 0
    first_bond = X_PARTS[0][3]
    for arm, name in ((0, "LOWER"), (1, "UPPER")):
        out(f"*ELEMENT, TYPE=C3D8, ELSET={name}")
        for k in range(NZ):
            for j in range(NY):
                for i in range(len(xs) - 1):
                    e += 1
                    c = [nodes[(arm, i + a, j + b, k + d)]
                         for (a, b, d) in ((0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0),
                                           (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1))]
                    out(f"{e}, " + ", ".join(map(str, c)))
    # cohesive elements on the bonded part: bottom face = top of the lower
    # arm, top face = bottom of the upper arm (normal +z)
    out("*ELEMENT, TYPE=COH3D8, ELSET=BOND")
    for j in range(NY):
        for i in range(first_bond, len(xs) - 1):
            e += 1
            quad = ((0, 0), (1, 0), (1, 1), (0, 1))
            c = [nodes[(0, i + a, j + b, NZ)] for a, b in quad]
            c += [nodes[(1, i + a, j + b, 0)] for a, b in quad]
            out(f"{e}, " + ", ".join(map(str, c)))

    def nset(name, keys):
        out(f"*NSET, NSET={name}")
        labels = sorted(nodes[key] for key in keys)
        for s in range(0, len(labels), 16):
            out(", ".join(map(str, labels[s:s + 16])))

    last = len(xs) - 1
    every = [(j, k) for j in range(NY + 1) for k in range(NZ + 1)]
    nset("LOAD_UP", [(1, 0, j, k) for j, k in every])
    nset("LOAD_LOW", [(0, 0, j, k) for j, k in every])
    nset("CLAMP", [(arm, last, j, k) for arm in (0, 1) for j, k in every])
    out("*ELSET, ELSET=ARMS")
    out("LOWER, UPPER")
    out("*MATERIAL, NAME=AS4PEEK")
    out("*ELASTIC, TYPE=ENGINEERING CONSTANTS")
    out(", ".join(repr(E[k]) for k in ("E1", "E2", "E3", "nu12", "nu13", "nu23", "G12", "G13")) + ",")
    out(repr(E["G23"]))
    out("*MATERIAL, NAME=CZ")
    out("*ELASTIC, TYPE=TRACTION")
    out(f"{K!r}, {K!r}, {K!r}")
    out("*DAMAGE INITIATION, CRITERION=QUADS")
    out(f"{N!r}, {S!r}, {S!r}")
    out(f"*DAMAGE EVOLUTION, TYPE=ENERGY, SOFTENING=LINEAR, MIXED MODE BEHAVIOR=BK, POWER={ETA!r}")
    out(f"{GIC!r}, {GIIC!r}, {GIIC!r}")
    out("*SOLID SECTION, ELSET=ARMS, MATERIAL=AS4PEEK")
    out("*COHESIVE SECTION, ELSET=BOND, MATERIAL=CZ, RESPONSE=TRACTION SEPARATION")
    out("1.0")
    out("*BOUNDARY")
    out("CLAMP, ENCASTRE")
    out("*STEP, NAME=OPEN, NLGEOM=NO, INC=1000")
    out("*STATIC")
    out(f"{DT0!r}, 1.0, {DTMIN!r}, {DTMAX!r}")
    out("*BOUNDARY")
    out(f"LOAD_UP, 3, 3, {DELTA_END / 2!r}")
    out(f"LOAD_LOW, 3, 3, {-DELTA_END / 2!r}")
    out("*NODE PRINT, NSET=LOAD_UP")
    out("U, RF")
    out("*END STEP")
    return "\n".join(lines) + "\n"


def scene():
    boxes = []
    for arm, z0 in (("lower", 0.0), ("upper", H)):
        for name, x0, lx, nx in X_PARTS:
            boxes.append(f"""[[mesh.boxes]]
name = "{arm}_{name}"
group = "{arm}"
origin = [{x0!r}, 0.0, {z0!r}]
size = [{lx!r}, {B!r}, {H!r}]
divisions = [{nx}, {NY}, {NZ}]
element = "h8"
material = "as4peek"
""")
    mats = "\n".join(f"{k} = {v!r}" for k, v in E.items())
    return f"""# The DCB of dcb.toml (AS4/PEEK, mode I) on the mesh of the Abaqus deck
# dcb_abaqus.inp: H8 arms with two elements through each arm's thickness,
# INTER8 on the bonded part (x >= a0 = 32.9 mm), 1 mm elements along the
# precrack, 0.5 mm along the first 35 mm of the bonded part, 2 mm beyond.
# Written by make_dcb_deck.py with the deck, so that the two are the same
# model: `junta run` gives the same curve.csv for both (the deck's load
# factor runs 0 -> 1 over its step, this scene's load factor is the opening
# delta in mm as in dcb.toml: lambda_scene = {DELTA_END!r} lambda_deck).
# Units: N, mm, MPa. Beam-theory and published references: see dcb.toml.
#
# Advice (`junta check`):
# - the mesh advice says too coarse (2.7 elements in the cohesive zone where
#   the crack runs, 3 wanted): kept, because 0.5 mm elements (2.7 in Rice's
#   zone, just under 3) keep the run short and the loads above are measured
#   on this mesh.
# - the law warns that its shear strength S breaks Turon's 2010 consistency
#   condition S = N sqrt(G_IIc/G_Ic) for one penalty K (mixed-mode onset and
#   propagation disagree): kept, because the material data above are used as
#   published and the example's numbers are measured with them (shear_penalty
#   = "turon2018" would change them).
# - the H8 locking warning is the point of this example: h8 against h8i on
#   the same mesh (numbers above).

[model]
title = "DCB, AS4/PEEK, mode I (H8 + INTER8, the mesh of dcb_abaqus.inp)"
units = "N, mm, MPa"

[materials.as4peek]
type = "orthotropic"
{mats}

[laws.cz]
type = "bilinear"
K = {K!r}
N = {N!r}
S = {S!r}
G_Ic = {GIC!r}
G_IIc = {GIIC!r}
eta = {ETA!r}
onset = "quadratic"

[mesh]
type = "boxes"

{chr(10).join(boxes)}
[[interface]]
name = "bond"
between = ["lower", "upper"]
law = "cz"
within = [[{A0!r}, -1.0, -1.0], [{L!r}, {B + 1.0!r}, {2 * H + 1.0!r}]]   # bonded part; x < a0 is the precrack

[[boundary]]
set = "lower_far.x1"
fixed = "all"
[[boundary]]
set = "upper_far.x1"
fixed = "all"
[[boundary]]
set = "upper_crack.x0"
displacement = {{ z = 0.5 }}
[[boundary]]
set = "lower_crack.x0"
displacement = {{ z = -0.5 }}

[analysis]
type = "static"
steps = [{DELTA_END!r}]

[analysis.newton]
initial_increment = {DT0!r}
min_increment = {DTMIN!r}
max_increment = {DTMAX!r}

[output]
curve = {{ reaction_set = "upper_crack.x0", reaction_component = "z", point_set = "upper_crack.x0", point_component = "z", relative_to = "lower_crack.x0" }}
every = 50
"""


if __name__ == "__main__":
    (HERE / "dcb_abaqus.inp").write_text(deck())
    (HERE / "dcb_h8.toml").write_text(scene())
    print("wrote", HERE / "dcb_abaqus.inp", "and", HERE / "dcb_h8.toml")
