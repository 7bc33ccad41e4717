"""The DCB of the examples run from Python in memory gives the command
line's curve.csv of the same scene, number for number (the wall-clock
``seconds`` column aside).

This is the slow test of the suite (the full DCB: about 500 increments,
minutes at the dev profile): the command line runs in a subprocess while
the Python run, which releases the GIL, runs in this process, once per
session. Deselect it with ``-m "not slow"``.
"""

import subprocess

import numpy as np
import pytest

import junta
from conftest import DCB, junta_command, read_curve_csv

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def dcb_runs(tmp_path_factory):
    out = tmp_path_factory.mktemp("dcb_cli")
    cli = subprocess.Popen(
        junta_command() + ["run", str(DCB), "-o", str(out), "-q"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        seen = []
        results = junta.Simulation.from_file(DCB).run(callback=lambda inc: seen.append(inc["increment"]))
    finally:
        stdout, stderr = cli.communicate()
    assert cli.returncode == 0, f"the CLI failed: {stdout}\n{stderr}"
    return results, read_curve_csv(out / "curve.csv"), seen


def test_python_curve_is_the_cli_curve(dcb_runs):
    results, cli, seen = dcb_runs
    assert results.status == "completed", results.status_line
    assert results.output is None  # in memory
    py = results.curve
    assert len(cli["increment"]) > 400  # the DCB converges ~500 increments
    assert sorted(py) == sorted(cli)  # the same columns as curve.csv's header
    for name, column in cli.items():
        if name == "seconds":
            continue
        if name == "control":
            assert py[name] == column
        else:
            assert py[name].dtype == np.float64
            assert np.array_equal(py[name], column, equal_nan=True), name
    # the callback saw every converged increment, in order
    assert seen == list(range(1, len(cli["increment"]) + 1))


def test_dcb_peak_is_the_beam_theory_peak(dcb_runs):
    # corrected beam theory peaks at 138.5 N (shared/BENCHMARKS.md section
    # 4, examples/delamination/dcb_beam_theory.csv); the scene's tolerance
    # is 3 %
    results, _, _ = dcb_runs
    peak = float(np.max(results.curve["reaction"]))
    assert abs(peak - 138.5) / 138.5 < 0.03, peak
