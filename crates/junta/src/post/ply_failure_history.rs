//! Ply failure through an incremental run: each `[[ply_failure]]`
//! criterion ([`super::ply_failure`]) evaluated after every converged
//! increment, and the load at which a ply first fails.
//!
//! ## The first-failure load
//!
//! After increment `i` (load factor `lambda_i`) a criterion's smallest
//! strength ratio over its points is `R_i`: the state scaled by `R_i`
//! fails first (`R_i <= 1` once a point has failed). The first increment
//! with `R_i <= 1` holds the first ply failure. Its load factor is found
//! between the increment before (`lambda_p`, `R_p > 1`) and this one by
//! linear interpolation of the inverse ratio `1 / R`, to `1 / R = 1`:
//!
//! ```text
//! lambda_f = lambda_p + (1 - 1/R_p) / (1/R_i - 1/R_p) (lambda_i - lambda_p)
//! ```
//!
//! For a response that is linear in the load up to the failure (every
//! stress proportional to `lambda`), `1 / R = lambda / lambda_f` exactly, so
//! the interpolation returns the linear run's first-ply-failure load
//! factor whatever the increments; the run's first increment starts from
//! the unloaded state (`lambda = 0`, `1 / R = 0`). The curve's reaction
//! and displacement are interpolated with the same weight. Across a
//! change of program step the load factor restarts, and the failing
//! increment's own values are reported (`interpolated = false`).

use super::ply_failure::{PlyFailureResult, WeakestPoint};
use crate::post::curve::CurveRow;
use serde::{Deserialize, Serialize};

/// The load at which a criterion first reached 1 (`summary.json`
/// `ply_failure.NAME.first_failure`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlyFirstFailure {
    /// The first increment (global, 1-based) with an index of at least 1.
    pub increment: usize,
    /// Its program step (0-based).
    pub step: usize,
    /// The load factor where the index reached 1 (see the module docs).
    pub load_factor: f64,
    /// The curve's reaction there (`None` without a curve).
    pub reaction: Option<f64>,
    /// The curve's displacement there (`None` without a curve).
    pub displacement: Option<f64>,
    /// Whether `load_factor` is interpolated from the increment before.
    pub interpolated: bool,
    /// The failing point at that increment: block, element, position,
    /// stress in the ply axes, mode.
    pub weakest: Option<WeakestPointRecord>,
}

/// [`WeakestPoint`] as kept across a restart.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WeakestPointRecord {
    /// Block name.
    pub block: String,
    /// Element label.
    pub element: usize,
    /// Reference position of the integration point.
    pub position: [f64; 3],
    /// Stress in the material axes, Voigt `[11, 22, 33, 12, 23, 31]`.
    pub stress: [f64; 6],
    /// Failure mode.
    pub mode: String,
}

impl From<&WeakestPoint> for WeakestPointRecord {
    fn from(w: &WeakestPoint) -> Self {
        WeakestPointRecord {
            block: w.block.clone(),
            element: w.element,
            position: w.position,
            stress: w.stress,
            mode: w.mode.to_string(),
        }
    }
}

/// One criterion's record of the last converged increment.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct LastIncrement {
    step: usize,
    lambda: f64,
    inverse_ratio: f64,
    reaction: Option<f64>,
    displacement: Option<f64>,
}

/// Per criterion (by name): its last increment and its first failure; kept
/// in the run's log and in `checkpoint.json`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct PlyFailureHistory {
    criteria: Vec<CriterionHistory>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct CriterionHistory {
    name: String,
    last: Option<LastIncrement>,
    first_failure: Option<PlyFirstFailure>,
}

impl PlyFailureHistory {
    /// Take in the results of the converged increment of `row`.
    pub fn record(&mut self, row: &CurveRow, results: &[PlyFailureResult]) {
        for r in results {
            let h = match self.criteria.iter().position(|c| c.name == r.name) {
                Some(i) => &mut self.criteria[i],
                None => {
                    self.criteria.push(CriterionHistory {
                        name: r.name.clone(),
                        last: None,
                        first_failure: None,
                    });
                    self.criteria.last_mut().expect("just pushed")
                }
            };
            let now = LastIncrement {
                step: row.step,
                lambda: row.lambda,
                inverse_ratio: inverse(r.strength_ratio),
                reaction: row.reaction,
                displacement: row.displacement,
            };
            if h.first_failure.is_none() && now.inverse_ratio >= 1.0 {
                h.first_failure = Some(first_failure(h.last.as_ref(), &now, row, r));
            }
            h.last = Some(now);
        }
    }

    /// The first failure of criterion `name`, if it has failed.
    pub fn first_failure(&self, name: &str) -> Option<&PlyFirstFailure> {
        self.criteria
            .iter()
            .find(|c| c.name == name)
            .and_then(|c| c.first_failure.as_ref())
    }
}

/// `1 / R` (0 where nothing is stressed, `R` infinite).
fn inverse(strength_ratio: f64) -> f64 {
    if strength_ratio.is_finite() && strength_ratio > 0.0 {
        1.0 / strength_ratio
    } else if strength_ratio == 0.0 {
        f64::INFINITY
    } else {
        0.0
    }
}

/// The first failure between `prev` (the increment before, `None` at the
/// start of the run: the unloaded state) and `now`.
fn first_failure(
    prev: Option<&LastIncrement>,
    now: &LastIncrement,
    row: &CurveRow,
    r: &PlyFailureResult,
) -> PlyFirstFailure {
    let unloaded = LastIncrement {
        step: 0,
        lambda: 0.0,
        inverse_ratio: 0.0,
        reaction: Some(0.0),
        displacement: Some(0.0),
    };
    let start = match prev {
        Some(p) => Some(p),
        None if row.step == 0 && row.increment == 1 => Some(&unloaded),
        None => None,
    };
    let weight = start
        .filter(|p| p.step == now.step && now.inverse_ratio.is_finite())
        .map(|p| {
            (
                p,
                (1.0 - p.inverse_ratio) / (now.inverse_ratio - p.inverse_ratio),
            )
        });
    let lerp = |a: Option<f64>, b: Option<f64>, w: f64| Some(a? + w * (b? - a?));
    let (load_factor, reaction, displacement, interpolated) = match weight {
        Some((p, w)) => (
            p.lambda + w * (now.lambda - p.lambda),
            lerp(p.reaction, now.reaction, w),
            lerp(p.displacement, now.displacement, w),
            true,
        ),
        None => (now.lambda, now.reaction, now.displacement, false),
    };
    PlyFirstFailure {
        increment: row.increment,
        step: row.step,
        load_factor,
        reaction,
        displacement,
        interpolated,
        weakest: r.weakest.as_ref().map(WeakestPointRecord::from),
    }
}

/// The header of `ply_failure.csv`: increment, step, load factor, then
/// per criterion its largest index and smallest strength ratio.
pub fn csv_header(names: &[String]) -> String {
    let mut h = String::from("increment,step,load_factor");
    for n in names {
        h += &format!(",{n}_max_index,{n}_strength_ratio");
    }
    h + "\n"
}

/// The `ply_failure.csv` line of the increment of `row`.
pub fn csv_line(row: &CurveRow, results: &[PlyFailureResult]) -> String {
    let mut line = format!("{},{},{:e}", row.increment, row.step, row.lambda);
    for r in results {
        line += &format!(",{:e},{:e}", r.max_index, r.strength_ratio);
    }
    line + "\n"
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(increment: usize, lambda: f64) -> CurveRow {
        CurveRow {
            increment,
            lambda,
            reaction: Some(10.0 * lambda),
            ..CurveRow::default()
        }
    }

    fn result(ratio: f64) -> PlyFailureResult {
        PlyFailureResult {
            name: "hashin".into(),
            cell_index: Vec::new(),
            max_index: 1.0 / ratio,
            strength_ratio: ratio,
            weakest: None,
        }
    }

    /// A linear response failing at `lambda_f = 0.37`: `R = lambda_f /
    /// lambda` at every increment, so the interpolated load is exact.
    #[test]
    fn proportional_response_gives_the_exact_load() {
        let lf = 0.37;
        let mut h = PlyFailureHistory::default();
        for i in 1..=5 {
            let lambda = 0.1 * i as f64;
            h.record(&row(i, lambda), &[result(lf / lambda)]);
        }
        let f = h.first_failure("hashin").unwrap();
        assert_eq!(f.increment, 4);
        assert!((f.load_factor - lf).abs() < 1e-14, "{}", f.load_factor);
        assert!((f.reaction.unwrap() - 10.0 * lf).abs() < 1e-12);
        assert!(f.interpolated);
        // failing in the first increment: from the unloaded state
        let mut h = PlyFailureHistory::default();
        h.record(&row(1, 0.5), &[result(0.2 / 0.5)]);
        assert!((h.first_failure("hashin").unwrap().load_factor - 0.2).abs() < 1e-14);
    }

    #[test]
    fn unloaded_and_unfailed_criteria_have_no_failure() {
        let mut h = PlyFailureHistory::default();
        h.record(&row(1, 0.1), &[result(f64::INFINITY)]);
        h.record(&row(2, 0.2), &[result(2.0)]);
        assert!(h.first_failure("hashin").is_none());
        assert!(h.first_failure("other").is_none());
    }
}
