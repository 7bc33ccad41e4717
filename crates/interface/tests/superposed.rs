//! One-point tests of `superposed` (crates/interface/src/law/superposed.rs):
//! an initiation and a bridging bilinear law in parallel make the
//! trilinear law of Davila, Rose & Camanho (2009), whose closed form is
//! the sum of two triangles (below), and dissipate the sum of their
//! toughnesses.

mod common;

use junta_core::element::StepInfo;
use junta_core::law::{output, InterfaceLaw, LawContext, LawResponse};
use junta_core::registry::{find, LawEntry};
use junta_interface as _;
use std::sync::Arc;

/// Initiation law: stiff, strong, brittle (onset 6e-4 mm, failure at 2 G /
/// N = 1e-2 mm).
const K1: f64 = 1.0e5;
const N1: f64 = 60.0;
const G1: f64 = 0.3;
/// Bridging law: the same onset (K2 / K1 = N2 / N1, Davila et al.'s
/// split), a tenth of the strength, failure at 0.2 mm.
const N2: f64 = 5.0;
const K2: f64 = K1 * N2 / N1;
const G2: f64 = 0.5;

fn bilinear(k: f64, n: f64, g: f64) -> String {
    // S and G_IIc consistent with one penalty (Turon 2010), eta 2
    format!(
        "type = \"bilinear\"\nK = {k:e}\nN = {n}\nS = {n}\nG_Ic = {g}\nG_IIc = {g}\neta = 2.0\n"
    )
}

fn scene_table(extra: &str) -> toml::Table {
    let text = format!(
        "[[laws]]\n{}\n[[laws]]\n{}\n{extra}",
        bilinear(K1, N1, G1),
        bilinear(K2, N2, G2)
    );
    toml::from_str(&text).unwrap()
}

fn build() -> Arc<dyn InterfaceLaw> {
    (find::<LawEntry>("superposed").unwrap().build)(&scene_table("")).unwrap()
}

fn build_err(text: &str) -> String {
    let t: toml::Table = toml::from_str(text).unwrap();
    (find::<LawEntry>("superposed").unwrap().build)(&t)
        .unwrap_err()
        .to_string()
}

/// The trilinear law in mode I: the sum of the two triangles.
fn trilinear(delta: f64) -> f64 {
    let triangle = |k: f64, n: f64, g: f64| {
        let (d0, df) = (n / k, 2.0 * g / n);
        if delta <= d0 {
            k * delta
        } else if delta < df {
            n * (df - delta) / (df - d0)
        } else {
            0.0
        }
    };
    triangle(K1, N1, G1) + triangle(K2, N2, G2)
}

struct Point {
    law: Arc<dyn InterfaceLaw>,
    state: Vec<f64>,
    inc: usize,
}

impl Point {
    fn new(law: Arc<dyn InterfaceLaw>) -> Self {
        let mut state = vec![0.0; law.state_len()];
        law.init_state(&mut state);
        Point { law, state, inc: 0 }
    }
    fn trial(&self, jump: [f64; 3]) -> (LawResponse, Vec<f64>) {
        let mut trial = vec![f64::NAN; self.state.len()];
        let step = StepInfo {
            increment: self.inc + 1,
            delta_load_factor: 1.0,
            ..StepInfo::default()
        };
        let ctx = LawContext {
            jump,
            state_committed: &self.state,
            step,
        };
        let r = self.law.evaluate(&ctx, &mut trial).unwrap();
        (r, trial)
    }
    fn step(&mut self, jump: [f64; 3]) -> LawResponse {
        let (r, t) = self.trial(jump);
        self.state = t;
        self.inc += 1;
        r
    }
    fn output(&self, name: &str) -> f64 {
        common::output_of(self.law.as_ref(), &self.state, name)
    }
    /// Central differences against the law's tangent.
    fn check_tangent(&self, jump: [f64; 3], what: &str) {
        common::check_fd_tangent(|j| self.trial(j).0, jump, 1e-7, what);
    }
}

/// A monotone mode I opening follows the trilinear closed form at every
/// point (onset, the kink where the initiation law fails, the bridging
/// tail, separation), and dissipates G1 + G2; the work of the traction
/// equals it.
#[test]
fn mode_i_opening_follows_the_trilinear_law_and_dissipates_both_toughnesses() {
    let mut p = Point::new(build());
    let steps = 4000;
    let end = 0.25;
    let mut work = 0.0;
    let mut last = (0.0, 0.0);
    for k in 1..=steps {
        let delta = end * k as f64 / steps as f64;
        let t = p.step([0.0, 0.0, delta]).traction[2];
        let exact = trilinear(delta);
        assert!(
            (t - exact).abs() <= 1e-9 * N1,
            "delta {delta}: {t} against {exact}"
        );
        work += 0.5 * (t + last.1) * (delta - last.0);
        last = (delta, t);
    }
    let dissipated = p.output(output::DISSIPATED_ENERGY);
    assert!((dissipated - (G1 + G2)).abs() < 1e-9, "{dissipated}");
    // the trapezoid rule on 4000 steps is exact for a piecewise linear
    // curve but at its three kinks
    assert!((work - (G1 + G2)).abs() < 1e-4, "{work}");
    assert!((p.output("law1.dissipated_energy") - G1).abs() < 1e-9);
    assert!((p.output("law2.dissipated_energy") - G2).abs() < 1e-9);
    assert!(p.law.is_failed(&p.state));
}

/// Between the failure of the initiation law and that of the bridging law
/// the point's damage (the first law's) is 1, so the crack front is the
/// initiation law's failure, while the point still carries the bridging
/// traction and has not failed.
#[test]
fn bridging_zone_carries_load_behind_the_crack_front() {
    let mut p = Point::new(build());
    let delta = 0.02;
    for k in 1..=100 {
        p.step([0.0, 0.0, delta * k as f64 / 100.0]);
    }
    assert_eq!(p.output(output::DAMAGE), 1.0);
    // the bridging law's secant damage, 1 - t / (K2 delta)
    let t2 = trilinear(delta);
    let d2 = 1.0 - t2 / (K2 * delta);
    assert!(
        (p.output("law2.damage") - d2).abs() < 1e-12,
        "{}",
        p.output("law2.damage")
    );
    assert!(d2 < 1.0);
    assert!(!p.law.is_failed(&p.state));
    assert_eq!(p.law.stage(&p.state), junta_core::PointStage::ProcessZone);
    let t = p.trial([0.0, 0.0, delta]).0.traction[2];
    assert!((t - t2).abs() < 1e-9, "{t}");
    assert!(t > 0.9 * N2, "{t}");
    // dissipated so far: all of G1, the part of G2 swept,
    // N2 df (delta - d0) / (2 (df - d0)) (swept area less the elastic rest)
    let d0 = N2 / K2;
    let df = 2.0 * G2 / N2;
    let swept = 0.5 * N2 * df * (delta - d0) / (df - d0);
    let dissipated = p.output(output::DISSIPATED_ENERGY);
    assert!(
        (dissipated - (G1 + swept)).abs() < 1e-9,
        "{dissipated} against {}",
        G1 + swept
    );
}

/// The tangent against central differences: both laws elastic, both
/// softening, the initiation law failed and the bridging law softening,
/// unloading, compression, mixed mode, all failed.
#[test]
fn tangent_matches_finite_differences_in_every_regime() {
    let law = build();
    let p = Point::new(law.clone());
    p.check_tangent([1e-4, -2e-4, 3e-4], "elastic");
    p.check_tangent([1e-4, 1e-4, -3e-4], "compression");
    p.check_tangent([0.0, 0.0, 2e-3], "both softening, mode I");
    p.check_tangent([1.5e-3, 0.0, 1.5e-3], "both softening, mixed");
    p.check_tangent([0.0, 0.0, 0.05], "initiation failed, bridging softening");
    p.check_tangent(
        [0.03, 0.0, 0.04],
        "initiation failed, bridging softening, mixed",
    );
    let mut q = Point::new(law.clone());
    for k in 1..=20 {
        q.step([0.0, 0.0, 0.03 * k as f64 / 20.0]);
    }
    q.check_tangent([0.0, 0.0, 0.01], "unloading");
    q.check_tangent([0.0, 0.0, 0.031], "bridging softening again");
    q.check_tangent([0.0, 1e-3, -1e-4], "damaged, closed");
    for k in 1..=20 {
        q.step([0.0, 0.0, 0.03 + 0.3 * k as f64 / 20.0]);
    }
    assert!(q.law.is_failed(&q.state));
    q.check_tangent([0.0, 0.0, 0.4], "all failed, open");
    let r = q.trial([0.0, 0.0, 0.4]).0;
    assert!(r.traction.iter().all(|t| t.abs() < 1e-12), "{r:?}");
}

/// The sum's fracture properties and penalties are the laws' sums.
#[test]
fn fracture_properties_are_the_sums() {
    let law = build();
    let f = law.fracture_properties().unwrap();
    assert_eq!(f.strength_normal, N1 + N2);
    assert_eq!(f.toughness_mode_i, G1 + G2);
    assert_eq!(law.initial_stiffness()[2], K1 + K2);
}

/// Input mistakes name what is wrong and what is valid.
#[test]
fn bad_tables_say_what_is_valid() {
    let e = build_err("");
    assert!(e.contains("give `laws`"), "{e}");
    let e = build_err(&format!("[[laws]]\n{}", bilinear(K1, N1, G1)));
    assert!(e.contains("give 2 to 8 laws"), "{e}");
    let e = build_err(&format!(
        "[[laws]]\n{}\n[[laws]]\nK = 1.0\n",
        bilinear(K1, N1, G1)
    ));
    assert!(e.contains("`laws[1].type` is missing"), "{e}");
    let e = build_err(&format!(
        "[[laws]]\n{}\n[[laws]]\ntype = \"bilinear\"\nK = 1.0\n",
        bilinear(K1, N1, G1)
    ));
    assert!(e.contains("`laws[1]` (`bilinear`)"), "{e}");
    let e = build_err(&format!(
        "[[laws]]\n{}\n[[laws]]\ntype = \"nope\"\n",
        bilinear(K1, N1, G1)
    ));
    assert!(e.contains("nope") && e.contains("bilinear"), "{e}");
    let mut t = scene_table("");
    t.insert("extra".into(), toml::Value::Integer(1));
    let e = (find::<LawEntry>("superposed").unwrap().build)(&t)
        .unwrap_err()
        .to_string();
    assert!(e.contains("unknown key `extra`"), "{e}");
}
