//! The linear solver `petsc`: one system distributed over the ranks,
//! solved by PETSc.
//!
//! **The matrix.** Each rank holds the tangent of its own elements
//! ([`junta_core::assembly::Assembler::for_rank`]) in Junta's upper-triangle
//! storage. `analyze` numbers the equations for PETSc so that each rank owns
//! a contiguous range of rows: an equation belongs to the lowest rank whose
//! elements touch it, and the ranks' equations follow one another (rank 0's
//! first), each in Junta's order. The entries of rows another rank owns (the
//! nodes shared with a lower rank) are sent to it, and each rank gives PETSc
//! its own rows, summed, in CSR form ([`crate::owned_rows`]). The pattern is
//! fixed, so the symbolic factorisation is PETSc's to reuse.
//!
//! **The methods** (`method`):
//! - `mumps` (default): MUMPS, `LDL^T` for a symmetric tangent (positive
//!   definite or not; MUMPS `SYM = 2`) and `LU` for a nonsymmetric one, with
//!   the inertia (`MatGetInertia`: `-mat_mumps_icntl_13 1`) that path
//!   following and the instability report read as negative pivots;
//! - `gamg`: conjugate gradients (GMRES for a nonsymmetric tangent)
//!   preconditioned by PETSc's smoothed-aggregation multigrid, given the six
//!   rigid-body modes of the equations' points as its near-null space;
//! - `hypre`: the same Krylov methods with hypre's BoomerAMG.
//!
//! `options` adds PETSc options (`"-ksp_monitor -pc_gamg_threshold
//! 0.02"`), read after the method's settings, as are those of the
//! `PETSC_OPTIONS` environment variable.
//!
//! **The vectors.** Right-hand sides and solutions are whole on every rank
//! (the run's vectors are replicated): each rank gives PETSc its own rows
//! and receives the whole solution (`VecScatterCreateToAll`).

use crate::ffi::{self, PetscInt};
use crate::owned_rows::{OwnedRows, RowMap};
use junta_core::registry::{ParamDoc, SolverEntry};
use junta_core::{
    CoreError, EquationLayout, LinearSolver, MatrixKind, SolveReport, SolverError, SymmetricCsc,
};
use std::ffi::{c_void, CString};
use std::time::Instant;

/// The PETSc methods.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// MUMPS direct factorisation.
    Mumps,
    /// Krylov + PETSc GAMG with the rigid-body near-null space.
    Gamg,
    /// Krylov + hypre BoomerAMG.
    Hypre,
}

impl Method {
    fn name(self) -> &'static str {
        match self {
            Method::Mumps => "mumps",
            Method::Gamg => "gamg",
            Method::Hypre => "hypre",
        }
    }
}

/// How Junta's equations map to PETSc's rows on this rank.
#[derive(Debug, Default)]
struct Numbering {
    /// PETSc row of each Junta equation (below 2^31: PETSc's 32-bit
    /// `PetscInt`).
    row: Vec<u32>,
    /// Junta equations of this rank's PETSc rows, in order.
    owned: Vec<usize>,
    /// First PETSc row of each rank, and the number of rows last.
    start: Vec<usize>,
}

/// The `petsc` back end ([module docs](self)).
#[derive(Debug)]
pub struct PetscSolver {
    method: Method,
    tolerance: f64,
    max_iterations: usize,
    /// The component (0 = x, 1 = y, 2 = z) of every equation, from
    /// `set_layout`, until the near-null space is built from it: all the
    /// equation layout GAMG needs (the whole layout, 13 bytes an equation,
    /// was kept on every rank for the run).
    components: Option<Vec<u8>>,
    numbering: Numbering,
    system: *mut c_void,
    general: bool,
    rows: OwnedRows,
    b_local: Vec<f64>,
    report: SolveReport,
}

// SAFETY: the PETSc system is used by one thread at a time (the driver's).
unsafe impl Send for PetscSolver {}

impl Drop for PetscSolver {
    fn drop(&mut self) {
        // SAFETY: created by junta_system_create or null.
        unsafe { ffi::junta_system_destroy(self.system) };
    }
}

/// PETSc's error code for a failed allocation (`PETSC_ERR_MEM`,
/// `petscerror.h`).
const PETSC_ERR_MEM: i32 = 55;

/// A PETSc call's error code as a solver error: a failed allocation is
/// "not enough memory", any other the call's failure with PETSc's text.
fn petsc(code: i32, what: &str) -> Result<(), SolverError> {
    match code {
        0 => Ok(()),
        PETSC_ERR_MEM => Err(SolverError::OutOfMemory {
            detail: format!("PETSc {what} could not allocate on a rank (PETSC_ERR_MEM); more ranks need less per rank"),
        }),
        // PETSc's own codes are below 100 (PETSC_ERR_MAX_VALUE); a larger
        // one comes from a library it called (MPI, a factorisation package)
        _ if code >= 100 => Err(SolverError::Library(format!(
            "PETSc {what} failed with error code {code}, not one of PETSc's own (below 100): a library PETSc calls failed, such as MPI; a rank short of memory is one cause"
        ))),
        _ => Err(SolverError::Library(format!(
            "PETSc {what} failed (error {code}: {})",
            ffi::error_text(code)
        ))),
    }
}

fn c_string(s: &str) -> CString {
    CString::new(s.replace('\0', " ")).expect("no NUL left")
}

impl PetscSolver {
    /// A solver of `method` (iterative methods stop at the relative
    /// residual `tolerance` or after `max_iterations`).
    pub fn new(method: Method, tolerance: f64, max_iterations: usize) -> Self {
        PetscSolver {
            method,
            tolerance,
            max_iterations,
            components: None,
            numbering: Numbering::default(),
            system: std::ptr::null_mut(),
            general: false,
            rows: OwnedRows::default(),
            b_local: Vec::new(),
            report: SolveReport {
                solver: format!("petsc ({})", method.name()),
                ..Default::default()
            },
        }
    }

    /// Number the equations for PETSc: each rank's rows contiguous, an
    /// equation the lowest touching rank's ([module docs](self)).
    fn number(&mut self, m: &SymmetricCsc) -> Result<(), SolverError> {
        let c = junta_core::distributed::collective().ok_or_else(|| {
            SolverError::Usage("petsc: MPI is not started (run under mpirun)".into())
        })?;
        let (rank, size) = (c.rank(), c.size());
        let mut owner = vec![size; m.n];
        for j in 0..m.n {
            for p in m.col_ptr[j]..m.col_ptr[j + 1] {
                owner[j] = rank;
                owner[m.row_idx[p]] = rank;
            }
        }
        c.min_in_place_usize(&mut owner);
        if let Some(j) = owner.iter().position(|&o| o == size) {
            return Err(SolverError::Usage(format!(
                "petsc: equation {j} belongs to no element of any rank"
            )));
        }
        // rank r's rows start after those of the ranks before it
        let mut start = vec![0; size + 1];
        for &o in &owner {
            start[o + 1] += 1;
        }
        for r in 0..size {
            start[r + 1] += start[r];
        }
        let first = start[rank];
        let mut next = start.clone();
        let mut row = vec![0; m.n];
        let mut owned = Vec::with_capacity(start[rank + 1] - first);
        for (j, &o) in owner.iter().enumerate() {
            row[j] = next[o] as u32;
            next[o] += 1;
            if o == rank {
                owned.push(j);
            }
        }
        self.numbering = Numbering { row, owned, start };
        Ok(())
    }

    /// Create the PETSc matrix, vectors and solver.
    fn create_system(&mut self, m: &SymmetricCsc, coords: &[[f64; 3]]) -> Result<(), SolverError> {
        let nb = &self.numbering;
        let map = RowMap {
            row: &nb.row,
            start: &nb.start,
            rank: junta_core::distributed::collective().map_or(0, |c| c.rank()),
        };
        let (rows, pattern) = OwnedRows::new(m, &map)?;
        self.rows = rows;
        // SAFETY: row_ptr has owned + 1 offsets into columns; system is out.
        petsc(
            unsafe {
                ffi::junta_system_create(
                    nb.owned.len() as PetscInt,
                    m.n as PetscInt,
                    pattern.row_ptr.as_ptr(),
                    pattern.columns.as_ptr(),
                    &mut self.system,
                )
            },
            "matrix creation (MatCreateMPIAIJWithArrays)",
        )?;
        let (ksp, pc, package) = match (self.method, self.general) {
            (Method::Mumps, false) => ("preonly", "cholesky", Some("mumps")),
            (Method::Mumps, true) => ("preonly", "lu", Some("mumps")),
            (Method::Gamg, g) => (if g { "gmres" } else { "cg" }, "gamg", None),
            (Method::Hypre, g) => (if g { "gmres" } else { "cg" }, "hypre", None),
        };
        let (ksp, pc) = (c_string(ksp), c_string(pc));
        let package = package.map(c_string);
        // SAFETY: valid C strings; system created above.
        petsc(
            unsafe {
                ffi::junta_system_solver(
                    self.system,
                    ksp.as_ptr(),
                    pc.as_ptr(),
                    package.as_ref().map_or(std::ptr::null(), |p| p.as_ptr()),
                    self.tolerance,
                    self.max_iterations.min(i32::MAX as usize) as PetscInt,
                )
            },
            "solver set-up (KSPSetFromOptions)",
        )?;
        if self.method == Method::Gamg {
            self.set_rigid_body_modes(coords)?;
        }
        let mut buf = vec![0u8; 128];
        // SAFETY: buf holds 128 bytes.
        if unsafe { ffi::junta_system_describe(self.system, buf.as_mut_ptr().cast(), buf.len()) }
            == 0
        {
            let end = buf.iter().position(|&b| b == 0).unwrap_or(buf.len());
            self.report.ordering = String::from_utf8_lossy(&buf[..end]).into_owned();
        }
        Ok(())
    }

    /// The six rigid-body modes of the equations' points (translations,
    /// rotations about the centroid), orthonormalised, as GAMG's
    /// near-null space. Needs the points and the equations' components.
    fn set_rigid_body_modes(&mut self, coords: &[[f64; 3]]) -> Result<(), SolverError> {
        let (Some(components), n) = (self.components.take(), self.numbering.row.len()) else {
            return Ok(());
        };
        if coords.len() != n || components.len() != n {
            return Ok(());
        }
        let centroid = coords
            .iter()
            .fold([0.0; 3], |a, x| [a[0] + x[0], a[1] + x[1], a[2] + x[2]])
            .map(|s| s / n.max(1) as f64);
        // this rank's rows of the modes; dot products summed over the ranks
        let owned = &self.numbering.owned;
        let mut modes = vec![vec![0.0; owned.len()]; 6];
        for (k, &j) in owned.iter().enumerate() {
            let c = components[j] as usize;
            let x = [
                coords[j][0] - centroid[0],
                coords[j][1] - centroid[1],
                coords[j][2] - centroid[2],
            ];
            let rot = [[0.0, -x[2], x[1]], [x[2], 0.0, -x[0]], [-x[1], x[0], 0.0]];
            modes[c][k] = 1.0;
            for a in 0..3 {
                modes[3 + a][k] = rot[a][c];
            }
        }
        let modes = orthonormal(modes, global_dot);
        let local: Vec<f64> = modes.concat();
        // SAFETY: local holds modes.len() * nlocal values.
        petsc(
            unsafe {
                ffi::junta_system_near_null_space(
                    self.system,
                    modes.len() as PetscInt,
                    local.as_ptr(),
                )
            },
            "near-null space (MatSetNearNullSpace)",
        )
    }
}

/// The error of a failed factorisation or preconditioner set-up, from
/// PETSc's `PCFailedReason` (`petscpc.h`: 1 and 2 a zero pivot, 3 out of
/// memory, 4 another factorisation failure, 6 a sub-preconditioner's).
fn set_up_failure(reason: i32, method: &str) -> SolverError {
    let what =
        |text: &str| format!(": PETSc {method} set-up failed (PCFailedReason {reason}: {text})");
    match reason {
        3 => SolverError::OutOfMemory {
            detail: format!(
                "PETSc {method}: the factorisation ran out of memory on a rank (PCFailedReason 3); more ranks, or `method = \"gamg\"`, need less per rank"
            ),
        },
        1 | 2 => SolverError::NotPositiveDefinite {
            detail: what("a zero pivot, a singular matrix"),
        },
        _ => SolverError::NotPositiveDefinite {
            detail: what("the factorisation or preconditioner failed"),
        },
    }
}

/// The dot product of two vectors held in parts by the ranks (each rank
/// its own rows), the same on every rank.
fn global_dot(a: &[f64], b: &[f64]) -> f64 {
    let mut d = [a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>()];
    if let Some(c) = junta_core::distributed::collective() {
        c.sum_in_place(&mut d);
    }
    d[0]
}

/// Modified Gram-Schmidt under the dot product `dot`; vectors that are
/// (nearly) dependent are dropped.
fn orthonormal(vectors: Vec<Vec<f64>>, dot: impl Fn(&[f64], &[f64]) -> f64) -> Vec<Vec<f64>> {
    let mut out: Vec<Vec<f64>> = Vec::new();
    for mut v in vectors {
        let norm0 = dot(&v, &v).sqrt();
        for q in &out {
            let d = dot(&v, q);
            v.iter_mut().zip(q).for_each(|(a, b)| *a -= d * b);
        }
        let norm = dot(&v, &v).sqrt();
        if norm > 1e-10 * norm0 && norm > 0.0 {
            v.iter_mut().for_each(|a| *a /= norm);
            out.push(v);
        }
    }
    out
}

impl LinearSolver for PetscSolver {
    fn key(&self) -> &'static str {
        "petsc"
    }

    fn analyze(
        &mut self,
        matrix: &SymmetricCsc,
        coords: Option<&[[f64; 3]]>,
    ) -> Result<(), SolverError> {
        let t = Instant::now();
        if matrix.n > i32::MAX as usize || 2 * matrix.nnz() > i32::MAX as usize {
            return Err(SolverError::OutOfMemory {
                detail: format!(
                    "petsc: {} equations and {} entries on this rank pass PETSc's 32-bit PetscInt (2^31 - 1) of the Debian build",
                    matrix.n,
                    2 * matrix.nnz()
                ),
            });
        }
        if !self.system.is_null() {
            // SAFETY: created by junta_system_create.
            unsafe { ffi::junta_system_destroy(self.system) };
            self.system = std::ptr::null_mut();
        }
        // a rank without elements holds an empty matrix, which reads as
        // symmetric: the ranks agree (every rank must set up the same PC)
        self.general = matrix.is_general();
        if let Some(c) = junta_core::distributed::collective() {
            self.general = c.any(self.general);
        }
        self.number(matrix)?;
        self.create_system(matrix, coords.unwrap_or_default())?;
        self.b_local = vec![0.0; self.numbering.owned.len()];
        self.report.analyze_seconds += t.elapsed().as_secs_f64();
        Ok(())
    }

    fn factorize(&mut self, matrix: &SymmetricCsc) -> Result<(), SolverError> {
        if self.system.is_null() {
            return Err(SolverError::Usage("petsc: factorize before analyze".into()));
        }
        let t = Instant::now();
        let general = self.general;
        self.rows.assemble(matrix);
        let mut failed = 0;
        // SAFETY: values holds one value per entry of the owned rows.
        petsc(
            unsafe {
                ffi::junta_system_values(self.system, self.rows.values.as_ptr(), (!general) as i32)
            },
            "MatUpdateMPIAIJWithArray",
        )?;
        // SAFETY: system valid.
        petsc(
            unsafe { ffi::junta_system_setup(self.system, &mut failed) },
            "KSPSetUp",
        )?;
        self.report.factorizations += 1;
        self.report.factor_seconds += t.elapsed().as_secs_f64();
        if failed != 0 {
            return Err(set_up_failure(failed, &self.report.ordering));
        }
        // MUMPS gives the inertia of its LDL^T factor (not of an LU one)
        if self.method == Method::Mumps && !general {
            let (mut neg, mut zero, mut pos) = (0, 0, 0);
            // SAFETY: a factored direct solver.
            petsc(
                unsafe { ffi::junta_system_inertia(self.system, &mut neg, &mut zero, &mut pos) },
                "MatGetInertia",
            )?;
            self.report.negative_pivots = Some(neg.max(0) as usize);
            if zero > 0 {
                return Err(SolverError::NotPositiveDefinite {
                    detail: format!(
                        ": MUMPS found {zero} null pivots ({neg} negative, {pos} positive)"
                    ),
                });
            }
        }
        Ok(())
    }

    fn solve_in_place(&mut self, _matrix: &SymmetricCsc, b: &mut [f64]) -> Result<(), SolverError> {
        let t = Instant::now();
        let n = self.numbering.row.len();
        if b.len() != n || self.system.is_null() {
            return Err(SolverError::Usage(format!(
                "petsc: a right-hand side of {} entries for {n} equations (or no analyze)",
                b.len()
            )));
        }
        for (v, &j) in self.b_local.iter_mut().zip(&self.numbering.owned) {
            *v = b[j];
        }
        let bnorm = b.iter().map(|x| x * x).sum::<f64>().sqrt();
        let mut x_all = vec![0.0; n];
        let (mut reason, mut its, mut rnorm) = (0, 0, 0.0);
        // SAFETY: b_local holds this rank's rows, x_all all n.
        petsc(
            unsafe {
                ffi::junta_system_solve(
                    self.system,
                    self.b_local.as_ptr(),
                    x_all.as_mut_ptr(),
                    &mut reason,
                    &mut its,
                    &mut rnorm,
                )
            },
            "KSPSolve",
        )?;
        self.report.iterations = its.max(0) as usize;
        self.report.residual = if bnorm > 0.0 { rnorm / bnorm } else { 0.0 };
        self.report.solve_seconds += t.elapsed().as_secs_f64();
        if reason < 0 {
            return Err(SolverError::NotConverged {
                method: format!(
                    "petsc {} (KSPConvergedReason {reason})",
                    self.report.ordering
                ),
                iterations: self.report.iterations,
                residual: self.report.residual,
                tolerance: self.tolerance,
            });
        }
        for (j, v) in b.iter_mut().enumerate() {
            *v = x_all[self.numbering.row[j] as usize];
        }
        if let Some(j) = b.iter().position(|v| !v.is_finite()) {
            return Err(SolverError::NonFinite {
                method: format!("petsc {} (equation {j})", self.report.ordering),
            });
        }
        Ok(())
    }

    fn set_layout(&mut self, layout: &EquationLayout) {
        self.components = Some(layout.component.clone());
    }

    fn report(&self) -> SolveReport {
        self.report.clone()
    }

    fn accepts(&self, _kind: MatrixKind) -> bool {
        true
    }
}

/// Build `petsc` from its `[solver]` table.
fn build(table: &toml::Table) -> Result<Box<dyn LinearSolver>, CoreError> {
    let bad = |message: String| CoreError::InvalidParameters {
        kind: "solver",
        key: "petsc".into(),
        message,
    };
    // PETSc (its options database) exists only in a run under mpirun
    if junta_core::distributed::collective().is_none() {
        return Err(bad(
            "the `petsc` solver runs under MPI only: start junta with `mpirun -np N junta run ...`"
                .into(),
        ));
    }
    for key in table.keys() {
        if !PARAMS.iter().any(|p| p.name == key) {
            return Err(bad(format!(
                "unknown key `{key}`; valid keys: {}",
                PARAMS.iter().map(|p| p.name).collect::<Vec<_>>().join(", ")
            )));
        }
    }
    let method = match table.get("method").map(|v| v.as_str()) {
        None | Some(Some("mumps")) => Method::Mumps,
        Some(Some("gamg")) => Method::Gamg,
        Some(Some("hypre")) => Method::Hypre,
        Some(other) => {
            return Err(bad(format!(
                "`method` = {:?} is not valid; use \"mumps\", \"gamg\" or \"hypre\"",
                other.unwrap_or("(not a string)")
            )))
        }
    };
    let number = |key: &str, default: f64| -> Result<f64, CoreError> {
        match table.get(key) {
            None => Ok(default),
            Some(v) => v
                .as_float()
                .or_else(|| v.as_integer().map(|i| i as f64))
                .filter(|x| x.is_finite() && *x > 0.0)
                .ok_or_else(|| bad(format!("`{key}` must be a positive number, not {v}"))),
        }
    };
    let tolerance = number("tolerance", 1e-10)?;
    let max_iterations = number("max_iterations", 10_000.0)? as usize;
    if let Some(options) = table.get("options") {
        let text = options.as_str().ok_or_else(|| {
            bad(format!(
                "`options` must be a string of PETSc options, not {options}"
            ))
        })?;
        let c = c_string(text);
        // SAFETY: a valid C string; PETSc initialised (MPI runs only).
        let code = unsafe { ffi::junta_insert_options(c.as_ptr()) };
        if code != 0 {
            return Err(bad(format!(
                "`options` = {text:?}: PETSc rejects them: {}",
                ffi::error_text(code)
            )));
        }
    }
    if method == Method::Hypre {
        // BoomerAMG's settings for 3D problems (its defaults, classical
        // coarsening without truncation, ran a 680k-dof cube out of 24 GB):
        // HMIS coarsening, extended+i interpolation truncated to 4 entries,
        // one level of aggressive coarsening, strength threshold 0.5
        for (name, value) in [
            ("-pc_hypre_boomeramg_coarsen_type", "HMIS"),
            ("-pc_hypre_boomeramg_interp_type", "ext+i"),
            ("-pc_hypre_boomeramg_P_max", "4"),
            ("-pc_hypre_boomeramg_agg_nl", "1"),
            ("-pc_hypre_boomeramg_strong_threshold", "0.5"),
        ] {
            crate::set_default_option(name, value);
        }
    }
    Ok(Box::new(PetscSolver::new(
        method,
        tolerance,
        max_iterations,
    )))
}

const PARAMS: &[ParamDoc] = &[
    ParamDoc {
        name: "method",
        doc: "\"mumps\" (default: MUMPS LDL^T or LU, with the inertia), \"gamg\" (PETSc smoothed aggregation, rigid-body near-null space) or \"hypre\" (BoomerAMG) (default \"mumps\")",
    },
    ParamDoc {
        name: "tolerance",
        doc: "relative residual of the iterative methods (KSP rtol) (default 1e-10)",
    },
    ParamDoc {
        name: "max_iterations",
        doc: "iteration limit of the iterative methods (default 10000)",
    },
    ParamDoc {
        name: "options",
        doc: "PETSc options, e.g. \"-ksp_monitor -pc_gamg_threshold 0.02\" (after the method's settings; PETSC_OPTIONS too)",
    },
];

inventory::submit! {
    SolverEntry {
        key: "petsc",
        description: "PETSc over MPI ranks: MUMPS (default), GAMG or hypre BoomerAMG (needs the MPI build and mpirun)",
        params: PARAMS,
        build,
    }
}
