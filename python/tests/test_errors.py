"""Bad inputs raise clean exceptions (one class per kind of error, the
message the CLI prints) and the interpreter survives them: every case runs
in this process, and a good scene runs after them all (the last test)."""

import numpy as np
import pytest

import junta
from conftest import CUBE, PULL, PyPenalty


def scene_with(tmp_path, old, new, source=CUBE):
    text = source.read_text()
    assert old in text
    p = tmp_path / source.name
    p.write_text(text.replace(old, new))
    return p


def test_missing_file():
    with pytest.raises(junta.FileNotFound, match="no_such_scene.toml") as e:
        junta.Simulation.from_file("no_such_scene.toml")
    assert isinstance(e.value, FileNotFoundError)
    assert isinstance(e.value, junta.JuntaError) and isinstance(e.value, OSError)


def test_bad_toml_key(tmp_path):
    p = scene_with(tmp_path, 'title = "Unit cube', 'titel = "Unit cube')
    with pytest.raises(junta.InputError, match="unknown field `titel`, expected (one of )?`title`") as e:
        junta.Simulation.from_file(p)
    assert isinstance(e.value, ValueError)
    assert str(p) in str(e.value)


def test_toml_syntax_error():
    with pytest.raises(junta.InputError, match="line 1"):
        junta.Simulation.from_text("[model\n")


def test_unknown_law_type(tmp_path, py_penalty):
    p = scene_with(tmp_path, 'type = "py_penalty"', 'type = "no_such_law"', source=PULL)
    with pytest.raises(junta.InputError, match="unknown law `no_such_law`") as e:
        junta.Simulation.from_file(p)
    # the valid keys, compiled and registered from Python
    assert "bilinear" in str(e.value) and "py_penalty" in str(e.value)


def test_bad_solver():
    with pytest.raises(junta.InputError, match="unknown solver `nope`"):
        junta.Simulation.from_file(CUBE, solver={"type": "nope"})


def register(name, cls):
    junta.register_law(name, cls)
    return {"laws.bond.type": name}


class LawRaises(PyPenalty):
    class Error(RuntimeError):
        pass

    def evaluate(self, jump, state, step):
        if step["load_factor"] > 0.6:
            raise LawRaises.Error("the law gave up")
        return super().evaluate(jump, state, step)


class FactoryRaises(PyPenalty):
    def __init__(self, params):
        raise ValueError(f"py_factory_raises: `d` = {params['d']} is not welcome")


def test_python_law_raising_propagates_its_exception():
    o = register("py_law_raises", LawRaises)
    with pytest.raises(LawRaises.Error, match="the law gave up") as e:
        junta.Simulation.from_file(PULL, overrides=o).run()
    cause = e.value.__cause__
    assert isinstance(cause, junta.JuntaError)
    assert "law `py_law_raises`" in str(cause) and "LawRaises.Error: the law gave up" in str(cause)


def test_python_law_factory_raising_propagates_its_exception():
    o = register("py_factory_raises", FactoryRaises)
    with pytest.raises(ValueError, match="is not welcome") as e:
        junta.Simulation.from_file(PULL, overrides=o)
    assert not isinstance(e.value, junta.JuntaError)  # the factory's own
    assert "py_factory_raises" in str(e.value.__cause__)


class ReturnsNaN(PyPenalty):
    def evaluate(self, jump, state, step):
        t, d, s = super().evaluate(jump, state, step)
        t = t.copy()
        t[2, 1] = np.nan
        return t, d, s


class TractionShape(PyPenalty):
    def evaluate(self, jump, state, step):
        t, d, s = super().evaluate(jump, state, step)
        return t[:, :2], d, s


class TangentShape(PyPenalty):
    def evaluate(self, jump, state, step):
        t, d, s = super().evaluate(jump, state, step)
        return t, d[:, :2, :], s


class NotATuple(PyPenalty):
    def evaluate(self, jump, state, step):
        return super().evaluate(jump, state, step)[0]


class StateShape(PyPenalty):
    state_len = 2

    def evaluate(self, jump, state, step):
        t, d, _ = super().evaluate(jump, state, step)
        return t, d, np.zeros((len(jump), 3))


@pytest.mark.parametrize(
    "name, cls, message",
    [
        ("py_nan", ReturnsNaN, r"law `py_nan`: evaluate returned a non-finite traction at point 2"),
        ("py_traction_shape", TractionShape, r"returned traction of shape \(4, 2\), expected \(4, 3\)"),
        ("py_tangent_shape", TangentShape, r"returned tangent of shape \(4, 2, 3\), expected \(4, 3, 3\)"),
        ("py_state_shape", StateShape, r"returned new_state of shape \(4, 3\), expected \(4, 2\)"),
        ("py_not_a_tuple", NotATuple, r"expected a tuple \(traction, tangent, new_state\)"),
    ],
)
def test_python_law_returning_garbage_is_a_law_error(name, cls, message):
    # the interface of pull.toml: one INTER8, 4 points in one batch
    o = register(name, cls)
    with pytest.raises(junta.LawError, match=message) as e:
        junta.Simulation.from_file(PULL, overrides=o).run()
    assert "pull.toml" in str(e.value)  # the run's context


class NoStateLen:
    initial_stiffness = (1.0, 1.0, 1.0)

    def __init__(self, params):
        pass

    def evaluate(self, jump, state, step):
        raise AssertionError("never called")


def test_python_law_object_without_state_len():
    o = register("py_no_state_len", NoStateLen)
    with pytest.raises(junta.InputError, match=r"law `py_no_state_len`.*no `state_len`"):
        junta.Simulation.from_file(PULL, overrides=o)


def test_python_law_names():
    with pytest.raises(junta.InputError, match="built-in law"):
        junta.register_law("bilinear", PyPenalty)
    with pytest.raises(junta.InputError, match="not a valid law name"):
        junta.register_law("Bad Name", PyPenalty)
    with pytest.raises(TypeError):
        junta.register_law("py_not_callable", 3)


def test_zz_a_good_scene_runs_after_all_the_errors(py_penalty):
    for name in ("py_law_raises", "py_factory_raises", "py_nan", "py_traction_shape", "py_tangent_shape",
                 "py_state_shape", "py_not_a_tuple", "py_no_state_len"):
        junta.unregister_law(name)
    r = junta.Simulation.from_file(PULL).run()
    assert r.status == "completed" and len(r.curve["reaction"]) == 4
    m = 2.1e11 * 0.7 / (1.3 * 0.4)
    assert abs(r.curve["reaction"][-1]) == pytest.approx(0.04 * 1.25e-5 / (0.01 / m + 1e-13), rel=1e-9)
    assert junta.Simulation.from_file(CUBE).run().summary["reactions"]["z1"][2] == pytest.approx(-2224.553, rel=1e-6)
