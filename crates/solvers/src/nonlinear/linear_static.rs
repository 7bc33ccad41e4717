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
//!
//! A model's temperature field ([`Model::temperature`]) is applied whole
//! (temperature factor 1): its thermal force is part of `f_int(u0)`, so
//! the solve answers the loads and the temperature change together.

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
    /// Relative residual on the free dofs, `|r_f| / max(|f_ext,f|, |f_int|, |r_0,f|)`
    /// (`r_0 = f_ext - f_int(u_0)`: the load the solve balances, thermal
    /// strains and prescribed displacements included).
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
    let case = LoadCase {
        prescribed: &model.dofs.prescribed,
        f_ext: &model.f_ext,
    };
    let mut results = solve_linear_static_cases(model, solver, &[case])?;
    Ok(results.pop().expect("one result per case"))
}

/// One load case of [`solve_linear_static_cases`]: the prescribed values
/// (full length, read on the model's constrained dofs) and the external
/// forces (full length).
#[derive(Debug, Clone, Copy)]
pub struct LoadCase<'a> {
    /// Prescribed displacement of every dof (length 3 x nodes); only the
    /// constrained dofs are read.
    pub prescribed: &'a [f64],
    /// External nodal forces of every dof (length 3 x nodes).
    pub f_ext: &'a [f64],
}

/// Solve several load cases that share the model's stiffness and its set
/// of constrained dofs (the steps of a linear deck): the stiffness is
/// assembled, analysed and factorised once, then each case costs one
/// force assembly for its prescribed values, one solve and one force
/// assembly for its reactions. The first result's timings hold the shared
/// work; each later one only its own.
pub fn solve_linear_static_cases(
    model: &Model,
    solver: &mut dyn LinearSolver,
    cases: &[LoadCase<'_>],
) -> Result<Vec<LinearStaticResult>, AnalysisError> {
    let ndof = model.dofs.num_dofs();
    check_cases(cases, ndof)?;
    let mut t0 = Instant::now();
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
    // pattern of the matrix it is given. The stiffness is assembled once,
    // at the first case's prescribed state (all cases share it: linear
    // elements), together with that case's f_int(u0).
    let mut k = std::mem::take(&mut asm.pattern);
    // a nonsymmetric tangent in full for a back end that solves it (else
    // its symmetric part, see `newton`)
    k.set_general(
        model.matrix_kind() == junta_core::MatrixKind::General
            && solver.accepts(junta_core::MatrixKind::General),
    );
    let mut f_int = vec![0.0; ndof];
    let step = StepInfo::at(0, 1.0, 1.0);
    let u0_first = cases
        .first()
        .map_or_else(|| vec![0.0; ndof], |c| initial_displacement(model, c));
    let t = Instant::now();
    asm.assemble(
        &model.mesh,
        &model.elements,
        &model.dofs,
        &u0_first,
        &mut model.initial_state(),
        step,
        Some(&mut k),
        &mut f_int,
    )?;
    timings.assemble += t.elapsed().as_secs_f64();
    drop(u0_first);
    // every dof prescribed (a displacement-driven patch test): nothing to
    // solve, u is the prescribed field
    let solves = k.n > 0;
    let t = Instant::now();
    if solves {
        solver.set_layout(&model.equation_layout());
        // the equations' points (GAMG's rigid-body modes), for the analysis only
        let coords = model.dofs.equation_coords(&model.mesh.nodes);
        solver.analyze(&k, Some(&coords))?;
    }
    timings.analyze = t.elapsed().as_secs_f64();
    let t = Instant::now();
    if solves {
        solver.factorize(&k)?;
    }
    timings.factor = t.elapsed().as_secs_f64();
    // norm of the reduced (free-equation) part of a force vector
    let free = |v: &[f64]| norm(model.dofs.reduce(v).into_iter());
    let mut results = Vec::with_capacity(cases.len());
    for (i, case) in cases.iter().enumerate() {
        let mut state = model.initial_state();
        // u0: the case's prescribed values on the constrained dofs, and
        // f_int(u0) (the first case's came with the stiffness)
        let u0 = initial_displacement(model, case);
        if i > 0 {
            let t = Instant::now();
            asm.assemble(
                &model.mesh,
                &model.elements,
                &model.dofs,
                &u0,
                &mut state,
                step,
                None,
                &mut f_int,
            )?;
            timings.assemble += t.elapsed().as_secs_f64();
        }
        let r: Vec<f64> = case.f_ext.iter().zip(&f_int).map(|(a, b)| a - b).collect();
        let mut rhs = model.dofs.reduce(&r);
        // the load the solve balances: applied forces, prescribed
        // displacements and thermal strains alike
        let initial_residual = norm(rhs.iter().copied());
        let factor_before = solver.report().factor_seconds;
        let t = Instant::now();
        if solves {
            solver.solve_in_place(&k, &mut rhs)?;
        }
        // a refactorisation inside the solve (mixed precision falling back
        // to double) is factor time
        let refactor = (solver.report().factor_seconds - factor_before).max(0.0);
        timings.factor += refactor;
        timings.solve = t.elapsed().as_secs_f64() - refactor;
        let mut u = u0;
        for (d, &e) in model.dofs.eq.iter().enumerate() {
            if e != CONSTRAINED {
                u[d] = rhs[e];
            }
        }
        model.dofs.fill_dependents(&mut u);
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
        let residual: Vec<f64> = f_int.iter().zip(case.f_ext).map(|(a, b)| a - b).collect();
        let scale = free(case.f_ext)
            .max(norm(f_int.iter().copied()))
            .max(initial_residual)
            .max(f64::MIN_POSITIVE);
        let free_residual = free(&residual) / scale;
        state.commit();
        timings.total = t0.elapsed().as_secs_f64();
        results.push(LinearStaticResult {
            u,
            residual,
            free_residual,
            state,
            report: solver.report(),
            timings,
        });
        timings = Timings::default();
        t0 = Instant::now();
    }
    drop(k);
    Ok(results)
}

/// Every load case gives a prescribed value and a force for each of the
/// model's `ndof` dofs.
fn check_cases(cases: &[LoadCase<'_>], ndof: usize) -> Result<(), AnalysisError> {
    for (i, c) in cases.iter().enumerate() {
        if c.prescribed.len() != ndof || c.f_ext.len() != ndof {
            return Err(CoreError::Invalid(format!(
                "load case {i}: {} prescribed values and {} forces for {ndof} dofs",
                c.prescribed.len(),
                c.f_ext.len()
            ))
            .into());
        }
    }
    Ok(())
}

/// The starting displacement of a load case: its prescribed values on the
/// constrained dofs (dependents of linear equations excepted), zero on the
/// free ones, the dependents from their equations.
fn initial_displacement(model: &Model, case: &LoadCase<'_>) -> Vec<f64> {
    let ndof = model.dofs.num_dofs();
    let mut u: Vec<f64> = (0..ndof)
        .map(|d| match model.dofs.eq[d] {
            CONSTRAINED if !model.dofs.dependents.contains(d) => case.prescribed[d],
            _ => 0.0,
        })
        .collect();
    model.dofs.fill_dependents(&mut u);
    u
}
