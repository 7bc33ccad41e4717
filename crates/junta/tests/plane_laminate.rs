//! The lay-up builder in a cross-section (plane elements):
//! `examples/laminates/curved_beam_plane.toml`, the ASTM D6415 L-section of
//! `curved_beam.toml` built from `cpe8` plies and `line_inter6` interfaces.
//!
//! * The radial stress through the bend against Lekhnitskii's curved beam
//!   under pure bending (Anisotropic Plates, 1968, sec. 31; a plane-strain
//!   solution), within 2 % at its peak, and the onset moment with the
//!   interface strength within 3 %.
//! * The cross-section is the 3D slab of `curved_beam.toml` (one H20
//!   across a width held in plane strain; the same in-plane mesh): the
//!   interface tractions agree to 1e-8 of their largest.
//! * The unstable delamination traced by the default control.

#[path = "support/lekhnitskii.rs"]
mod lekhnitskii;

use junta::{RunSettings, Simulation};
use std::path::PathBuf;

/// Inner radius, ply thickness, plies, strength, toughness (`G_Ic =
/// G_IIc`) and the moment per unit load factor on the unit thickness (the
/// example's header and law).
const A: f64 = 6.0;
const T: f64 = 0.25;
const PLIES: usize = 8;
const N: f64 = 40.0;
const G_C: f64 = 0.2;
const M_UNIT: f64 = 100.0;

fn example(name: &str) -> (PathBuf, String) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/laminates")
        .join(name);
    let text = std::fs::read_to_string(&path).unwrap();
    (path, text)
}

/// The example as a linear run.
fn linear(name: &str) -> junta::Frame {
    let (path, text) = example(name);
    let linear = text.replace("type = \"static\"\nsteps = [6.0]", "type = \"linear\"");
    assert_ne!(linear, text);
    Simulation::from_scene_text(&linear, path)
        .unwrap()
        .run(&RunSettings::in_memory(), &mut [])
        .unwrap()
        .frame
        .unwrap()
}

/// Lekhnitskii's beam of the example (T300/5208 hoop plies in plane
/// strain, `k = sqrt(b_rr / b_tt)`), under the moment `m` per unit width.
fn beam(m: f64) -> lekhnitskii::CurvedBeam {
    let b = A + PLIES as f64 * T;
    let k = lekhnitskii::hoop_ply_k(181.0e3, 10.3e3, 0.28, 0.4);
    lekhnitskii::CurvedBeam::new(A, b, k, m)
}

/// Where a point of the cross-section lies in the bend: its radius and
/// its angle in degrees from `-x` towards `+y` (the bend runs 0..90).
fn in_bend(x: &[f64]) -> (f64, f64) {
    (x[0].hypot(x[1]), x[1].atan2(-x[0]).to_degrees())
}

#[test]
fn radial_stress_and_onset_match_lekhnitskii() {
    let frame = linear("curved_beam_plane.toml");
    let solid = &frame.solid;
    let b = A + PLIES as f64 * T;
    // the mid-section of the bend (45 degrees)
    let pts: Vec<usize> = (0..solid.block.len())
        .filter(|&q| {
            let x = &solid.position[3 * q..3 * q + 3];
            let (_, angle) = in_bend(x);
            (angle - 45.0).abs() < 2.0 && x[0] < 0.0 && x[1] > 0.0
        })
        .collect();
    assert!(
        pts.len() >= 2 * PLIES,
        "{} points near 45 degrees",
        pts.len()
    );
    // the sign of the moment: the hoop stress at the inner radius says which way it bends
    let radius = |q: usize| in_bend(&solid.position[3 * q..3 * q + 3]).0;
    let inner = *pts
        .iter()
        .min_by(|&&p, &&q| radius(p).total_cmp(&radius(q)))
        .unwrap();
    let hoop_inner = solid.material_stress[6 * inner];
    let mut lek = beam(M_UNIT);
    if lek.sigma_theta(A).signum() != hoop_inner.signum() {
        lek = beam(-M_UNIT);
    }
    let peak = (0..=200)
        .map(|i| lek.sigma_r(A + (b - A) * i as f64 / 200.0))
        .fold(0.0f64, |m, s| if s.abs() > m.abs() { s } else { m });
    let (mut err, mut fe_peak) = (0.0f64, 0.0f64);
    for &q in &pts {
        // ply axes: 1 the hoop, 3 the radius
        let s = solid.material_stress[6 * q + 2];
        err = err.max((s - lek.sigma_r(radius(q))).abs());
        if s.abs() > fe_peak.abs() {
            fe_peak = s;
        }
    }
    eprintln!(
        "plane strain: Lekhnitskii peak sigma_r {peak:.5e}, model {fe_peak:.5e} ({:+.2} %); largest difference {:.2} % of the peak",
        100.0 * (fe_peak / peak - 1.0),
        100.0 * err / peak.abs()
    );
    assert!((fe_peak / peak - 1.0).abs() < 0.02, "{fe_peak} vs {peak}");
    assert!(err < 0.03 * peak.abs());

    // the onset: the largest interface normal traction reaches N
    let f = &frame.interface;
    let (q, sn) = (0..f.block.len())
        .map(|q| (q, f.traction[3 * q + 2]))
        .max_by(|p, q| p.1.total_cmp(&q.1))
        .unwrap();
    let (r, angle) = in_bend(&f.position[3 * q..3 * q + 3]);
    let (r_l, s_l) = (1..PLIES)
        .map(|j| A + j as f64 * T)
        .map(|r| (r, lek.sigma_r(r).abs()))
        .max_by(|p, q| p.1.total_cmp(&q.1))
        .unwrap();
    let (onset, onset_l) = (N / sn, N / s_l);
    eprintln!(
        "onset {:.2} N mm at r = {r:.3}, {angle:.1} degrees; Lekhnitskii {:.2} N mm at r = {r_l} ({:+.2} %)",
        onset * M_UNIT,
        onset_l * M_UNIT,
        100.0 * (onset / onset_l - 1.0)
    );
    assert!((r - r_l).abs() < 1e-9, "onset at r = {r}, not {r_l}");
    assert!(angle > 0.0 && angle < 90.0, "onset outside the bend");
    assert!((onset / onset_l - 1.0).abs() < 0.03);
}

/// The cross-section against the 3D slab: the 3D L-section lies in the
/// `x`-`z` plane with arm b along `-x`; the cross-section in the `x`-`y`
/// plane with arm b along `+x`. A 3D interface point `(x, y, z)` is the
/// plane point `(-x, z)`, with the same normal traction and the shear of
/// opposite sign.
#[test]
fn cross_section_is_the_plane_strain_slab() {
    let plane = linear("curved_beam_plane.toml").interface;
    let slab = linear("curved_beam.toml").interface;
    let scale = plane.traction.iter().fold(0.0f64, |m, t| m.max(t.abs()));
    let (mut worst, mut matched) = (0.0f64, 0);
    for q in 0..plane.block.len() {
        let x = &plane.position[3 * q..3 * q + 3];
        for p in 0..slab.block.len() {
            let y = &slab.position[3 * p..3 * p + 3];
            if (y[0] + x[0]).abs() + (y[2] - x[1]).abs() > 1e-9 {
                continue;
            }
            matched += 1;
            let (tp, ts) = (
                &plane.traction[3 * q..3 * q + 3],
                &slab.traction[3 * p..3 * p + 3],
            );
            worst = worst.max((tp[2] - ts[2]).abs()).max((tp[0] + ts[0]).abs());
        }
    }
    eprintln!(
        "plane {} interface points, slab {}; {matched} matched; largest difference {:.2e} of the largest traction {scale:.4e}",
        plane.block.len(),
        slab.block.len(),
        worst / scale
    );
    // every slab point across the width (three Gauss rows) matches one plane point
    assert_eq!(matched, slab.block.len());
    assert_eq!(3 * plane.block.len(), slab.block.len());
    assert!(worst < 1e-8 * scale, "{}", worst / scale);
}

/// The default control traces the unstable delamination to its end: load
/// control up to the peak (the onset, within 3 % of Lekhnitskii's), the
/// snap-back, the mid-plane interface (r = 7) failed through the whole
/// bend, the crack growing along both arms, then arm b's crack running out
/// through the loaded end while the load falls back to zero. There the run
/// ends by itself ("the delamination has run to its end"): at a positive
/// load below 1e-3 of the peak (the increment that would carry it through
/// zero is cut back), with the load's whole work dissipated (Clapeyron: the
/// stored energy `½ M θ` is gone) and that energy `G_c` per unit of the
/// failed area (Griffith) plus the process zone left at arm a's tip.
#[test]
fn unstable_delamination_is_traced_by_the_default_control() {
    let (path, text) = example("curved_beam_plane.toml");
    assert!(
        !text.contains("control ="),
        "the example takes the default control"
    );
    let settings = RunSettings {
        // a bound only: the run ends by itself at 116
        max_increments: Some(300),
        ..RunSettings::in_memory()
    };
    // keeps the last increment's fields
    let mut frames = junta::FrameCollector::every(1000);
    let r = Simulation::from_scene_text(&text, &path)
        .unwrap()
        .run(&settings, &mut [&mut frames])
        .unwrap();
    assert!(r.failure.is_none(), "{}", r.status_line);
    let rows = &r.rows;
    let peak = (0..rows.len())
        .max_by(|&i, &j| rows[i].lambda.total_cmp(&rows[j].lambda))
        .unwrap();
    let lambda_max = rows[peak].lambda;
    let onset_l = {
        let lek = beam(M_UNIT);
        N / (1..PLIES)
            .map(|j| lek.sigma_r(A + j as f64 * T).abs())
            .fold(0.0, f64::max)
    };
    let after = rows[peak..]
        .iter()
        .find(|row| row.lambda < 0.4 * lambda_max && row.conjugate < 0.5 * rows[peak].conjugate);
    // the crack tips along the arms: where the r = 7 interface has failed
    let f = &frames.frames.last().unwrap().interface;
    let failed = &f.outputs["failed"];
    let (mut tip_a, mut tip_b, mut bend_failed) = (0.0f64, 0.0f64, 0);
    for q in 0..f.block.len() {
        let x = &f.position[3 * q..3 * q + 3];
        if failed[q] < 0.5 {
            continue;
        }
        let (radius, angle) = in_bend(x);
        if (x[0] + 7.0).abs() < 1e-9 && x[1] < 0.0 {
            tip_a = tip_a.min(x[1]);
        } else if (x[1] - 7.0).abs() < 1e-9 && x[0] > 0.0 {
            tip_b = tip_b.max(x[0]);
        } else if (radius - 7.0).abs() < 1e-3 && (0.0..=90.0).contains(&angle) {
            bend_failed += 1;
        }
    }
    eprintln!(
        "plane curved beam: peak {:.2} N mm ({:+.2} % of Lekhnitskii's onset), snap-back to {:.2} N mm; {} increments; crack tips at y = {tip_a:.2} (arm a) and x = {tip_b:.2} (arm b); {bend_failed} bend points failed; last moment {:.2} N mm",
        lambda_max * M_UNIT,
        100.0 * (lambda_max / onset_l - 1.0),
        after.map_or(f64::NAN, |row| row.lambda * M_UNIT),
        rows.len(),
        rows.last().unwrap().lambda * M_UNIT
    );
    assert!((lambda_max / onset_l - 1.0).abs() < 0.03);
    assert!(rows[..peak].iter().all(|row| row.control == "load"));
    assert!(after.is_some(), "no snap-back after the peak");
    // 24 elements of 3 points around the bend
    assert_eq!(bend_failed, 72);
    // arm b's crack ran out through its loaded end (x = 10; the last Gauss
    // point of its last element lies at 9.89); arm a's stopped half-way
    assert!(tip_b > 9.8, "arm b's tip at {tip_b}");
    assert!(tip_a < -3.0 && tip_a > -9.0, "arm a's tip at {tip_a}");
    // the run ended by itself at the end of the crack's run
    assert!(
        r.status_line
            .contains("the delamination has run to its end"),
        "{}",
        r.status_line
    );
    let last = rows.last().unwrap();
    assert!(
        last.lambda > 0.0 && last.lambda < 1e-3 * lambda_max,
        "last load factor {} of {lambda_max}",
        last.lambda
    );
    assert!(rows.iter().all(|row| row.lambda >= 0.0));
    // Clapeyron: the load's work was all dissipated
    let (work, dissipated) = (last.external_work, last.dissipated);
    // Griffith: G_c per unit failed area, plus arm a's process zone
    let griffith = G_C * last.damaged_area;
    eprintln!(
        "end of the run: work {work:.4} N mm, dissipated {dissipated:.4} N mm ({:+.2} %), G_c x failed area {griffith:.4} ({:+.2} %)",
        100.0 * (dissipated / work - 1.0),
        100.0 * (dissipated / griffith - 1.0)
    );
    assert!((work - dissipated).abs() < 0.01 * work);
    assert!(dissipated > griffith && dissipated < 1.05 * griffith);
}
