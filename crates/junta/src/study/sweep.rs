//! `junta sweep penalty`: the speed/accuracy chart of the penalty method.
//!
//! Runs a scene over a log range of the penalty stiffness d (every
//! `linear_penalty` law of the scene gets `d`), with the direct (`cholesky`,
//! double precision), the mixed-precision direct (`cholesky_mixed`: single
//! precision factor refined in double, which falls back to double by itself
//! when the penalty makes single precision useless) and the iterative (`cg`)
//! back end with block-Jacobi (`cg`) and with the smoothed-aggregation AMG
//! (`amg`) preconditioner, and records for each run: the relative
//! error of the reference reaction (`[reference]` of the scene, e.g. the
//! perfectly bonded closed form of the confined prism), the largest normal
//! jump |delta_3| (interpenetration or opening), the solve time, and what
//! the solver reported (warnings, failures with their numbers). Writes
//! `sweep.csv` and `sweep.svg`; the chart also draws the paper's error
//! estimate (eq. 53) and the advisor's optimum d_op (eq. 55).

use crate::error::{bail, err, Context, Result};
use crate::{input::scene, output::plot};
use junta_core::registry::{self, SolverEntry};
use junta_solvers::linear_static::solve_linear_static;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

/// One run of the sweep.
#[derive(Debug, Clone)]
pub struct SweepRow {
    /// Penalty stiffness d of every `linear_penalty` law in this run.
    pub d: f64,
    /// The back end's label (direct or CG variant).
    pub solver: String,
    /// Whether the solve succeeded.
    pub ok: bool,
    /// |computed - reference| / |reference| of the scene's `[reference]`.
    pub rel_error: Option<f64>,
    /// Largest |delta_3| (normal jump, the constraint error) of the interfaces.
    pub max_normal_jump: Option<f64>,
    /// Wall time of the solve (s).
    pub seconds: f64,
    /// Iterations of an iterative back end (0 for a direct one).
    pub iterations: usize,
    /// The back end's own residual ||b - K u|| / ||b||.
    pub residual: f64,
    /// Relative equilibrium residual of the free dofs after the solve.
    pub equilibrium: f64,
    /// The back end's warnings (lost digits, pivots).
    pub warnings: Vec<String>,
    /// Precision of the direct solver's final factor (`double`/`mixed`).
    pub precision: String,
    /// What the back end decided on its own (mixed-precision fallback).
    pub notes: Vec<String>,
    /// The error of a failed run (empty when `ok`).
    pub message: String,
}

/// The back ends of the sweep: label, registry key, parameters.
pub const SWEEP_SOLVERS: [(&str, &str, &str); 4] = [
    ("cholesky", "cholesky", "precision = \"double\""),
    (
        "cholesky_mixed",
        "cholesky",
        "precision = \"mixed\"\nmixed_min_equations = 0",
    ),
    ("cg", "cg", ""),
    ("amg", "cg", "preconditioner = \"amg\""),
];

/// Log-spaced values from `from` to `to`, `per_decade` per decade.
pub fn log_range(from: f64, to: f64, per_decade: usize) -> Vec<f64> {
    let (a, b) = (from.log10(), to.log10());
    let n = ((b - a) * per_decade as f64).round().max(0.0) as usize;
    (0..=n)
        .map(|i| 10f64.powf(a + (b - a) * i as f64 / n.max(1) as f64))
        .collect()
}

fn set_penalty(sf: &mut scene::SceneFile, d: f64) -> usize {
    let mut n = 0;
    for t in sf.scene.laws.values_mut() {
        if t.get("type").and_then(|v| v.as_str()) == Some("linear_penalty") {
            for k in ["d1", "d2", "d3"] {
                t.remove(k);
            }
            t.insert("d".into(), toml::Value::Float(d));
            n += 1;
        }
    }
    n
}

/// Run the sweep and write `sweep.csv` and `sweep.svg` into `out`.
///
/// Stages: `check_range`; the scene and the advisor's numbers (they do not
/// depend on d); per d, one `sweep_row` per back end of
/// [`SWEEP_SOLVERS`]; `sweep_csv` and `sweep_panels` (the chart).
pub fn sweep_penalty(
    input: &Path,
    from: f64,
    to: f64,
    per_decade: usize,
    out: &Path,
) -> Result<Vec<SweepRow>> {
    check_range(from, to, per_decade)?;
    let mut sf = crate::input::validate::read_scene(input)?;
    if set_penalty(&mut sf, from) == 0 {
        bail!(
            "{}: the sweep changes the `d` of `linear_penalty` laws, and the scene has none in [laws]",
            input.display()
        );
    }
    let reference = match &sf.scene.reference {
        Some(r) => Some((r.clone(), r.component_index(&sf.path)?)),
        None => None,
    };
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    // the advisor's numbers do not depend on d
    let model0 = scene::build_model(&sf)?;
    let advice_block = model0
        .mesh
        .blocks
        .iter()
        .position(|b| b.shape.is_interface())
        .ok_or_else(|| err!("{}: the scene has no interface", input.display()))?;
    let advice = junta_interface::penalty_advice(&model0, advice_block, None)?;
    drop(model0);
    let mut rows = Vec::new();
    for d in log_range(from, to, per_decade) {
        set_penalty(&mut sf, d);
        let model = scene::build_model(&sf)?;
        for (label, key, params) in SWEEP_SOLVERS {
            rows.push(sweep_row(
                &model,
                d,
                (label, key, params),
                reference.as_ref(),
            )?);
        }
    }
    let csv = sweep_csv(&rows, &advice)?;
    std::fs::write(out.join("sweep.csv"), csv).context("cannot write sweep.csv")?;
    let ds = log_range(from, to, per_decade * 4);
    let panels = sweep_panels(&rows, &advice, reference.as_ref(), &ds);
    plot::write_svg(&out.join("sweep.svg"), &panels)?;
    Ok(rows)
}

/// `--from`, `--to` and `--per-decade`: a positive range, at most 10000
/// values.
fn check_range(from: f64, to: f64, per_decade: usize) -> Result<()> {
    if !(from > 0.0 && to > from && from.is_finite() && to.is_finite()) {
        bail!("--from and --to must be positive with from < to (got {from:e}, {to:e})");
    }
    if per_decade == 0 || (to.log10() - from.log10()) * per_decade as f64 > 10_000.0 {
        bail!(
            "--per-decade {per_decade}: give 1 or more values per decade and at most 10000 values in all ({:.1} decades from {from:e} to {to:e})",
            to.log10() - from.log10()
        );
    }
    Ok(())
}

/// One run of the sweep: `model` (penalty `d`) solved with the back end
/// `(label, registry key, parameters)`; the relative error of the
/// reference reaction (`reference`: the spec and its component) and the
/// largest |delta_3| over the interface points when it solved, the error
/// message when it failed.
fn sweep_row(
    model: &junta_core::Model,
    d: f64,
    (label, key, params): (&str, &str, &str),
    reference: Option<&(scene::ReferenceSpec, usize)>,
) -> Result<SweepRow> {
    let entry = registry::find::<SolverEntry>(key)?;
    let table: toml::Table = toml::from_str(params)?;
    let mut solver = (entry.build)(&table)?;
    let t = Instant::now();
    let res = solve_linear_static(model, solver.as_mut());
    let seconds = t.elapsed().as_secs_f64();
    let mut row = SweepRow {
        d,
        solver: label.into(),
        ok: false,
        rel_error: None,
        max_normal_jump: None,
        seconds,
        iterations: 0,
        residual: f64::NAN,
        equilibrium: f64::NAN,
        warnings: Vec::new(),
        precision: String::new(),
        notes: Vec::new(),
        message: String::new(),
    };
    match res {
        Ok(r) => {
            row.ok = true;
            row.seconds = r.timings.analyze + r.timings.factor + r.timings.solve;
            row.iterations = r.report.iterations;
            row.residual = r.report.residual;
            row.equilibrium = r.free_residual;
            row.warnings = r.report.warnings.clone();
            row.precision = r.report.precision.clone();
            row.notes = r.report.notes.clone();
            if let Some((rs, c)) = reference {
                let v = model.set_total(&rs.set, &r.residual)?[*c];
                row.rel_error = Some((v - rs.value).abs() / rs.value.abs());
            }
            let ifs = crate::post::fields::interface_results(model, &r.u, &r.state)?;
            row.max_normal_jump = ifs
                .iter()
                .flat_map(|i| i.points.iter())
                .filter_map(|p| p.get("jump"))
                .map(|j| j[2].abs())
                .reduce(f64::max);
        }
        Err(e) => row.message = format!("{e:#}"),
    }
    Ok(row)
}

/// `sweep.csv`: one line per run, with the paper's error estimate (eq. 53)
/// at its d.
fn sweep_csv(rows: &[SweepRow], advice: &junta_interface::PenaltyAdvice) -> Result<String> {
    let mut csv = String::from(
        "d,solver,status,relative_error,max_abs_normal_jump,solve_seconds,iterations,solver_residual,equilibrium_residual,eq53_estimate,precision,message\n",
    );
    for r in rows {
        let (ce, re) = advice.errors_at(r.d);
        let msg = if r.ok {
            r.warnings
                .iter()
                .chain(&r.notes)
                .cloned()
                .collect::<Vec<_>>()
                .join(" | ")
        } else {
            r.message.clone()
        };
        writeln!(
            csv,
            "{:e},{},{},{},{},{:e},{},{:e},{:e},{:e},{},\"{}\"",
            r.d,
            r.solver,
            if !r.ok {
                "failed"
            } else if r.warnings.is_empty() {
                "ok"
            } else {
                "warning"
            },
            r.rel_error.map(|v| format!("{v:e}")).unwrap_or_default(),
            r.max_normal_jump
                .map(|v| format!("{v:e}"))
                .unwrap_or_default(),
            r.seconds,
            r.iterations,
            r.residual,
            r.equilibrium,
            ce + re,
            r.precision,
            msg.replace('"', "'")
        )?;
    }
    Ok(csv)
}

/// The line of `f` over d for the runs of `solver` that solved.
fn series(
    rows: &[SweepRow],
    solver: &str,
    color: usize,
    f: &dyn Fn(&SweepRow) -> Option<f64>,
) -> plot::Series {
    plot::Series {
        name: solver.to_string(),
        points: rows
            .iter()
            .filter(|r| r.solver == solver && r.ok)
            .filter_map(|r| f(r).map(|v| (r.d, v)))
            .collect(),
        color,
        markers_only: false,
    }
}

/// Markers at the runs of `solver` that failed or warned (at their
/// relative error, `y` without one).
fn failed_series(rows: &[SweepRow], solver: &str, color: usize, y: f64) -> plot::Series {
    plot::Series {
        name: format!("{solver} failed / warned"),
        points: rows
            .iter()
            .filter(|r| r.solver == solver && (!r.ok || !r.warnings.is_empty()))
            .map(|r| (r.d, r.rel_error.unwrap_or(y)))
            .collect(),
        color,
        markers_only: true,
    }
}

/// A series drawn as markers only.
fn dots(mut s: plot::Series) -> plot::Series {
    s.markers_only = true;
    s
}

/// The chart's panels: relative error of the reference reaction (with the
/// eq. 53 estimate over `ds` and the advisor's d_op, eq. 55), the largest
/// |delta_3|, and the solve time, over d.
fn sweep_panels(
    rows: &[SweepRow],
    advice: &junta_interface::PenaltyAdvice,
    reference: Option<&(scene::ReferenceSpec, usize)>,
    ds: &[f64],
) -> Vec<plot::Panel> {
    // the mixed mode as markers over the double line: where it holds, the
    // two coincide
    let mut error_series = vec![
        series(rows, "cg", 1, &|r| r.rel_error),
        series(rows, "cholesky", 0, &|r| r.rel_error),
        dots(series(rows, "cholesky_mixed", 2, &|r| r.rel_error)),
        plot::Series {
            name: "cholesky_mixed fell back to double".into(),
            points: rows
                .iter()
                .filter(|r| r.solver == "cholesky_mixed" && !r.notes.is_empty())
                .map(|r| (r.d, r.rel_error.unwrap_or(1.0)))
                .collect(),
            color: 6,
            markers_only: true,
        },
        failed_series(rows, "cholesky", 4, 1.0),
        failed_series(rows, "cg", 3, 1.0),
        series(rows, "amg", 5, &|r| r.rel_error),
        failed_series(rows, "amg", 5, 1.0),
    ];
    error_series.push(plot::Series {
        name: "eq. 53 estimate k/(d a) + n e_c d a / k".into(),
        points: ds
            .iter()
            .map(|&d| {
                let (c, r) = advice.errors_at(d);
                (d, c + r)
            })
            .collect(),
        color: 5,
        markers_only: false,
    });
    vec![
        plot::Panel {
            title: format!(
                "relative error of the reference reaction ({})",
                reference
                    .map(|(r, _)| r.set.as_str())
                    .unwrap_or("no [reference] in the scene")
            ),
            x_label: "penalty d".into(),
            y_label: "relative error".into(),
            log_x: true,
            log_y: true,
            series: error_series,
            vlines: vec![(
                advice.d_op,
                format!("advisor d_op = {:.2e} (eq. 55)", advice.d_op),
            )],
        },
        plot::Panel {
            title: "largest |delta_3| at the interface (interpenetration / opening)".into(),
            x_label: "penalty d".into(),
            y_label: "|delta_3|".into(),
            log_x: true,
            log_y: true,
            series: vec![
                series(rows, "cg", 1, &|r| r.max_normal_jump),
                series(rows, "cholesky", 0, &|r| r.max_normal_jump),
                dots(series(rows, "cholesky_mixed", 2, &|r| r.max_normal_jump)),
                series(rows, "amg", 5, &|r| r.max_normal_jump),
            ],
            vlines: vec![],
        },
        plot::Panel {
            title: "solve time (analysis + factorisation + solve, or CG iterations)".into(),
            x_label: "penalty d".into(),
            y_label: "seconds".into(),
            log_x: true,
            log_y: true,
            series: vec![
                series(rows, "cholesky", 0, &|r| Some(r.seconds)),
                series(rows, "cholesky_mixed", 2, &|r| Some(r.seconds)),
                series(rows, "cg", 1, &|r| Some(r.seconds)),
                series(rows, "amg", 5, &|r| Some(r.seconds)),
            ],
            vlines: vec![],
        },
    ]
}

/// Normal-traction profile along one axis for one (d, rule) run.
#[derive(Debug, Clone)]
pub struct Profile {
    /// Penalty of the run (None: the scene's own).
    pub d: Option<f64>,
    /// Integration rule of the interfaces (`gauss` or `lobatto`).
    pub rule: String,
    /// `(coordinate, mean normal traction of the points at that coordinate)`, sorted.
    pub points: Vec<(f64, f64)>,
    /// Oscillation measure: sum |t_{i+1} - 2 t_i + t_{i-1}| / (max - min).
    pub roughness: f64,
    /// Number of sign changes of the slope dt/dx (local extrema).
    pub extrema: usize,
}

fn set_integration(sf: &mut scene::SceneFile, rule: &str) {
    for f in sf.scene.interface.iter_mut() {
        f.integration = Some(rule.to_string());
    }
}

/// Roughness and extrema of a sorted profile.
pub fn oscillation(points: &[(f64, f64)]) -> (f64, usize) {
    if points.len() < 3 {
        return (0.0, 0);
    }
    let (lo, hi) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.1), b.max(p.1))
        });
    let span = (hi - lo).max(f64::MIN_POSITIVE);
    let mut rough = 0.0;
    let mut extrema = 0;
    for w in points.windows(3) {
        rough += (w[2].1 - 2.0 * w[1].1 + w[0].1).abs();
        let (s1, s2) = (w[1].1 - w[0].1, w[2].1 - w[1].1);
        if s1 * s2 < 0.0 {
            extrema += 1;
        }
    }
    (rough / span, extrema)
}

/// `junta sweep integration`: run the scene with Gauss and Lobatto
/// integration of every interface (and, if given, for several penalty
/// values), and write the normal traction along `axis` (traction.csv,
/// traction.svg).
pub fn sweep_integration(
    input: &Path,
    ds: &[f64],
    axis: usize,
    out: &Path,
) -> Result<Vec<Profile>> {
    let mut sf = crate::input::validate::read_scene(input)?;
    if sf.scene.interface.is_empty() {
        bail!("{}: the scene has no [[interface]]", input.display());
    }
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let d_values: Vec<Option<f64>> = if ds.is_empty() {
        vec![None]
    } else {
        ds.iter().map(|&d| Some(d)).collect()
    };
    let mut profiles = Vec::new();
    let mut csv = String::from("d,rule,x,y,z,t1,t2,tn\n");
    for d in &d_values {
        if let Some(d) = d {
            if set_penalty(&mut sf, *d) == 0 {
                bail!(
                    "{}: --d needs `linear_penalty` laws in [laws]",
                    input.display()
                );
            }
        }
        for rule in ["gauss", "lobatto"] {
            set_integration(&mut sf, rule);
            let model = scene::build_model(&sf)?;
            let (mut key, table) = scene::solver_table(&sf);
            let mut notes = Vec::new();
            let mut solver = crate::prepare::resolve_solver(
                &mut key,
                &table,
                &model,
                &input.display().to_string(),
                &mut notes,
            )?;
            let res = solve_linear_static(&model, solver.as_mut())
                .with_context(|| format!("solving with {rule} integration"))?;
            let ifs = crate::post::fields::interface_results(&model, &res.u, &res.state)?;
            let mut pts: Vec<(f64, f64)> = Vec::new();
            for p in ifs.iter().flat_map(|i| i.points.iter()) {
                let t = p.get("traction").unwrap_or(&[0.0; 3]);
                writeln!(
                    csv,
                    "{},{rule},{:e},{:e},{:e},{:e},{:e},{:e}",
                    d.map(|v| format!("{v:e}")).unwrap_or_default(),
                    p.position[0],
                    p.position[1],
                    p.position[2],
                    t[0],
                    t[1],
                    t[2]
                )?;
                pts.push((p.position[axis], t[2]));
            }
            pts.sort_by(|a, b| a.0.partial_cmp(&b.0).unwrap());
            // average the points that share a coordinate (through the depth)
            let scale = pts
                .last()
                .map_or(1.0, |l| (l.0 - pts[0].0).abs())
                .max(1e-300);
            let mut profile: Vec<(f64, f64, usize)> = Vec::new();
            for (x, t) in pts {
                match profile.last_mut() {
                    Some(last) if (x - last.0).abs() <= 1e-9 * scale => {
                        last.1 += t;
                        last.2 += 1;
                    }
                    _ => profile.push((x, t, 1)),
                }
            }
            let points: Vec<(f64, f64)> = profile
                .iter()
                .map(|(x, t, n)| (*x, t / *n as f64))
                .collect();
            let (roughness, extrema) = oscillation(&points);
            profiles.push(Profile {
                d: *d,
                rule: rule.into(),
                points,
                roughness,
                extrema,
            });
        }
    }
    std::fs::write(out.join("traction.csv"), csv).context("cannot write traction.csv")?;
    let axis_name = ["x", "y", "z"][axis];
    let panels: Vec<plot::Panel> = d_values
        .iter()
        .map(|d| plot::Panel {
            title: format!(
                "normal traction along {axis_name}{}",
                d.map(|v| format!(", d = {v:.1e}")).unwrap_or_default()
            ),
            x_label: axis_name.into(),
            y_label: "normal traction t_n".into(),
            log_x: false,
            log_y: false,
            series: profiles
                .iter()
                .filter(|p| p.d == *d)
                .enumerate()
                .map(|(i, p)| plot::Series {
                    name: format!(
                        "{} (roughness {:.2}, {} extrema)",
                        p.rule, p.roughness, p.extrema
                    ),
                    points: p.points.clone(),
                    color: i,
                    markers_only: false,
                })
                .collect(),
            vlines: vec![],
        })
        .collect();
    plot::write_svg(&out.join("traction.svg"), &panels)?;
    Ok(profiles)
}
