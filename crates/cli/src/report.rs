//! Tables the sweeps print.

use junta::study::sweep::SweepRow;
use junta::study::sweep_control::ControlRun;

/// Print the sweep's table and its findings.
pub fn sweep(rows: &[SweepRow]) {
    println!(
        "{:>10} {:>9} {:>8} {:>11} {:>11} {:>9} {:>6}  note",
        "d", "solver", "status", "rel.error", "|delta_3|", "seconds", "iters"
    );
    for r in rows {
        let status = if !r.ok {
            "FAILED"
        } else if r.warnings.is_empty() {
            "ok"
        } else {
            "warning"
        };
        let note = if r.ok {
            r.warnings.first().cloned().unwrap_or_default()
        } else {
            r.message.clone()
        };
        println!(
            "{:>10.2e} {:>9} {:>8} {:>11} {:>11} {:>9.2e} {:>6}  {}",
            r.d,
            r.solver,
            status,
            r.rel_error
                .map(|v| format!("{v:.2e}"))
                .unwrap_or("-".into()),
            r.max_normal_jump
                .map(|v| format!("{v:.2e}"))
                .unwrap_or("-".into()),
            r.seconds,
            r.iterations,
            note.chars().take(100).collect::<String>()
        );
    }
    for (solver, _, _) in junta::study::sweep::SWEEP_SOLVERS {
        let mine: Vec<&SweepRow> = rows.iter().filter(|r| r.solver == solver).collect();
        if let Some(first) = mine.iter().find(|r| !r.notes.is_empty()) {
            // the mixed-precision back end notes its fallbacks; the others
            // note what they built (e.g. the AMG hierarchy)
            let what = if solver == "cholesky_mixed" {
                "falls back to double precision from"
            } else {
                "notes from"
            };
            println!(
                "{solver}: {what} d = {:.2e}: {}",
                first.d,
                first.notes.join("; ")
            );
        }
        if let Some(best) = mine
            .iter()
            .filter(|r| r.ok && r.rel_error.is_some())
            .min_by(|a, b| a.rel_error.partial_cmp(&b.rel_error).unwrap())
        {
            println!(
                "{solver}: best relative error {:.2e} at d = {:.2e}",
                best.rel_error.unwrap(),
                best.d
            );
        }
        if let Some(first) = mine.iter().find(|r| !r.ok || !r.warnings.is_empty()) {
            println!(
                "{solver}: {} from d = {:.2e}: {}",
                if first.ok {
                    "warns (lost digits)"
                } else {
                    "fails"
                },
                first.d,
                if first.ok {
                    first.warnings.join("; ")
                } else {
                    first.message.clone()
                }
            );
        }
    }
}

/// Print the per-method table.
pub fn control(runs: &[ControlRun]) {
    println!(
        "{:<13} {:>10} {:>13} {:>13}  status",
        "method", "increments", "peak", "last"
    );
    for r in runs {
        println!(
            "{:<13} {:>10} {:>13} {:>13}  {}",
            r.method,
            r.points.len(),
            r.peak().map_or("-".into(), |p| format!("{:.4e}", p.1)),
            r.points
                .last()
                .map_or("-".into(), |p| format!("({:.3e}, {:.3e})", p.0, p.1)),
            r.status
        );
    }
}
