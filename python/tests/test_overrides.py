"""``overrides`` change the result as the edited scene would; an unknown
key is an ``InputError`` naming it; ``solver`` options reach the solver."""

import shutil

import numpy as np
import pytest

import junta
from conftest import CUBE, DCB_COARSE

N = 30  # increments: past the peak of the coarse DCB's curve (~increment 15)


def curve_without_seconds(r):
    return {k: v for k, v in r.curve.items() if k != "seconds"}


def assert_same_curve(a, b):
    assert a.keys() == b.keys()
    for k in a:
        if k == "control":
            assert a[k] == b[k]
        else:
            assert np.array_equal(a[k], b[k], equal_nan=True), k


def test_override_is_the_edited_scene(tmp_path):
    # the edited copy sits next to a copy of its reference curve file
    shutil.copy(DCB_COARSE.parent / "dcb_beam_theory.csv", tmp_path)
    text = DCB_COARSE.read_text()
    assert "G_Ic = 0.969\n" in text
    edited = tmp_path / "dcb_coarse.toml"
    edited.write_text(text.replace("G_Ic = 0.969\n", "G_Ic = 0.5\n"))

    overridden = junta.Simulation.from_file(DCB_COARSE, overrides={"laws.cz.G_Ic": 0.5})
    by_override = overridden.run(max_increments=N)
    by_edit = junta.Simulation.from_file(edited).run(max_increments=N)
    original = junta.Simulation.from_file(DCB_COARSE).run(max_increments=N)
    assert len(by_override.curve["increment"]) == N
    assert_same_curve(curve_without_seconds(by_override), curve_without_seconds(by_edit))
    # and it is a change: a lower toughness, a lower peak load
    assert np.max(by_override.curve["reaction"]) < 0.9 * np.max(original.curve["reaction"])


def test_override_values_of_every_type():
    sim = junta.Simulation.from_file(
        DCB_COARSE,
        overrides={"model.title": "overridden", "analysis.newton.initial_increment": 0.05, "output.every": 7},
    )
    assert sim.check()["title"] == "overridden"


def test_unknown_override_key_names_it():
    with pytest.raises(junta.InputError, match=r"override `laws\.nope\.G_Ic`: the scene has no `laws\.nope`"):
        junta.Simulation.from_file(DCB_COARSE, overrides={"laws.nope.G_Ic": 0.5})
    with pytest.raises(junta.InputError, match="unknown field `G_Icc`"):
        junta.Simulation.from_file(DCB_COARSE, overrides={"laws.cz.G_Icc": 0.5})
    with pytest.raises(TypeError, match="cannot be a scene value"):
        junta.Simulation.from_file(DCB_COARSE, overrides={"laws.cz.G_Ic": object()})


def test_solver_options():
    assert junta.Simulation.from_file(CUBE).check()["solver"] == "cholesky"
    assert junta.Simulation.from_file(CUBE, solver={"type": "cg"}).check()["solver"] == "cg"
    assert junta.Simulation.from_file(CUBE, solver="lu").check()["solver"] == "lu"
    r = junta.Simulation.from_file(CUBE, solver=["type=cg"]).run()
    assert r.summary["reactions"]["z1"][2] == pytest.approx(-2224.553, rel=1e-6)
