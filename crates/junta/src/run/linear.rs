//! Linear runs: one solve, or the steps of a deck as load cases sharing a
//! factorisation, and the files and summary they leave.

use crate::error::{err, Context, Result};
use crate::input::deck;
use crate::prepare::{build_solver, Prepared};
use crate::run::observer::Observer;
use crate::run::observer::{Phase, RunEnd, RunLog};
use crate::run::results::{RunResults, Status};
use junta_core::Model;
use junta_solvers::linear_static::solve_linear_static;
use serde_json::json;
use std::path::Path;
use std::time::Instant;

/// Run the linear analysis of `p`: write the standard files into `dir`
/// (when given) and hand the end state to the observers' `on_end`; keep the
/// end fields in [`RunResults::frame`] when `keep_frame`.
pub(crate) fn run_linear(
    input: &Path,
    p: &mut Prepared,
    dir: Option<&Path>,
    observers: &mut [&mut dyn Observer],
    keep_frame: bool,
) -> Result<RunResults> {
    let t0 = Instant::now();
    let mut notes = p.notes.clone();
    let mut warnings = Vec::new();
    for o in observers.iter_mut() {
        o.on_phase(&Phase::Solving {
            equations: p.model.dofs.num_free,
            elements: p.model.mesh.num_elements(),
            solver: p.solver.key().to_string(),
        });
    }
    let mut prints = std::mem::take(&mut p.prints);
    let (res, steps_summary) = if p.deck_steps.len() > 1 {
        let (res, steps) = solve_deck_steps(p, dir, observers, input, &mut prints)?;
        (res, Some(steps))
    } else {
        let res = solve_linear_static(&p.model, p.solver.as_mut())
            .with_context(|| format!("solving {}", input.display()))?;
        if !prints.is_empty() {
            prints.add_step(
                &p.model,
                0,
                &res.u,
                &res.residual,
                &p.model.f_ext,
                &res.state,
            )?;
        }
        (res, None)
    };
    warnings.extend(res.report.warnings.iter().cloned());
    notes.extend(res.report.notes.iter().cloned());
    if res.free_residual > 1e-6 {
        warnings.push(format!(
            "equilibrium residual after the solve is {:.3e} (relative); the result has lost digits",
            res.free_residual
        ));
    }
    for o in observers.iter_mut() {
        o.on_phase(&Phase::WritingResults);
    }
    let t_out = Instant::now();
    let interfaces = crate::post::fields::interface_results(&p.model, &res.u, &res.state)?;
    // a rank of an MPI run other than the writer, keeping no frame, has no
    // use for the whole model's cell averages and ply indices (about 60
    // bytes per element, and the time of every element's point outputs)
    let silent_rank =
        dir.is_none() && !keep_frame && junta_core::distributed::collective().is_some();
    let (cells, ply) = if silent_rank {
        (crate::post::fields::CellResults::default(), Vec::new())
    } else {
        let mut cells = crate::post::fields::cell_results(&p.model, &res.u, &res.state)?;
        let ply = ply_failure_cells(p, &res, &mut cells)?;
        (cells, ply)
    };
    if let Some(dir) = dir {
        write_result_files(dir, p, &res, &cells, &interfaces)?;
        notes.extend(prints.write(dir)?);
    }
    let (advice, _, advice_warnings) =
        crate::output::summary::penalty_advice(&p.model, &|b| p.thickness.get(b).copied())?;
    warnings.extend(advice_warnings);
    warnings.extend(crate::prepare::bending::bending_warnings(&p.model));
    let (largest_rotation, rotation_warning) = crate::post::rotation::summary_entry(
        &p.model,
        &res.u,
        crate::post::rotation::is_deck(input),
    );
    warnings.extend(rotation_warning);
    let reference = reference_entry(p, &res.residual)?;
    let output_seconds = t_out.elapsed().as_secs_f64();
    let reactions = crate::output::summary::reactions(&p.model, &res.residual)?;
    let probes =
        crate::output::summary::probes(&p.model, &p.probes, &res.u).context("[output] probes")?;
    let summary = json!({
        "input": input.display().to_string(),
        "title": p.title,
        "units": p.units,
        "analysis": "linear_static",
        "temperature": p.temperature,
        "nodes": p.model.mesh.nodes.len(),
        "dofs": p.model.dofs.num_dofs(),
        "equations": p.model.dofs.num_free,
        "elements": crate::output::summary::element_counts(&p.model),
        "distributed": crate::output::summary::distributed_summary(&p.model),
        "plane": crate::output::summary::plane_summary(&p.model),
        "reactions": reactions,
        "displacement_max": crate::output::summary::displacement_max(&res.u),
        "largest_rotation": largest_rotation,
        "probes": probes,
        "solids": crate::output::summary::solid_summary(&cells),
        "interfaces": crate::output::summary::interface_summary(&p.model, &interfaces),
        "penalty_advice": advice,
        "reference": reference,
        "equilibrium_residual": res.free_residual,
        "timings": timings_entry(p, &res.timings, output_seconds, t0),
        "solver": {
            "name": res.report.solver,
            "iterations": res.report.iterations,
            "residual": res.report.residual,
            "factor_nonzeros": res.report.factor_nonzeros,
            "ordering": res.report.ordering,
            "predicted_factor_nonzeros": crate::output::summary::ordering_candidates(&res.report),
            "precision": res.report.precision,
            "refinement_steps": res.report.refinement_steps,
            "warnings": res.report.warnings,
            "notes": res.report.notes,
        },
        "notes": p.notes,
    });
    let mut summary = summary;
    if !ply.is_empty() {
        summary["ply_failure"] = crate::post::ply_failure::summary(&ply, true);
    }
    crate::post::constraint_force::add_generalized_reactions(
        &mut summary,
        &p.model,
        &res.residual,
    )?;
    if !warnings.is_empty() {
        summary["warnings"] = json!(warnings);
    }
    if let Some(steps) = steps_summary {
        summary["steps"] = json!(steps);
    }
    let summary = crate::run::results::Summary::from_json(summary)?;
    if let Some(dir) = dir {
        crate::output::summary::write_json(&dir.join("summary.json"), &summary.to_json())?;
    }
    let frame = end_linear(&p.model, &res, &summary, observers, keep_frame)?;
    Ok(RunResults {
        status: Status::Completed,
        reason: crate::run::results::EndReason::EndOfProgram,
        status_line: "completed".into(),
        summary,
        rows: Vec::new(),
        output: dir.map(Path::to_path_buf),
        notes,
        warnings,
        failure: None,
        frame,
    })
}

/// `summary.json` `timings` of a linear run that started at `t0`.
fn timings_entry(
    p: &Prepared,
    t: &junta_solvers::linear_static::Timings,
    output_seconds: f64,
    t0: Instant,
) -> serde_json::Value {
    json!({
        "read": p.read_seconds,
        "choose_solver": p.choose_solver_seconds,
        "build": p.build.map(|b| b.seconds),
        "build_peak_bytes": p.build.and_then(|b| b.peak_bytes),
        "pattern": t.pattern,
        "assemble": t.assemble,
        "analyze": t.analyze,
        "factor": t.factor,
        "solve": t.solve,
        "output": output_seconds,
        "total": p.read_seconds + p.choose_solver_seconds + t0.elapsed().as_secs_f64(),
    })
}

/// `summary.json` `reference`: the scene's `[reference]` value against the
/// computed total of its set (`null` without one).
fn reference_entry(p: &Prepared, residual: &[f64]) -> Result<serde_json::Value> {
    Ok(match &p.reference {
        Some((r, c)) => {
            let computed = p
                .model
                .set_total(&r.set, residual)
                .context("key `reference.set`")?[*c];
            json!({
                "set": r.set, "component": r.component, "value": r.value, "source": r.source,
                "computed": computed, "relative_error": (computed - r.value).abs() / r.value.abs(),
            })
        }
        None => serde_json::Value::Null,
    })
}

/// `results.vtu`, the interface files and the fractions of a linear run.
/// The `[[ply_failure]]` criteria at the solution, their indices added to
/// the cell data.
fn ply_failure_cells(
    p: &Prepared,
    res: &junta_solvers::linear_static::LinearStaticResult,
    cells: &mut crate::post::fields::CellResults,
) -> Result<Vec<crate::post::ply_failure::PlyFailureResult>> {
    let step = junta_core::element::StepInfo::default();
    let ply =
        crate::post::ply_failure::evaluate(&p.model, &res.u, &res.state, step, &p.ply_criteria)?;
    crate::post::ply_failure::add_cell_data(&ply, cells);
    Ok(ply)
}

fn write_result_files(
    dir: &Path,
    p: &Prepared,
    res: &junta_solvers::linear_static::LinearStaticResult,
    cells: &crate::post::fields::CellResults,
    interfaces: &[crate::post::fields::InterfaceResults],
) -> Result<()> {
    if p.vtu {
        crate::output::vtu::write_vtu(&dir.join("results.vtu"), &p.model, &res.u, cells)?;
        crate::output::vtu::write_interface_vtu(dir, &p.model, &res.u, interfaces)?;
        if !p.fractions.is_empty() {
            crate::output::vtu::write_fractions(dir, &p.model, &res.u, &res.state, &p.fractions)?;
        }
    }
    Ok(())
}

/// The steps of a deck as linear load cases: steps that constrain the same
/// dofs share one factorisation; a step that changes the constrained dofs
/// starts a new model. Writes `results_stepN.vtu` per step and
/// `results.pvd`; returns the last step's result (with the timings of all
/// steps) and one summary object per step. On return `p.model` is the model
/// of the last step.
#[allow(clippy::too_many_arguments)]
fn solve_deck_steps(
    p: &mut Prepared,
    dir: Option<&Path>,
    observers: &mut [&mut dyn Observer],
    input: &Path,
    prints: &mut crate::output::deck_print::PrintTables,
) -> Result<(
    junta_solvers::linear_static::LinearStaticResult,
    Vec<serde_json::Value>,
)> {
    use junta_solvers::linear_static::{solve_linear_static_cases, LoadCase, Timings};
    let file = input.display().to_string();
    let steps = std::mem::take(&mut p.deck_steps);
    let dofs_of = |s: &deck::DeckStep| s.constraints.iter().map(|c| c.0).collect::<Vec<_>>();
    let mut summaries = Vec::with_capacity(steps.len());
    let mut frames = Vec::new();
    let mut total = Timings::default();
    let mut last = None;
    let mut k = 0;
    while k < steps.len() {
        // steps with the same constrained dofs and temperatures share a
        // factorisation
        let mut end = k + 1;
        while end < steps.len()
            && dofs_of(&steps[end]) == dofs_of(&steps[k])
            && steps[end].temperature == steps[k].temperature
        {
            end += 1;
        }
        if k > 0 {
            // other constrained dofs: another dof map, pattern and factor
            let m = &p.model;
            p.model = Model::new(
                m.mesh.clone(),
                m.elements.clone(),
                &steps[k].constraints,
                steps[k].f_ext.clone(),
                m.reaction_sets.clone(),
            )
            .and_then(|mut new| {
                new.add_equations(&m.equations)?;
                Ok(new)
            })
            .map_err(|e| err!("{file}: {} (line {}): {e}", steps[k].name, steps[k].line))?;
            p.solver = build_solver(&p.solver_key, &p.solver_table, &file)?;
        }
        // the steps' temperature change (their thermal load and stresses)
        p.model
            .set_temperature(steps[k].temperature.clone())
            .map_err(|e| err!("{file}: {} (line {}): {e}", steps[k].name, steps[k].line))?;
        let ndof = p.model.dofs.num_dofs();
        let prescribed: Vec<Vec<f64>> = steps[k..end]
            .iter()
            .map(|s| {
                let mut v = vec![0.0; ndof];
                for &(d, x) in &s.constraints {
                    v[d] = x;
                }
                v
            })
            .collect();
        let cases: Vec<LoadCase<'_>> = steps[k..end]
            .iter()
            .zip(&prescribed)
            .map(|(s, pr)| LoadCase {
                prescribed: pr,
                f_ext: &s.f_ext,
            })
            .collect();
        let phase = Phase::SolvingSteps {
            first: k + 1,
            last: end,
            total: steps.len(),
            equations: p.model.dofs.num_free,
        };
        for o in observers.iter_mut() {
            o.on_phase(&phase);
        }
        let results =
            solve_linear_static_cases(&p.model, p.solver.as_mut(), &cases).with_context(|| {
                format!("solving {file}, {} (line {})", steps[k].name, steps[k].line)
            })?;
        for (i, mut res) in results.into_iter().enumerate() {
            let s = &steps[k + i];
            let t = res.timings;
            total.pattern += t.pattern;
            total.assemble += t.assemble;
            total.analyze += t.analyze;
            total.factor += t.factor;
            total.solve += t.solve;
            total.total += t.total;
            // the step's own load vector, for its reactions
            p.model.f_ext.clone_from(&s.f_ext);
            if !prints.is_empty() {
                prints.add_step(&p.model, k + i, &res.u, &res.residual, &s.f_ext, &res.state)?;
            }
            if let (true, Some(dir)) = (p.vtu, dir) {
                let name = format!("results_step{}.vtu", k + i + 1);
                let cells = crate::post::fields::cell_results(&p.model, &res.u, &res.state)?;
                crate::output::vtu::write_vtu(&dir.join(&name), &p.model, &res.u, &cells)?;
                frames.push(((k + i + 1) as f64, name));
            }
            summaries.push(json!({
                "name": s.name,
                "line": s.line,
                "reactions": crate::output::summary::reactions(&p.model, &res.residual)?,
                "displacement_max": crate::output::summary::displacement_max(&res.u),
                "equilibrium_residual": res.free_residual,
                "shares_factorisation_with_previous": i > 0,
                "timings": {
                    "assemble": t.assemble, "analyze": t.analyze, "factor": t.factor,
                    "solve": t.solve, "total": t.total,
                },
                "solver": {
                    "residual": res.report.residual,
                    "precision": res.report.precision,
                    "refinement_steps": res.report.refinement_steps,
                },
            }));
            res.timings = total;
            last = Some(res);
        }
        k = end;
    }
    if let (true, Some(dir)) = (p.vtu, dir) {
        crate::output::vtu::write_pvd(&dir.join("results.pvd"), &frames)?;
    }
    Ok((last.expect("at least one step"), summaries))
}

/// Observers' `on_end` for a linear run (its one state).
fn end_linear(
    model: &junta_core::Model,
    res: &junta_solvers::linear_static::LinearStaticResult,
    summary: &crate::run::results::Summary,
    observers: &mut [&mut dyn Observer],
    keep_frame: bool,
) -> Result<Option<crate::post::frame::Frame>> {
    let step = junta_core::StepInfo::at(0, 1.0, 0.0);
    let interfaces = crate::post::fields::interface_results(model, &res.u, &res.state)?;
    let end = RunEnd {
        model,
        u: Some(&res.u),
        state: Some(&res.state),
        residual: Some(&res.residual),
        interfaces: &interfaces,
        step,
        converged_here: true,
        status: "completed",
        reason: &crate::run::results::EndReason::EndOfProgram,
        summary,
    };
    let log = RunLog::default();
    for o in observers.iter_mut() {
        o.on_end(&end, &log)?;
    }
    if !keep_frame {
        return Ok(None);
    }
    Ok(Some(crate::post::frame::Frame::at(
        model,
        &res.u,
        &res.state,
        &interfaces,
        step,
    )?))
}
