"""The package's type stubs (``junta/__init__.pyi``, ``junta/_junta.pyi``,
``py.typed``): ``mypy --strict`` accepts a short script that uses them and
catches a type error in another."""

import subprocess
import sys

import pytest

pytest.importorskip("mypy")

GOOD = '''
from typing import Any, Optional, Union

import numpy as np
from numpy.typing import NDArray

import junta


class Penalty(junta.Law):
    state_len = 0
    tangent_kind = "spd"

    def __init__(self, params: dict[str, Any]) -> None:
        self.k = float(params["K"])
        self.initial_stiffness = (self.k, self.k, self.k)

    def evaluate(
        self, jump: NDArray[np.float64], state: NDArray[np.float64], step: dict[str, Any]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        cycles: float = step["cycles"]
        n = len(jump)
        return jump * self.k, np.broadcast_to(np.eye(3) * self.k, (n, 3, 3)), state


def stop_at_two(inc: dict[str, Any]) -> Optional[junta.Stop]:
    return junta.Stop("two") if inc["increment"] == 2 else None


junta.register_law("typed_penalty", Penalty)
sim = junta.Simulation.from_file("scene.toml", overrides={"laws.cz.G_Ic": 0.5})
r: junta.Results = sim.run(callback=stop_at_two, max_increments=3)
ok: bool = r.status is junta.Status.STOPPED
line: str = r.status_line
reaction: NDArray[np.float64] = r.curve["reaction"]
keys = [p["key"] for sec in junta.catalog() for p in sec["plugins"]]
t, d, s = junta.evaluate_law(Penalty({"K": 1.0}), [[0.0, 0.0, 1e-3]], step={"cycles": 1.0})
flow: Union[None, junta.Flow, junta.Stop] = junta.Flow.STOP
'''

BAD = '''
import junta

r = junta.Simulation.from_file("scene.toml").run()
n: int = r.status_line
'''


def mypy(tmp_path, text):
    script = tmp_path / "script.py"
    script.write_text(text)
    return subprocess.run(
        [sys.executable, "-m", "mypy", "--strict", "--no-incremental", str(script)],
        capture_output=True,
        text=True,
        cwd=tmp_path,
    )


def test_mypy_strict_accepts_a_script_using_the_stubs(tmp_path):
    r = mypy(tmp_path, GOOD)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "Success" in r.stdout


def test_mypy_strict_catches_a_type_error(tmp_path):
    r = mypy(tmp_path, BAD)
    assert r.returncode == 1, r.stdout + r.stderr
    assert 'incompatible types in assignment (expression has type "str", variable has type "int")' in r.stdout.lower()
