//! Tests of the ply failure criteria `ply_max_stress`, `hashin`, `tsai_wu`
//! and `puck`: failure exactly at the strengths, exact strength ratios on
//! random stress states, Hashin's modes, a Tsai-Wu biaxial case solved by
//! hand, Puck's 3D action-plane search against his closed-form 2D
//! envelope, parameter checks and the registry.

use junta_core::registry::{find, PlyCriterionEntry};
use junta_core::{PlyCriterion, PlyFailureMode};
use junta_criteria::{Hashin, Puck, TsaiWu};
use std::sync::Arc;

/// A carbon/epoxy ply (stress units MPa), round numbers in the range of
/// Soden, Hinton & Kaddour's WWFE data (Compos. Sci. Technol. 58 (1998)
/// 1011-1022): Xt, Xc, Yt, Yc, S12.
const PLY: &str = "Xt = 1500.0\nXc = 1200.0\nYt = 50.0\nYc = 200.0\nS12 = 80.0\n";

fn build(key: &str, extra: &str) -> Arc<dyn PlyCriterion> {
    let table: toml::Table = format!("{PLY}{extra}").parse().unwrap();
    (find::<PlyCriterionEntry>(key).unwrap().build)(&table).unwrap()
}

/// The four criteria, with the parameters each needs beyond `PLY`.
fn all_criteria() -> Vec<Arc<dyn PlyCriterion>> {
    vec![
        build("ply_max_stress", "S23 = 60.0\n"),
        build("hashin", ""),
        build("hashin", "S23 = 70.0\n"),
        build("tsai_wu", ""),
        build("tsai_wu", "S23 = 70.0\nf12_star = -0.3\n"),
        build("puck", ""),
    ]
}

fn along(component: usize, value: f64) -> [f64; 6] {
    let mut s = [0.0; 6];
    s[component] = value;
    s
}

/// Uniaxial tension/compression along 1 and 2 and pure shear 12 at the
/// strengths (Xt, -Xc, Yt, -Yc, S12): index 1 and strength ratio 1; at half
/// the strength, ratio 2 (every criterion) and index 1/2 (degree-1
/// criteria: maximum stress, Puck) or 1/4 (Hashin's quadratic modes with
/// S23 = Yc/2, where matrix compression has no linear term).
#[test]
fn every_criterion_fails_exactly_at_the_strengths() {
    let cases = [
        (0, 1500.0),
        (0, -1200.0),
        (1, 50.0),
        (1, -200.0),
        (3, 80.0),
        (3, -80.0),
    ];
    for c in all_criteria() {
        for (component, strength) in cases {
            let at = c.evaluate(along(component, strength));
            assert!(
                (at.index - 1.0).abs() < 1e-12,
                "{c:?} {component} {strength}: index {}",
                at.index
            );
            assert!(
                (at.strength_ratio - 1.0).abs() < 1e-12,
                "{c:?} {component}: R {}",
                at.strength_ratio
            );
            let half = c.evaluate(along(component, 0.5 * strength));
            assert!(
                (half.strength_ratio - 2.0).abs() < 1e-12,
                "{c:?} {component}: R {}",
                half.strength_ratio
            );
            let expected_half = match c.key() {
                "ply_max_stress" | "puck" => Some(0.5),
                "hashin" if !format!("{c:?}").contains("s23: 70.0") => Some(0.25),
                _ => None,
            };
            if let Some(e) = expected_half {
                assert!(
                    (half.index - e).abs() < 1e-12,
                    "{c:?} {component}: index {}",
                    half.index
                );
            }
        }
    }
}

/// Through-thickness strengths default to the transverse ones (Zt = Yt,
/// Zc = Yc), so s33 = Yt and s33 = -Yc fail at index 1 too.
#[test]
fn through_thickness_defaults_to_transverse() {
    for c in all_criteria() {
        for s in [50.0, -200.0] {
            let r = c.evaluate(along(2, s));
            assert!(
                (r.index - 1.0).abs() < 1e-12,
                "{c:?} s33 = {s}: {}",
                r.index
            );
        }
    }
}

/// xorshift64*: a small deterministic pseudo-random generator, uniform in [-1, 1).
struct Random(u64);

impl Random {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let bits = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11;
        bits as f64 / (1u64 << 52) as f64 - 1.0
    }

    /// A stress with components in [-150, 150) MPa, s11 in [-1500, 1500).
    fn stress(&mut self) -> [f64; 6] {
        let mut s = [0.0; 6];
        for (i, v) in s.iter_mut().enumerate() {
            *v = self.next() * if i == 0 { 1500.0 } else { 150.0 };
        }
        s
    }
}

/// index(R stress) = 1 within 1e-10 for 2000 random states per criterion
/// (R finite), and R stress is on the safe side for 0.999 R.
#[test]
fn strength_ratio_scales_onto_the_failure_surface() {
    let mut random = Random(0x9e37_79b9_7f4a_7c15);
    let mut worst = 0.0f64;
    for c in all_criteria() {
        for _ in 0..2000 {
            let s = random.stress();
            let r = c.evaluate(s).strength_ratio;
            assert!(r.is_finite() && r > 0.0, "{c:?} {s:?}: R {r}");
            let scaled = c.evaluate(s.map(|v| v * r)).index;
            worst = worst.max((scaled - 1.0).abs());
            assert!(
                (scaled - 1.0).abs() < 1e-10,
                "{c:?} {s:?}: index(R s) = {scaled}"
            );
            assert!(c.evaluate(s.map(|v| v * 0.999 * r)).index < 1.0);
        }
    }
    println!("largest |index(R s) - 1| = {worst:e}");
}

/// Hashin reports the mode of the stress: fibre tension/compression along
/// 1, matrix tension/compression along 2 and along 3 (Hashin 1980, the
/// sign conditions of eqs. 16-19, 23-24).
#[test]
fn hashin_reports_the_mode_of_each_axis() {
    use PlyFailureMode::*;
    let h = build("hashin", "");
    let cases = [
        (along(0, 1000.0), FibreTension),
        (along(0, -1000.0), FibreCompression),
        (along(1, 30.0), MatrixTension),
        (along(1, -100.0), MatrixCompression),
        (along(2, 30.0), MatrixTension),
        (along(2, -100.0), MatrixCompression),
        (along(3, 40.0), MatrixTension),
        ([0.0; 6], Interaction),
    ];
    for (s, mode) in cases {
        assert_eq!(h.evaluate(s).mode, mode, "{s:?}");
    }
    // Fibre tension with shear: (1000/1500)^2 + (40/80)^2 = 0.6944 > matrix (40/80)^2.
    let r = h.evaluate([1000.0, 0.0, 0.0, 40.0, 0.0, 0.0]);
    assert_eq!(r.mode, FibreTension);
    assert!((r.index - (4.0 / 9.0 + 0.25)).abs() < 1e-14);
}

/// Hashin's matrix compression with S23 != Yc/2 has a linear term. By
/// hand, s22 = -100, S23 = 70, Yc = 200:
/// F_mc = ((Yc/(2 S23))^2 - 1) s22/Yc + (s22/(2 S23))^2 = a + b with
/// a = (100/49 - 1)(-1/2) = -51/98, b = (100/140)^2 = 25/49, so
/// F_mc = -1/98 < 0 = F_fibre: the index is 0 (the largest mode value), the
/// mode the one that fails first along the ray (matrix compression), and
/// R = 2 exactly (-100 is half of -Yc: 2a + 4b = -102/98 + 200/98 = 1).
#[test]
fn hashin_matrix_compression_hand_value() {
    let h = Hashin::from_table(&format!("{PLY}S23 = 70.0\n").parse().unwrap()).unwrap();
    let r = h.evaluate(along(1, -100.0));
    let (a, b): (f64, f64) = (-51.0 / 98.0, 25.0 / 49.0);
    assert_eq!(r.index, 0.0);
    assert_eq!(r.mode, PlyFailureMode::MatrixCompression);
    // with a little s11 the fibre mode is positive but still below: index = F_fibre
    let r2 = h.evaluate([15.0, -100.0, 0.0, 0.0, 0.0, 0.0]);
    assert!((r2.index - 1e-4).abs() < 1e-15, "{}", r2.index);
    // the matrix function itself at 1.5x: a 1.5 + b 2.25 = (-76.5 + 112.5)/98
    let r3 = h.evaluate(along(1, -150.0));
    assert!((r3.index - 36.0 / 98.0).abs() < 1e-14, "{}", r3.index);
    // a R + b R^2 = 1 by the textbook root (-a + sqrt(a^2 + 4b)) / (2b)
    let root = (-a + (a * a + 4.0 * b).sqrt()) / (2.0 * b);
    assert!((root - 2.0).abs() < 1e-14);
    assert!(
        (r.strength_ratio - 2.0).abs() < 1e-14,
        "{}",
        r.strength_ratio
    );
}

/// Tsai-Wu, equal biaxial stress s11 = s22 = s solved by hand:
/// (F1 + F2) s + (F11 + F22 + 2 F12) s^2 = 1 with F12 = f12* / sqrt(Xt Xc Yt Yc).
/// With the PLY strengths and f12* = -0.5: F1 = 1/1500 - 1/1200 = -1/6000,
/// F2 = 1/50 - 1/200 = 3/200, F11 = 1/1.8e6, F22 = 1/1e4,
/// F12 = -0.5/sqrt(1.8e10) = -3.726780e-6, so b = F1 + F2 = 0.01483333 and
/// a = F11 + F22 + 2 F12 = 9.310200e-5; the textbook roots
/// s = (-b +- sqrt(b^2 + 4a)) / (2a) are 51.0551 MPa and -210.3786 MPa
/// (the quadratic formula evaluated outside this code, in Python, and
/// written here as literals).
#[test]
fn tsai_wu_equal_biaxial_by_hand() {
    let t = TsaiWu::from_table(&PLY.parse().unwrap()).unwrap();
    let f12 = -0.5 / (1500.0f64 * 1200.0 * 50.0 * 200.0).sqrt();
    let b = -1.0 / 6000.0 + 3.0 / 200.0;
    let a = 1.0 / 1.8e6 + 1.0 / 1e4 + 2.0 * f12;
    let s = (-b + (b * b + 4.0 * a).sqrt()) / (2.0 * a);
    assert!((s - 51.0551).abs() < 1e-4, "{s}");
    let at = t.evaluate([s, s, 0.0, 0.0, 0.0, 0.0]);
    assert!((at.index - 1.0).abs() < 1e-13, "{}", at.index);
    let r = t.evaluate([10.0, 10.0, 0.0, 0.0, 0.0, 0.0]).strength_ratio;
    assert!((r - s / 10.0).abs() < 1e-12, "{r}");
    // Both biaxial compressions: s = -t, the negative root.
    let neg = (-b - (b * b + 4.0 * a).sqrt()) / (2.0 * a);
    assert!((neg + 210.3786).abs() < 1e-4, "{neg}");
    let r = t
        .evaluate([-10.0, -10.0, 0.0, 0.0, 0.0, 0.0])
        .strength_ratio;
    assert!((r - neg / -10.0).abs() < 1e-12, "{r} vs {}", neg / -10.0);
}

/// Tsai-Wu's transverse isotropy: with S23 omitted it is Yc/2 = 100, and
/// pure t23 at that value fails exactly; F44 = 2 (F22 - F23) gives the
/// same F at a stress rotated by 30 degrees about axis 1.
#[test]
fn tsai_wu_is_transversely_isotropic() {
    let t = TsaiWu::from_table(&PLY.parse().unwrap()).unwrap();
    let s23 = 100.0;
    assert!((t.evaluate(along(4, s23)).index - 1.0).abs() < 1e-13);
    let s = [300.0, 20.0, -40.0, 10.0, 15.0, -5.0];
    let (c, n) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    let rotated = [
        s[0],
        c * c * s[1] + n * n * s[2] + 2.0 * c * n * s[4],
        n * n * s[1] + c * c * s[2] - 2.0 * c * n * s[4],
        c * s[3] + n * s[5],
        (s[2] - s[1]) * c * n + s[4] * (c * c - n * n),
        -n * s[3] + c * s[5],
    ];
    let (a, b) = (t.evaluate(s).index, t.evaluate(rotated).index);
    assert!((a - b).abs() < 1e-13, "{a} vs {b}");
}

/// Puck's closed-form 2D IFF envelope for (s22, t21), s33 = t23 = t31 = 0
/// (Puck & Schürmann 2002, Compos. Sci. Technol. 62:1633-1662, eqs. for
/// modes A, B, C; VDI 2014 Part 3):
///
/// ```text
/// A (s22 >= 0):   f_E = sqrt((t21/R_par)^2 + (1 - p_par+ R_t/R_par)^2 (s22/R_t)^2) + p_par+ s22/R_par
/// B (s22 < 0, |s22/t21| <= R_A/|t21c|):  f_E = (sqrt(t21^2 + (p_par- s22)^2) + p_par- s22) / R_par
/// C (s22 < 0, |s22/t21| >= R_A/|t21c|):  f_E = [(t21/(2 (1 + p_perp-) R_par))^2 + (s22/R_c)^2] R_c/(-s22)
/// t21c = R_par sqrt(1 + 2 p_perp-),  R_A = R_c / (2 (1 + p_perp-))
/// fracture angle: 0 in A and B;  C: cos^2 theta_fp = [(R_A t21/(R_par s22))^2 + 1] / (2 (1 + p_perp-))
/// ```
///
/// These hold when p_perp-/R_A = p_par-/R_par, which the default derived
/// p_perp_perp_minus ensures (here R_A = 80, p_perp- = 0.25). The 3D
/// search must reproduce f_E within 1e-6 and |theta_fp| within 1e-6 rad
/// (away from the B-C boundary, where f_E is flat in theta to fourth order).
#[test]
fn puck_search_reproduces_the_2d_envelope() {
    let puck = Puck::from_table(&PLY.parse().unwrap()).unwrap();
    let (r_t, r_c, r_par) = (50.0, 200.0, 80.0);
    let (p_plus, p_minus) = (0.3, 0.25);
    let p_perp = puck.p_perp_perp_minus;
    let r_a = r_c / (2.0 * (1.0 + p_perp));
    assert!((r_a - 80.0).abs() < 1e-12 && (p_perp - 0.25).abs() < 1e-12);
    let t21c = r_par * (1.0 + 2.0 * p_perp).sqrt();
    let (mut worst_f, mut worst_angle, mut counts) = (0.0f64, 0.0f64, [0; 3]);
    for step in 0..72 {
        let phi = (step as f64 * 5.0 + 1.0).to_radians();
        let (s22, t21) = (100.0 * phi.cos(), 100.0 * phi.sin());
        let (f, angle, mode) = if s22 >= 0.0 {
            let f = ((t21 / r_par).powi(2)
                + (1.0 - p_plus * r_t / r_par).powi(2) * (s22 / r_t).powi(2))
            .sqrt()
                + p_plus * s22 / r_par;
            (f, 0.0, 0)
        } else if (s22 / t21).abs() <= r_a / t21c {
            let f = ((t21 * t21 + (p_minus * s22).powi(2)).sqrt() + p_minus * s22) / r_par;
            (f, 0.0, 1)
        } else {
            let f =
                ((t21 / (2.0 * (1.0 + p_perp) * r_par)).powi(2) + (s22 / r_c).powi(2)) * r_c / -s22;
            let cos2 = ((r_a * t21 / (r_par * s22)).powi(2) + 1.0) / (2.0 * (1.0 + p_perp));
            (f, cos2.sqrt().acos(), 2)
        };
        counts[mode] += 1;
        let plane = puck.action_plane(&[0.0, s22, 0.0, t21, 0.0, 0.0]);
        worst_f = worst_f.max((plane.exposure - f).abs());
        assert!(
            (plane.exposure - f).abs() < 1e-6,
            "phi {phi}: {} vs {f} (mode {mode})",
            plane.exposure
        );
        let near_boundary = ((s22 / t21).abs() - r_a / t21c).abs() < 0.05;
        if !near_boundary {
            worst_angle = worst_angle.max((plane.angle.abs() - angle).abs());
            assert!(
                (plane.angle.abs() - angle).abs() < 1e-6,
                "phi {phi}: angle {} vs {angle} (mode {mode})",
                plane.angle
            );
        }
    }
    assert!(counts.iter().all(|&n| n > 5), "{counts:?}");
    println!("Puck 2D: largest |f_E - closed form| = {worst_f:e}, |theta - theta_fp| = {worst_angle:e} rad; points per mode A, B, C = {counts:?}");
    // Uniaxial transverse compression: theta_fp = acos(sqrt(1/2.5)) = 50.77 degrees.
    let plane = puck.action_plane(&along(1, -200.0));
    assert!(
        (plane.angle.abs().to_degrees() - 50.768_479_516).abs() < 1e-6,
        "{}",
        plane.angle.to_degrees()
    );
}

/// Puck's modes: fibre by the sign of s11, matrix by the sign of the
/// normal stress on the fracture plane.
#[test]
fn puck_reports_modes() {
    use PlyFailureMode::*;
    let p = build("puck", "");
    assert_eq!(p.evaluate(along(0, 1000.0)).mode, FibreTension);
    assert_eq!(p.evaluate(along(0, -1000.0)).mode, FibreCompression);
    assert_eq!(p.evaluate(along(1, 30.0)).mode, MatrixTension);
    assert_eq!(p.evaluate(along(1, -150.0)).mode, MatrixCompression);
    assert_eq!(p.evaluate([0.0; 6]).mode, Interaction);
    assert_eq!(p.evaluate([0.0; 6]).strength_ratio, f64::INFINITY);
}

/// A NaN component gives a NaN index and ratio, never a panic.
#[test]
fn nan_stress_gives_nan() {
    for c in all_criteria() {
        let r = c.evaluate([f64::NAN, 0.0, 0.0, 0.0, 0.0, 0.0]);
        assert!(r.index.is_nan() && r.strength_ratio.is_nan(), "{c:?}");
        assert_eq!(r.mode, PlyFailureMode::Interaction);
    }
}

/// The registry holds the four keys; an unknown key lists them; a
/// misspelt parameter, a bad strength and a bad interaction are refused,
/// naming the parameter.
#[test]
fn registry_finds_and_refuses() {
    for key in ["ply_max_stress", "hashin", "tsai_wu", "puck"] {
        assert_eq!(find::<PlyCriterionEntry>(key).unwrap().key, key);
    }
    let e = find::<PlyCriterionEntry>("hashn")
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("unknown ply criterion `hashn`"), "{e}");
    assert!(e.contains("hashin, ply_max_stress, puck, tsai_wu"), "{e}");
    let try_build = |key: &str, src: &str| {
        let table: toml::Table = src.parse().unwrap();
        (find::<PlyCriterionEntry>(key).unwrap().build)(&table)
            .err()
            .unwrap()
            .to_string()
    };
    let e = try_build("hashin", &PLY.replace("Xt", "xt"));
    assert!(e.contains("`xt`") && e.contains("Xt"), "{e}");
    let e = try_build("hashin", &PLY.replace("Yt = 50.0", "Yt = -50.0"));
    assert!(
        e.contains("`Yt` = -50") && e.contains("positive and finite"),
        "{e}"
    );
    let e = try_build("tsai_wu", &format!("{PLY}f12_star = 1.5\n"));
    assert!(e.contains("`f12_star` = 1.5 must lie in (-1, 1)"), "{e}");
    let e = try_build("tsai_wu", &format!("{PLY}S23 = 20.0\n"));
    assert!(e.contains("positive definite"), "{e}");
    let e = try_build("puck", &format!("{PLY}p_perp_par_plus = 1.2\n"));
    assert!(e.contains("`p_perp_par_plus` = 1.2"), "{e}");
    let e = try_build("ply_max_stress", PLY);
    assert!(e.contains("S23"), "{e}");
}
