"""Plane models from Python (issue 39): an axisymmetric Lamé cylinder
written as a scene text, its fields and mesh; the 2D DCB with a callback
and frames."""

import numpy as np
import pytest

import junta
from conftest import EXAMPLES

# Lamé's thick cylinder (Timoshenko & Goodier, Theory of Elasticity, 3rd
# ed., sec. 28): bore a = 1, outside b = 2, pressure p = 100, the ends held
# axially; sigma_r = A - B / r^2, sigma_t = A + B / r^2 with
# A = p a^2 / (b^2 - a^2), B = p a^2 b^2 / (b^2 - a^2).
A_IN, B_OUT, P = 1.0, 2.0, 100.0
LAME = f"""
[materials.steel]
type = "isotropic"
E = 200000.0
nu = 0.3

[mesh]
type = "box"
size = [{B_OUT - A_IN}, 0.25]
origin = [{A_IN}, 0.0]
divisions = [32, 1]
element = "cax8"
material = "steel"

[[boundary]]
set = "y0"
fixed = ["y"]
[[boundary]]
set = "y1"
fixed = ["y"]

[[load]]
face_set = "x0"
pressure = {P}
"""


def test_axisymmetric_lame_cylinder_from_text():
    sim = junta.Simulation.from_text(LAME, "lame.toml")
    r = sim.run()
    assert r.status == "completed"
    assert r.summary["plane"]["width"] == "full_ring"
    f = r.frame
    # two equations per node: x the radius, y the axis; z is 0 everywhere
    assert f.displacement.shape[1] == 3 and np.all(f.displacement[:, 2] == 0.0)
    x = f.solid_position
    rad = x[:, 0]
    aa = P * A_IN**2 / (B_OUT**2 - A_IN**2)
    bb = aa * B_OUT**2
    s = f.solid_stress  # xx (radial), yy (axial), zz (hoop), xy, yz, xz
    assert np.max(np.abs(s[:, 0] - (aa - bb / rad**2))) < 1e-3 * P
    assert np.max(np.abs(s[:, 2] - (aa + bb / rad**2))) < 1e-3 * P
    cells = {c["meshio_type"] for c in r.mesh.cells}
    assert cells == {"quad8"}


def test_plane_dcb_callback_and_frames():
    seen = []
    sim = junta.Simulation.from_file(EXAMPLES / "plane" / "dcb_plane_strain.toml")
    r = sim.run(callback=lambda inc: seen.append(inc["reaction"]), max_increments=6, frames_every=3)
    assert r.status == "stopped"
    assert len(seen) == 6 and list(r.curve["reaction"]) == seen
    # the elastic branch: the load grows with the opening (load control)
    assert all(b > a for a, b in zip(seen, seen[1:]))
    assert [fr.increment for fr in r.frames] == [3, 6]
    last = r.frames[-1]
    # three points along each LINE_INTER6 of the bond
    assert last.interface_traction.shape[1] == 3
    assert np.all(last.interface_traction[:, 1] == 0.0)
    assert r.summary["plane"]["section"] == "plane_strain"
    assert r.summary["plane"]["thickness"] == pytest.approx(25.4)
