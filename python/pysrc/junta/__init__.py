"""Junta from Python: run finite-element models of solids joined by
cohesive interfaces, get the results as numpy arrays, and write traction
laws in Python.

>>> import junta
>>> sim = junta.Simulation.from_file("examples/delamination/dcb_coarse.toml",
...                                  overrides={"laws.cz.G_Ic": 0.8})
>>> sim.check()["equations"]
2936
>>> r = sim.run(callback=lambda inc: junta.Stop("enough") if inc["increment"] == 50 else None)
>>> r.status, r.status_line
(<Status.STOPPED: 'stopped'>, 'stopped: enough')

The run releases the GIL for its whole length and takes it back only after
each converged increment, to call ``callback`` and to notice Ctrl-C. Every
Rust error is one of the exceptions of :mod:`junta._errors`
(``JuntaError`` and its subclasses); a run that fails numerically is not
an exception: ``Results.status == "failed"``.
"""

import builtins as _builtins
import enum as _enum
import os as _os
import warnings as _warnings

import numpy as _np

from . import _junta
from ._errors import (
    FileError,
    FileNotFound,
    InputError,
    JuntaError,
    LawError,
    TangentError,
)

__version__ = _junta.__version__

__all__ = [
    "Simulation",
    "Results",
    "Frame",
    "Mesh",
    "Status",
    "Flow",
    "Stop",
    "Law",
    "catalog",
    "register_law",
    "unregister_law",
    "check_tangent",
    "evaluate_law",
    "JuntaError",
    "InputError",
    "FileError",
    "FileNotFound",
    "LawError",
    "TangentError",
]


class Status(str, _enum.Enum):
    """How a run ended (``Results.status``). A ``str`` enum: its values
    are the status words of the command line's status line, so
    ``r.status == "completed"`` holds too."""

    #: The load program ran to its end.
    COMPLETED = "completed"
    #: A stop rule, ``max_increments``, or the callback ended the run
    #: (a valid restart point).
    STOPPED = "stopped"
    #: An increment could not converge down to the smallest size
    #: (``Results.failure`` holds the message).
    FAILED = "failed"
    #: Ctrl-C (SIGINT) ended the run after an increment.
    INTERRUPTED = "interrupted"

    def __str__(self):
        return self.value

    @classmethod
    def from_status_line(cls, line):
        """The status of a status line (``"stopped: ..."``), by its first
        word."""
        word = str(line).split(":", 1)[0].split()[0] if str(line).strip() else ""
        return cls(word)


class Flow(_enum.Enum):
    """What a run's callback returns: ``None`` (or ``Flow.CONTINUE``) goes
    on; ``Flow.STOP`` ends the run after this increment (status
    :attr:`Status.STOPPED`, status line ``stopped: stopped by the Python
    callback``). :class:`Stop` stops with a reason of your own."""

    CONTINUE = "continue"
    STOP = "stop"


class Stop:
    """Returned by a run's callback: end the run after this increment with
    ``reason`` (the status line is ``stopped: <reason>``)."""

    __slots__ = ("reason",)

    def __init__(self, reason="stopped by the Python callback"):
        reason = str(reason)
        self.reason = reason if reason else "stopped by the Python callback"

    def __repr__(self):
        return f"junta.Stop({self.reason!r})"


_DEFAULT_STOP = "stopped by the Python callback"


def _callback_answer(value):
    """The native module's protocol for the callback's answer: ``None``
    goes on, a str stops with that reason."""
    if value is None or value is Flow.CONTINUE:
        return None
    if value is Flow.STOP:
        return _DEFAULT_STOP
    if isinstance(value, Stop):
        return value.reason
    if isinstance(value, bool) or value == "stop":
        _warnings.warn(
            "a run callback that returns True/False or \"stop\" is deprecated: return None to "
            "go on and junta.Flow.STOP or junta.Stop(\"reason\") to stop",
            DeprecationWarning,
            stacklevel=3,
        )
        return None if value is True else _DEFAULT_STOP
    raise TypeError(
        f"a run callback returns None (go on), junta.Flow.STOP or junta.Stop(reason), not {value!r}"
    )


def _wrap_callback(callback):
    if callback is None:
        return None
    if not callable(callback):
        raise TypeError("run: `callback` must be callable")

    def answer(inc):
        return _callback_answer(callback(inc))

    return answer


class Law:
    """The protocol of a traction law written in Python (the object a
    :func:`register_law` factory returns). Subclassing is optional: any
    object with these attributes works; this class documents them and
    gives the optional ones their defaults.

    Required:

    * ``state_len`` (int): state values per integration point;
    * ``initial_stiffness`` ``(d1, d2, d3)``: the undamaged stiffness;
    * ``evaluate(jump, state, step) -> (traction, tangent, new_state)``:
      ``jump`` float64 ``[n, 3]`` (local ``[s1, s2, n]``, positive
      opening), ``state`` ``[n, k]`` (the committed state; a copy) and
      ``step`` a dict with every field of the step a compiled law sees:
      ``increment``, ``load_factor``, ``delta_load_factor``, ``secant``,
      ``exact_tangent``, ``temperature_factor``, ``cycles``,
      ``delta_cycles``, ``load_ratio`` and ``crack_drive`` (``None``, or a
      dict ``{energy_release_rate, mode_ratio, process_zone_length}``);
      returns traction ``[n, 3]``, tangent ``[n, 3, 3]`` (``d traction /
      d jump``) and ``new_state`` ``[n, k]``. Called once per interface
      block and assembly with every point of the block; keep no state of
      your own.

    Optional (the defaults below):

    * ``tangent_kind``: ``"spd"``, ``"indefinite"`` or ``"general"``
      (nonsymmetric; otherwise the element assembles the symmetric part);
    * ``init_state(n) -> [n, k]`` (``None``: zeros);
    * ``output_names`` and ``outputs(state) -> [n, len(names)]`` (a
      ``damage`` output marks a point failed at 1 (traction-free), a
      ``dissipated_energy`` output per unit area feeds the curve's
      dissipated energy and arc-length path following);
    * ``failure_index(state) -> [n]`` (``None``: no index);
      ``outputs`` and ``failure_index`` are called once per interface
      block with its distinct states, and must depend on the state alone;
    * ``fracture_properties``: dict ``N, S, G_Ic, G_IIc`` (penalty and
      mesh advice);
    * ``warnings``: list of str.
    """

    state_len = 0
    initial_stiffness = (0.0, 0.0, 0.0)
    tangent_kind = "indefinite"
    output_names = ()
    fracture_properties = None
    warnings = ()
    init_state = None
    outputs = None
    failure_index = None

    def evaluate(self, jump, state, step):
        """``(traction [n, 3], tangent [n, 3, 3], new_state [n, k])``."""
        raise NotImplementedError(f"{type(self).__name__}.evaluate(jump, state, step)")


class Simulation:
    """A model read from a file (a TOML scene or an Abaqus/CalculiX deck),
    ready to check and to run **once** (a run consumes it: read it again to
    run again).

    Use :meth:`Simulation.from_file` or :meth:`Simulation.from_text`.
    """

    __slots__ = ("_native",)

    def __init__(self, native):
        if not isinstance(native, _junta.Simulation):
            raise TypeError(
                "use junta.Simulation.from_file(path, ...) or Simulation.from_text(text)"
            )
        self._native = native

    @classmethod
    def from_file(cls, path, overrides=None, solver=None):
        """Read ``path`` (``.toml`` scene or ``.inp`` deck).

        ``overrides``: scene keys by dotted path and their new value, e.g.
        ``{"laws.cz.G_Ic": 0.5, "analysis.arc_length.max_increments": 50,
        "boundary.1.value": 2.0}`` (values: bool, int, float, str, list,
        dict); TOML scenes only. A key whose parent is not in the scene
        raises :class:`InputError` naming it.

        ``solver``: linear-solver options as ``junta run --solver``, e.g.
        ``{"type": "cg"}``, ``"ldlt"`` or ``["type=cg", "precision=double"]``.

        Raises :class:`InputError` (a bad key, law, value),
        :class:`FileNotFound`, or the exception a Python law's factory
        raised.
        """
        return cls(_junta.Simulation.from_file(_os.fspath(path), overrides, solver))

    @classmethod
    def from_text(cls, text, path="scene.toml"):
        """A scene given as TOML text; ``path`` names it in messages and
        relative file names in it (mesh, reference curve) are read next to
        it."""
        return cls(_junta.Simulation.from_text(text, _os.fspath(path)))

    @property
    def input(self):
        """The input file."""
        return self._native.input

    @property
    def is_incremental(self):
        """True for an incremental (``[analysis] type = "static"``) run."""
        return self._native.is_incremental

    @property
    def notes(self):
        """Notes from reading the input (solver choice, edited keys)."""
        return self._native.notes

    @property
    def mesh(self):
        """The model's :class:`Mesh` (reference nodes, solid cells)."""
        return Mesh(self._native.mesh())

    def check(self):
        """What ``junta check`` reports, as a dict: ``nodes``, ``dofs``,
        ``equations``, ``elements``, ``blocks``, ``solver``,
        ``penalty_advice``, ``mesh_advice``, ``warnings``, ``notes``, ..."""
        return self._native.check()

    def run(self, callback=None, output=None, max_increments=None, frames_every=None):
        """Run the simulation (once) and return its :class:`Results`.

        ``callback(inc)`` is called after every converged increment with a
        dict ``{increment, step, load_factor, reaction, displacement,
        failed_points, iterations, row}`` (``row``: every column of
        ``curve.csv`` for this increment). It returns ``None`` to go on;
        :attr:`Flow.STOP` or :class:`Stop` ``("reason")`` ends the run
        after this increment (status :attr:`Status.STOPPED`, status line
        ``stopped: reason``, a valid restart point when ``output`` is
        given); an exception it raises ends the run the same way and is
        re-raised here. Returning ``False`` or ``"stop"`` still stops
        (deprecated: a ``DeprecationWarning``).

        ``output``: a directory to write the command line's files into
        (``curve.csv``, frames, ``checkpoint.json``, ``summary.json``);
        ``None`` (default) keeps everything in memory.

        ``max_increments``: stop after this many increments.

        ``frames_every``: keep the fields (:class:`Frame`) of every n-th
        increment and of the last one in ``Results.frames``. A linear run
        always has its one frame.

        Ctrl-C ends the run after the current increment and raises
        ``KeyboardInterrupt`` with the status line. An exception raised by
        a Python law is re-raised as itself (its ``__cause__`` is the run's
        message). When an exception ends a run that returned, the results
        are in its ``results`` attribute.
        """
        if output is not None:
            output = _os.fspath(output)
        try:
            d = self._native.run(_wrap_callback(callback), output, max_increments, frames_every)
        except BaseException as e:
            r = getattr(e, "_junta_results", None)
            if isinstance(r, dict):
                try:
                    e.results = Results(r)
                except Exception:  # an exception type without a __dict__
                    pass
            raise
        return Results(d)

    def __repr__(self):
        return repr(self._native)


class Mesh:
    """Reference node coordinates ``nodes [n, 3]`` and the solid cells,
    ``cells``: a list of dicts ``{block, name, material, element, vtk_type,
    meshio_type, connectivity [cells, nodes per cell]}`` in VTK node order
    (what the VTU frames hold)."""

    __slots__ = ("nodes", "cells")

    def __init__(self, d):
        self.nodes = d["nodes"]
        self.cells = d["cells"]

    def __repr__(self):
        n = sum(len(c["connectivity"]) for c in self.cells)
        return f"<junta.Mesh {len(self.nodes)} nodes, {n} solid cells>"


class Frame:
    """The fields of one converged state.

    ==========================  =========================================
    ``increment``, ``load_factor``
    ``displacement``            ``[nodes, 3]`` at the reference nodes
    ``solid_stress``            ``[points, 6]`` Voigt xx, yy, zz, xy, yz, zx
    ``solid_strain``            ``[points, 6]`` (engineering shear)
    ``solid_material_stress``   ``[points, 6]`` in the material's axes
                                (Voigt 11, 22, 33, 12, 23, 31; a ply: 1
                                the fibre); NaN where it has none
    ``solid_position``          ``[points, 3]`` reference position
    ``solid_block``/``_element`` ``[points]`` int
    ``interface_traction``      ``[points, 3]`` local ``[s1, s2, n]``
    ``interface_jump``          ``[points, 3]`` local ``[s1, s2, n]``
    ``interface_position``      ``[points, 3]``
    ``interface_outputs``       dict name -> ``[points]`` (``damage``,
                                ``dissipated_energy``, ``failed``,
                                ``failure_index``, ``area``, law outputs)
    ==========================  =========================================
    """

    def __init__(self, d, mesh=None):
        self.__dict__.update(d)
        self.mesh = mesh

    def to_meshio(self):
        """A ``meshio.Mesh`` of the solid cells with the displacement as
        point data (needs ``meshio``)."""
        import meshio

        m = self._need_mesh()
        cells = [(c["meshio_type"], _np.asarray(c["connectivity"])) for c in m.cells]
        block = [_np.full(len(c["connectivity"]), c["block"]) for c in m.cells]
        return meshio.Mesh(
            points=m.nodes,
            cells=cells,
            point_data={"displacement": self.displacement},
            cell_data={"block": block},
        )

    def to_pyvista(self):
        """A ``pyvista.UnstructuredGrid`` of the solid cells with the
        displacement as point data (needs ``pyvista``)."""
        import pyvista

        m = self._need_mesh()
        by_type = {}
        for c in m.cells:
            by_type.setdefault(c["vtk_type"], []).append(c["connectivity"])
        cells = {t: _np.concatenate(v) for t, v in by_type.items()}
        grid = pyvista.UnstructuredGrid(cells, _np.asarray(m.nodes))
        grid.point_data["displacement"] = self.displacement
        return grid

    def _need_mesh(self):
        if self.mesh is None:
            raise JuntaError("this frame has no mesh")
        return self.mesh

    def __repr__(self):
        return (
            f"<junta.Frame increment {self.increment}, load factor {self.load_factor:.6g}, "
            f"{len(self.displacement)} nodes, {len(self.solid_stress)} solid and "
            f"{len(self.interface_traction)} interface points>"
        )


class Results:
    """What a run returns.

    ===============  ==========================================================
    ``status``       a :class:`Status` (a ``str`` enum: ``"completed"``,
                     ``"stopped"``, ``"failed"``, ``"interrupted"``)
    ``status_line``  the command line's status (``stopped: ...``)
    ``curve``        dict of float64 arrays keyed as ``curve.csv``'s header
                     (``reaction``, ``displacement``, ``load_factor``, ...;
                     an empty cell is NaN), and ``control`` (list of str)
    ``summary``      dict (what ``summary.json`` holds)
    ``frames``       list of :class:`Frame` (``frames_every``, or a linear
                     run's one frame)
    ``frame``        a linear run's frame (else None)
    ``mesh``         the model's :class:`Mesh`
    ``output``       the output directory, or None (in memory)
    ``failure``      the message of a failed run (else None)
    ``notes``, ``warnings``
    ===============  ==========================================================
    """

    def __init__(self, d):
        self.status = Status.from_status_line(d["status"])
        self.status_line = d["status_line"]
        self.summary = d["summary"]
        self.curve = d["curve"]
        self.output = d["output"]
        self.notes = d["notes"]
        self.warnings = d["warnings"]
        self.failure = d["failure"]
        self.mesh = Mesh(d["mesh"])
        self.frames = [Frame(f, self.mesh) for f in d["frames"]]
        self.frame = Frame(d["frame"], self.mesh) if d["frame"] is not None else None

    def __repr__(self):
        n = len(self.curve.get("control", []))
        return f"<junta.Results {self.status_line!r}, {n} increments, {len(self.frames)} frames>"


def catalog():
    """Every registered plugin, as ``junta list`` prints them: a list of
    sections ``{title, plugins: [{key, description, params: [{name, doc}],
    runtime}]}``; laws registered from Python are in the ``interface laws``
    section with ``runtime: True``."""
    return _junta.catalog()


def list():  # noqa: A001 (the deprecated name of catalog())
    """Deprecated: :func:`catalog` (``list`` shadowed the builtin; this
    alias goes in the next release)."""
    _warnings.warn(
        "junta.list() is deprecated (it shadows the builtin): use junta.catalog()",
        DeprecationWarning,
        stacklevel=2,
    )
    return catalog()


def register_law(name, factory, description=None, params=None):
    """Register a traction law written in Python under ``name``; scenes use
    it as ``[laws.X] type = "name"`` (registering a name again replaces the
    law; built-in names are refused).

    ``factory(params)`` gets the scene's ``[laws.X]`` table without
    ``type`` (a dict) and returns a law object (:class:`Law` documents the
    protocol); raise ``ValueError`` on bad parameters (it reaches the user
    as itself). The law object has:

    * ``state_len`` (int): state values per integration point;
    * ``initial_stiffness`` ``(d1, d2, d3)``: undamaged stiffness;
    * ``tangent_kind`` (optional): ``"spd"``, ``"indefinite"`` (default) or
      ``"general"`` (nonsymmetric; otherwise the element assembles the
      symmetric part of the tangent);
    * ``evaluate(jump, state, step) -> (traction, tangent, new_state)``:
      ``jump`` float64 ``[n, 3]`` (local ``[s1, s2, n]``, positive opening),
      ``state`` ``[n, k]`` (the committed state; a copy), ``step`` a dict of
      every step field (:class:`Law`: ``increment``, ``load_factor``, ...,
      ``temperature_factor``, ``cycles``, ``load_ratio``, ``crack_drive``); returns traction ``[n, 3]``,
      tangent ``[n, 3, 3]`` (``d traction / d jump``) and ``new_state``
      ``[n, k]``. It is called once per interface block and assembly with
      every point of the block, and must not keep state of its own;
    * ``init_state(n) -> [n, k]`` (optional, default zeros);
    * ``output_names`` (list of str) and ``outputs(state) -> [n, len(names)]``
      (optional; a ``damage`` output marks a point failed at 1 (traction-free), and a
      ``dissipated_energy`` output per unit area feeds the dissipated energy
      of the curve and arc-length path following);
    * ``failure_index(state) -> [n]`` (optional);
    * ``fracture_properties`` (optional): dict ``N, S, G_Ic, G_IIc`` for the
      penalty and mesh advice; ``warnings`` (optional): list of str.

    ``params``: documentation of the parameters for :func:`catalog`, a dict
    ``{name: doc}`` or a list of ``(name, doc)``.
    """
    if isinstance(params, dict):
        params = _builtins.list(params.items())
    elif params is not None:
        params = [(str(n), str(d)) for n, d in params]
    _junta.register_law(name, factory, description, params)


def unregister_law(name):
    """Remove a law registered with :func:`register_law`; True when it was
    registered."""
    return _junta.unregister_law(name)


def _default_step(step):
    """The step dict a law sees (every field), with ``step``'s values."""
    s = {
        "increment": 1,
        "load_factor": 1.0,
        "delta_load_factor": 0.1,
        "secant": False,
        "exact_tangent": False,
        "temperature_factor": 1.0,
        "cycles": 0.0,
        "delta_cycles": 0.0,
        "load_ratio": 0.0,
        "crack_drive": None,
    }
    if step:
        s.update(step)
    return s


def _initial_state(law, n):
    k = int(law.state_len)
    init = getattr(law, "init_state", None)
    if init is not None:
        return _np.array(init(n), dtype=float).reshape(n, k)
    return _np.zeros((n, k))


def evaluate_law(law, jumps, state=None, step=None):
    """Evaluate a law object as a run would, with the same checks of the
    returned shapes and values (:class:`LawError` on a wrong shape or a
    NaN): ``(traction [n, 3], tangent [n, 3, 3], new_state [n, k])``."""
    jumps = _np.atleast_2d(_np.asarray(jumps, dtype=float))
    n = len(jumps)
    if state is None:
        state = _initial_state(law, n)
    state = _np.asarray(state, dtype=float).reshape(n, int(law.state_len))
    s = _default_step(step)
    return _junta.evaluate_law(law, [tuple(j) for j in jumps], state.ravel().tolist(), s)


def check_tangent(law, jumps, state=None, step=None, h=1e-7, rtol=1e-5, raise_on_error=False):
    """Compare a law's tangent with central finite differences of its
    traction in the jump, at the points ``jumps [n, 3]`` with the committed
    ``state [n, k]`` (default: the law's initial state) and ``step`` (a dict,
    default ``{increment: 1, load_factor: 1, delta_load_factor: 0.1,
    secant: False, temperature_factor: 1, cycles: 0, ...}``).

    ``h`` is the absolute step in jump units (choose points at least a few
    ``h`` away from a kink of the law: onset, full separation, contact).
    The error of a point is ``max |D - D_fd| / max(|D|_max, |D_fd|_max)``
    over its 9 entries.

    Returns ``{"max_rel_error", "worst_point", "ok", "errors" [n],
    "tangent" [n, 3, 3], "fd_tangent" [n, 3, 3]}``; with
    ``raise_on_error=True`` a failed check raises :class:`TangentError`
    naming the point and the entries that differ.
    """
    jumps = _np.atleast_2d(_np.asarray(jumps, dtype=float))
    n = len(jumps)
    if jumps.shape != (n, 3):
        raise ValueError(f"jumps must be [n, 3], not {jumps.shape}")
    if state is None:
        state = _initial_state(law, n)
    state = _np.asarray(state, dtype=float).reshape(n, int(law.state_len))
    step = _default_step(step)

    def traction(j):
        t, _, _ = law.evaluate(j.copy(), state.copy(), dict(step))
        return _np.asarray(t, dtype=float).reshape(n, 3)

    _, d, _ = law.evaluate(jumps.copy(), state.copy(), dict(step))
    d = _np.asarray(d, dtype=float).reshape(n, 3, 3)
    fd = _np.empty((n, 3, 3))
    for c in range(3):
        jp = jumps.copy()
        jm = jumps.copy()
        jp[:, c] += h
        jm[:, c] -= h
        fd[:, :, c] = (traction(jp) - traction(jm)) / (2.0 * h)
    scale = _np.maximum(_np.abs(d).reshape(n, 9).max(axis=1), _np.abs(fd).reshape(n, 9).max(axis=1))
    scale = _np.where(scale > 0.0, scale, 1.0)
    errors = _np.abs(d - fd).reshape(n, 9).max(axis=1) / scale
    worst = int(_np.argmax(errors)) if n else -1
    max_err = float(errors[worst]) if n else 0.0
    ok = bool(max_err <= rtol)
    if not ok and raise_on_error:
        bad = _np.argwhere(_np.abs(d[worst] - fd[worst]) > rtol * scale[worst])
        entries = "; ".join(
            f"[{i}, {k}]: tangent {d[worst, i, k]:.9g}, central differences {fd[worst, i, k]:.9g}"
            for i, k in bad
        )
        raise TangentError(
            f"the tangent of point {worst} (jump {jumps[worst].tolist()}) differs from central "
            f"differences of the traction by {max_err:.3e} (relative, rtol {rtol:g}, h {h:g}): {entries}"
        )
    return {
        "max_rel_error": max_err,
        "worst_point": worst,
        "ok": ok,
        "errors": errors,
        "tangent": d,
        "fd_tangent": fd,
    }
