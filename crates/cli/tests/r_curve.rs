//! The R-curve of superposed laws (issue 26, part 4) on a DCB under pure
//! end moments, `examples/delamination/dcb_r_curve.toml`: the J-integral
//! from the loads, `J = M^2 / (B E I)` (exact for pure moments), against
//! the R-curve the laws give, `J_R = G1 + W2(delta*)` with `W2` the work of
//! the bridging law up to the opening `delta*` at the precrack's end (Rice
//! 1968; Sorensen & Jacobsen 1998, Compos. A 29, 1443-1451).

mod common;
use common::*;

/// Arm: E1, width, thickness of one arm.
const E1: f64 = 122700.0;
const B: f64 = 25.4;
const H: f64 = 1.56;
/// Initiation toughness; bridging law: strength, toughness, onset jump.
const G1: f64 = 0.5;
const N2: f64 = 2.0;
const G2: f64 = 1.0;
const DELTA0: f64 = N2 / (1.0e6 * N2 / 60.0);
/// The initiation law's final opening `2 G1 / N1` (N1 = 60 MPa).
const DELTA_F1: f64 = 2.0 * G1 / 60.0;

/// Work of the bridging law's traction (bilinear, mode I) up to `delta`:
/// the rising line to `DELTA0`, then the falling one to `2 G2 / N2`.
fn bridging_work(delta: f64) -> f64 {
    let df = 2.0 * G2 / N2;
    if delta <= DELTA0 {
        return 0.5 * N2 * delta * delta / DELTA0;
    }
    let d = delta.min(df);
    0.5 * N2 * DELTA0 + N2 * (df * (d - DELTA0) - 0.5 * (d * d - DELTA0 * DELTA0)) / (df - DELTA0)
}

/// Rows of curve.csv: (moment, delta*, crack growth from the damaged area).
fn rows(dir: &std::path::Path) -> Vec<(f64, f64, f64)> {
    let text = std::fs::read_to_string(dir.join("curve.csv")).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| head.iter().position(|h| *h == n).unwrap();
    let (l, d, a) = (col("load_factor"), col("displacement"), col("damaged_area"));
    lines
        .map(|line| {
            let f: Vec<f64> = line
                .split(',')
                .map(|v| v.parse().unwrap_or(f64::NAN))
                .collect();
            (1000.0 * f[l], f[d], f[a] / B)
        })
        .collect()
}

/// At every increment of the growth the moment's J is the laws' R-curve
/// within 3 %, within 1 % on average while it rises, and the moment is
/// beam theory's with that R-curve, `M = sqrt(J_R(delta*) B E I)`, within
/// 3 % (the tolerance for the load-opening curve); the curve rises
/// from the initiation toughness (J within 10 % of G1 once the initiation
/// law has failed at the precrack's end, `delta* >= 2 G1 / N1`) to the sum
/// of both (the steady plateau's mean within 1 % of
/// G1 + G2, every point within 4 %). Measured: J -1.1 .. +1.3 %, mean
/// -0.02 % while rising; the moment within 0.65 %; initiation +7.2 %;
/// plateau mean within 0.01 %, spread 0.7 %.
#[test]
fn superposed_laws_give_the_r_curve_of_the_j_integral() {
    let dir = tempfile::tempdir().unwrap();
    let s = run_ok(
        &repo().join("examples/delamination/dcb_r_curve.toml"),
        dir.path(),
    );
    assert!(
        s["status"].as_str().unwrap().contains("max_increments"),
        "{s}"
    );
    let ei = E1 * B * H.powi(3) / 12.0;
    let j = |m: f64| m * m / (B * ei);
    let rows = rows(dir.path());
    // the growth: from the initiation law's failure at the precrack's end
    // (a point fails, `damaged_area`, only when both laws have dissipated
    // their toughness: the bridging zone is the process zone)
    let growing: Vec<_> = rows.iter().filter(|r| r.1 >= DELTA_F1).collect();
    let init = j(growing[0].0) / G1 - 1.0;
    assert!(
        init.abs() < 0.1,
        "initiation: J {} against G1 {G1}",
        j(growing[0].0)
    );
    // the bridged crack (both laws failed) has grown 18.9 mm, with the
    // 12 mm bridging zone ahead of it
    assert!(growing.last().unwrap().2 > 15.0, "{:?}", growing.last());
    let mut plateau = Vec::new();
    let (mut lo, mut hi) = (f64::MAX, f64::MIN);
    let (mut rising, mut rising_sum) = (0usize, 0.0);
    let mut load = 0.0f64;
    for &&(m, delta, _) in &growing {
        let j_r = G1 + bridging_work(delta);
        let ratio = j(m) / j_r - 1.0;
        lo = lo.min(ratio);
        hi = hi.max(ratio);
        // the load-opening curve: beam theory with the R-curve gives the
        // moment at the opening delta*, M = sqrt(J_R B E I)
        load = load.max((m / (j_r * B * ei).sqrt() - 1.0).abs());
        if delta > 2.0 * G2 / N2 {
            plateau.push(j(m));
        } else {
            rising += 1;
            rising_sum += ratio;
        }
    }
    let rising_mean = rising_sum / rising as f64;
    println!(
        "J / J_R - 1 within {lo:.4} .. {hi:.4}, mean {rising_mean:.5} while it rises; initiation {init:.4}"
    );
    println!("moment against beam theory with the R-curve: within {load:.4}");
    assert!(lo > -0.03 && hi < 0.03, "{lo} .. {hi}");
    assert!(load < 0.03, "{load}");
    assert!(
        rising > 50 && rising_mean.abs() < 0.01,
        "{rising}: {rising_mean}"
    );
    // the rise: less than half way at a fifth of the bridging law's final
    // opening
    let early = growing.iter().find(|r| r.1 > 0.2 * 2.0 * G2 / N2).unwrap();
    assert!(j(early.0) < G1 + 0.5 * G2, "{early:?}");
    assert!(plateau.len() > 100, "{}", plateau.len());
    let mean = plateau.iter().sum::<f64>() / plateau.len() as f64;
    let spread = plateau
        .iter()
        .fold(0.0f64, |m, v| m.max((v / (G1 + G2) - 1.0).abs()));
    println!(
        "plateau mean {mean:.4} (G1 + G2 = {}), spread {spread:.4}",
        G1 + G2
    );
    assert!((mean / (G1 + G2) - 1.0).abs() < 0.01, "{mean}");
    assert!(spread < 0.04, "{spread}");
}
