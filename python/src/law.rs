//! Traction laws written in Python: `junta.register_law(name, factory)`
//! registers a run-time law (`junta_core::registry::register_runtime_law`)
//! whose builder calls `factory(params)` under the GIL and wraps the law
//! object it returns in a [`PyLaw`], an [`InterfaceLaw`] evaluated in
//! batches: the assembler calls [`InterfaceLaw::evaluate_batch`] once per
//! interface block and assembly with every point of the block, and the law
//! sees numpy arrays `jump [n, 3]`, `state [n, k]`.
//!
//! The law object (see the package's `junta.register_law` docstring):
//!
//! | attribute | |
//! |---|---|
//! | `state_len: int` | state values per point |
//! | `initial_stiffness: (d1, d2, d3)` | undamaged stiffness, for diagnostics |
//! | `tangent_kind` | `"spd"`, `"indefinite"` (default) or `"general"` |
//! | `evaluate(jump, state, step)` | `-> (traction [n,3], tangent [n,3,3], new_state [n,k])` |
//! | `init_state(n)` | optional, `-> [n, k]` (default zeros) |
//! | `output_names`, `outputs(state)` | optional, `-> [n, len(names)]`; a `damage` output gives the point stage: failed at 1 (traction-free), process zone between 0 and 1 |
//! | `failure_index(state)` | optional, `-> [n]` |
//! | `fracture_properties` | optional dict `N, S, G_Ic, G_IIc` (mesh and penalty advice) |
//! | `warnings` | optional list of str |
//!
//! What a law returns is checked exactly: a wrong shape or a non-finite
//! value is a `LawError::Failed` naming the law, the array and the
//! expected and returned shapes. A Python exception is a
//! `LawError::Failed` with its type and message, and the exception itself
//! is kept in the law's [`ErrorSlot`] so that `Simulation.run` re-raises it
//! (chained to the run's message) instead of a generic error.

use crate::convert::{array, toml_table_to_py};
use crate::errors::describe;
use junta_core::element::StepInfo;
use junta_core::law::{
    output, FractureProperties, InterfaceLaw, LawContext, LawError, LawResponse, PointStage,
};
use junta_core::registry::{self, RuntimeLaw};
use junta_core::{CoreError, MatrixKind};
use numpy::{PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyTuple};
use std::cell::RefCell;
use std::collections::{BTreeMap, HashMap, HashSet};
use std::sync::{Arc, Mutex};

/// What went wrong in a Python law, kept for `Simulation.run`.
pub enum LawFailure {
    /// The law raised this exception.
    Python(PyErr),
    /// The law returned something invalid (shape, NaN): the message.
    Invalid(String),
}

/// The first failure of a law (shared by the law and the simulation that
/// built it).
#[derive(Default)]
pub struct ErrorSlot {
    first: Mutex<Option<LawFailure>>,
    key: std::sync::OnceLock<&'static str>,
}

impl ErrorSlot {
    fn record(&self, f: LawFailure) {
        let mut g = self.first.lock().unwrap_or_else(|p| p.into_inner());
        if g.is_none() {
            *g = Some(f);
        }
    }
    /// True once the law failed.
    pub fn failed(&self) -> bool {
        self.first
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .is_some()
    }
    /// Take the failure out.
    pub fn take(&self) -> Option<LawFailure> {
        self.first.lock().unwrap_or_else(|p| p.into_inner()).take()
    }
    /// `message` without the law's name twice in a row (the assembler
    /// names the law in front of the law's own message, which names it
    /// too, for the element path that does not).
    pub fn tidy(&self, message: &str) -> String {
        match self.key.get() {
            Some(k) => {
                let once = format!("law `{k}`: ");
                message.replace(&format!("{once}{once}"), &once)
            }
            None => message.to_string(),
        }
    }
}

/// `(law id, state, outputs)` of the last point asked for.
type CachedOutputs = (u64, Vec<f64>, Vec<f64>);

/// Parameter documentation by law key.
type ParamDocs = BTreeMap<String, Vec<(String, String)>>;

thread_local! {
    /// The error slots of the laws built on this thread while a
    /// simulation is being read ([`collect_laws`]).
    static BUILT: RefCell<Option<Vec<Arc<ErrorSlot>>>> = const { RefCell::new(None) };
    /// The exception a factory raised while a simulation was being read.
    static FACTORY_ERROR: RefCell<Option<PyErr>> = const { RefCell::new(None) };
    /// The outputs of the last state asked for (`outputs`, `stage`
    /// and `failure_index` read the same point in a row).
    static LAST_OUTPUTS: RefCell<Option<CachedOutputs>> = const { RefCell::new(None) };
}

/// Run `f` (which reads a simulation) and return the error slots of the
/// Python laws it built, and the first exception a factory raised.
pub fn collect_laws<T>(f: impl FnOnce() -> T) -> (T, Vec<Arc<ErrorSlot>>, Option<PyErr>) {
    BUILT.with(|b| *b.borrow_mut() = Some(Vec::new()));
    FACTORY_ERROR.with(|e| *e.borrow_mut() = None);
    let r = f();
    let slots = BUILT.with(|b| b.borrow_mut().take()).unwrap_or_default();
    let err = FACTORY_ERROR.with(|e| e.borrow_mut().take());
    (r, slots, err)
}

/// Interned strings: the trait hands out `&'static str` keys and output
/// names; a law rebuilt for every simulation must not leak each time.
fn intern(s: &str) -> &'static str {
    static SET: Mutex<Option<HashSet<&'static str>>> = Mutex::new(None);
    let mut g = SET.lock().unwrap_or_else(|p| p.into_inner());
    let set = g.get_or_insert_with(HashSet::new);
    if let Some(x) = set.get(s) {
        return x;
    }
    let x: &'static str = Box::leak(s.to_string().into_boxed_str());
    set.insert(x);
    x
}

fn intern_names(names: &[String]) -> &'static [&'static str] {
    static MAP: Mutex<Option<BTreeMap<Vec<String>, &'static [&'static str]>>> = Mutex::new(None);
    let mut g = MAP.lock().unwrap_or_else(|p| p.into_inner());
    let map = g.get_or_insert_with(BTreeMap::new);
    if let Some(x) = map.get(names) {
        return x;
    }
    let v: Vec<&'static str> = names.iter().map(|n| intern(n)).collect();
    let x: &'static [&'static str] = Box::leak(v.into_boxed_slice());
    map.insert(names.to_vec(), x);
    x
}

/// Parameter docs of the laws registered from Python (for `junta.catalog()`).
pub fn law_params() -> ParamDocs {
    PARAMS
        .lock()
        .unwrap_or_else(|p| p.into_inner())
        .clone()
        .unwrap_or_default()
}

static PARAMS: Mutex<Option<ParamDocs>> = Mutex::new(None);

/// A law written in Python.
pub struct PyLaw {
    key: &'static str,
    /// Unique among the laws built in this process (the outputs cache).
    id: u64,
    evaluate: Py<PyAny>,
    init_fn: Option<Py<PyAny>>,
    outputs_fn: Option<Py<PyAny>>,
    failure_index_fn: Option<Py<PyAny>>,
    state_len: usize,
    stiffness: [f64; 3],
    kind: MatrixKind,
    output_names: &'static [&'static str],
    damage: Option<usize>,
    fracture: Option<FractureProperties>,
    warnings: Vec<String>,
    slot: Arc<ErrorSlot>,
    /// The outputs and failure indices of the states of the last
    /// [`InterfaceLaw::prefetch_outputs`].
    prefetched: Mutex<Prefetched>,
}

/// What one batched call of `outputs` and `failure_index` gave for a
/// block's distinct committed states, by state.
#[derive(Default)]
struct Prefetched {
    /// Row of each distinct state (its bits).
    rows: HashMap<Vec<u64>, usize>,
    /// `outputs`, `output_names.len()` values per row (empty without the
    /// method).
    outputs: Vec<f64>,
    /// `failure_index`, one per row (empty without the method).
    failure_index: Vec<f64>,
}

impl Prefetched {
    fn row(&self, state: &[f64]) -> Option<usize> {
        let key: Vec<u64> = state.iter().map(|v| v.to_bits()).collect();
        self.rows.get(&key).copied()
    }
}

impl std::fmt::Debug for PyLaw {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PyLaw")
            .field("key", &self.key)
            .field("state_len", &self.state_len)
            .field("initial_stiffness", &self.stiffness)
            .field("tangent_kind", &self.kind)
            .field("output_names", &self.output_names)
            .finish()
    }
}

/// Why one evaluation failed.
enum Failure {
    Python(PyErr),
    Invalid(String),
}

impl From<PyErr> for Failure {
    fn from(e: PyErr) -> Self {
        Failure::Python(e)
    }
}

/// Python's text of a shape: `(40, 3)`, `(40,)`.
fn shape_text(s: &[usize]) -> String {
    match s {
        [one] => format!("({one},)"),
        _ => format!(
            "({})",
            s.iter()
                .map(|x| x.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// `numpy.ascontiguousarray`.
fn ascontiguous<'py>(py: Python<'py>, v: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    static F: PyOnceLock<Py<PyAny>> = PyOnceLock::new();
    let f = F.get_or_try_init(py, || -> PyResult<Py<PyAny>> {
        Ok(py.import("numpy")?.getattr("ascontiguousarray")?.unbind())
    })?;
    let kw = PyDict::new(py);
    kw.set_item("dtype", "float64")?;
    f.bind(py).call((v,), Some(&kw))
}

impl PyLaw {
    /// `value` (what the law's `method` returned as `what`) as float64
    /// values of exactly the shape `expected`, all finite.
    fn values(
        &self,
        py: Python<'_>,
        value: &Bound<'_, PyAny>,
        method: &str,
        what: &str,
        expected: &[usize],
    ) -> Result<Vec<f64>, Failure> {
        let a = ascontiguous(py, value).map_err(|e| {
            Failure::Invalid(format!(
                "law `{}`: {method} returned {what} that is not an array of numbers ({})",
                self.key,
                describe(py, &e)
            ))
        })?;
        let a = a.cast_into::<PyArrayDyn<f64>>().map_err(|_| {
            Failure::Invalid(format!(
                "law `{}`: {method} returned {what} that numpy cannot read as float64",
                self.key
            ))
        })?;
        if a.shape() != expected {
            return Err(Failure::Invalid(format!(
                "law `{}`: {method} returned {what} of shape {}, expected {}",
                self.key,
                shape_text(a.shape()),
                shape_text(expected)
            )));
        }
        let v = a
            .to_vec()
            .map_err(|e| Failure::Invalid(format!("law `{}`: {method}: {what}: {e}", self.key)))?;
        if let Some(i) = v.iter().position(|x| !x.is_finite()) {
            let per = expected[1..].iter().product::<usize>().max(1);
            return Err(Failure::Invalid(format!(
                "law `{}`: {method} returned a non-finite {what} at point {} ({} at flat index {i})",
                self.key,
                i / per,
                v[i]
            )));
        }
        Ok(v)
    }

    fn call_evaluate(
        &self,
        py: Python<'_>,
        jumps: &[[f64; 3]],
        committed: &[f64],
        step: StepInfo,
        trial: &mut [f64],
        out: &mut [LawResponse],
    ) -> Result<(), Failure> {
        let n = jumps.len();
        let k = self.state_len;
        let jump = array(py, jumps.iter().flatten().copied().collect(), 3)?;
        let state = array(py, committed.to_vec(), 0)?.call_method1("reshape", ((n, k),))?;
        let info = step_dict(py, &step)?;
        let r = self.evaluate.bind(py).call1((jump, state, info))?;
        let r =
            r.cast_into::<PyTuple>().map_err(|e| {
                Failure::Invalid(format!(
                "law `{}`: evaluate returned {}, expected a tuple (traction, tangent, new_state)",
                self.key,
                e.into_inner().get_type().qualname().map(|s| s.to_string()).unwrap_or_default()
            ))
            })?;
        if r.len() != 3 {
            return Err(Failure::Invalid(format!(
                "law `{}`: evaluate returned a tuple of {} items, expected 3 (traction, tangent, new_state)",
                self.key,
                r.len()
            )));
        }
        let t = self.values(py, &r.get_item(0)?, "evaluate", "traction", &[n, 3])?;
        let d = self.values(py, &r.get_item(1)?, "evaluate", "tangent", &[n, 3, 3])?;
        let s_obj = r.get_item(2)?;
        if k > 0 || !s_obj.is_none() {
            let s = self.values(py, &s_obj, "evaluate", "new_state", &[n, k])?;
            trial[..n * k].copy_from_slice(&s);
        }
        for (i, o) in out.iter_mut().enumerate().take(n) {
            o.traction.copy_from_slice(&t[3 * i..3 * i + 3]);
            for a in 0..3 {
                o.tangent[a].copy_from_slice(&d[9 * i + 3 * a..9 * i + 3 * a + 3]);
            }
        }
        Ok(())
    }

    /// Record a failure and make the law's error of it.
    fn fail(&self, py: Python<'_>, f: Failure, method: &str) -> LawError {
        match f {
            Failure::Python(e) => {
                let message = format!("law `{}`: {method} raised {}", self.key, describe(py, &e));
                self.slot.record(LawFailure::Python(e));
                LawError::Failed(message)
            }
            Failure::Invalid(message) => {
                self.slot.record(LawFailure::Invalid(message.clone()));
                LawError::Failed(message)
            }
        }
    }

    /// Call `f(state[1, k])` and read `[1, m]` (or `[1]` when `m` is 0
    /// and the method returns one value per point).
    fn per_point(
        &self,
        py: Python<'_>,
        f: &Py<PyAny>,
        state: &[f64],
        method: &str,
        expected: &[usize],
    ) -> Result<Vec<f64>, Failure> {
        self.on_states(py, f, state, 1, method, expected)
    }

    /// Call `f(states[n, k])` and read the shape `expected`.
    fn on_states(
        &self,
        py: Python<'_>,
        f: &Py<PyAny>,
        states: &[f64],
        n: usize,
        method: &str,
        expected: &[usize],
    ) -> Result<Vec<f64>, Failure> {
        let s = array(py, states.to_vec(), self.state_len.max(1))?;
        let s = if self.state_len == 0 {
            s.call_method1("reshape", ((n, 0),))?
        } else {
            s
        };
        let r = f.bind(py).call1((s,))?;
        self.values(py, &r, method, "values", expected)
    }

    /// `outputs` and `failure_index` of the distinct states among
    /// `committed` (`state_len` values each), one call each.
    fn prefetch(
        &self,
        py: Python<'_>,
        committed: &[f64],
    ) -> Result<Prefetched, (Failure, &'static str)> {
        let k = self.state_len;
        let mut p = Prefetched::default();
        let mut distinct = Vec::new();
        for s in committed.chunks(k) {
            let key: Vec<u64> = s.iter().map(|v| v.to_bits()).collect();
            let next = p.rows.len();
            if let std::collections::hash_map::Entry::Vacant(e) = p.rows.entry(key) {
                e.insert(next);
                distinct.extend_from_slice(s);
            }
        }
        let n = p.rows.len();
        let m = self.output_names.len();
        if let Some(f) = &self.outputs_fn {
            p.outputs = self
                .on_states(py, f, &distinct, n, "outputs", &[n, m])
                .map_err(|e| (e, "outputs"))?;
        }
        if let Some(f) = &self.failure_index_fn {
            p.failure_index = self
                .on_states(py, f, &distinct, n, "failure_index", &[n])
                .map_err(|e| (e, "failure_index"))?;
        }
        Ok(p)
    }

    /// The prefetched outputs of `state`, if the last prefetch had it.
    fn prefetched_outputs(&self, state: &[f64]) -> Option<Vec<f64>> {
        let p = self.prefetched.lock().ok()?;
        let m = self.output_names.len();
        let r = p.row(state).filter(|_| !p.outputs.is_empty())?;
        Some(p.outputs[r * m..(r + 1) * m].to_vec())
    }

    /// The outputs of one point's state (NaN after an error, recorded).
    fn outputs_of(&self, state: &[f64]) -> Vec<f64> {
        if let Some(v) = self.prefetched_outputs(state) {
            return v;
        }
        let m = self.output_names.len();
        let me = self.id;
        if let Some(v) = LAST_OUTPUTS.with(|c| {
            c.borrow()
                .as_ref()
                .filter(|(id, s, _)| *id == me && s.as_slice() == state)
                .map(|(_, _, v)| v.clone())
        }) {
            return v;
        }
        let Some(f) = &self.outputs_fn else {
            return vec![f64::NAN; m];
        };
        let v = Python::attach(
            |py| match self.per_point(py, f, state, "outputs", &[1, m]) {
                Ok(v) => v,
                Err(e) => {
                    self.fail(py, e, "outputs");
                    vec![f64::NAN; m]
                }
            },
        );
        LAST_OUTPUTS.with(|c| *c.borrow_mut() = Some((me, state.to_vec(), v.clone())));
        v
    }
}

impl InterfaceLaw for PyLaw {
    fn key(&self) -> &'static str {
        self.key
    }
    fn state_len(&self) -> usize {
        self.state_len
    }
    fn init_state(&self, state: &mut [f64]) {
        state.iter_mut().for_each(|v| *v = 0.0);
        let Some(f) = &self.init_fn else { return };
        Python::attach(|py| {
            let r = (|| -> Result<Vec<f64>, Failure> {
                let r = f.bind(py).call1((1usize,))?;
                self.values(py, &r, "init_state", "state", &[1, self.state_len])
            })();
            match r {
                Ok(v) => state.copy_from_slice(&v),
                Err(e) => {
                    self.fail(py, e, "init_state");
                }
            }
        });
    }
    fn evaluate(
        &self,
        ctx: &LawContext<'_>,
        state_trial: &mut [f64],
    ) -> Result<LawResponse, LawError> {
        let mut out = [LawResponse::default()];
        self.evaluate_batch(
            &[ctx.jump],
            ctx.state_committed,
            ctx.step,
            state_trial,
            &mut out,
        )?;
        Ok(out[0])
    }
    fn initial_stiffness(&self) -> [f64; 3] {
        self.stiffness
    }
    fn stage(&self, state: &[f64]) -> PointStage {
        match self.damage {
            Some(i) => PointStage::of_damage(self.outputs_of(state)[i]),
            None => PointStage::Intact,
        }
    }
    fn failure_index(&self, state: &[f64]) -> Option<f64> {
        let f = self.failure_index_fn.as_ref()?;
        if let Ok(p) = self.prefetched.lock() {
            if let Some(r) = p.row(state).filter(|_| !p.failure_index.is_empty()) {
                return Some(p.failure_index[r]);
            }
        }
        Python::attach(
            |py| match self.per_point(py, f, state, "failure_index", &[1]) {
                Ok(v) => Some(v[0]),
                Err(e) => {
                    self.fail(py, e, "failure_index");
                    None
                }
            },
        )
    }
    fn tangent_kind(&self) -> MatrixKind {
        self.kind
    }
    fn output_names(&self) -> &'static [&'static str] {
        self.output_names
    }
    fn outputs(&self, state: &[f64], out: &mut [f64]) {
        let v = self.outputs_of(state);
        for (o, x) in out.iter_mut().zip(v) {
            *o = x;
        }
    }
    fn fracture_properties(&self) -> Option<FractureProperties> {
        self.fracture
    }
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }
    fn is_batched(&self) -> bool {
        true
    }
    fn prefetch_outputs(&self, committed: &[f64]) {
        if self.state_len == 0 || (self.outputs_fn.is_none() && self.failure_index_fn.is_none()) {
            return;
        }
        let fresh = Python::attach(|py| match self.prefetch(py, committed) {
            Ok(p) => p,
            Err((e, method)) => {
                self.fail(py, e, method);
                Prefetched::default()
            }
        });
        if let Ok(mut p) = self.prefetched.lock() {
            *p = fresh;
        }
    }
    fn init_states(&self, states: &mut [f64]) {
        let k = self.state_len;
        states.iter_mut().for_each(|v| *v = 0.0);
        let Some(f) = self.init_fn.as_ref().filter(|_| k > 0) else {
            return;
        };
        let n = states.len() / k;
        Python::attach(|py| {
            let r = (|| -> Result<Vec<f64>, Failure> {
                let r = f.bind(py).call1((n,))?;
                self.values(py, &r, "init_state", "state", &[n, k])
            })();
            match r {
                Ok(v) => states.copy_from_slice(&v),
                Err(e) => {
                    self.fail(py, e, "init_state");
                }
            }
        });
    }
    fn evaluate_batch(
        &self,
        jumps: &[[f64; 3]],
        committed: &[f64],
        step: StepInfo,
        trial: &mut [f64],
        out: &mut [LawResponse],
    ) -> Result<(), LawError> {
        let k = self.state_len;
        if committed.len() != jumps.len() * k
            || trial.len() != jumps.len() * k
            || out.len() < jumps.len()
        {
            return Err(LawError::Failed(format!(
                "law `{}`: {} points with {} committed and {} trial state values (state_len {k})",
                self.key,
                jumps.len(),
                committed.len(),
                trial.len()
            )));
        }
        if jumps.is_empty() {
            return Ok(());
        }
        Python::attach(|py| {
            self.call_evaluate(py, jumps, committed, step, trial, out)
                .map_err(|f| self.fail(py, f, "evaluate"))
        })
    }
}

/// The step a Python law's `evaluate` sees: every field of [`StepInfo`]
/// (`crack_drive` a dict `{energy_release_rate, mode_ratio,
/// process_zone_length}` or `None`).
pub fn step_dict<'py>(py: Python<'py>, step: &StepInfo) -> PyResult<Bound<'py, PyDict>> {
    let info = PyDict::new(py);
    info.set_item("increment", step.increment)?;
    info.set_item("load_factor", step.load_factor)?;
    info.set_item("delta_load_factor", step.delta_load_factor)?;
    info.set_item("secant", step.secant)?;
    info.set_item("exact_tangent", step.exact_tangent)?;
    info.set_item("temperature_factor", step.temperature_factor)?;
    info.set_item("cycles", step.cycles)?;
    info.set_item("delta_cycles", step.delta_cycles)?;
    info.set_item("load_ratio", step.load_ratio)?;
    let drive = match &step.crack_drive {
        Some(c) => {
            let d = PyDict::new(py);
            d.set_item("energy_release_rate", c.energy_release_rate)?;
            d.set_item("mode_ratio", c.mode_ratio)?;
            d.set_item("process_zone_length", c.process_zone_length)?;
            Some(d)
        }
        None => None,
    };
    info.set_item("crack_drive", drive)?;
    Ok(info)
}

/// A [`StepInfo`] from a dict with any of [`step_dict`]'s keys (the
/// others at [`StepInfo::default`]); an unknown key is an error naming the
/// valid ones.
pub fn step_from_dict(step: Option<&Bound<'_, PyDict>>) -> PyResult<StepInfo> {
    let mut s = StepInfo::default();
    let Some(d) = step else { return Ok(s) };
    for (k, v) in d.iter() {
        let key: String = k.extract()?;
        match key.as_str() {
            "increment" => s.increment = v.extract()?,
            "load_factor" => s.load_factor = v.extract()?,
            "delta_load_factor" => s.delta_load_factor = v.extract()?,
            "secant" => s.secant = v.extract()?,
            "exact_tangent" => s.exact_tangent = v.extract()?,
            "temperature_factor" => s.temperature_factor = v.extract()?,
            "cycles" => s.cycles = v.extract()?,
            "delta_cycles" => s.delta_cycles = v.extract()?,
            "load_ratio" => s.load_ratio = v.extract()?,
            "crack_drive" if v.is_none() => s.crack_drive = None,
            "crack_drive" => {
                let c: BTreeMap<String, f64> = v.extract()?;
                let get = |name: &str| c.get(name).copied().unwrap_or(0.0);
                s.crack_drive = Some(junta_core::crack_drive::CrackDrive {
                    energy_release_rate: get("energy_release_rate"),
                    mode_ratio: get("mode_ratio"),
                    process_zone_length: get("process_zone_length"),
                });
            }
            _ => {
                return Err(pyo3::exceptions::PyKeyError::new_err(format!(
                    "step: unknown key `{key}`; valid: {}",
                    STEP_KEYS.join(", ")
                )))
            }
        }
    }
    Ok(s)
}

/// The keys of a step dict.
pub const STEP_KEYS: [&str; 10] = [
    "increment",
    "load_factor",
    "delta_load_factor",
    "secant",
    "exact_tangent",
    "temperature_factor",
    "cycles",
    "delta_cycles",
    "load_ratio",
    "crack_drive",
];

/// Build the law `key` from its factory and the scene's parameters.
fn build(
    key: &str,
    factory: &Py<PyAny>,
    table: &toml::Table,
) -> Result<Arc<dyn InterfaceLaw>, CoreError> {
    let invalid = |message: String| CoreError::InvalidParameters {
        kind: "law",
        key: key.to_string(),
        message,
    };
    Python::attach(|py| {
        let params = toml_table_to_py(py, table).map_err(|e| invalid(describe(py, &e)))?;
        let obj = factory.bind(py).call1((params,)).map_err(|e| {
            let m = format!("the Python factory raised {}", describe(py, &e));
            FACTORY_ERROR.with(|f| {
                let mut f = f.borrow_mut();
                if f.is_none() {
                    *f = Some(e);
                }
            });
            invalid(m)
        })?;
        let law = from_object(py, key, &obj).map_err(invalid)?;
        BUILT.with(|b| {
            if let Some(v) = b.borrow_mut().as_mut() {
                v.push(law.slot.clone());
            }
        });
        Ok(Arc::new(law) as Arc<dyn InterfaceLaw>)
    })
}

/// A [`PyLaw`] of a law object, checked: what is wrong, else the law.
pub fn from_object(py: Python<'_>, key: &str, obj: &Bound<'_, PyAny>) -> Result<PyLaw, String> {
    let d = |e: PyErr| describe(py, &e);
    let attr = |name: &str| obj.getattr_opt(name).map_err(d);
    let method = |name: &str| -> Result<Option<Py<PyAny>>, String> {
        match attr(name)? {
            Some(m) if m.is_callable() => Ok(Some(m.unbind())),
            Some(m) if m.is_none() => Ok(None),
            Some(_) => Err(format!("`{name}` of the law object is not callable")),
            None => Ok(None),
        }
    };
    let what = obj
        .get_type()
        .qualname()
        .map(|s| s.to_string())
        .unwrap_or_default();
    let state_len: usize = match attr("state_len")? {
        Some(v) => v
            .extract()
            .map_err(|_| format!("`state_len` of the law object ({what}) must be an int >= 0"))?,
        None => {
            return Err(format!(
                "the law object ({what}) has no `state_len` (an int >= 0)"
            ))
        }
    };
    let stiffness: [f64; 3] = match attr("initial_stiffness")? {
        Some(v) => {
            let s: Vec<f64> = v.extract().map_err(|_| {
                format!("`initial_stiffness` of the law object ({what}) must be three numbers (d1, d2, d3)")
            })?;
            if s.len() != 3 || !s.iter().all(|x| x.is_finite() && *x >= 0.0) {
                return Err(format!(
                    "`initial_stiffness` must be three finite numbers >= 0 (d1, d2, d3), not {s:?}"
                ));
            }
            [s[0], s[1], s[2]]
        }
        None => {
            return Err(format!(
                "the law object ({what}) has no `initial_stiffness` (d1, d2, d3)"
            ))
        }
    };
    let kind = match attr("tangent_kind")? {
        None => MatrixKind::SymmetricIndefinite,
        Some(v) if v.is_none() => MatrixKind::SymmetricIndefinite,
        Some(v) => match v.extract::<String>().as_deref() {
            Ok("spd") => MatrixKind::SymmetricPositiveDefinite,
            Ok("indefinite") => MatrixKind::SymmetricIndefinite,
            Ok("general") => MatrixKind::General,
            _ => {
                return Err(format!(
                    "`tangent_kind` = {} : use \"spd\", \"indefinite\" or \"general\"",
                    v.repr().map(|s| s.to_string()).unwrap_or_default()
                ))
            }
        },
    };
    let evaluate = method("evaluate")?.ok_or_else(|| {
        format!("the law object ({what}) has no `evaluate(jump, state, step)` method")
    })?;
    let names: Vec<String> = match attr("output_names")? {
        Some(v) if !v.is_none() => v
            .extract()
            .map_err(|_| "`output_names` must be a list of str".to_string())?,
        _ => Vec::new(),
    };
    if names.len() > 16 {
        return Err(format!(
            "{} output names; at most 16 are kept per point",
            names.len()
        ));
    }
    // the names every interface point reports whatever its law
    let reserved = junta::post::fields::FIXED_POINT_VALUES;
    if let Some(n) = names.iter().find(|n| reserved.contains(&n.as_str())) {
        return Err(format!(
            "output name `{n}` is reserved (the interface element reports it); reserved: {}",
            reserved.join(", ")
        ));
    }
    let outputs_fn = method("outputs")?;
    if !names.is_empty() && outputs_fn.is_none() {
        return Err("the law object has `output_names` but no `outputs(state)` method".into());
    }
    let fracture = match attr("fracture_properties")? {
        Some(v) if !v.is_none() => {
            let m: BTreeMap<String, f64> = v.extract().map_err(|_| {
                "`fracture_properties` must be a dict of numbers with N, S, G_Ic, G_IIc".to_string()
            })?;
            let get = |k: &str| {
                m.get(k)
                    .copied()
                    .ok_or_else(|| format!("`fracture_properties` lacks `{k}` (N, S, G_Ic, G_IIc)"))
            };
            Some(FractureProperties {
                strength_normal: get("N")?,
                strength_shear: get("S")?,
                toughness_mode_i: get("G_Ic")?,
                toughness_mode_ii: get("G_IIc")?,
                penalty: stiffness,
            })
        }
        _ => None,
    };
    let warnings: Vec<String> = match attr("warnings")? {
        Some(v) if !v.is_none() => v
            .extract()
            .map_err(|_| "`warnings` must be a list of str".to_string())?,
        _ => Vec::new(),
    };
    Ok(PyLaw {
        key: intern(key),
        id: {
            static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
            NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
        },
        evaluate,
        init_fn: method("init_state")?,
        outputs_fn,
        failure_index_fn: method("failure_index")?,
        state_len,
        stiffness,
        kind,
        damage: names.iter().position(|n| n == output::DAMAGE),
        output_names: intern_names(&names),
        fracture,
        warnings,
        slot: {
            let slot = Arc::new(ErrorSlot::default());
            let _ = slot.key.set(intern(key));
            slot
        },
        prefetched: Mutex::new(Prefetched::default()),
    })
}

/// `junta.register_law(name, factory, description, params)`: the law's
/// evaluate method is bound (the bound method keeps the object alive).
#[pyfunction]
#[pyo3(signature = (name, factory, description = None, params = None))]
pub fn register_law(
    py: Python<'_>,
    name: String,
    factory: Py<PyAny>,
    description: Option<String>,
    params: Option<Vec<(String, String)>>,
) -> PyResult<()> {
    if !factory.bind(py).is_callable() {
        return Err(pyo3::exceptions::PyTypeError::new_err(
            "register_law: `factory` must be callable: factory(params: dict) -> law object",
        ));
    }
    let valid = !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
    if !valid {
        return Err(crate::errors::new_error(
            py,
            "InputError",
            format!("register_law: `{name}` is not a valid law name (snake_case: a-z, 0-9, _)"),
        ));
    }
    let key = name.clone();
    let law = RuntimeLaw {
        key: name.clone(),
        description: description.unwrap_or_else(|| "a traction law written in Python".into()),
        build: Arc::new(move |t: &toml::Table| build(&key, &factory, t)),
    };
    registry::register_runtime_law(law)
        .map_err(|e| crate::errors::new_error(py, "InputError", e.to_string()))?;
    let mut g = PARAMS.lock().unwrap_or_else(|p| p.into_inner());
    g.get_or_insert_with(BTreeMap::new)
        .insert(name, params.unwrap_or_default());
    Ok(())
}

/// `junta.unregister_law(name)`: true when it was registered.
#[pyfunction]
pub fn unregister_law(name: &str) -> bool {
    let mut g = PARAMS.lock().unwrap_or_else(|p| p.into_inner());
    if let Some(m) = g.as_mut() {
        m.remove(name);
    }
    registry::unregister_runtime_law(name)
}

/// `junta._junta.evaluate_law(law_object, jump, state, step)`: evaluate a law
/// object through the same checks as a run (for tests and `check_tangent`).
#[pyfunction]
#[pyo3(signature = (law, jump, state, step = None))]
pub fn evaluate_law<'py>(
    py: Python<'py>,
    law: &Bound<'py, PyAny>,
    jump: Vec<[f64; 3]>,
    state: Vec<f64>,
    step: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyTuple>> {
    let l = from_object(py, "(law object)", law)
        .map_err(|m| crate::errors::new_error(py, "LawError", m))?;
    let n = jump.len();
    let mut trial = vec![0.0; n * l.state_len];
    let mut out = vec![LawResponse::default(); n];
    let step = step_from_dict(step)?;
    if let Err(f) = l.call_evaluate(py, &jump, &state, step, &mut trial, &mut out) {
        return Err(match f {
            Failure::Python(e) => e,
            Failure::Invalid(m) => crate::errors::new_error(py, "LawError", m),
        });
    }
    let t: Vec<f64> = out.iter().flat_map(|r| r.traction).collect();
    let d: Vec<f64> = out
        .iter()
        .flat_map(|r| r.tangent.into_iter().flatten())
        .collect();
    let d = array(py, d, 0)?.call_method1("reshape", ((n, 3, 3),))?;
    let s = array(py, trial, 0)?.call_method1("reshape", ((n, l.state_len),))?;
    PyTuple::new(py, [array(py, t, 3)?, d, s])
}

/// `junta._junta.evaluate_registered(key, params, jump, state, ...)`: build
/// the law `key` from the registry (compiled or registered at run time)
/// with `params` and evaluate it at the points `jump` with the committed
/// `state` (`None`: the law's initial state) point by point, as the
/// elements do: `(traction [n, 3], tangent [n, 3, 3], new_state [n, k])`.
/// For comparing a Python law with a compiled one.
#[pyfunction]
#[pyo3(signature = (key, params, jump, state = None, step = None))]
pub fn evaluate_registered<'py>(
    py: Python<'py>,
    key: &str,
    params: &Bound<'py, PyDict>,
    jump: Vec<[f64; 3]>,
    state: Option<Vec<f64>>,
    step: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyTuple>> {
    let table = match crate::convert::py_to_toml(params.as_any(), "params")? {
        toml::Value::Table(t) => t,
        _ => unreachable!("a dict converts to a table"),
    };
    let law = registry::build_law(key, &table)
        .map_err(|e| crate::errors::new_error(py, "InputError", e.to_string()))?;
    let n = jump.len();
    let k = law.state_len();
    let committed = match state {
        Some(s) => s,
        None => {
            let mut s = vec![0.0; n * k];
            if k > 0 {
                s.chunks_mut(k).for_each(|c| law.init_state(c));
            }
            s
        }
    };
    if committed.len() != n * k {
        return Err(crate::errors::new_error(
            py,
            "InputError",
            format!("state: {} values for {n} points of {k}", committed.len()),
        ));
    }
    let step = step_from_dict(step)?;
    let mut trial = vec![0.0; n * k];
    let mut t = Vec::with_capacity(3 * n);
    let mut d = Vec::with_capacity(9 * n);
    for (i, j) in jump.iter().enumerate() {
        let ctx = LawContext {
            jump: *j,
            state_committed: &committed[i * k..(i + 1) * k],
            step,
        };
        let r = law
            .evaluate(&ctx, &mut trial[i * k..(i + 1) * k])
            .map_err(|e| crate::errors::new_error(py, "LawError", format!("point {i}: {e}")))?;
        t.extend(r.traction);
        d.extend(r.tangent.into_iter().flatten());
    }
    let d = array(py, d, 0)?.call_method1("reshape", ((n, 3, 3),))?;
    let s = array(py, trial, 0)?.call_method1("reshape", ((n, k),))?;
    PyTuple::new(py, [array(py, t, 3)?, d, s])
}
