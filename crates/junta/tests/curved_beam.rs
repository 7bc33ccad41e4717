//! Curved-beam strength (ASTM D6415), `examples/laminates/curved_beam.toml`:
//! a `[0_8]` L-section of T300/5208 opened by a pure moment, an interface
//! between every pair of plies (N = 40 MPa).
//!
//! * The onset moment against Lekhnitskii's curved beam (Anisotropic
//!   Plates, 1968, sec. 31; [`lekhnitskii`]) with the interface strength:
//!   the moment at which the radial stress at the most loaded interface
//!   radius `r_j = r_i + j t` reaches N. The model's, from a linear run
//!   (the largest normal traction of any interface point) and from the
//!   incremental run (its peak: the delamination is unstable from its
//!   onset), within 3 %. ASTM D6415's approximation `sigma_r = 3 M / (2 w
//!   t sqrt(r_i r_o))` is reported.
//! * The unstable delamination traced to its end by the default control:
//!   from load control up to the peak, through the snap-back (load and its
//!   conjugate displacement both fall) to a whole interface failed through
//!   the bend, the crack growing along the arms and running out through
//!   the loaded end as the load falls back to zero, where the run ends by
//!   itself (182 increments): the load's work all dissipated (Clapeyron)
//!   and that energy `G_c` per unit of the failed area (Griffith) plus the
//!   process zone left at the other arm's tip.

#[path = "support/lekhnitskii.rs"]
mod lekhnitskii;

use junta::{RunSettings, Simulation};
use std::path::PathBuf;

/// Inner and outer radius, ply thickness, plies, width, strength, and the
/// moment per unit load factor (the example's header).
const A: f64 = 6.0;
const T: f64 = 0.25;
const PLIES: usize = 8;
const W: f64 = 1.0;
const N: f64 = 40.0;
/// The interfaces' toughness (`G_Ic = G_IIc`, the example's law).
const G_C: f64 = 0.2;
const M_UNIT: f64 = 100.0;
/// A bound on the incremental test's increments (it ends by itself at 182).
const INCREMENTS: usize = 400;

fn example() -> (PathBuf, String) {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/laminates/curved_beam.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    (path, text)
}

/// The load factor at which Lekhnitskii's radial stress at the most loaded
/// interface radius reaches `N`, and that radius.
fn lekhnitskii_onset() -> (f64, f64) {
    let b = A + PLIES as f64 * T;
    let k = lekhnitskii::hoop_ply_k(181.0e3, 10.3e3, 0.28, 0.4);
    let beam = lekhnitskii::CurvedBeam::new(A, b, k, M_UNIT / W);
    let (r, s) = (1..PLIES)
        .map(|j| {
            let r = A + j as f64 * T;
            (r, beam.sigma_r(r).abs())
        })
        .max_by(|p, q| p.1.total_cmp(&q.1))
        .unwrap();
    (N / s, r)
}

/// ASTM D6415's onset load factor: `sigma_r = 3 M / (2 w t sqrt(r_i r_o))`.
fn astm_onset() -> f64 {
    let (b, t) = (A + PLIES as f64 * T, PLIES as f64 * T);
    N / (3.0 * M_UNIT / (2.0 * W * t * (A * b).sqrt()))
}

#[test]
fn onset_moment_matches_lekhnitskii_with_the_interface_strength() {
    let (_, text) = example();
    let linear = text.replace("type = \"static\"\nsteps = [6.0]", "type = \"linear\"");
    assert_ne!(linear, text);
    let r = Simulation::from_scene_text(&linear, "curved_beam.toml")
        .unwrap()
        .run(&RunSettings::in_memory(), &mut [])
        .unwrap();
    let f = r.frame.unwrap().interface;
    let (q, sn) = (0..f.block.len())
        .map(|q| (q, f.traction[3 * q + 2]))
        .max_by(|p, q| p.1.total_cmp(&q.1))
        .unwrap();
    let x = &f.position[3 * q..3 * q + 3];
    let (lambda_fe, (lambda_l, r_l)) = (N / sn, lekhnitskii_onset());
    let radius = x[0].hypot(x[2]);
    eprintln!(
        "onset: model {:.2} N mm ({:+.2} % of Lekhnitskii's {:.2} at r = {r_l}; the model's at r = {radius:.3}, {:.1} degrees); ASTM D6415 {:.2} N mm ({:+.2} %)",
        lambda_fe * M_UNIT,
        100.0 * (lambda_fe / lambda_l - 1.0),
        lambda_l * M_UNIT,
        x[2].atan2(x[0]).to_degrees(),
        astm_onset() * M_UNIT,
        100.0 * (astm_onset() / lambda_l - 1.0)
    );
    // in the bend, at Lekhnitskii's interface
    assert!(x[0] > 0.0 && x[2] > 0.0, "onset at {x:?}");
    assert!(
        (radius - r_l).abs() < 1e-6,
        "onset at r = {radius}, not {r_l}"
    );
    assert!(
        (lambda_fe / lambda_l - 1.0).abs() < 0.03,
        "{lambda_fe} vs {lambda_l}"
    );
}

#[test]
fn unstable_delamination_is_traced_by_the_default_control() {
    let (path, text) = example();
    assert!(
        !text.contains("control ="),
        "the example takes the default control"
    );
    // to the end of the crack's run (docs/laminates.md, "The curved
    // beam's delamination to its end")
    let settings = RunSettings {
        max_increments: Some(INCREMENTS),
        ..RunSettings::in_memory()
    };
    let r = Simulation::from_scene_text(&text, &path)
        .unwrap()
        .run(&settings, &mut [])
        .unwrap();
    assert!(r.failure.is_none(), "{}", r.status_line);
    let rows = &r.rows;
    assert!(rows.len() < INCREMENTS, "{}", r.status_line);
    assert!(
        r.status_line
            .contains("the delamination has run to its end"),
        "{}",
        r.status_line
    );
    let peak = (0..rows.len())
        .max_by(|&i, &j| rows[i].lambda.total_cmp(&rows[j].lambda))
        .unwrap();
    let (lambda_l, _) = lekhnitskii_onset();
    let lambda_max = rows[peak].lambda;
    // the snap-back: load and conjugate displacement both well below the peak's
    let after = rows[peak..]
        .iter()
        .find(|row| row.lambda < 0.4 * lambda_max && row.conjugate < 0.5 * rows[peak].conjugate);
    let last = rows.last().unwrap();
    // a whole interface through the bend: 24 elements of 3 x 3 points
    let bend_points = 24 * 9;
    eprintln!(
        "curved beam: peak {:.2} N mm ({:+.2} % of Lekhnitskii's onset), snap-back to {:.2} N mm; {} increments ({}), {} interface points failed, {:.3} N mm dissipated over {:.2} mm2 damaged",
        lambda_max * M_UNIT,
        100.0 * (lambda_max / lambda_l - 1.0),
        after.map_or(f64::NAN, |row| row.lambda * M_UNIT),
        rows.len(),
        r.status_line,
        last.failed,
        last.dissipated,
        last.damaged_area
    );
    assert!(
        (lambda_max / lambda_l - 1.0).abs() < 0.03,
        "peak {lambda_max} vs {lambda_l}"
    );
    assert!(
        rows[..peak].iter().all(|row| row.control == "load"),
        "load control up to the peak"
    );
    assert!(after.is_some(), "no snap-back after the peak");
    assert!(last.failed >= bend_points, "{} failed", last.failed);
    // the end: the load positive and below 1e-3 of the peak, never negative
    assert!(
        last.lambda > 0.0 && last.lambda < 1e-3 * lambda_max,
        "last load factor {} of {lambda_max}",
        last.lambda
    );
    assert!(rows.iter().all(|row| row.lambda >= 0.0));
    // Clapeyron: the load's work all dissipated; Griffith: G_c per unit
    // failed area, plus the process zone left at arm a's tip
    let griffith = G_C * last.damaged_area;
    eprintln!(
        "end of the run: work {:.4} N mm, dissipated {:.4} N mm, G_c x failed area {griffith:.4} N mm",
        last.external_work, last.dissipated
    );
    assert!((last.external_work - last.dissipated).abs() < 0.01 * last.external_work);
    assert!(last.dissipated > griffith && last.dissipated < 1.05 * griffith);
}
