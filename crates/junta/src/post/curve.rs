//! The load-displacement curve of an incremental run: one [`CurveRow`] per
//! converged increment (`curve.csv`), the limit points along it, the hint
//! a run that stops past a peak gives, and reference curves to compare.

use crate::error::{bail, Context, Result};
use serde_json::json;
use std::path::Path;

/// One row of `curve.csv`: one converged increment (its columns, and how
/// a row is written: [`crate::post::curve_columns`]).
#[derive(Debug, Clone, Default)]
pub struct CurveRow {
    /// Global index of the increment (1-based, converged increments only,
    /// counted across restarts).
    pub increment: usize,
    /// Step of the program it belongs to (0-based).
    pub step: usize,
    /// Load factor reached (`load_factor` column).
    pub lambda: f64,
    /// Total internal force of the curve's reaction set in its component
    /// (the reaction on supports, the applied load on a loaded free set),
    /// sign per `negate`; the load factor with `conjugate`. `None` (an
    /// empty column) without a curve.
    pub reaction: Option<f64>,
    /// Mean displacement of the curve's point set in its component, less
    /// that of `relative_to`, sign per `negate`; `f_ext . u` with
    /// `conjugate`. `None` without a curve.
    pub displacement: Option<f64>,
    /// Interface integration points that have failed (`failed_points`).
    pub failed: usize,
    /// Interface integration points in the model (`interface_points`).
    pub points: usize,
    /// Newton iterations of the converged attempt.
    pub iterations: usize,
    /// Cut-backs before the increment converged.
    pub cutbacks: usize,
    /// Wall-clock seconds spent on the increment, failed attempts included.
    pub seconds: f64,
    /// Whether the increment was sized by the paper's small-increment rule
    /// (`small_increment` column, 1 or 0).
    pub small: bool,
    /// Fracture energy dissipated in all interfaces so far.
    pub dissipated: f64,
    /// Damaged area (the failed points, [`junta_core::PointStage::Failed`])
    /// of all interfaces.
    pub damaged_area: f64,
    /// Negative pivots of the last factorised tangent (inertia), when the
    /// back end knows it.
    pub negative_pivots: Option<usize>,
    /// Sign of the load-factor increment: 1, -1 or 0.
    pub load_sign: i8,
    /// What constrained the increment (`load`, `arc`, `dissipation`).
    pub control: String,
    /// `f_ext . u`: the displacement work-conjugate to the load factor of
    /// the applied forces (with forces of a unit total load, the load
    /// point's displacement, e.g. the lever's in a mixed-mode bending test).
    pub conjugate: f64,
    /// Energy dissipated by friction / interface plasticity so far.
    pub frictional: f64,
    /// Temperature factor reached (`temperature_factor` column): the
    /// fraction of the model's temperature change applied, 0 -> 1 over a
    /// cool-down step; 1 without a temperature program.
    pub temperature_factor: f64,
    /// Energy dissipated by the laws' viscous regularisation so far
    /// (`viscous_energy` column).
    pub viscous: f64,
    /// Work of the reactions of the prescribed dofs and of the applied
    /// loads so far (`external_work` column): the trapezoid rule over the
    /// converged increments.
    pub external_work: f64,
    /// Damaged area over the crack width (`crack_length`); `None` without
    /// damage ([`crate::post::crack`]).
    pub crack_length: Option<f64>,
    /// Largest coordinate of a damaged point along the crack direction,
    /// from the origin (`crack_front`); `None` before the first.
    pub crack_front: Option<f64>,
    /// Extent of the process zone ahead of the front along the direction
    /// (`process_zone_length`).
    pub process_zone_length: Option<f64>,
    /// Process-zone points along the direction (`process_zone_points`).
    pub process_zone_points: Option<usize>,
    /// Load cycles reached (`cycles`): 0 outside a fatigue program
    /// ([`junta_core::FatigueProgram`]).
    pub cycles: f64,
    /// Energy release rate of the crack measured on the interface, the J
    /// integral of the cohesive tractions (`energy_release_rate`,
    /// [`junta_core::crack_drive`]); `None` outside a fatigue program that
    /// measures it.
    pub energy_release_rate: Option<f64>,
    /// Mode ratio `G_II / G` of that J integral (`crack_mode_ratio`).
    pub crack_mode_ratio: Option<f64>,
    /// Crack growth per cycle `da/dN` (`crack_growth_rate`): on a row of a
    /// fatigue step where the crack grew, its growth since the last row
    /// where it grew (or since the fatigue step began) over the cycles in
    /// between ([`crate::post::crack::growth_rate`]); `None` elsewhere.
    pub crack_growth_rate: Option<f64>,
}

impl CurveRow {
    /// A row from a line of `curve.csv` (without its newline), or `None` if
    /// it is not one. Reads files of older runs too: 14 columns (before the
    /// path-following and frictional columns), 16, 17 or 18 (before the
    /// temperature factor), 19 (before the energy and crack columns), 25
    /// (before `cycles`), 26 (before `energy_release_rate`,
    /// `crack_mode_ratio` and `crack_growth_rate`); a
    /// missing column takes its neutral value (`load_sign` 0, `control`
    /// `load`, 0.0, temperature factor 1, empty crack columns).
    pub fn parse(line: &str) -> Option<CurveRow> {
        let f: Vec<&str> = line.split(',').collect();
        // 14 columns: a run written before the path-following and
        // frictional columns
        if ![14, 16, 17, 18, 19, 25, 26, 29].contains(&f.len()) {
            return None;
        }
        Some(CurveRow {
            increment: f[0].parse().ok()?,
            step: f[1].parse().ok()?,
            lambda: f[2].parse().ok()?,
            reaction: f[3].parse().ok(),
            displacement: f[4].parse().ok(),
            failed: f[5].parse().ok()?,
            points: f[6].parse().ok()?,
            iterations: f[7].parse().ok()?,
            cutbacks: f[8].parse().ok()?,
            seconds: f[9].parse().ok()?,
            small: f[10].trim() == "1",
            dissipated: f[11].parse().ok()?,
            damaged_area: f[12].parse().ok()?,
            negative_pivots: f[13].trim().parse().ok(),
            load_sign: f.get(14).and_then(|v| v.trim().parse().ok()).unwrap_or(0),
            control: f.get(15).map_or("load", |v| v.trim()).to_string(),
            conjugate: f.get(16).and_then(|v| v.trim().parse().ok()).unwrap_or(0.0),
            frictional: f.get(17).and_then(|v| v.trim().parse().ok()).unwrap_or(0.0),
            temperature_factor: f.get(18).and_then(|v| v.trim().parse().ok()).unwrap_or(1.0),
            viscous: f.get(19).and_then(|v| v.trim().parse().ok()).unwrap_or(0.0),
            external_work: f.get(20).and_then(|v| v.trim().parse().ok()).unwrap_or(0.0),
            crack_length: f.get(21).and_then(|v| v.trim().parse().ok()),
            crack_front: f.get(22).and_then(|v| v.trim().parse().ok()),
            process_zone_length: f.get(23).and_then(|v| v.trim().parse().ok()),
            process_zone_points: f.get(24).and_then(|v| v.trim().parse().ok()),
            cycles: f.get(25).and_then(|v| v.trim().parse().ok()).unwrap_or(0.0),
            energy_release_rate: f.get(26).and_then(|v| v.trim().parse().ok()),
            crack_mode_ratio: f.get(27).and_then(|v| v.trim().parse().ok()),
            crack_growth_rate: f.get(28).and_then(|v| v.trim().parse().ok()),
        })
    }
}

/// When a run of a softening model stops at or after a limit point, say so
/// with the numbers: the reaction passed a maximum (a snap-back, an unstable
/// drop of the load, e.g. an element separating, that load or displacement
/// control cannot follow at any increment size), or, under load control,
/// the curve flattened to a horizontal tangent (a load maximum).
pub(crate) fn past_peak_hint(
    rows: &[CurveRow],
    kind: junta_core::MatrixKind,
    control: crate::input::scene::Control,
    nlgeom: bool,
) -> String {
    if kind == junta_core::MatrixKind::SymmetricPositiveDefinite {
        return String::new();
    }
    let remedy = remedy_past_peak(control, nlgeom);
    let remedy = remedy.as_str();
    let unstable = rows
        .iter()
        .filter(|r| r.negative_pivots.unwrap_or(0) > 0)
        .count();
    let Some((peak_row, peak)) = rows
        .iter()
        .filter_map(|r| Some((r, r.reaction?.abs())))
        .max_by(|a, b| a.1.total_cmp(&b.1))
    else {
        return String::new();
    };
    let last = rows.last().and_then(|r| r.reaction).map_or(peak, f64::abs);
    if last < peak * (1.0 - 1e-4) {
        return format!(
            ". Limit point: the reaction peaked at {peak:.6e} (increment {}, load factor {:.6e}) and the run stopped after that maximum, at {:.6e} ({} increments with a negative pivot so far): most likely a snap-back. To trace it, {remedy}",
            peak_row.increment, peak_row.lambda, last, unstable
        );
    }
    // stalled at the largest load so far: the increments shrank in each of
    // the last increments (typically an element separating: a local
    // snap-back that starts at this load)
    let n = rows.len();
    if n >= 3 && rows[n - 3..].iter().all(|r| r.cutbacks > 0) && last >= peak * (1.0 - 1e-3) {
        return format!(
            ". Limit point: the increments were cut back in each of the last three while the reaction peaked at {peak:.6e} (increment {}, load factor {:.6e}), its largest value so far: most likely a snap-back starting there (e.g. an element separating). To trace it, {remedy}",
            peak_row.increment, peak_row.lambda
        );
    }
    // load control: the slope of the curve at the end against the start
    let slope = |a: &CurveRow, b: &CurveRow| -> Option<f64> {
        let dp = b.reaction? - a.reaction?;
        let du = b.displacement? - a.displacement?;
        (du != 0.0).then(|| dp / du)
    };
    if n >= 3 {
        if let (Some(k0), Some(k1)) = (slope(&rows[0], &rows[1]), slope(&rows[n - 2], &rows[n - 1]))
        {
            if k0 != 0.0 && (k1 / k0) < 0.05 {
                return format!(
                    ". Limit point: the load-displacement slope fell to {:.2} % of its initial value at reaction {last:.6e} (load factor {:.6e}): a load maximum, past which load control has no solution. To go past it, {remedy}",
                    100.0 * k1 / k0,
                    rows[n - 1].lambda
                );
            }
        }
    }
    if rows.last().and_then(|r| r.negative_pivots).unwrap_or(0) > 0 {
        return format!(
            ". The tangent of the last converged increment is indefinite ({} negative pivots): the structure is past a limit point or a bifurcation. To go past it, {remedy}",
            rows.last().and_then(|r| r.negative_pivots).unwrap_or(0)
        );
    }
    String::new()
}

/// What to change to trace a limit point, never what was already in force:
/// under load control, the default `auto` or path following throughout;
/// under `auto` (which switched to path following at the limit point),
/// path following from the start or a smaller dissipation step; under path
/// following, shorter path steps. Under `nlgeom` the dissipation constraint
/// reads the interfaces' energy balance (`junta_solvers`, module
/// `nonlinear::balance`), which the text says. A small `viscosity` always
/// helps.
fn remedy_past_peak(control: crate::input::scene::Control, nlgeom: bool) -> String {
    use crate::input::scene::Control;
    const VISCOSITY: &str =
        "add a small `viscosity` to the softening law (its energy is reported apart)";
    let balance = if nlgeom {
        ", under `nlgeom` on the interfaces' energy balance"
    } else {
        ""
    };
    let arc = format!(
        "path following throughout (`[analysis] control = \"arc_length\"`, which follows snap-backs through the dissipated energy{balance})"
    );
    match control {
        Control::Load => format!(
            "leave `control` out (the default `auto` switches to path following at a limit point and back; for a deck, drop `--solver control=load`), or use {arc}, or {VISCOSITY}"
        ),
        Control::Auto => format!(
            "use {arc} or a smaller dissipation step (`[analysis.arc_length] max_dissipation`; `auto`, in force here, switched to path following at the limit point and could not follow it), or {VISCOSITY}"
        ),
        Control::ArcLength => format!(
            "shorten the path steps (`[analysis.arc_length] max_arc` or `max_dissipation`, or a smaller first increment `[analysis.newton] initial_increment`; path following was in force here{balance}), or {VISCOSITY}"
        ),
    }
}

/// Limit points and changes of stability along the converged increments:
/// load maxima and minima (of the reaction, else of the load factor),
/// displacement turning points (a snap-back starts at a displacement
/// maximum), and increments where the number of negative pivots of the
/// tangent changed (a limit point or a bifurcation was crossed).
pub(crate) fn limit_points(rows: &[CurveRow]) -> serde_json::Value {
    const MAX_LISTED: usize = 50;
    let load = |r: &CurveRow| r.reaction.unwrap_or(r.lambda);
    let mut points = Vec::new();
    let mut counts = [0usize; 5];
    let kinds = [
        "load_maximum",
        "load_minimum",
        "displacement_maximum",
        "displacement_minimum",
        "stability_change",
    ];
    let mut push = |k: usize, r: &CurveRow, extra: Option<String>| {
        counts[k] += 1;
        if points.len() < MAX_LISTED {
            let mut v = json!({
                "kind": kinds[k],
                "increment": r.increment,
                "load_factor": r.lambda,
                "load": load(r),
                "displacement": r.displacement,
            });
            if let Some(e) = extra {
                v["negative_pivots"] = json!(e);
            }
            points.push(v);
        }
    };
    for w in rows.windows(3) {
        let (a, b, c) = (&w[0], &w[1], &w[2]);
        let (la, lb, lc) = (load(a), load(b), load(c));
        if lb > la && lb > lc {
            push(0, b, None);
        } else if lb < la && lb < lc {
            push(1, b, None);
        }
        if let (Some(da), Some(db), Some(dc)) = (a.displacement, b.displacement, c.displacement) {
            if db > da && db > dc {
                push(2, b, None);
            } else if db < da && db < dc {
                push(3, b, None);
            }
        }
    }
    for w in rows.windows(2) {
        if let (Some(x), Some(y)) = (w[0].negative_pivots, w[1].negative_pivots) {
            if x != y {
                push(4, &w[1], Some(format!("{x} -> {y}")));
            }
        }
    }
    let mut count = serde_json::Map::new();
    for (k, n) in kinds.iter().zip(counts) {
        count.insert((*k).into(), json!(n));
    }
    json!({ "counts": count, "first": points })
}

/// Points `(x, y)` of a reference curve file: CSV, two numeric columns,
/// `#` comments and a header line allowed; the path is relative to the
/// scene's folder.
pub(crate) fn read_reference_curve(input: &Path, file: &str) -> Result<Vec<(f64, f64)>> {
    read_reference_points(&input.parent().unwrap_or(Path::new(".")).join(file))
        .with_context(|| format!("{}: key `output.curve.reference.file`", input.display()))
}

/// Points `(x, y)` of the reference curve file `path` (see
/// [`read_reference_curve`]).
pub(crate) fn read_reference_points(path: &Path) -> Result<Vec<(f64, f64)>> {
    let path = path.to_path_buf();
    let text = std::fs::read_to_string(&path)
        .with_context(|| format!("cannot read {}", path.display()))?;
    let mut pts = Vec::new();
    for line in text.lines().map(str::trim) {
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        match (
            f.first().and_then(|v| v.parse().ok()),
            f.get(1).and_then(|v| v.parse().ok()),
        ) {
            (Some(x), Some(y)) => pts.push((x, y)),
            _ if pts.is_empty() => {} // header
            _ => bail!("{}: `{line}` is not two numbers x, y", path.display()),
        }
    }
    Ok(pts)
}

/// The curve as columns, named as the header of `curve.csv`: every column
/// is `f64` (an empty cell is NaN) except `control`.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
pub struct Curve {
    /// `(name, values)` in the order of `curve.csv`, `control` left out.
    pub columns: Vec<(String, Vec<f64>)>,
    /// What constrained each increment (`load`, `arc`, `dissipation`).
    pub control: Vec<String>,
}

impl Curve {
    /// The column `name`, if there is one.
    pub fn get(&self, name: &str) -> Option<&[f64]> {
        self.columns
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_slice())
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.control.len()
    }

    /// True when no increment converged.
    pub fn is_empty(&self) -> bool {
        self.control.is_empty()
    }

    /// The rows of `DIR/curve.csv` up to increment `last` (a restart's past).
    pub fn read_rows(dir: &std::path::Path, last: usize) -> Vec<CurveRow> {
        let text = std::fs::read_to_string(dir.join("curve.csv")).unwrap_or_default();
        text.lines()
            .skip(1)
            .filter_map(CurveRow::parse)
            .filter(|row| row.increment <= last)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::post::curve_columns::curve_header;

    /// The stop's remedy never recommends the control that was in force
    /// (issue 37: a DCB under nlgeom without `control` stopped at its
    /// peak and was told to leave `control` out).
    #[test]
    fn the_remedy_never_names_what_was_in_force() {
        use crate::input::scene::Control;
        for nlgeom in [false, true] {
            let load = remedy_past_peak(Control::Load, nlgeom);
            assert!(load.contains("leave `control` out"), "{load}");
            let auto = remedy_past_peak(Control::Auto, nlgeom);
            assert!(!auto.contains("leave `control` out"), "{auto}");
            assert!(auto.contains("control = \"arc_length\""), "{auto}");
            let arc = remedy_past_peak(Control::ArcLength, nlgeom);
            assert!(!arc.contains("leave `control` out"), "{arc}");
            assert!(!arc.contains("control = \"arc_length\""), "{arc}");
            assert!(arc.contains("max_arc"), "{arc}");
            for r in [&load, &auto, &arc] {
                assert!(r.contains("viscosity"), "{r}");
                assert_eq!(r.contains("nlgeom"), nlgeom, "{r}");
            }
        }
    }

    #[test]
    fn columns_follow_the_csv_header_and_read_back_the_rows() {
        let line = "3,0,5e-1,1.5e2,2e-1,4,10,2,0,1.2e0,0,3e-3,1e-1,,1,arc,2.5e-1,0e0,7.5e-1,1e-4,4e-3,2.5e0,2.25e0,1.5e0,6,1.25e5,4.5e-1,5e-1,2e-5";
        let row = CurveRow::parse(line).expect("29 columns");
        assert_eq!(row.csv().trim_end(), line);
        let c = Curve::from_rows(&[row]);
        // the header every run since the fatigue columns wrote
        let old = "increment,step,load_factor,reaction,displacement,failed_points,interface_points,newton_iterations,cutbacks,seconds,small_increment,dissipated_energy,damaged_area,negative_pivots,load_increment_sign,control,conjugate_displacement,frictional_dissipation,temperature_factor,viscous_energy,external_work,crack_length,crack_front,process_zone_length,process_zone_points,cycles,energy_release_rate,crack_mode_ratio,crack_growth_rate\n";
        assert_eq!(curve_header(), old);
        let header: Vec<&str> = old
            .trim_end()
            .split(',')
            .filter(|h| *h != "control")
            .collect();
        let names: Vec<&str> = c.columns.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, header);
        assert_eq!(c.get("reaction"), Some(&[150.0][..]));
        assert!(c.get("negative_pivots").unwrap()[0].is_nan());
        assert_eq!(c.control, vec!["arc".to_string()]);
        assert_eq!(c.get("process_zone_points"), Some(&[6.0][..]));
        assert_eq!(c.get("cycles"), Some(&[1.25e5][..]));
        assert_eq!(c.get("energy_release_rate"), Some(&[0.45][..]));
        assert_eq!(c.get("crack_growth_rate"), Some(&[2e-5][..]));
        // a row of a run before the J integral and da/dN (26 columns)
        assert_eq!(c.get("crack_mode_ratio"), Some(&[0.5][..]));
        let line = line.rsplitn(4, ',').nth(3).unwrap();
        let before = CurveRow::parse(line).expect("26 columns");
        assert_eq!(before.cycles, 1.25e5);
        assert_eq!(before.crack_growth_rate, None);
        // a row of a run before the cycles (25 columns): 0 cycles
        let before = CurveRow::parse(line.rsplit_once(',').unwrap().0).expect("25 columns");
        assert_eq!(before.cycles, 0.0);
        // a row of an older run (19 columns): no crack, no external work
        let old = CurveRow::parse(
            "3,0,5e-1,1.5e2,2e-1,4,10,2,0,1.2e0,0,3e-3,1e-1,,1,arc,2.5e-1,0e0,7.5e-1",
        )
        .expect("19 columns");
        assert_eq!((old.crack_length, old.external_work), (None, 0.0));
    }
}
