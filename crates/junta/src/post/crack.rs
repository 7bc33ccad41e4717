//! Crack-front outputs of an incremental run, from the interface points'
//! `damage` (fracture-energy laws): the crack length, the position of the
//! crack front along a direction, and the length of the process zone ahead
//! of it with the number of integration points it spans (a mesh-resolution
//! check, as Code_Aster's `POST_CZM_FISS` makes).
//!
//! Along the unit direction `d` of `[output] crack` (default: the global
//! axis along which the measured interfaces' nodes spread the most) every
//! integration point has the coordinate `s = (x - origin) . d` of its
//! reference position `x`. Then, with each point's stage
//! ([`junta_core::PointStage`], the law's one definition: failed once it
//! has dissipated its fracture energy for its mode mix or carries no
//! traction; process zone from damage onset until then):
//!
//! - crack length `a = A_d / w`: the damaged area `A_d` (the failed points,
//!   integrated over their reference area) over the width
//!   `w` (`width`, default the interface's area over its extent along `d`);
//! - crack front: the largest `s` of a failed point (none before the
//!   first point fails);
//! - process zone: the distinct coordinates `s` of the points (on a mesh
//!   structured along `d`, the rows across it) are classed failed (a
//!   failed point there), process zone (else a process-zone point there)
//!   or intact; a process zone is a run of consecutive process-zone
//!   coordinates, and the one reported is the run with the most of them:
//!   its point count, and its length from the failed coordinate next to
//!   it (on either side; from its own first coordinate before anything
//!   has failed) to its far end. A crack that grows from both ends of the
//!   direction (a coupon's two free edges) has two such runs, one ahead
//!   of each front.

use crate::error::{bail, Result};
use crate::input::scene::CrackFrontSpec;
use crate::post::fields::{point_stage, InterfaceResults};
use junta_core::law::output;
use junta_core::Model;
use junta_core::PointStage;

/// Fewer process-zone points along the direction than this in most of the
/// increments in which the crack grows draws a warning: the cohesive zone
/// is not resolved.
pub const MIN_PROCESS_ZONE_POINTS: usize = 3;

/// How the crack of a run is measured: direction, origin, width and the
/// interface blocks.
#[derive(Debug, Clone)]
pub(crate) struct CrackProbe {
    /// Unit direction of growth.
    pub direction: [f64; 3],
    /// Point the front is measured from.
    pub origin: [f64; 3],
    /// Width given in the scene (else computed from the first results).
    width: Option<f64>,
    /// Interface blocks measured.
    blocks: Vec<usize>,
    /// Extent of the interfaces' nodes along the direction.
    extent: f64,
}

/// The crack of one converged state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CrackFront {
    /// Damaged area over the width.
    pub length: f64,
    /// Largest coordinate of a damaged point along the direction, from
    /// the origin (`None` before any point is damaged).
    pub front: Option<f64>,
    /// Extent of the process zone ahead of the front along the direction.
    pub process_zone_length: f64,
    /// Distinct coordinates of process-zone points along the direction.
    pub process_zone_points: usize,
    /// Width used.
    pub width: f64,
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl CrackProbe {
    /// The probe of `model`'s interfaces as `spec` (a scene's `[output]
    /// crack`) says, else the default; `None` without interfaces. `file`
    /// names the input in error messages.
    pub(crate) fn of(
        model: &Model,
        spec: Option<&CrackFrontSpec>,
        file: &str,
    ) -> Result<Option<CrackProbe>> {
        let interfaces = interface_blocks(model);
        let blocks = match spec.and_then(|c| c.interface.as_ref()) {
            Some(name) => match interfaces
                .iter()
                .find(|&&b| &model.mesh.blocks[b].name == name)
            {
                Some(&b) => vec![b],
                None => {
                    let names: Vec<&str> = interfaces
                        .iter()
                        .map(|&b| model.mesh.blocks[b].name.as_str())
                        .collect();
                    bail!(
                        "{file}: key `output.crack.interface`: no interface `{name}`; the interfaces are: {}",
                        if names.is_empty() { "none".to_string() } else { names.join(", ") }
                    );
                }
            },
            None => interfaces,
        };
        if blocks.is_empty() {
            return Ok(None);
        }
        let nodes = block_nodes(model, &blocks);
        let direction = match spec {
            Some(c) => unit_direction(c.direction, file, "output.crack.direction")?,
            None => default_direction(&nodes),
        };
        let (lo, hi) = nodes
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| {
                let s = dot(*x, direction);
                (l.min(s), h.max(s))
            });
        let origin = match spec.and_then(|c| c.origin) {
            Some(o) => o,
            None => [direction[0] * lo, direction[1] * lo, direction[2] * lo],
        };
        let width = spec.and_then(|c| c.width);
        if let Some(w) = width {
            if !(w.is_finite() && w > 0.0) {
                bail!(
                    "{file}: key `output.crack.width`: {w} is not a width; give a positive length"
                );
            }
        }
        Ok(Some(CrackProbe {
            direction,
            origin,
            width,
            blocks,
            extent: (hi - lo).max(0.0),
        }))
    }

    /// The crack of the interface results `ifs`, or `None` when the
    /// measured interfaces report no damage.
    pub(crate) fn measure(&mut self, ifs: &[InterfaceResults]) -> Option<CrackFront> {
        let s0 = dot(self.origin, self.direction);
        let mut has_damage = false;
        let mut total_area = 0.0;
        let mut damaged_area = 0.0;
        let mut front: Option<f64> = None;
        let mut stages: Vec<(f64, PointStage)> = Vec::new();
        for r in ifs.iter().filter(|r| self.blocks.contains(&r.block)) {
            for p in &r.points {
                let area = p
                    .get("reference_area")
                    .or_else(|| p.get("area"))
                    .map_or(0.0, |a| a[0]);
                total_area += area;
                let s = dot(p.position, self.direction) - s0;
                if p.get(output::DAMAGE).is_none() {
                    stages.push((s, PointStage::Intact));
                    continue;
                }
                has_damage = true;
                let stage = point_stage(p);
                if stage == PointStage::Failed {
                    damaged_area += area;
                    front = Some(front.map_or(s, |f| f.max(s)));
                }
                stages.push((s, stage));
            }
        }
        if !has_damage {
            return None;
        }
        // the default width: a rectangular bond's width (fixed once, from
        // the reference areas, so that a restart finds the same)
        let width = *self.width.get_or_insert_with(|| {
            if self.extent > 0.0 {
                total_area / self.extent
            } else {
                1.0
            }
        });
        let tol = 1e-6 * self.extent.max(f64::MIN_POSITIVE);
        let (process_zone_points, process_zone_length) = widest_process_zone(stages, tol);
        Some(CrackFront {
            length: damaged_area / width,
            front,
            process_zone_length,
            process_zone_points,
            width,
        })
    }

    /// `summary.json` `crack` entry without the end state's numbers.
    pub(crate) fn describe(&self) -> serde_json::Value {
        serde_json::json!({
            "direction": self.direction,
            "origin": self.origin,
            "width": self.width,
        })
    }
}

/// The interface blocks of `model`, in block order.
pub(crate) fn interface_blocks(model: &Model) -> Vec<usize> {
    (0..model.mesh.blocks.len())
        .filter(|&b| model.mesh.blocks[b].shape.is_interface())
        .collect()
}

/// The coordinates of the nodes of `blocks`' elements, element by element
/// (a node shared by elements appears once per element).
pub(crate) fn block_nodes(model: &Model, blocks: &[usize]) -> Vec<[f64; 3]> {
    blocks
        .iter()
        .flat_map(|&b| {
            let block = &model.mesh.blocks[b];
            (0..block.len()).flat_map(move |e| block.element(e).to_vec())
        })
        .map(|n| model.mesh.nodes[n])
        .collect()
}

/// `d / |d|`, or an error naming `file` and `key` when `d` is zero or not
/// finite.
pub(crate) fn unit_direction(d: [f64; 3], file: &str, key: &str) -> Result<[f64; 3]> {
    let n = dot(d, d).sqrt();
    if !(n.is_finite() && n > 0.0) {
        bail!("{file}: key `{key}`: {d:?} is not a direction; give a non-zero vector, e.g. [1.0, 0.0, 0.0]");
    }
    Ok([d[0] / n, d[1] / n, d[2] / n])
}

/// The global axis along which the points spread the most.
pub(crate) fn default_direction(nodes: &[[f64; 3]]) -> [f64; 3] {
    let mut best = (0, f64::NEG_INFINITY);
    for c in 0..3 {
        let (lo, hi) = nodes
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| {
                (l.min(x[c]), h.max(x[c]))
            });
        if hi - lo > best.1 {
            best = (c, hi - lo);
        }
    }
    let mut d = [0.0; 3];
    d[best.0] = 1.0;
    d
}

/// The crack growth per cycle of a fatigue row with crack length `a` at
/// `cycles`, after the converged `rows` before it: when the crack grew
/// (longer than in the last row), its growth since the last row where it
/// grew, or since the last row before the fatigue step (0 cycles), over
/// the cycles in between. The crack grows by whole rows of failing points,
/// so the rate of a single row between two growths would be zero or one
/// row's length over one increment; over a growth interval it is the
/// secant `da/dN` a test reduction takes between two crack readings.
pub(crate) fn growth_rate(
    rows: &[crate::post::curve::CurveRow],
    a: Option<f64>,
    cycles: f64,
) -> Option<f64> {
    let a = a?;
    let last = rows.last()?;
    if cycles <= 0.0 || a <= last.crack_length.unwrap_or(0.0) {
        return None;
    }
    let grew = |i: usize| {
        i > 0
            && rows[i].cycles > 0.0
            && rows[i].crack_length.unwrap_or(0.0) > rows[i - 1].crack_length.unwrap_or(0.0)
    };
    let reference = (0..rows.len())
        .rev()
        .find(|&i| grew(i) || rows[i].cycles <= 0.0)?;
    let (a0, n0) = (
        rows[reference].crack_length.unwrap_or(0.0),
        rows[reference].cycles,
    );
    (cycles > n0).then(|| (a - a0) / (cycles - n0))
}

/// Share of the static law above which a measured-crack fatigue run warns
/// ([`fatigue_static_share`]).
pub const STATIC_SHARE_WARNING: f64 = 0.2;

/// The part of the damage of the points that failed during a fatigue step
/// that the static law, not the cycles, brought: `1 - fatigue_damage` of
/// every failed point with some fatigue damage (its energy damage is 1),
/// averaged; with the number of such points. `None` without one.
///
/// The measured-crack Paris rate moves the process zone at the Paris rate
/// by fatigue damage alone; static damage on top (the zone's tractions
/// redistributing as G nears G_c, more in mixed mode) makes the crack run
/// fast: measured on split beams at G_II / G = 0.5, a share of 0.14 at
/// 0.3 G_c with da/dN +7.6 % over Paris, 0.25 at 0.4 G_c with +24 %; a
/// DCB in mode I, 0.04 and within -3 .. +6 % (docs/laws.md).
pub(crate) fn fatigue_static_share(ifs: &[InterfaceResults]) -> Option<(f64, usize)> {
    let (mut sum, mut n) = (0.0, 0usize);
    for p in ifs.iter().flat_map(|i| &i.points) {
        let (Some(d), Some(f)) = (p.get(output::DAMAGE), p.get(output::FATIGUE_DAMAGE)) else {
            continue;
        };
        if d[0] >= 1.0 && f[0] > 0.0 {
            sum += 1.0 - f[0].min(1.0);
            n += 1;
        }
    }
    (n > 0).then(|| (sum / n as f64, n))
}

/// The warning for a static share above [`STATIC_SHARE_WARNING`].
pub(crate) fn static_share_warning(share: f64, points: usize) -> Option<String> {
    (share > STATIC_SHARE_WARNING).then(|| format!(
        "fatigue: the {points} points that failed in the fatigue step took {:.0} % of their damage from the static law, not from the cycles; the crack then grows faster than the Paris law the fatigue rate is built for (measured on a split beam at G_II / G = 0.5: a share of 25 % and da/dN +24 %); lower the load (G_max / G_c) or read da/dN as an upper bound, see docs/laws.md",
        100.0 * share
    ))
}

/// The steady-zone warning of a fatigue run: over its fatigue steps (the
/// rows with cycles) the crack of failed points grew less than the length
/// of its process zone at the end. The zone then has not reached the
/// steady length the Paris rate of a measured crack presumes, and da/dN
/// is a transient's: measured on ENF specimens held at G_II / G_IIc = 0.5
/// (AS4/PEEK arms 1.55 mm thick, S = 40 MPa, zone 15-17 mm), 0.78 of
/// the Paris rate over the first 9 mm of growth and 0.97 over the next 9
/// mm on a 300 mm span; on a 100 mm span, whose 12.5 mm ligament
/// to the load point is shorter than the zone, the crack of failed
/// points grew 1.25 mm in 90 cycles while the zone stretched from 8 to
/// 16 mm (issue 37). `None` when the crack grew at least one zone length,
/// or the run has no fatigue step or no measured crack.
pub(crate) fn steady_zone_warning(rows: &[crate::post::curve::CurveRow]) -> Option<String> {
    let last = rows.iter().rev().find(|r| r.cycles > 0.0)?;
    let start = rows
        .iter()
        .take_while(|r| r.cycles <= 0.0)
        .last()
        .and_then(|r| r.crack_length)
        .unwrap_or(0.0);
    let grown = last.crack_length? - start;
    let zone = last.process_zone_length?;
    (grown < zone).then(|| format!(
        "fatigue: the crack of failed points grew {grown:.4} in the fatigue step, less than its process zone is long ({zone:.4}; lengths in the scene's unit): the zone has not reached a steady length, and da/dN over this step is a transient's, below the Paris law the fatigue rate is built for (measured on an ENF at G_II / G_IIc = 0.5: 0.78 of it over the first zone length of growth, 0.97 after). Cycle longer; a zone longer than the bonded ligament ahead of it (an ENF whose crack tip is close to the load point) never becomes steady: lengthen the specimen, see docs/laws.md"
    ))
}

/// The stage of each distinct coordinate of `stages` (`(s, stage)` of
/// every point; coordinates within `tol` are one): failed if a point
/// there failed, else process zone if one is there, else intact.
fn stage_per_coordinate(mut stages: Vec<(f64, PointStage)>, tol: f64) -> Vec<(f64, PointStage)> {
    stages.sort_by(|a, b| a.0.total_cmp(&b.0));
    let rank = |st: PointStage| match st {
        PointStage::Failed => 2,
        PointStage::ProcessZone => 1,
        PointStage::Intact => 0,
    };
    let mut rows: Vec<(f64, PointStage)> = Vec::new();
    for (s, st) in stages {
        match rows.last_mut() {
            Some(last) if s - last.0 <= tol => {
                if rank(st) > rank(last.1) {
                    last.1 = st;
                }
            }
            _ => rows.push((s, st)),
        }
    }
    rows
}

/// The process zone with the most coordinates (module doc): its number
/// of distinct coordinates and its length, `(0, 0.0)` without one.
fn widest_process_zone(stages: Vec<(f64, PointStage)>, tol: f64) -> (usize, f64) {
    let rows = stage_per_coordinate(stages, tol);
    let mut best = (0usize, 0.0f64);
    let mut k = 0;
    while k < rows.len() {
        if rows[k].1 != PointStage::ProcessZone {
            k += 1;
            continue;
        }
        let first = k;
        while k < rows.len() && rows[k].1 == PointStage::ProcessZone {
            k += 1;
        }
        let failed_at = |i: Option<usize>| {
            i.and_then(|i| rows.get(i))
                .filter(|r| r.1 == PointStage::Failed)
                .map(|r| r.0)
        };
        let start = failed_at(first.checked_sub(1)).unwrap_or(rows[first].0);
        let end = failed_at(Some(k)).unwrap_or(rows[k - 1].0);
        let run = (k - first, end - start);
        if run.0 > best.0 || (run.0 == best.0 && run.1 > best.1) {
            best = run;
        }
    }
    best
}

/// The process-zone warning: in most of the rows where the crack grew
/// (its length larger than the row before), fewer than
/// [`MIN_PROCESS_ZONE_POINTS`] points lay in the process zone along the
/// direction. A few such rows on a resolved mesh are the saw-tooth of its
/// elements (the zone shrinks for an increment as a row of points passes
/// the damage threshold); a zone short in most of the growth is a mesh
/// too coarse for it.
pub(crate) fn process_zone_warning(rows: &[crate::post::curve::CurveRow]) -> Option<String> {
    let mut under = 0usize;
    let mut growing = 0usize;
    let mut worst: Option<(usize, usize, f64)> = None;
    for w in rows.windows(2) {
        let (Some(a0), Some(a1)) = (w[0].crack_length, w[1].crack_length) else {
            continue;
        };
        if a1 <= a0 {
            continue;
        }
        growing += 1;
        let n = w[1].process_zone_points.unwrap_or(0);
        if n < MIN_PROCESS_ZONE_POINTS {
            under += 1;
            if worst.is_none_or(|(k, _, _)| n < k) {
                worst = Some((n, w[1].increment, w[1].process_zone_length.unwrap_or(0.0)));
            }
        }
    }
    let (n, inc, len) = worst?;
    if 2 * under <= growing {
        return None;
    }
    Some(format!(
        "the process zone (damage started, point not failed) spans fewer than {MIN_PROCESS_ZONE_POINTS} integration points along the crack direction in {under} of the {growing} increments in which the crack grew (fewest: {n} at increment {inc}, process zone {len:.4e} long): the cohesive zone is not resolved, so the load and the crack growth depend on the mesh; refine the interface along the crack direction (summary.json `mesh_advice` gives the cohesive-zone length), see docs/outputs.md"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use junta_core::PointOutput;

    /// A curve row of increment `inc` with the crack length `a` and `n`
    /// process-zone points (the other columns zero).
    fn row(inc: usize, a: f64, n: usize) -> crate::post::curve::CurveRow {
        let line = format!("{inc},0,0,0,0,0,0,0,0,0,0,0,0,0,0,load,0,0,1,0,0,{a},{a},0.1,{n}");
        crate::post::curve::CurveRow::parse(&line).unwrap()
    }

    /// da/dN over the cycles since the last growth: none while the crack
    /// stands or before the fatigue step.
    #[test]
    fn growth_rate_is_the_secant_between_growths() {
        let mut rows: Vec<_> = [(1, 0.0), (2, 0.5)].map(|(i, a)| row(i, a, 4)).to_vec();
        // static rows: no rate
        assert_eq!(growth_rate(&rows, Some(1.0), 0.0), None);
        let fatigue = |inc, a, n| {
            let mut r = row(inc, a, 4);
            r.cycles = n;
            r
        };
        // the first growth in the fatigue step: from its start (0 cycles)
        assert_eq!(growth_rate(&rows, Some(0.75), 100.0), Some(0.25 / 100.0));
        rows.push(fatigue(3, 0.75, 100.0));
        rows.push(fatigue(4, 0.75, 300.0));
        // no growth this row
        assert_eq!(growth_rate(&rows, Some(0.75), 400.0), None);
        // growth: since the row where it last grew (100 cycles)
        assert_eq!(growth_rate(&rows, Some(1.0), 500.0), Some(0.25 / 400.0));
    }

    /// Two of five growing increments under 3 points: the saw-tooth of a
    /// resolved mesh, no warning; three of five: a warning naming the
    /// fewest.
    #[test]
    fn process_zone_warning_needs_most_of_the_growth_under_three_points() {
        // an undamaged row, then five growing ones with these zone counts
        let growth = |counts: [usize; 5]| -> Vec<_> {
            std::iter::once(row(1, 0.0, 0))
                .chain(
                    counts
                        .iter()
                        .enumerate()
                        .map(|(i, &n)| row(i + 2, (i + 1) as f64, n)),
                )
                .collect()
        };
        assert_eq!(process_zone_warning(&growth([4, 2, 5, 2, 4])), None);
        let w = process_zone_warning(&growth([1, 2, 5, 2, 4])).unwrap();
        assert!(
            w.contains("in 3 of the 5 increments") && w.contains("fewest: 1 at increment 2"),
            "{w}"
        );
    }

    /// A point whose law's stage follows its damage (failed at 1, as
    /// the bilinear law's).
    fn point(x: f64, damage: f64) -> PointOutput {
        PointOutput {
            position: [x, 0.5, 0.0],
            values: vec![
                ("area", vec![0.5]),
                (output::DAMAGE, vec![damage]),
                ("stage", vec![PointStage::of_damage(damage).code()]),
            ],
        }
    }

    /// The crack of a row of points 0.5 apart along x (from 0.25), each
    /// of area 0.5, with these damages: the bond `0.5 n` long, 1 wide.
    fn measure_row(damages: &[f64]) -> CrackFront {
        let points: Vec<PointOutput> = damages
            .iter()
            .enumerate()
            .map(|(k, &d)| point(0.25 + 0.5 * k as f64, d))
            .collect();
        let ifs = [InterfaceResults {
            block: 0,
            points,
            points_per_element: 1,
        }];
        let mut probe = CrackProbe {
            direction: [1.0, 0.0, 0.0],
            origin: [0.0; 3],
            width: None,
            blocks: vec![0],
            extent: 0.5 * damages.len() as f64,
        };
        probe.measure(&ifs).unwrap()
    }

    #[test]
    fn front_length_and_process_zone_of_a_row_of_points() {
        // a row of points 0.5 apart, each of area 0.5: the bond 4.5 long, 1
        // wide; failed (damage 1, traction-free) up to x = 0.75, softening
        // up to x = 3.25 (damage 0.995 still carries traction: process zone)
        let c = measure_row(&[1.0, 1.0, 0.995, 0.5, 0.3, 0.1, 0.01, 0.0, 0.0]);
        assert!((c.width - 1.0).abs() < 1e-12);
        assert!((c.length - 1.0).abs() < 1e-12);
        assert_eq!(c.front, Some(0.75));
        assert_eq!(c.process_zone_points, 5);
        assert!((c.process_zone_length - (3.25 - 0.75)).abs() < 1e-12);
    }

    /// A crack from both ends of a row (a coupon's two free edges): the
    /// process zone ahead of each front is a run of its own, and the
    /// reported one is the longer run, not the points beyond the far
    /// front (none).
    #[test]
    fn two_fronts_each_have_their_process_zone() {
        let c = measure_row(&[1.0, 1.0, 0.6, 0.3, 0.0, 0.0, 0.2, 0.4, 0.7, 1.0]);
        // the right front's run: 3.25, 3.75, 4.25, up to the failed 4.75
        assert_eq!(c.process_zone_points, 3);
        assert!((c.process_zone_length - (4.75 - 3.25)).abs() < 1e-12);
        assert!((c.length - 1.5).abs() < 1e-12);
    }
}
