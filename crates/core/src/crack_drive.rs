//! The crack's driving force, measured on the interface: the energy
//! release rate as the J integral of the cohesive tractions over the
//! process zone, and the length of that zone. A fatigue law that sees one
//! point cannot know either; the cycle-jump driver measures them at the
//! start of each fatigue increment and hands them to every law through
//! [`crate::element::StepInfo::crack_drive`].
//!
//! # J integral of a cohesive zone (Rice 1968)
//!
//! Around a cohesive zone in an elastic body, Rice's J integral shrinks to
//! the zone itself: with `s` the coordinate along the direction of growth
//! (the crack behind, at small `s`), `t(s)` the traction and `delta(s)` the
//! jump at the same instant,
//!
//! ```text
//! J = - int t(s) . d delta/ds ds
//! ```
//!
//! over the whole line of interface points, from the failed points (no
//! traction) through the process zone to the elastic points ahead
//! (whose contributions `K delta d delta` add up to the elastic energy of
//! the springs and to zero where the jump returns to 0). J equals the
//! energy release rate of the crack whatever shape the tractions have: the
//! static softening curve or one lowered by fatigue damage, unlike the
//! area under one point's static curve, which is what a law alone can use.
//! Bak, Turon, Lindgaard & Lund 2016 (Int. J. Numer. Meth. Eng. 106,
//! 163-191) drive their fatigue damage rate by a crack-front energy
//! release rate and a measured process zone for the same reason.
//!
//! # Discretisation
//!
//! Interface integration points are grouped into lines along the
//! direction `d`: the points whose reference positions differ only along
//! `d` (their transverse position `x - (x . d) d` equal to within 1e-6 of
//! the interfaces' size). Along each line, sorted by `s = x . d`, the
//! integral is the trapezoid rule in the jump,
//!
//! ```text
//! J_line = | sum_i (t_i + t_{i+1}) / 2 . (delta_i - delta_{i+1}) |
//! ```
//!
//! exact for the linear springs ahead of the zone; its shear components'
//! part over the whole is the mode ratio `G_II / G`. The process zone of a
//! line is its points past onset (`failure_index >= 1`) or damaged, with
//! damage below 1 (the points a fatigue law damages in the next
//! increment); its length is the sum of their tributary lengths along `d`
//! (half the distance to each neighbour on the line). The measure of the
//! run is that of the line with the largest J: on a straight front of
//! uniform width (a DCB, an ENF) every line gives the same J; on a curved
//! front that line speaks for the whole front.

use crate::element::PointOutput;
use crate::state::StateStore;
use crate::{CoreError, Model};

pub use crate::step::CrackDrive;

/// One interface point, as the J integral reads it.
struct LinePoint {
    line: [i64; 3],
    s: f64,
    jump: [f64; 3],
    traction: [f64; 3],
    in_zone: bool,
}

fn three(v: Option<&[f64]>) -> [f64; 3] {
    match v {
        Some(v) if v.len() >= 3 => [v[0], v[1], v[2]],
        _ => [0.0; 3],
    }
}

fn scalar(p: &PointOutput, name: &str) -> f64 {
    p.get(name).and_then(|v| v.first().copied()).unwrap_or(0.0)
}

/// J, its mode ratio and the process-zone length of one line of points
/// sorted by `s`.
fn line_measure(line: &[LinePoint]) -> CrackDrive {
    // the shear (0, 1) and normal (2) parts of the integral
    let mut parts = [0.0; 3];
    for w in line.windows(2) {
        for c in 0..3 {
            parts[c] += 0.5 * (w[0].traction[c] + w[1].traction[c]) * (w[0].jump[c] - w[1].jump[c]);
        }
    }
    let j = parts[0] + parts[1] + parts[2];
    let shear = parts[0] + parts[1];
    let n = line.len();
    let mut zone = 0.0;
    for (i, p) in line.iter().enumerate() {
        if !p.in_zone {
            continue;
        }
        let back = if i > 0 { p.s - line[i - 1].s } else { 0.0 };
        let ahead = if i + 1 < n { line[i + 1].s - p.s } else { 0.0 };
        // a line of one point has no length to give
        let length = match (i > 0, i + 1 < n) {
            (true, true) => 0.5 * (back + ahead),
            _ => back + ahead,
        };
        zone += length;
    }
    CrackDrive {
        energy_release_rate: j.abs(),
        mode_ratio: if j != 0.0 {
            (shear / j).clamp(0.0, 1.0)
        } else {
            0.0
        },
        process_zone_length: zone,
    }
}

/// The crack's driving force along the unit `direction` from the outputs
/// of every interface point (see the module docs); `None` without points.
pub fn crack_drive_of<'a>(
    outputs: impl IntoIterator<Item = &'a PointOutput>,
    direction: [f64; 3],
) -> Option<CrackDrive> {
    let raw = outputs
        .into_iter()
        .map(|p| line_point(p, direction))
        .collect();
    measure(raw)
}

/// A point's transverse position (which line it is on) and what the J
/// integral reads of it.
fn line_point(p: &PointOutput, d: [f64; 3]) -> ([f64; 3], LinePoint) {
    let s = p.position[0] * d[0] + p.position[1] * d[1] + p.position[2] * d[2];
    let transverse = [0, 1, 2].map(|c| p.position[c] - s * d[c]);
    let damage = p.get(crate::law::output::DAMAGE).map_or(0.0, |v| v[0]);
    let in_zone = damage < 1.0 && (damage > 0.0 || scalar(p, "failure_index") >= 1.0);
    (
        transverse,
        LinePoint {
            line: [0; 3],
            s,
            jump: three(p.get("jump")),
            traction: three(p.get("traction")),
            in_zone,
        },
    )
}

/// The points grouped into lines, and the measure of the line with the
/// largest J.
fn measure(raw: Vec<([f64; 3], LinePoint)>) -> Option<CrackDrive> {
    if raw.is_empty() {
        return None;
    }
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for (x, _) in &raw {
        for c in 0..3 {
            lo[c] = lo[c].min(x[c]);
            hi[c] = hi[c].max(x[c]);
        }
    }
    let size = (0..3).map(|c| hi[c] - lo[c]).fold(0.0, f64::max);
    let tol = 1e-6 * size.max(f64::MIN_POSITIVE);
    let mut points: Vec<LinePoint> = raw
        .into_iter()
        .map(|(x, mut p)| {
            p.line = [0, 1, 2].map(|c| ((x[c] - lo[c]) / tol).round() as i64);
            p
        })
        .collect();
    points.sort_by(|a, b| a.line.cmp(&b.line).then(a.s.total_cmp(&b.s)));
    let mut best = CrackDrive::default();
    for line in points.chunk_by(|a, b| a.line == b.line) {
        let m = line_measure(line);
        if m.energy_release_rate > best.energy_release_rate {
            best = m;
        }
    }
    Some(best)
}

impl Model {
    /// The crack's driving force along the unit `direction` at the
    /// displacement `u` and the committed `state` ([`crack_drive_of`]);
    /// `None` for a model without interface points.
    pub fn crack_drive(
        &self,
        u: &[f64],
        state: &StateStore,
        direction: [f64; 3],
    ) -> Result<Option<CrackDrive>, CoreError> {
        let mut raw = Vec::new();
        self.for_each_interface_point(u, state, |p| raw.push(line_point(p, direction)))?;
        Ok(measure(raw))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A point at `x` along the line `y`, with normal and shear jumps and
    /// a linear spring `K` scaled by `(1 - d)`.
    fn point(x: f64, y: f64, opening: f64, slip: f64, d: f64, index: f64) -> PointOutput {
        let k = 1.0e4 * (1.0 - d);
        PointOutput {
            position: [x, y, 0.0],
            values: vec![
                ("jump", vec![slip, 0.0, opening]),
                ("traction", vec![k * slip, 0.0, k * opening]),
                ("damage", vec![d]),
                ("failure_index", vec![index]),
            ],
        }
    }

    /// Two lines of linear springs whose jumps fall linearly from the
    /// crack mouth to 0: the trapezoid sum telescopes, so J is exactly the
    /// energy of the first spring, `K (delta_n^2 + delta_s^2) / 2`, and
    /// the mode ratio its shear part; the line with the larger J is the
    /// one reported, whatever the direction's sign; the zone is the
    /// tributary length of its points past onset (x = 0 and 1: 1 + 1).
    #[test]
    fn j_of_linear_springs_is_the_mouth_springs_energy() {
        let mut pts = Vec::new();
        for (y, scale) in [(0.0, 1.0), (1.0, 0.5)] {
            for i in 0..=10 {
                let x = i as f64;
                let jump = 1e-3 * scale * (10.0 - x) / 10.0;
                pts.push(point(
                    x,
                    y,
                    jump,
                    0.5 * jump,
                    0.0,
                    if i <= 1 { 1.2 } else { 0.3 },
                ));
            }
        }
        let expect = 0.5 * 1.0e4 * (1e-3f64.powi(2) + 0.5e-3f64.powi(2));
        for dir in [[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]] {
            let c = crack_drive_of(&pts, dir).unwrap();
            assert!(
                (c.energy_release_rate / expect - 1.0).abs() < 1e-12,
                "{} against {expect}",
                c.energy_release_rate
            );
            assert!((c.mode_ratio - 0.2).abs() < 1e-12, "{}", c.mode_ratio);
            assert!(
                (c.process_zone_length - 2.0).abs() < 1e-12,
                "{}",
                c.process_zone_length
            );
        }
        assert!(crack_drive_of(&[], [1.0, 0.0, 0.0]).is_none());
    }
}
