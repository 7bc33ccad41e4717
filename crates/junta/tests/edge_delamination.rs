//! Edge delamination of a [±25/90]s coupon in tension (O'Brien 1982),
//! `examples/laminates/edge_delamination.toml`: a generalized plane
//! strain slice (`[[tie]]`) of the upper half of a 12 mm wide coupon.
//!
//! References, from classical lamination theory (Jones 1999, in
//! tests/support/clt.rs; T300/5208 of Tsai & Hahn 1980):
//! - `E_LAM`, the laminate's modulus `1 / (t a_11)`;
//! - `E*`, O'Brien's delaminated modulus: the sublaminates [±25] (twice)
//!   and [90]2 apart, each with its `A` alone, `E* = (4 E_[±25] + 2 E_90) / 6`;
//! - `eps_c = sqrt(2 G_c / ((t/m) (E_LAM - E*)))`, `t/m = 0.375` mm (two
//!   delaminated interfaces over the 0.75 mm thickness; here one over the
//!   half).
//!
//! A coupon of finite width is softer than CLT by its free-edge layers
//! (`E(b) = E_inf - c / b`); two widths extrapolate to `E_inf`.

#[path = "support/clt.rs"]
mod clt;
use clt::*;
use junta::{RunSettings, Simulation};
use std::path::PathBuf;

const HALF_THICKNESS: f64 = 0.375;
const SLICE: f64 = 0.2;
const G_C: f64 = 0.2;

fn example() -> (PathBuf, String) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/laminates/edge_delamination.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    (path, text)
}

/// CLT modulus along x of a balanced lay-up, from its `A` alone.
fn modulus(angles: &[f64]) -> f64 {
    let abd = clt_abd(angles);
    let a = [
        [abd[0][0], abd[0][1], abd[0][2]],
        [abd[1][0], abd[1][1], abd[1][2]],
        [abd[2][0], abd[2][1], abd[2][2]],
    ];
    let det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
        - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    let a11_inv = (a[1][1] * a[2][2] - a[1][2] * a[2][1]) / det;
    1.0 / (a11_inv * T * angles.len() as f64)
}

fn e_lam() -> f64 {
    modulus(&[25.0, -25.0, 90.0, 90.0, -25.0, 25.0])
}

fn e_star() -> f64 {
    (4.0 * modulus(&[25.0, -25.0]) + 2.0 * modulus(&[90.0])) / 6.0
}

/// The generalized reaction at `ref1` of a linear run of the slice
/// `width` wide, as a modulus.
fn linear_modulus(text: &str, width: f64) -> f64 {
    let divisions = (5.0 * width).round() as usize;
    let text = text
        .replace(
            "size = [0.2, 12.0], divisions = [1, 60]",
            &format!("size = [0.2, {width}], divisions = [1, {divisions}]"),
        )
        .replace("type = \"static\"\nsteps = [1.5]", "type = \"linear\"");
    let r = Simulation::from_scene_text(&text, "edge_delamination.toml")
        .unwrap()
        .run(&RunSettings::in_memory(), &mut [])
        .unwrap();
    let g = r.summary.section("generalized_reactions").unwrap()["ref1"][0]
        .as_f64()
        .unwrap();
    g / (width * HALF_THICKNESS) / (0.002 / SLICE)
}

/// The tied slice's modulus, extrapolated in width, is CLT's `E_LAM`;
/// and each width's is below it, by the free-edge layers.
#[test]
fn tied_slice_modulus_extrapolated_in_width_is_clt() {
    let (_, text) = example();
    let (e6, e12) = (linear_modulus(&text, 6.0), linear_modulus(&text, 12.0));
    let e_inf = 2.0 * e12 - e6;
    let reference = e_lam();
    assert!(e6 < e12 && e12 < reference, "{e6} {e12} {reference}");
    assert!(
        ((e_inf - reference) / reference).abs() < 2e-3,
        "E_inf {e_inf} vs CLT E_LAM {reference}"
    );
}

/// The delamination grows at O'Brien's strain, and the modulus falls
/// with the crack length at CLT's rate `(E_LAM - E*) / b`.
#[test]
fn delamination_strain_and_stiffness_loss_match_obrien() {
    let (path, text) = example();
    let r = Simulation::from_scene_text(&text, &path)
        .unwrap()
        .run(&RunSettings::in_memory(), &mut [])
        .unwrap();
    assert!(r.failure.is_none(), "{}", r.status_line);
    let drop = e_lam() - e_star();
    let eps_c = (2.0 * G_C / (HALF_THICKNESS * drop)).sqrt();
    // the rows of steady growth: a crack of 1 to 8 mm in the 12 mm width
    let growth: Vec<(f64, f64, f64)> = r
        .rows
        .iter()
        .filter_map(|row| {
            let a = row.crack_length?;
            let (f, u) = (row.reaction?, row.displacement?);
            let eps = u / SLICE;
            (a > 1.0 && a < 8.0).then_some((a, eps, f / (12.0 * HALF_THICKNESS) / eps))
        })
        .collect();
    assert!(growth.len() >= 10, "{} rows of growth", growth.len());
    let mean_eps = growth.iter().map(|g| g.1).sum::<f64>() / growth.len() as f64;
    assert!(
        ((mean_eps - eps_c) / eps_c).abs() < 0.01,
        "growth strain {mean_eps} vs O'Brien {eps_c}"
    );
    // least-squares slope of the secant modulus against the crack length
    let n = growth.len() as f64;
    let (ma, me) = (
        growth.iter().map(|g| g.0).sum::<f64>() / n,
        growth.iter().map(|g| g.2).sum::<f64>() / n,
    );
    let sxy: f64 = growth.iter().map(|g| (g.0 - ma) * (g.2 - me)).sum();
    let sxx: f64 = growth.iter().map(|g| (g.0 - ma).powi(2)).sum();
    let measured_drop = -12.0 * sxy / sxx;
    assert!(
        ((measured_drop - drop) / drop).abs() < 0.02,
        "E_LAM - E*: {measured_drop} vs CLT {drop}"
    );
}

/// A `[[tie]]` whose dependent node has no partner names the table, the
/// node and where it looked.
#[test]
fn tie_without_a_partner_names_the_node() {
    let (_, text) = example();
    let text = text.replacen(
        "[[tie]]\nsets = [\"x1\", \"x0\"]\ncomponents = [\"y\", \"z\"]",
        "[[tie]]\nsets = [\"x1\", \"x0\"]\ncomponents = [\"y\", \"z\"]\noffset = [0.2, 0.05, 0.0]",
        1,
    );
    let e = Simulation::from_scene_text(&text, "ed.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("ed.toml") && e.contains("tie"), "{e}");
}
