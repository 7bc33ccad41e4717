#!/usr/bin/env python3
"""Write the mixed-mode bending scenes and their beam-theory curves
(NAME_beam_theory.csv), and print the numbers: mmb20.toml, mmb50.toml,
mmb80.toml (G_II/G_T = 0.2, 0.5, 0.8 on the DCB specimen, a0 = 32.9 mm:
a load maximum, then stable propagation) and mmb50_short.toml,
mmb80_short.toml (a0 = 0.4 L: the two that snap back).

Specimen: the AS4/PEEK beam of dcb.toml used as an MMB (Reeder & Crews):
half span L = 51 mm, b = 25.4 mm, h = 1.56 mm per arm, precrack a0. By
simple beam theory the lever's
load-point displacement along the propagation branch,
delta_P(a) = P_c(a) C_P(a), C_P(a) = C_0 + (2 b / 3) g a with
G = P^2 g (g ~ a^2) and C_0 = (c + L)^2 L / (4 E11 b h^3) (the uncracked
beam), decreases while a < a* = (3 C_0 / (4 b g / a^2))^(1/3): a* = 20.7,
28.1 and 32.8 mm for G_II/G_T = 0.2, 0.5, 0.8: with a0 = 32.9 mm none
snaps back; with a0 = 0.4 L = 20.4 mm the 50 % and 80 % cases do.
The lever of length c (from the mid-span hinge to the load P) is replaced
by the two forces it applies: P c / L pulling the upper arm's end up, and
P (c + L) / L pushing the mid-span down (BENCHMARKS.md section 4:
P_I = P (3c - L)/(4L), P_II = P (c + L)/L). With these forces for P = 1 N
the load factor *is* P, and curve.csv's `conjugate_displacement` is the
lever's load-point displacement. Each force is a uniform line load across
the width: `split = "consistent"` gives the three nodes of the (one
element wide, H20) load edge 1/6, 2/3, 1/6 of it; the equal split (1/3
each) loads the specimen's sides harder, adds a local compliance at the
load points (about 4 % of the lever compliance) and, with the short
precrack, lowers the peak by 3-4 % (numbers in each scene's header).
Run: python3 make_mmb.py
"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
E11, E22, G13 = 122700.0, 10100.0, 5500.0
GIC, GIIC, ETA = 0.969, 1.719, 2.284
B, H, L = 25.4, 1.56, 51.0
A0 = 0.4 * L  # 20.4 mm: short enough for the 50 % and 80 % cases to snap back


def chi():
    gamma = 1.18 * math.sqrt(E11 * E22) / G13
    return math.sqrt(E11 / (11.0 * G13) * (3.0 - 2.0 * (gamma / (1.0 + gamma)) ** 2))


def lever(ratio):
    """Lever length c giving G_II/G_T = ratio by simple beam theory."""
    q = math.sqrt(4.0 * ratio / (3.0 * (1.0 - ratio)))
    return L * (1.0 + q) / (3.0 * q - 1.0)


def critical_load(c, a, corrected=True):
    """P from G_I + G_II = G_c(B) (BK); corrected beam theory uses
    a + chi h for mode I and a + 0.42 chi h for mode II (Reeder)."""
    a1 = a + (chi() * H if corrected else 0.0)
    a2 = a + (0.42 * chi() * H if corrected else 0.0)
    g1 = 3.0 * (3.0 * c - L) ** 2 * a1 ** 2 / (4.0 * B ** 2 * H ** 3 * L ** 2 * E11)
    g2 = 9.0 * (c + L) ** 2 * a2 ** 2 / (16.0 * B ** 2 * H ** 3 * L ** 2 * E11)
    mix = g2 / (g1 + g2)
    gc = GIC + (GIIC - GIC) * mix ** ETA
    return math.sqrt(gc / (g1 + g2)), mix


MATERIAL = """[materials.as4peek]
type = "orthotropic"
E1 = 122700.0
E2 = 10100.0
E3 = 10100.0
nu12 = 0.25
nu13 = 0.25
nu23 = 0.45
G12 = 5500.0
G13 = 5500.0
G23 = 3700.0

[laws.cz]
type = "bilinear"
K = 1.0e6
N = 80.0
S = 100.0
G_Ic = 0.969
G_IIc = 1.719
eta = 2.284

[laws.touch]
type = "contact"
K = 1.0e6
"""


JUNTA = {
    "mmb20": """peak 92.1 N at 9.27 mm (-0.17 % against corrected beam
# theory), then the load follows corrected beam theory within +1.2 to
# +2.3 % at the crack length read from the damaged area (a = 35 to
# 49 mm); 42 increments to a = L, about 20 s. (With `split = "equal"`:
# 92.0 N at 9.62 mm.)""",
    "mmb50": """peak 258.7 N at 5.16 mm (-1.9 % against corrected beam
# theory), then within 0.0 to +1.1 % along the branch (a = 35 to 49 mm);
# 33 increments to a = L, about 15 s. (With `split = "equal"`: 259.1 N
# at 5.37 mm.)""",
    "mmb80": """peak 436.9 N at 4.88 mm (-4.5 % against corrected beam
# theory), then within -1.4 to -0.8 % along the branch (a = 35 to 49 mm);
# 32 increments to a = L, about 15 s. (With `split = "equal"`: 436.3 N
# at 5.05 mm.)""",
    "mmb50_short": """peak 398.3 N at 5.10 mm (-2.8 % against corrected beam theory),
# the lever's load point moves back to 4.92 mm, then the load follows
# corrected beam theory within +0.3 to +1.3 % at the crack length read
# from the damaged area (a = 22.0 to 49.2 mm); 46 increments to a = L,
# ~27 s (crates/cli/tests/path_following.rs checks the first 32). With
# `split = "equal"` (a third of each lever force on each of the three
# nodes of the load edges, where a uniform line load puts 1/6, 2/3, 1/6):
# peak 388.3 N at 5.36 mm (-5.3 %), back to 5.17 mm.""",
    "mmb80_short": """peak 673.0 N at 5.48 mm (-6.1 % against corrected beam
# theory), the lever's load point moves back to 4.89 mm (a = 32.8 mm),
# then the load follows corrected beam theory within -1.2 to -0.2 % at the
# crack length read from the damaged area (a = 23.4 to 49.4 mm); the crack
# reaches the mid-span at increment 40 and the run ends at increment 66,
# 444 Newton iterations, about 19 s (with `split = "equal"`: peak
# 649.6 N at 5.61 mm, -9.3 %, back to 5.08 mm). It uses `tangent = "exact"`: the
# mixed-mode tangent is not symmetric when the mode ratio changes with
# the jump, and on its symmetric part (the default without this line)
# Newton stalls past the peak; the driver then measures the exact
# tangent's skew (1.2e-2) and switches to it by itself at increment 21,
# on the same path (82 increments, crates/cli/tests/tangent_switch.rs;
# before that switch existed the run crawled to a = 30.5 mm in 150
# increments). The exact tangent is solved by `lu` (row interchanges
# within panels: 1.7M stored entries, 26 ms per factorisation here);
# `curve.csv` then has no negative-pivot count (an LU gives no inertia).
# crates/cli/tests/path_following.rs checks the first 40 increments.""",
}


def scene(ratio, a0, name, max_increments, exact_tangent=False):
    c = lever(ratio)
    p_s, _ = critical_load(c, a0, corrected=False)
    p_c, mix = critical_load(c, a0)
    p_45, _ = critical_load(c, 45.0)
        # LEFM reference (simple beam theory): linear branch, then propagation
    g1 = 3.0 * (3.0 * c - L) ** 2 / (4.0 * B ** 2 * H ** 3 * L ** 2 * E11)
    g2 = 9.0 * (c + L) ** 2 / (16.0 * B ** 2 * H ** 3 * L ** 2 * E11)
    gk = g1 + g2
    gc = GIC + (GIIC - GIC) * (g2 / gk) ** ETA
    c0 = (c + L) ** 2 * L / (4.0 * E11 * B * H ** 3)
    comp = lambda a: c0 + 2.0 * B / 3.0 * gk * a ** 3
    pc = lambda a: math.sqrt(gc / (gk * a * a))
    pts = [(pc(a0) * comp(a0) * i / 20.0, pc(a0) * i / 20.0) for i in range(21)]
    pts += [(pc(a) * comp(a), pc(a)) for a in (a0 + (L - a0) * i / 200.0 for i in range(1, 201))]
    astar = (3.0 * c0 / (4.0 * B * gk)) ** (1.0 / 3.0)
    dmin = min(x for x, _ in pts[21:])
    with open(os.path.join(HERE, f"{name}_beam_theory.csv"), "w") as f:
        f.write(f"# MMB G_II/G_T = {ratio}, a0 = {a0:.1f}: simple beam theory, lever load-point displacement (mm), load P (N); written by make_mmb.py\n")
        for x, y in pts:
            f.write(f"{x:.6e},{y:.6e}\n")
    material = MATERIAL
    if exact_tangent:
        material = material.replace(
            "eta = 2.284",
            'eta = 2.284\ntangent = "exact"   # nonsymmetric consistent tangent (lu): see the header',
        )
    text = f"""# Mixed-mode bending, G_II/G_T = {ratio} (written by make_mmb.py; see its
# docstring for the specimen and the lever forces). Units: N, mm, MPa.
# AS4/PEEK (BENCHMARKS.md section 4), lever c = {c:.3f} mm, a0 = {a0:.1f} mm.
#
# The load factor is the lever load P (N). curve.csv (`conjugate = true`):
# `reaction` = P, `displacement` = the lever's load-point displacement
# (f_ext . u), `damaged_area` / b = crack growth. Under load control the
# run stops at the peak (a load maximum); path following
# (`control = "arc_length"`) traces the propagation that follows (in a
# snap-back the load point moves back too). It stops after
# `max_increments`.
#
# Reference (beam theory, Reeder & Crews, BK): simple {p_s:.1f} N,
# corrected {p_c:.1f} N at a0 (mode ratio {mix:.3f} with the corrections);
# along the propagation branch P_c(a) = {p_45:.1f} N at a = 45 mm. Simple
# beam theory's lever displacement: {pc(a0) * comp(a0):.3f} mm at the peak,
# {"snapping back to " + format(dmin, ".3f") + " mm (while a < " + format(astar, ".1f") + " mm)" if dmin < pc(a0) * comp(a0) - 1e-9 else "no snap-back"};
# {name}_beam_theory.csv is drawn in curve.svg.
# Junta: {JUNTA[name]}
#
# Smallest model that shows it: H20, one element through each arm and
# across the width, 0.5 mm along the bond, INTER16; the precrack faces
# touch without friction (`contact`).
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

[model]
title = "MMB G_II/G_T = {ratio}, a0 = {a0:.1f} mm, AS4/PEEK"
units = "N, mm, MPa"

{material}
[mesh]
type = "boxes"
"""
    for arm, z in (("lower", 0.0), ("upper", H)):
        for part, x0, lx, div in (("crack", 0.0, a0, round(a0 / 2.3)), ("bond1", a0, L - a0, round((L - a0) / 0.5)), ("bond2", L, L, 102)):
            text += f"""[[mesh.boxes]]
name = "{arm}_{part}"
group = "{arm}"
origin = [{x0:.6g}, 0.0, {z}]
size = [{lx:.6g}, 25.4, 1.56]
divisions = [{div}, 1, 1]
element = "h20"
material = "as4peek"
"""
    text += f"""
[[interface]]
name = "bond"
between = ["lower", "upper"]
law = "cz"
precrack = {{ within = [[0.0, -1.0, -1.0], [{a0:.6g}, 26.4, 4.0]], law = "touch" }}

[[node_set]]
name = "left_support"
within = [[0.0, 0.0, 0.0], [0.0, 25.4, 0.0]]
[[node_set]]
name = "right_support"
within = [[102.0, 0.0, 0.0], [102.0, 25.4, 0.0]]
[[node_set]]
name = "lever_end"
within = [[0.0, 0.0, 3.12], [0.0, 25.4, 3.12]]
[[node_set]]
name = "load_line"
within = [[51.0, 0.0, 3.12], [51.0, 25.4, 3.12]]

[[boundary]]
set = "left_support"
fixed = ["x", "y", "z"]
[[boundary]]
set = "right_support"
fixed = ["z"]

[[load]]
set = "lever_end"
total_force = [0.0, 0.0, {c / L:.9f}]
split = "consistent"   # the edge shares 1/6, 2/3, 1/6 of a uniform line load
[[load]]
set = "load_line"
total_force = [0.0, 0.0, {-(c + L) / L:.9f}]
split = "consistent"   # the edge shares 1/6, 2/3, 1/6 of a uniform line load

[analysis]
type = "static"
steps = [{1.5 * p_s:.0f}.0]
control = "arc_length"

[analysis.newton]
initial_increment = 0.1
tol_force = 1e-3   # Abaqus's default is 5e-3; at 1e-4 Newton crawls where many points switch between loading and unloading

[analysis.arc_length]
target_iterations = 8
max_increments = {max_increments}

[output]
curve = {{ reaction_set = "load_line", reaction_component = "z", point_set = "load_line", point_component = "z", conjugate = true, reference = {{ file = "{name}_beam_theory.csv", label = "beam theory (LEFM)" }} }}
every = 25
"""
    with open(os.path.join(HERE, f"{name}.toml"), "w") as f:
        f.write(text)
    print(f"{name}.toml: c = {c:.3f} mm, peak simple {p_s:.1f} N, corrected {p_c:.1f} N; lever displacement at the peak {pc(a0) * comp(a0):.3f} mm, minimum after it {dmin:.3f} mm (a* = {astar:.1f} mm)")


if __name__ == "__main__":
    # the DCB specimen's precrack: stable propagation after the peak
    for r, n in ((0.2, 42), (0.5, 33), (0.8, 32)):
        scene(r, 32.9, f"mmb{round(100 * r)}", n)
    # a short precrack: the 50 % and 80 % cases snap back
    scene(0.5, A0, "mmb50_short", 46)
    scene(0.8, A0, "mmb80_short", 150, exact_tangent=True)
