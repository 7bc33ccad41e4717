//! `junta._junta.Simulation`: a [`junta::Simulation`] read from a file
//! (with overrides) or from scene text, checked, and run once with the GIL
//! released; the per-increment observer re-takes the GIL to check for
//! Ctrl-C and to call the Python callback. Results come back as a dict of
//! numpy arrays and plain values that `junta.Results` wraps.

use crate::convert::{array, int_array, json_to_py, py_to_toml, to_py};
use crate::errors::{guard, junta_error, new_error, reraise_with_cause, to_pyerr};
use crate::law::{collect_laws, ErrorSlot, LawFailure};
use junta::{
    Curve, Flow, Frame, FrameCollector, Increment, Observer, Options, RunLog, RunResults,
    RunSettings, Simulation, Status,
};
use junta_core::topology::{CellShape, WEDGE15_TO_VTK};
use pyo3::exceptions::{PyKeyboardInterrupt, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyList, PyString};
use std::path::PathBuf;
use std::sync::{mpsc, Arc, Mutex};

/// A simulation read from a file, ready to check and to run once.
#[pyclass(name = "Simulation", module = "junta._junta")]
pub struct PySimulation {
    /// `None` once it has run (a `Mutex` for `Sync`: the model's linear
    /// solver is `Send` only; never held across a `detach`).
    sim: Mutex<Option<Simulation>>,
    /// The error slots of the Python laws of this simulation.
    slots: Vec<Arc<ErrorSlot>>,
    input: String,
}

/// `solver=` as `KEY=VALUE` strings: a dict `{"type": "cg"}`, a str
/// (`"cg"`: the type), or a list of `"key=value"`.
fn solver_args(solver: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<String>> {
    let Some(s) = solver else {
        return Ok(Vec::new());
    };
    if s.is_none() {
        return Ok(Vec::new());
    }
    let text = |v: &Bound<'_, PyAny>| -> PyResult<String> {
        if v.is_instance_of::<PyBool>() {
            Ok(if v.is_truthy()? { "true" } else { "false" }.to_string())
        } else {
            Ok(v.str()?.to_string())
        }
    };
    if let Ok(d) = s.cast::<PyDict>() {
        return d
            .iter()
            .map(|(k, v)| Ok(format!("{}={}", k.str()?, text(&v)?)))
            .collect();
    }
    if s.is_instance_of::<PyString>() {
        let v: String = s.extract()?;
        return Ok(vec![if v.contains('=') {
            v
        } else {
            format!("type={v}")
        }]);
    }
    s.try_iter()?
        .map(|x| x?.extract::<String>())
        .collect::<PyResult<Vec<_>>>()
        .map_err(|_| {
            PyTypeError::new_err(
                "solver: a dict {\"type\": \"cg\", ...}, a solver name, or a list of \"key=value\"",
            )
        })
}

/// `overrides=` as `(dotted key, TOML value)` pairs: a dict or a list of
/// pairs.
fn override_args(overrides: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<(String, toml::Value)>> {
    let Some(o) = overrides else {
        return Ok(Vec::new());
    };
    if o.is_none() {
        return Ok(Vec::new());
    }
    let pairs: Vec<(Bound<'_, PyAny>, Bound<'_, PyAny>)> = if let Ok(d) = o.cast::<PyDict>() {
        d.iter().collect()
    } else {
        o.try_iter()?
            .map(|x| x?.extract())
            .collect::<PyResult<Vec<_>>>()
            .map_err(|_| {
                PyTypeError::new_err(
                    "overrides: a dict {\"laws.cz.G_Ic\": 0.5} or a list of (key, value)",
                )
            })?
    };
    pairs
        .into_iter()
        .map(|(k, v)| {
            let key: String = k
                .extract()
                .map_err(|_| PyTypeError::new_err(format!("overrides: key {k} is not a str")))?;
            let value = py_to_toml(&v, &format!("overrides[{key:?}]"))?;
            Ok((key, value))
        })
        .collect()
}

/// Read with the GIL released; the Python laws' error slots are kept, and
/// a factory's exception is re-raised as itself.
fn read(
    py: Python<'_>,
    f: impl FnOnce() -> junta::Result<Simulation> + Send,
) -> PyResult<(Simulation, Vec<Arc<ErrorSlot>>)> {
    let (r, slots, factory_error) = py.detach(|| collect_laws(|| guard(f)));
    match r {
        Err(panic) => Err(junta_error(py, panic)),
        Ok(Ok(sim)) => Ok((sim, slots)),
        Ok(Err(e)) => Err(match factory_error {
            Some(original) => reraise_with_cause(py, original, Some(e.chain())),
            None => to_pyerr(py, &e),
        }),
    }
}

#[pymethods]
impl PySimulation {
    /// Read a scene (`.toml`) or a deck (`.inp`) with scene overrides and
    /// linear-solver options.
    #[staticmethod]
    #[pyo3(signature = (path, overrides = None, solver = None))]
    fn from_file(
        py: Python<'_>,
        path: PathBuf,
        overrides: Option<&Bound<'_, PyAny>>,
        solver: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let options = Options {
            solver: solver_args(solver)?,
            overrides: override_args(overrides)?,
        };
        let input = path.display().to_string();
        let (sim, slots) = read(py, move || Simulation::from_file_with(&path, options))?;
        Ok(PySimulation {
            sim: Mutex::new(Some(sim)),
            slots,
            input,
        })
    }

    /// A scene given as TOML text; `path` names it in messages, and
    /// relative file names in it are read next to `path`.
    #[staticmethod]
    #[pyo3(signature = (text, path = PathBuf::from("scene.toml")))]
    fn from_text(py: Python<'_>, text: String, path: PathBuf) -> PyResult<Self> {
        let input = path.display().to_string();
        let (sim, slots) = read(py, move || Simulation::from_scene_text(&text, &path))?;
        Ok(PySimulation {
            sim: Mutex::new(Some(sim)),
            slots,
            input,
        })
    }

    /// The input file.
    #[getter]
    fn input(&self) -> String {
        self.input.clone()
    }

    /// True until the simulation has run.
    #[getter]
    fn ready(&self) -> bool {
        self.lock().is_some()
    }

    /// True for an incremental run.
    #[getter]
    fn is_incremental(&self, py: Python<'_>) -> PyResult<bool> {
        self.with(py, |s| s.is_incremental())
    }

    /// Notes from reading the input.
    #[getter]
    fn notes(&self, py: Python<'_>) -> PyResult<Vec<String>> {
        self.with(py, |s| s.notes().to_vec())
    }

    /// The model's mesh: reference node coordinates and the solid cells in
    /// VTK node order.
    fn mesh<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let g = self.lock();
        let sim = g.as_ref().ok_or_else(|| self.gone(py))?;
        mesh_dict(py, sim.model())
    }

    /// What `junta check` reports, as a dict.
    fn check<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        // out of the lock while the GIL is released, back in after
        let sim = self.lock().take().ok_or_else(|| self.gone(py))?;
        let (sim, r) = py.detach(move || {
            let r = guard(|| sim.check());
            (sim, r)
        });
        *self.lock() = Some(sim);
        match r {
            Err(panic) => Err(junta_error(py, panic)),
            Ok(Err(e)) => Err(to_pyerr(py, &e)),
            Ok(Ok(report)) => to_py(py, &report),
        }
    }

    /// Run (once). See `junta.Simulation.run`.
    #[pyo3(signature = (callback = None, output = None, max_increments = None, frames_every = None))]
    fn run<'py>(
        &mut self,
        py: Python<'py>,
        callback: Option<Py<PyAny>>,
        output: Option<PathBuf>,
        max_increments: Option<usize>,
        frames_every: Option<usize>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let callback = callback.filter(|c| !c.bind(py).is_none());
        if let Some(c) = &callback {
            if !c.bind(py).is_callable() {
                return Err(PyTypeError::new_err("run: `callback` must be callable"));
            }
        }
        let sim = self.lock().take().ok_or_else(|| self.gone(py))?;
        let mesh = mesh_dict(py, sim.model())?;
        let settings = RunSettings {
            output,
            max_increments,
            ..RunSettings::default()
        };
        let slots = self.slots.clone();
        let (to_main, main_inbox) = mpsc::channel();
        let mut observer = PyObserver {
            callback,
            slots: slots.clone(),
            error: None,
            interrupted: false,
            main_thread: to_main.clone(),
        };
        let mut collector = frames_every.map(FrameCollector::every);
        let ran = py.detach(|| {
            // the run on a thread of rayon's pool (`Simulation::run`), this
            // thread answering its signal checks until it is done
            let main_inbox = main_inbox;
            rayon::in_place_scope(|scope| {
                scope.spawn(|_| {
                    let r = guard(|| {
                        let mut observers: Vec<&mut dyn Observer> = Vec::new();
                        if let Some(c) = collector.as_mut() {
                            observers.push(c);
                        }
                        observers.push(&mut observer);
                        sim.run(&settings, &mut observers)
                    });
                    let _ = to_main.send(ToMain::Done(Box::new(r)));
                });
                serve_signal_checks(&main_inbox)
            })
        });
        let result = match ran {
            Err(panic) => return Err(junta_error(py, panic)),
            Ok(r) => r,
        };
        // a law that raised (or returned garbage) comes first: it is the
        // cause of whatever the run ended with
        let law_failure = slots.iter().find_map(|s| s.take().map(|f| (s, f)));
        let context = match &result {
            Ok(r) => r
                .failure
                .as_ref()
                .map(|e| e.chain())
                .or_else(|| Some(r.status_line.clone())),
            Err(e) => Some(e.chain()),
        };
        let results = match &result {
            Ok(r) => Some(results_dict(
                py,
                r,
                collector.map(|c| c.frames).unwrap_or_default(),
                mesh,
            )?),
            Err(_) => None,
        };
        let attach = |e: PyErr| -> PyErr {
            if let Some(d) = &results {
                let _ = e.value(py).setattr("_junta_results", d.clone());
            }
            e
        };
        if let Some((slot, f)) = law_failure {
            let context = context.map(|c| slot.tidy(&c));
            return Err(attach(match f {
                LawFailure::Python(e) => reraise_with_cause(py, e, context),
                LawFailure::Invalid(m) => new_error(py, "LawError", context.unwrap_or(m)),
            }));
        }
        if let Some(e) = observer.error {
            return Err(attach(e));
        }
        match result {
            Err(e) => Err(to_pyerr(py, &e)),
            Ok(r) => {
                if observer.interrupted || r.status == Status::Interrupted {
                    return Err(attach(PyKeyboardInterrupt::new_err(format!(
                        "{}: {}",
                        self.input, r.status_line
                    ))));
                }
                Ok(results.clone().expect("results of a run that returned"))
            }
        }
    }

    fn __repr__(&self) -> String {
        match &*self.lock() {
            Some(s) => format!(
                "<junta.Simulation {} ({} equations, {})>",
                self.input,
                s.model().dofs.num_free,
                if s.is_incremental() {
                    "incremental"
                } else {
                    "linear"
                }
            ),
            None => format!("<junta.Simulation {} (has run)>", self.input),
        }
    }
}

impl PySimulation {
    fn lock(&self) -> std::sync::MutexGuard<'_, Option<Simulation>> {
        self.sim.lock().unwrap_or_else(|p| p.into_inner())
    }
    /// The error of using a simulation that has run.
    fn gone(&self, py: Python<'_>) -> PyErr {
        junta_error(
            py,
            format!(
                "{}: a Simulation runs once; read it again (junta.Simulation.from_file) to run it again",
                self.input
            ),
        )
    }
    fn with<T>(&self, py: Python<'_>, f: impl FnOnce(&Simulation) -> T) -> PyResult<T> {
        let g = self.lock();
        let sim = g.as_ref().ok_or_else(|| self.gone(py))?;
        Ok(f(sim))
    }
}

/// The observer of a run from Python: Ctrl-C, the callback, the laws'
/// failures.
struct PyObserver {
    callback: Option<Py<PyAny>>,
    slots: Vec<Arc<ErrorSlot>>,
    /// The exception the callback raised.
    error: Option<PyErr>,
    interrupted: bool,
    /// Python's main thread, waiting for the run: the signal checks go
    /// there (`check_signals` sees Ctrl-C only on the main thread).
    main_thread: mpsc::Sender<ToMain>,
}

/// What a run on rayon's pool sends the Python thread that started it.
enum ToMain {
    /// Check for signals (Ctrl-C) and answer with the exception it raised.
    CheckSignals(mpsc::Sender<Option<PyErr>>),
    /// The run's end.
    Done(Box<Result<junta::Result<junta::RunResults>, String>>),
}

/// On the thread that started a run: answer its signal checks until it is
/// done, then give its end.
fn serve_signal_checks(
    inbox: &mpsc::Receiver<ToMain>,
) -> Result<junta::Result<junta::RunResults>, String> {
    loop {
        match inbox.recv() {
            Ok(ToMain::CheckSignals(answer)) => {
                let raised = Python::attach(|py| py.check_signals().err());
                let _ = answer.send(raised);
            }
            Ok(ToMain::Done(end)) => return *end,
            Err(_) => return Err("internal error: the run ended without its result".into()),
        }
    }
}

impl Observer for PyObserver {
    /// Signals are checked before the callback and after it (a Ctrl-C, or
    /// a SIGINT the callback sent, ends the run at this increment, as when
    /// the run was on Python's main thread and the callback raised it).
    fn on_increment(&mut self, inc: &Increment<'_>, _log: &RunLog) -> junta::Result<Flow> {
        if let Some(e) = self.signal_raised() {
            return Ok(Python::attach(|py| self.raised(py, e)));
        }
        let flow = Python::attach(|py| self.increment(py, inc));
        if !matches!(flow, Flow::Continue) {
            return Ok(flow);
        }
        Ok(match self.signal_raised() {
            Some(e) => Python::attach(|py| self.raised(py, e)),
            None => flow,
        })
    }
}

impl PyObserver {
    /// The exception Python's signal handlers raised, asked of the main
    /// thread (without holding the GIL, which the main thread needs to
    /// answer).
    fn signal_raised(&self) -> Option<PyErr> {
        let (answer, reply) = mpsc::channel();
        self.main_thread.send(ToMain::CheckSignals(answer)).ok()?;
        reply.recv().ok().flatten()
    }
}

/// What the (wrapped) callback's answer means: `None` (or anything else
/// but the two below) goes on; a str stops with that reason (`junta.Stop`
/// and `junta.Flow.STOP` reach here as their reason from the package's
/// wrapper); `False` stops (the deprecated protocol, when the native
/// module is called directly).
fn callback_flow(v: &Bound<'_, PyAny>) -> Flow {
    const DEFAULT: &str = "stopped by the Python callback";
    if v.is_instance_of::<PyBool>() {
        return if v.is_truthy().unwrap_or(true) {
            Flow::Continue
        } else {
            Flow::Stop(DEFAULT.into())
        };
    }
    match v.extract::<String>() {
        Ok(s) if s == "stop" || s.is_empty() => Flow::Stop(DEFAULT.into()),
        Ok(s) => Flow::Stop(s),
        Err(_) => Flow::Continue,
    }
}

impl PyObserver {
    fn increment(&mut self, py: Python<'_>, inc: &Increment<'_>) -> Flow {
        if self.slots.iter().any(|s| s.failed()) {
            return Flow::Stop("a Python law failed".into());
        }
        let Some(cb) = &self.callback else {
            return Flow::Continue;
        };
        let answer = increment_dict(py, inc).and_then(|d| cb.bind(py).call1((d,)));
        match answer {
            Err(e) => self.raised(py, e),
            Ok(v) => callback_flow(&v),
        }
    }

    fn raised(&mut self, py: Python<'_>, e: PyErr) -> Flow {
        if e.is_instance_of::<PyKeyboardInterrupt>(py) {
            self.interrupted = true;
            return Flow::Interrupt;
        }
        let what = crate::errors::describe(py, &e);
        self.error = Some(e);
        Flow::Stop(format!("the Python callback raised {what}"))
    }
}

/// The curve columns of rows as a dict of numpy arrays, `control` a list.
fn curve_dict<'py>(py: Python<'py>, c: &Curve) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (name, v) in &c.columns {
        d.set_item(name, array(py, v.clone(), 0)?)?;
    }
    d.set_item("control", PyList::new(py, &c.control)?)?;
    Ok(d)
}

/// What the callback receives after each converged increment.
fn increment_dict<'py>(py: Python<'py>, inc: &Increment<'_>) -> PyResult<Bound<'py, PyDict>> {
    let r = inc.row;
    let d = PyDict::new(py);
    d.set_item("increment", r.increment)?;
    d.set_item("step", r.step)?;
    d.set_item("load_factor", r.lambda)?;
    d.set_item("reaction", r.reaction)?;
    d.set_item("displacement", r.displacement)?;
    d.set_item("failed_points", r.failed)?;
    d.set_item("iterations", r.iterations)?;
    let row = PyDict::new(py);
    let c = Curve::from_rows(std::slice::from_ref(r));
    for (name, v) in &c.columns {
        row.set_item(name, v[0])?;
    }
    row.set_item("control", &r.control)?;
    d.set_item("row", row)?;
    Ok(d)
}

/// One frame's fields as numpy arrays.
fn frame_dict<'py>(py: Python<'py>, f: Frame) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let ints = |v: Vec<usize>| v.into_iter().map(|x| x as i64).collect::<Vec<i64>>();
    d.set_item("increment", f.increment)?;
    d.set_item("load_factor", f.load_factor)?;
    d.set_item("displacement", array(py, f.displacement, 3)?)?;
    let s = f.solid;
    d.set_item("solid_block", int_array(py, ints(s.block), 0)?)?;
    d.set_item("solid_element", int_array(py, ints(s.element), 0)?)?;
    d.set_item("solid_position", array(py, s.position, 3)?)?;
    d.set_item("solid_stress", array(py, s.stress, 6)?)?;
    d.set_item("solid_strain", array(py, s.strain, 6)?)?;
    d.set_item("solid_material_stress", array(py, s.material_stress, 6)?)?;
    let i = f.interface;
    d.set_item("interface_block", int_array(py, ints(i.block), 0)?)?;
    d.set_item("interface_element", int_array(py, ints(i.element), 0)?)?;
    d.set_item("interface_position", array(py, i.position, 3)?)?;
    d.set_item("interface_jump", array(py, i.jump, 3)?)?;
    d.set_item("interface_traction", array(py, i.traction, 3)?)?;
    let outs = PyDict::new(py);
    for (name, v) in i.outputs {
        outs.set_item(name, array(py, v, 0)?)?;
    }
    d.set_item("interface_outputs", outs)?;
    Ok(d)
}

/// meshio's name of a solid cell shape (3D or plane).
fn meshio_name(s: CellShape) -> &'static str {
    match s {
        CellShape::Hex8 => "hexahedron",
        CellShape::Hex20 => "hexahedron20",
        CellShape::Hex27 => "hexahedron27",
        CellShape::Wedge6 => "wedge",
        CellShape::Wedge15 => "wedge15",
        CellShape::PlaneQuad4 => "quad",
        CellShape::PlaneQuad8 => "quad8",
        CellShape::PlaneQuad9 => "quad9",
        CellShape::PlaneTri3 => "triangle",
        CellShape::PlaneTri6 => "triangle6",
        _ => "",
    }
}

/// The reference nodes and the solid blocks' cells in VTK node order (as
/// `junta::output::vtu::write_vtu` writes them).
fn mesh_dict<'py>(py: Python<'py>, model: &junta_core::Model) -> PyResult<Bound<'py, PyDict>> {
    let mesh = &model.mesh;
    let d = PyDict::new(py);
    let nodes: Vec<f64> = mesh.nodes.iter().flatten().copied().collect();
    d.set_item("nodes", array(py, nodes, 3)?)?;
    let cells = PyList::empty(py);
    for (bi, b) in mesh.blocks.iter().enumerate() {
        if !b.shape.is_solid() {
            continue;
        }
        let npe = b.nodes_per_element();
        let wedge = matches!(b.shape, CellShape::Wedge6 | CellShape::Wedge15);
        let conn: Vec<i64> = b
            .connectivity
            .chunks(npe)
            .flat_map(|e| {
                (0..npe).map(move |k| if wedge { e[WEDGE15_TO_VTK[k]] } else { e[k] } as i64)
            })
            .collect();
        let c = PyDict::new(py);
        c.set_item("block", bi)?;
        c.set_item("name", &b.name)?;
        c.set_item("material", &b.material)?;
        c.set_item("element", &b.element_type)?;
        c.set_item("vtk_type", b.shape.vtk_type())?;
        c.set_item("meshio_type", meshio_name(b.shape))?;
        c.set_item("connectivity", int_array(py, conn, npe)?)?;
        cells.append(c)?;
    }
    d.set_item("cells", cells)?;
    Ok(d)
}

fn status_name(s: &Status) -> &'static str {
    match s {
        Status::Completed => "completed",
        Status::Stopped => "stopped",
        Status::Failed => "failed",
        Status::Interrupted => "interrupted",
    }
}

/// What `Simulation.run` returns (wrapped by `junta.Results`).
fn results_dict<'py>(
    py: Python<'py>,
    r: &RunResults,
    frames: Vec<Frame>,
    mesh: Bound<'py, PyDict>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("status", status_name(&r.status))?;
    d.set_item("status_line", &r.status_line)?;
    d.set_item("summary", json_to_py(py, &r.summary.to_json())?)?;
    d.set_item("curve", curve_dict(py, &r.curve())?)?;
    d.set_item("output", r.output.as_ref().map(|p| p.display().to_string()))?;
    d.set_item("notes", PyList::new(py, &r.notes)?)?;
    d.set_item("warnings", PyList::new(py, &r.warnings)?)?;
    d.set_item("failure", r.failure.as_ref().map(|e| e.chain()))?;
    let list = PyList::empty(py);
    for f in frames {
        list.append(frame_dict(py, f)?)?;
    }
    let frame = match &r.frame {
        Some(f) => {
            let fd = frame_dict(py, f.clone())?;
            if list.is_empty() {
                list.append(&fd)?;
            }
            Some(fd)
        }
        None => None,
    };
    d.set_item("frames", list)?;
    d.set_item("frame", frame)?;
    d.set_item("mesh", mesh)?;
    Ok(d)
}
