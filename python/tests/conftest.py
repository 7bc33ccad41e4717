"""Shared paths and helpers of the Python tests.

The scenes are the repository's examples and the small scenes of
``tests/data``; ``examples/python`` (the Python ``bilinear`` law) is put on
``sys.path``. The command line binary is ``$JUNTA_BIN``, else
``$CARGO_TARGET_DIR/debug/junta``, ``target/debug/junta`` or
``target/release/junta`` of the repository, else ``cargo run -p junta-cli``.
"""

import csv
import math
import os
import pathlib
import shutil
import sys

import numpy as np
import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
DATA = pathlib.Path(__file__).resolve().parent / "data"
EXAMPLES = REPO / "examples"
DCB = EXAMPLES / "delamination" / "dcb.toml"
DCB_COARSE = EXAMPLES / "delamination" / "dcb_coarse.toml"
CUBE = EXAMPLES / "cube.toml"
PULL = DATA / "pull.toml"

sys.path.insert(0, str(EXAMPLES / "python"))


def junta_command():
    """The command that runs the CLI, as a list."""
    env = os.environ.get("JUNTA_BIN")
    if env:
        return [env]
    dirs = []
    if os.environ.get("CARGO_TARGET_DIR"):
        dirs.append(pathlib.Path(os.environ["CARGO_TARGET_DIR"]))
    dirs.append(REPO / "target")
    for d in dirs:
        for profile in ("debug", "release"):
            p = d / profile / "junta"
            if p.exists():
                return [str(p)]
    if shutil.which("junta"):
        return [shutil.which("junta")]
    return ["cargo", "run", "-q", "-p", "junta-cli", "--manifest-path", str(REPO / "Cargo.toml"), "--"]


def read_curve_csv(path):
    """curve.csv as {column: float64 array}, ``control`` a list of str
    (an empty cell is NaN, as in ``Results.curve``)."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, rows = rows[0], rows[1:]
    out = {}
    for k, name in enumerate(header):
        col = [r[k] for r in rows]
        if name == "control":
            out[name] = col
        else:
            out[name] = np.array([float(x) if x.strip() else math.nan for x in col])
    return out


def rel_diff(a, b):
    """``max |a - b| / max |b|``."""
    a, b = np.asarray(a), np.asarray(b)
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


class PyPenalty:
    """A linear penalty law in Python: ``t = d * jump``, ``D = d I``."""

    state_len = 0
    tangent_kind = "spd"

    def __init__(self, params):
        self.d = float(params["d"])
        self.initial_stiffness = (self.d, self.d, self.d)

    def evaluate(self, jump, state, step):
        n = len(jump)
        return jump * self.d, np.broadcast_to(np.eye(3) * self.d, (n, 3, 3)), state


@pytest.fixture(scope="session")
def py_penalty():
    import junta

    junta.register_law("py_penalty", PyPenalty, description="linear penalty in Python (tests)")
    yield "py_penalty"
    junta.unregister_law("py_penalty")


@pytest.fixture(scope="session")
def py_bilinear():
    import bilinear_law
    import junta

    bilinear_law.register("py_bilinear")
    yield "py_bilinear"
    junta.unregister_law("py_bilinear")
