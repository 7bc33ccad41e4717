//! Linear static analysis: one Newton step from the prescribed state.
//!
//! With `u0` holding the prescribed values (zero elsewhere), the internal
//! force of the elements carries the prescribed displacements into the
//! right-hand side (elimination of Dirichlet conditions):
//!
//! ```text
//! K_ff du_f = f_ext,f - f_int,f(u0),   u = u0 + du
//! reactions r = f_int(u) - f_ext   (read on constrained dofs)
//! ```
//!
//! For linear elements this is exact in one step; the residual on the free
//! dofs after the solve measures the solve's accuracy and is reported.

use junta_core::dof::CONSTRAINED;
use junta_core::element::StepInfo;
use junta_core::state::StateStore;
use junta_core::{CoreError, LinearSolver, Model, SolveReport, SolverError};
use std::time::Instant;
use thiserror::Error;

/// Failure of an analysis.
#[derive(Debug, Error)]
pub enum AnalysisError {
    /// Model or element failure.
    #[error(transparent)]
    Core(#[from] CoreError),
    /// Linear solver failure.
    #[error(transparent)]
    Solver(#[from] SolverError),
}

/// Wall-clock seconds of the phases of a run.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Timings {
    /// Pattern construction (symbolic assembly).
    pub pattern: f64,
    /// Numeric assembly (all calls).
    pub assemble: f64,
    /// Symbolic analysis of the solver (ordering).
    pub analyze: f64,
    /// Numeric factorisation.
    pub factor: f64,
    /// Triangular solves / iterations.
    pub solve: f64,
    /// Whole analysis.
    pub total: f64,
}

/// Result of a linear static analysis.
#[derive(Debug, Clone)]
pub struct LinearStaticResult {
    /// Nodal displacements (length = dofs).
    pub u: Vec<f64>,
    /// `f_int(u) - f_ext` (reactions on constrained dofs, ~0 elsewhere).
    pub residual: Vec<f64>,
    /// Relative residual on the free dofs, `|r_f| / max(|f_ext,f|, |f_int|)`.
    pub free_residual: f64,
    /// Final element state.
    pub state: StateStore,
    /// Solver report.
    pub report: SolveReport,
    /// Timings.
    pub timings: Timings,
}

fn norm(v: impl Iterator<Item = f64>) -> f64 {
    v.map(|x| x * x).sum::<f64>().sqrt()
}

/// Solve a linear static problem at load factor 1.
pub fn solve_linear_static(
    model: &Model,
    solver: &mut dyn LinearSolver,
) -> Result<LinearStaticResult, AnalysisError> {
    let t0 = Instant::now();
    let mut timings = Timings::default();
    let t = Instant::now();
    let mut asm = model.assembler();
    timings.pattern = t.elapsed().as_secs_f64();
    tracing::info!(
        equations = model.dofs.num_free,
        nonzeros = asm.pattern.nnz(),
        colors = asm.colors.len(),
        "pattern built"
    );
    // Assemble into the assembler's own pattern (taken, not cloned: one copy
    // of K is 130 MB at 100k 3D equations); `assemble` only reads the
    // pattern of the matrix it is given.
    let mut k = std::mem::take(&mut asm.pattern);
    let ndof = model.dofs.num_dofs();
    let mut f_int = vec![0.0; ndof];
    let mut state = model.initial_state();
    let step = StepInfo {
        increment: 0,
        load_factor: 1.0,
        delta_load_factor: 1.0,
    };
    let u0 = model.dofs.expand(None, 1.0);
    let t = Instant::now();
    asm.assemble(
        &model.mesh,
        &model.elements,
        &model.dofs,
        &u0,
        &mut state,
        step,
        Some(&mut k),
        &mut f_int,
    )?;
    timings.assemble += t.elapsed().as_secs_f64();
    let mut rhs: Vec<f64> = vec![0.0; model.dofs.num_free];
    for (d, &e) in model.dofs.eq.iter().enumerate() {
        if e != CONSTRAINED {
            rhs[e] = model.f_ext[d] - f_int[d];
        }
    }
    let coords = model.dofs.equation_coords(&model.mesh.nodes);
    let t = Instant::now();
    solver.analyze(&k, Some(&coords))?;
    timings.analyze = t.elapsed().as_secs_f64();
    let t = Instant::now();
    solver.factorize(&k)?;
    timings.factor = t.elapsed().as_secs_f64();
    let t = Instant::now();
    solver.solve_in_place(&k, &mut rhs)?;
    timings.solve = t.elapsed().as_secs_f64();
    drop(k);
    let u = model.dofs.expand(Some(&rhs), 1.0);
    let t = Instant::now();
    asm.assemble(
        &model.mesh,
        &model.elements,
        &model.dofs,
        &u,
        &mut state,
        step,
        None,
        &mut f_int,
    )?;
    timings.assemble += t.elapsed().as_secs_f64();
    let residual: Vec<f64> = f_int.iter().zip(&model.f_ext).map(|(a, b)| a - b).collect();
    let free = |v: &[f64]| {
        norm(
            model
                .dofs
                .eq
                .iter()
                .enumerate()
                .filter(|(_, &e)| e != CONSTRAINED)
                .map(|(d, _)| v[d]),
        )
    };
    let scale = free(&model.f_ext)
        .max(norm(f_int.iter().copied()))
        .max(f64::MIN_POSITIVE);
    let free_residual = free(&residual) / scale;
    state.commit();
    timings.total = t0.elapsed().as_secs_f64();
    Ok(LinearStaticResult {
        u,
        residual,
        free_residual,
        state,
        report: solver.report(),
        timings,
    })
}
