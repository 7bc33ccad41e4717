"""Running from Python: the results of a linear and an incremental run,
the callback (stop, its dict, an exception), frames and their meshes,
Ctrl-C, a simulation that has run, files written like the CLI's."""

import os
import signal

import numpy as np
import pytest

import junta
from conftest import CUBE, DCB_COARSE, PULL, read_curve_csv


def test_linear_cube_reaction_and_frame():
    sim = junta.Simulation.from_file(CUBE)
    report = sim.check()
    # 3 x 3 x 3 nodes; z0 fixed (27 dofs), z1 prescribed in z (9 dofs)
    assert (report["nodes"], report["dofs"], report["equations"]) == (27, 81, 45)
    assert not sim.is_incremental
    r = sim.run()
    assert r.status == "completed"
    # shared/BENCHMARKS.md section 1 (CalculiX 2.20, scikit-fem 12.0.2):
    # total z reaction on the top face -2224.553
    assert r.summary["reactions"]["z1"][2] == pytest.approx(-2224.553, rel=1e-6)
    f = r.frame
    assert f is not None and len(r.frames) == 1 and r.frames[0].increment == f.increment == 0
    assert f.displacement.shape == (27, 3) and f.displacement.dtype == np.float64
    top = r.mesh.nodes[:, 2] == 1.0
    assert np.allclose(f.displacement[top, 2], -0.01)
    assert f.solid_stress.shape == (64, 6) and f.solid_strain.shape == (64, 6)
    assert f.solid_position.shape == (64, 3)
    assert f.interface_traction.shape == (0, 3)


def test_callback_stop_at_increment_5():
    seen = []

    def cb(inc):
        seen.append(inc)
        return junta.Flow.STOP if inc["increment"] == 5 else None

    r = junta.Simulation.from_file(DCB_COARSE).run(callback=cb)
    assert r.status is junta.Status.STOPPED and r.status == "stopped"
    assert r.status_line == "stopped: stopped by the Python callback"
    assert list(r.curve["increment"]) == [1, 2, 3, 4, 5]
    assert [i["increment"] for i in seen] == [1, 2, 3, 4, 5]
    last = seen[-1]
    assert set(last) == {"increment", "step", "load_factor", "reaction", "displacement",
                         "failed_points", "iterations", "row"}
    assert set(last["row"]) == set(r.curve)  # every column of curve.csv
    assert last["reaction"] == r.curve["reaction"][4] == last["row"]["reaction"]
    assert last["load_factor"] == r.curve["load_factor"][4]
    assert last["row"]["control"] == r.curve["control"][4]


def test_callback_stop_with_a_reason():
    r = junta.Simulation.from_file(DCB_COARSE).run(
        callback=lambda inc: junta.Stop("the reaction is enough") if inc["increment"] == 3 else None
    )
    assert r.status is junta.Status.STOPPED and len(r.curve["increment"]) == 3
    assert r.status_line == "stopped: the reaction is enough"


def test_callback_false_and_stop_string_are_deprecated():
    with pytest.warns(DeprecationWarning, match="junta.Flow.STOP"):
        r = junta.Simulation.from_file(DCB_COARSE).run(callback=lambda inc: inc["increment"] < 2)
    assert r.status == "stopped" and r.status_line == "stopped: stopped by the Python callback"
    assert len(r.curve["increment"]) == 2
    with pytest.warns(DeprecationWarning):
        r = junta.Simulation.from_file(DCB_COARSE).run(callback=lambda inc: "stop" if inc["increment"] == 2 else None)
    assert r.status == "stopped" and len(r.curve["increment"]) == 2


def test_callback_answer_of_another_type_is_a_type_error():
    with pytest.raises(TypeError, match=r"returns None \(go on\), junta.Flow.STOP") as e:
        junta.Simulation.from_file(DCB_COARSE).run(callback=lambda inc: 1)
    assert e.value.results.status == "stopped" and len(e.value.results.curve["increment"]) == 1


def test_max_increments():
    r = junta.Simulation.from_file(DCB_COARSE).run(max_increments=3)
    assert r.status == "stopped" and len(r.curve["increment"]) == 3


class Boom(Exception):
    pass


def test_callback_exception_stops_the_run_and_is_reraised(tmp_path):
    def cb(inc):
        if inc["increment"] == 3:
            raise Boom("at three")

    with pytest.raises(Boom, match="at three") as e:
        junta.Simulation.from_file(DCB_COARSE).run(callback=cb, output=tmp_path)
    r = e.value.results
    assert r.status == "stopped" and "Boom" in r.status_line
    assert len(r.curve["increment"]) == 3
    # the files stay a valid run directory: the curve holds the 3 increments
    assert list(read_curve_csv(tmp_path / "curve.csv")["increment"]) == [1, 2, 3]
    assert (tmp_path / "checkpoint.json").exists()


def test_frames_every(tmp_path):
    sim = junta.Simulation.from_file(DCB_COARSE)
    report = sim.check()
    solid_points = sum(b["elements"] * b["points_per_element"] for b in report["blocks"] if b["element"].startswith("h"))
    iface_points = sum(b["elements"] * b["points_per_element"] for b in report["blocks"] if b["element"].startswith("inter"))
    r = sim.run(frames_every=2, max_increments=5)
    # every 2nd increment, and the last one
    assert [f.increment for f in r.frames] == [2, 4, 5]
    assert r.frame is None
    nodes = report["nodes"]
    for f, lam in zip(r.frames, r.curve["load_factor"][[1, 3, 4]]):
        assert f.load_factor == lam
        assert f.displacement.shape == (nodes, 3)
        assert f.solid_stress.shape == (solid_points, 6) and f.solid_strain.shape == (solid_points, 6)
        assert f.solid_position.shape == (solid_points, 3)
        assert f.interface_traction.shape == (iface_points, 3) == f.interface_jump.shape
        assert f.interface_position.shape == (iface_points, 3)
        assert {"damage", "dissipated_energy", "failed", "area"} <= set(f.interface_outputs)
        assert all(v.shape == (iface_points,) for v in f.interface_outputs.values())
        assert np.all(np.isfinite(f.displacement))
    # the arms open: the loaded end moves +-0.5 lambda in z (the scene's BCs)
    f = r.frames[-1]
    x0 = r.mesh.nodes[:, 0] == 0.0
    assert np.isclose(np.max(f.displacement[x0, 2]), 0.5 * f.load_factor)


def test_to_meshio(tmp_path):
    meshio = pytest.importorskip("meshio")
    r = junta.Simulation.from_file(DCB_COARSE).run(frames_every=1, max_increments=1)
    m = r.frames[0].to_meshio()
    cells = sum(len(c["connectivity"]) for c in r.mesh.cells)
    assert [c.type for c in m.cells] == ["hexahedron20"] * len(r.mesh.cells)
    # two arms of 6 (precrack) + 35 (bond) H20 elements (the scene's boxes)
    assert sum(len(c.data) for c in m.cells) == cells == 2 * (6 + 35)
    path = tmp_path / "frame.vtu"
    m.write(path)
    back = meshio.read(path)
    assert back.points.shape == r.mesh.nodes.shape
    assert np.allclose(back.point_data["displacement"], r.frames[0].displacement)


def test_to_pyvista():
    pytest.importorskip("pyvista")
    r = junta.Simulation.from_file(CUBE).run()
    g = r.frame.to_pyvista()
    assert g.n_points == 27 and g.n_cells == 8


def test_ctrl_c_interrupts_after_the_increment():
    # a real SIGINT through the OS and Python's handler, sent by the run's
    # own callback at increment 3: no timer, so no race with the run
    def cb(inc):
        if inc["increment"] == 3:
            os.kill(os.getpid(), signal.SIGINT)

    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    with pytest.raises(KeyboardInterrupt, match="interrupted") as e:
        junta.Simulation.from_file(DCB_COARSE).run(callback=cb)
    r = e.value.results
    assert r.status is junta.Status.INTERRUPTED
    # the increment that saw the signal is the last one (the whole run is
    # about 100 increments)
    assert list(r.curve["increment"]) == [1, 2, 3]


def test_a_simulation_runs_once():
    sim = junta.Simulation.from_file(CUBE)
    sim.run()
    with pytest.raises(junta.JuntaError, match="runs once; read it again"):
        sim.run()
    with pytest.raises(junta.JuntaError, match="runs once"):
        sim.check()


def test_output_directory_holds_the_cli_files(tmp_path, py_penalty):
    r = junta.Simulation.from_file(PULL).run(output=tmp_path / "out")
    out = tmp_path / "out"
    assert r.output == str(out)
    for f in ("curve.csv", "summary.json", "checkpoint.json"):
        assert (out / f).exists(), f
    csv = read_curve_csv(out / "curve.csv")
    for name, col in csv.items():
        if name not in ("seconds", "control"):
            assert np.array_equal(col, r.curve[name], equal_nan=True), name
    # closed form (tests/data/pull.toml, shared/BENCHMARKS.md section 3):
    # sigma = Delta / (H / M + 1 / d), reaction = sigma x 0.04 m^2
    m = 2.1e11 * 0.7 / (1.3 * 0.4)
    sigma = 1.25e-5 / (0.01 / m + 1.0 / 1e13)
    assert abs(r.curve["reaction"][-1]) == pytest.approx(sigma * 0.04, rel=1e-9)
    assert np.allclose(np.abs(r.curve["reaction"]), sigma * 0.04 * np.array([0.25, 0.5, 0.75, 1.0]), rtol=1e-9)
