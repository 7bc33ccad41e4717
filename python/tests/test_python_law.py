"""A traction law written in Python: the compiled ``bilinear`` law written
again in numpy (``examples/python/bilinear_law.py``, registered as
``py_bilinear``) gives the compiled law's values point by point and its
curve on the coarse DCB; ``check_tangent`` passes on it in every regime and
catches a wrong tangent."""

import numpy as np
import pytest

import bilinear_law
import junta
from conftest import DCB_COARSE, EXAMPLES, rel_diff
from junta import _junta

# the DCB's law (examples/delamination/dcb_coarse.toml [laws.cz], AS4/PEEK)
PARAMS = {"K": 1.0e6, "N": 80.0, "S": 100.0, "G_Ic": 0.969, "G_IIc": 1.719, "eta": 2.284}
STEP = {"increment": 3, "load_factor": 1.0, "delta_load_factor": 0.1, "secant": False}


def random_points(n, seed):
    """Jumps from far below onset (~1e-4 mm) to past full separation
    (~2e-2 mm) in every direction, with committed states from undamaged
    to fully damaged."""
    rng = np.random.default_rng(seed)
    jump = rng.normal(size=(n, 3)) * 10 ** rng.uniform(-6, -1.5, size=(n, 1))
    state = np.zeros((n, bilinear_law.STATE_LEN))
    d = rng.uniform(0, 1, n) * (rng.uniform(size=n) < 0.6)
    d[rng.uniform(size=n) < 0.1] = 1.0
    state[:, bilinear_law.DAMAGE_HISTORY] = d
    state[:, bilinear_law.DAMAGE] = d * rng.uniform(0.5, 1.0, n)  # viscous lag
    state[:, bilinear_law.ENERGY] = rng.uniform(0, 0.5, n)
    state[:, bilinear_law.MODE_RATIO] = rng.uniform(0, 1, n)
    return jump, state


@pytest.mark.parametrize("viscosity", [0.0, 1e-3])
@pytest.mark.parametrize("secant", [False, True])
def test_python_bilinear_gives_the_compiled_values(viscosity, secant):
    params = dict(PARAMS, viscosity=viscosity)
    law = bilinear_law.PyBilinear(params)
    jump, state = random_points(3000, seed=7)
    step = dict(STEP, secant=secant)
    t1, d1, s1 = _junta.evaluate_registered(
        "bilinear", params, [tuple(j) for j in jump], state.ravel().tolist(), step
    )
    t2, d2, s2 = law.evaluate(jump, state, step)
    # the same operations in the same order (and the C library's pow):
    # equal to round-off; here, to the bit
    for a, b in [(t1, t2), (d1, d2), (s1, s2)]:
        assert np.max(np.abs(a - b)) <= 1e-13 * np.max(np.abs(a))
    # every regime was visited: undamaged, softening, fully damaged, contact
    assert np.any(s1[:, 0] == 0) and np.any((s1[:, 0] > 0) & (s1[:, 0] < 1)) and np.any(s1[:, 0] == 1)
    assert np.any(jump[:, 2] < 0) and np.any(s1[:, 0] > state[:, 0])


def test_python_bilinear_traces_the_compiled_dcb_curve(py_bilinear):
    compiled = junta.Simulation.from_file(DCB_COARSE).run(frames_every=40)
    python = junta.Simulation.from_file(DCB_COARSE, overrides={"laws.cz.type": py_bilinear}).run(frames_every=40)
    assert compiled.status == python.status == "completed", python.status_line
    a, b = compiled.curve, python.curve
    assert len(a["increment"]) == len(b["increment"]) > 50
    # the same operations in the same order as the compiled law: the curve
    # and the law's outputs to the last bit (measured: all equal)
    for name in ("reaction", "displacement", "load_factor", "dissipated_energy"):
        assert np.array_equal(b[name], a[name]), (name, rel_diff(b[name], a[name]))
    # the same path: the same iterations, failed points (the law's `damage`
    # output) and controls
    for name in ("newton_iterations", "failed_points", "damaged_area"):
        assert np.array_equal(a[name], b[name]), name
    assert a["control"] == b["control"]
    assert np.max(a["failed_points"]) > 0  # the crack grew
    # the law's outputs reach the frames
    fa, fb = compiled.frames[-1], python.frames[-1]
    assert fa.increment == fb.increment
    assert set(fa.interface_outputs) == set(fb.interface_outputs)
    for name in ("damage", "dissipated_energy", "mode_ratio", "failure_index", "failed", "stage"):
        assert np.array_equal(fa.interface_outputs[name], fb.interface_outputs[name]), name
    assert np.array_equal(fa.interface_traction, fb.interface_traction)


def law():
    return bilinear_law.PyBilinear(PARAMS)


# onset in mode I at N / K = 8e-5 mm, full separation at 2 G_Ic / N = 2.4e-2 mm
REGIMES = {
    "elastic": (np.array([[1e-5, -2e-5, 3e-5], [0.0, 0.0, 5e-5], [4e-5, 0.0, 0.0], [3e-5, 3e-5, -2e-5]]), None),
    "softening": (np.array([[0.0, 0.0, 1e-3], [5e-4, 2e-4, 1e-3], [1e-3, 0.0, 5e-4], [2e-3, 0.0, -1e-5]]), None),
    "fully damaged": (np.array([[0.0, 0.0, 5e-2], [3e-2, 1e-2, 4e-2], [6e-2, 0.0, 1e-3]]), None),
    "closed": (np.array([[0.0, 0.0, -1e-4], [3e-5, 0.0, -1e-4], [1e-5, 2e-5, -3e-3]]), None),
}


def states_after(jumps):
    """The state after loading to `jumps` (committed for the next check)."""
    _, _, s = law().evaluate(jumps, np.zeros((len(jumps), 6)), STEP)
    return s


@pytest.mark.parametrize("regime", sorted(REGIMES))
def test_check_tangent_passes_in_every_regime(regime):
    jumps, state = REGIMES[regime]
    r = junta.check_tangent(law(), jumps, state=state, step=STEP)
    assert r["ok"], r
    assert r["max_rel_error"] < 1e-5
    assert r["tangent"].shape == r["fd_tangent"].shape == (len(jumps), 3, 3)


def test_check_tangent_passes_on_damaged_points():
    base = np.array([[0.0, 0.0, 2e-3], [1e-3, 5e-4, 1e-3], [1e-4, 0.0, 3e-3]])
    committed = states_after(base)
    assert np.all((committed[:, 0] > 0) & (committed[:, 0] < 1))
    # reloading past the damage surface (softening), unloading inside it,
    # and closing a damaged point (contact keeps the penalty)
    for jumps in (1.2 * base, 0.5 * base, base * [1.0, 1.0, -1.0]):
        r = junta.check_tangent(law(), jumps, state=committed, step=STEP, raise_on_error=True)
        assert r["ok"]
    # the unloading tangent is the damaged secant: (1 - d) K on the opening
    r = junta.check_tangent(law(), 0.5 * base[:1], state=committed[:1], step=STEP)
    assert r["tangent"][0, 2, 2] == pytest.approx((1 - committed[0, 0]) * PARAMS["K"], rel=1e-12)


class Transposed(bilinear_law.PyBilinear):
    """The law with the transpose of its (nonsymmetric) tangent."""

    def evaluate(self, jump, state, step):
        t, d, s = super().evaluate(jump, state, step)
        return t, np.transpose(d, (0, 2, 1)), s


class OneEntryOff(bilinear_law.PyBilinear):
    """The law with d t_1 / d delta_n scaled by 0.9."""

    def evaluate(self, jump, state, step):
        t, d, s = super().evaluate(jump, state, step)
        d = d.copy()
        d[:, 0, 2] *= 0.9
        return t, d, s


def test_check_tangent_catches_a_transposed_tangent():
    # mixed-mode softening: the exact tangent is not symmetric (the mode
    # ratio changes with the jump)
    jumps = np.array([[0.0, 0.0, 5e-5], [5e-4, 2e-4, 1e-3]])
    _, d, _ = law().evaluate(jumps, np.zeros((2, 6)), STEP)
    assert np.abs(d[1] - d[1].T).max() > 0.1 * np.abs(d[1]).max()
    r = junta.check_tangent(Transposed(PARAMS), jumps, step=STEP)
    assert not r["ok"] and r["worst_point"] == 1 and r["errors"][0] < 1e-5
    with pytest.raises(junta.TangentError, match=r"point 1 .*\[0, 2\]"):
        junta.check_tangent(Transposed(PARAMS), jumps, step=STEP, raise_on_error=True)


def test_check_tangent_catches_one_entry_off_by_ten_percent():
    jumps = np.array([[1e-3, 0.0, 5e-4]])
    r = junta.check_tangent(OneEntryOff(PARAMS), jumps, step=STEP)
    assert not r["ok"]
    assert 0.01 < r["max_rel_error"] < 0.2
    with pytest.raises(junta.TangentError, match=r"\[0, 2\]: tangent"):
        junta.check_tangent(OneEntryOff(PARAMS), jumps, step=STEP, raise_on_error=True)


def test_evaluate_law_checks_like_a_run():
    t, d, s = junta.evaluate_law(law(), [[0.0, 0.0, 1e-3]], step=STEP)
    assert t.shape == (1, 3) and d.shape == (1, 3, 3) and s.shape == (1, 6)
    assert 0 < s[0, 0] < 1


class StepRecorder(junta.Law):
    """A linear penalty (``t = K jump``) that records the step dict of
    every call: a Python law sees every step field a compiled law sees."""

    state_len = 0
    tangent_kind = "spd"
    seen = []

    def __init__(self, params):
        self.k = float(params["K"])
        self.initial_stiffness = (self.k, self.k, self.k)

    def evaluate(self, jump, state, step):
        StepRecorder.seen.append(dict(step))
        n = len(jump)
        return jump * self.k, np.broadcast_to(np.eye(3) * self.k, (n, 3, 3)), state


@pytest.fixture()
def step_recorder():
    StepRecorder.seen = []
    junta.register_law("py_step_recorder", StepRecorder)
    yield "py_step_recorder"
    junta.unregister_law("py_step_recorder")


def test_a_python_law_sees_every_step_field(step_recorder):
    r = junta.Simulation.from_file(
        EXAMPLES / "fatigue" / "held_opening.toml", overrides={"laws.paris.type": step_recorder}
    ).run()
    assert r.status == junta.Status.COMPLETED, r.status_line
    seen = StepRecorder.seen
    assert set(seen[0]) == {
        "increment", "load_factor", "delta_load_factor", "secant", "exact_tangent",
        "temperature_factor", "cycles", "delta_cycles", "load_ratio", "crack_drive",
    }
    # the scene's [fatigue]: 2e7 cycles at R = 0.1 after the static step
    fatigue = [s for s in seen if s["delta_cycles"] > 0]
    assert fatigue, "no call of the fatigue step"
    assert all(s["load_ratio"] == 0.1 for s in fatigue)
    assert max(s["cycles"] for s in seen) == 2.0e7
    # cycles grow through the fatigue step
    cycles = [s["cycles"] for s in fatigue]
    assert cycles == sorted(cycles) and cycles[0] < cycles[-1]


def test_a_python_law_sees_the_temperature_factor(step_recorder):
    # examples/thermal/cool_down.toml: a cool-down step (load factor 0,
    # increments of 0.25: [analysis.newton]) before the opening, which
    # holds the whole temperature change (factor 1)
    r = junta.Simulation.from_file(
        EXAMPLES / "thermal" / "cool_down.toml", overrides={"laws.cz.type": step_recorder}
    ).run()
    assert r.status == junta.Status.COMPLETED, r.status_line
    seen = StepRecorder.seen
    thermal = sorted({s["temperature_factor"] for s in seen if s["load_factor"] == 0.0})
    assert thermal == [0.25, 0.5, 0.75, 1.0]
    assert all(s["temperature_factor"] == 1.0 for s in seen if s["load_factor"] > 0.0)
    assert all(s["cycles"] == 0.0 for s in seen)


def test_evaluate_law_hands_the_step_fields_over():
    rec = StepRecorder({"K": 1.0})
    StepRecorder.seen = []
    junta.evaluate_law(rec, [[0.0, 0.0, 1e-3]], step={"cycles": 1e5, "temperature_factor": 0.5})
    s = StepRecorder.seen[-1]
    assert (s["cycles"], s["temperature_factor"], s["increment"]) == (1e5, 0.5, 1)
    with pytest.raises(KeyError, match="unknown key `cycle`"):
        _junta.evaluate_law(rec, [(0.0, 0.0, 1e-3)], [], {"cycle": 1.0})


class CountingBilinear(bilinear_law.PyBilinear):
    """``py_bilinear`` that counts the calls of each method and the points
    each call saw."""

    calls = {}

    def _count(self, name, n):
        CountingBilinear.calls.setdefault(name, []).append(n)

    def evaluate(self, jump, state, step):
        self._count("evaluate", len(jump))
        return super().evaluate(jump, state, step)

    def outputs(self, state):
        self._count("outputs", len(state))
        return super().outputs(state)

    def failure_index(self, state):
        self._count("failure_index", len(state))
        return super().failure_index(state)

    def init_state(self, n):
        self._count("init_state", n)
        return np.zeros((n, bilinear_law.STATE_LEN))


@pytest.fixture
def counting_bilinear():
    CountingBilinear.calls = {}
    junta.register_law("py_counting_bilinear", CountingBilinear)
    yield "py_counting_bilinear"
    junta.unregister_law("py_counting_bilinear")


def test_a_python_law_is_called_once_per_block_in_the_output_pass(counting_bilinear):
    """The output pass after each increment asks the law once for the whole
    interface block (its outputs, failure indices and responses), not once
    per element and point; the results equal the per-point law's (the
    compiled curve, test above)."""
    increments = 8
    r = junta.Simulation.from_file(DCB_COARSE, overrides={"laws.cz.type": counting_bilinear}).run(
        max_increments=increments
    )
    assert len(r.curve["increment"]) == increments, r.status_line
    calls = CountingBilinear.calls
    # two passes per increment (its curve row; the dissipated energy the
    # driver checks) and one for the end state, against one call per point
    # (315 points) before; the check before the run may ask a single point
    for name in ("outputs", "failure_index"):
        assert len(calls[name]) <= 2 * increments + 4, (name, len(calls[name]))
    # evaluate: every call (assembly, residual checks, output passes) holds
    # every point of the block, none one element's
    points = int(r.curve["interface_points"][0])
    assert set(calls["evaluate"]) == {points}, sorted(set(calls["evaluate"]))
    # initial states: one call per element, never one per point
    assert min(calls["init_state"]) > 1
