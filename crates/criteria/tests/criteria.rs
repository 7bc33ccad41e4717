//! Tests of the stress criteria `quadratic` (paper eq. 40) and `max_stress`:
//! hand values, the compression option, exactly-at-limit points, modes,
//! parameter checks and the registry.

use junta_core::registry::{entries, find, CriterionEntry};
use junta_core::{FailureCriterion, FailureMode};
use junta_criteria as _;
use junta_criteria::{CompressionRule, MaxStress, Quadratic};

fn table(src: &str) -> toml::Table {
    src.parse().unwrap()
}

#[test]
fn quadratic_hand_values() {
    let q = Quadratic::new(2e6, 4e6, CompressionRule::PositivePart).unwrap();
    // 0.25 + 0.25
    let r = q.evaluate([2e6, 0.0, 1e6]);
    assert_eq!(r.index, 0.5);
    assert_eq!(r.mode, FailureMode::Tension);
    let r = q.evaluate([0.0, 2e6, 0.0]);
    assert_eq!(r.index, 0.25);
    assert_eq!(r.mode, FailureMode::Shear);
    // exactly at the limits
    assert_eq!(q.evaluate([0.0, 0.0, 2e6]).index, 1.0);
    assert_eq!(q.evaluate([4e6, 0.0, 0.0]).index, 1.0);
    assert_eq!(q.evaluate([0.0, -4e6, 0.0]).index, 1.0);
    assert_eq!(q.evaluate([0.0, 0.0, 4e6]).index, 4.0);
}

#[test]
fn quadratic_compression_option() {
    let pos = Quadratic::new(2e6, 4e6, CompressionRule::PositivePart).unwrap();
    let lit = Quadratic::new(2e6, 4e6, CompressionRule::AsWritten).unwrap();
    let t = [2e6, 0.0, -1e6];
    let r = pos.evaluate(t);
    assert_eq!(r.index, 0.25);
    assert_eq!(r.mode, FailureMode::Compression);
    let r = lit.evaluate(t);
    assert_eq!(r.index, 0.5);
    assert_eq!(r.mode, FailureMode::Compression);
    // pure compression at the limit: never fails with the positive part
    assert_eq!(pos.evaluate([0.0, 0.0, -2e6]).index, 0.0);
    assert_eq!(lit.evaluate([0.0, 0.0, -2e6]).index, 1.0);
    // tension is the same either way
    assert_eq!(pos.evaluate([0.0, 0.0, 1e6]), lit.evaluate([0.0, 0.0, 1e6]));
}

#[test]
fn max_stress_hand_values() {
    let m = MaxStress::new(2e6, 4e6, CompressionRule::PositivePart).unwrap();
    let r = m.evaluate([2e6, 0.0, 1e6]);
    assert_eq!(r.index, 0.5);
    assert_eq!(r.mode, FailureMode::Tension);
    // |tau| = hypot(2.4e6, 3.2e6) = 4e6 -> 1.0 exactly at the limit
    let r = m.evaluate([2.4e6, 3.2e6, 0.0]);
    assert!((r.index - 1.0).abs() <= 1e-15, "{}", r.index);
    assert_eq!(r.mode, FailureMode::Shear);
    assert_eq!(m.evaluate([0.0, 0.0, 2e6]).index, 1.0);
    assert_eq!(m.evaluate([4e6, 0.0, 0.0]).index, 1.0);
    assert_eq!(m.evaluate([1e6, 0.0, 1.5e6]).index, 0.75);
    // compression
    assert_eq!(m.evaluate([1e6, 0.0, -3e6]).index, 0.25);
    assert_eq!(m.evaluate([1e6, 0.0, -3e6]).mode, FailureMode::Compression);
    let lit = MaxStress::new(2e6, 4e6, CompressionRule::AsWritten).unwrap();
    assert_eq!(lit.evaluate([1e6, 0.0, -3e6]).index, 1.5);
}

#[test]
fn from_table_and_defaults() {
    let q = Quadratic::from_table(&table("sigma_lim = 2e6\ntau_lim = 4e6")).unwrap();
    assert_eq!(
        q,
        Quadratic::new(2e6, 4e6, CompressionRule::PositivePart).unwrap()
    );
    let q = Quadratic::from_table(&table(
        "sigma_lim = 2e6\ntau_lim = 4e6\ncompression = \"as_written\"",
    ))
    .unwrap();
    assert_eq!(q.compression, CompressionRule::AsWritten);
    let m = MaxStress::from_table(&table(
        "sigma_lim = 1.0\ntau_lim = 3.0\ncompression = \"positive_part\"",
    ))
    .unwrap();
    assert_eq!(
        m,
        MaxStress::new(1.0, 3.0, CompressionRule::PositivePart).unwrap()
    );
}

#[test]
fn bad_params_are_rejected_with_the_key() {
    for bad in [0.0, -1.0, f64::INFINITY, f64::NAN] {
        let e = Quadratic::new(bad, 1.0, CompressionRule::PositivePart)
            .unwrap_err()
            .to_string();
        assert!(e.contains("sigma_lim") && e.contains("positive"), "{e}");
        let e = MaxStress::new(1.0, bad, CompressionRule::AsWritten)
            .unwrap_err()
            .to_string();
        assert!(e.contains("tau_lim") && e.contains("positive"), "{e}");
    }
    let e = Quadratic::from_table(&table("tau_lim = 4e6"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("missing `sigma_lim`"), "{e}");
    let e = MaxStress::from_table(&table("sigma_lim = 4e6"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("missing `tau_lim`"), "{e}");
    let e = Quadratic::from_table(&table("sigma_lim = 1.0\ntau_lim = -4e6"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("tau_lim"), "{e}");
    let e = Quadratic::from_table(&table("sigma_lim = 1.0\ntau_lim = 1.0\nsigma_max = 1.0"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("sigma_max") && e.contains("sigma_lim"), "{e}");
    let e = Quadratic::from_table(&table(
        "sigma_lim = 1.0\ntau_lim = 1.0\ncompression = \"abs\"",
    ))
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("positive_part") && e.contains("as_written"),
        "{e}"
    );
}

#[test]
fn registry_holds_both() {
    let keys: Vec<_> = entries::<CriterionEntry>().iter().map(|e| e.key).collect();
    assert!(
        keys.contains(&"quadratic") && keys.contains(&"max_stress"),
        "{keys:?}"
    );
    let t = table("sigma_lim = 2e6\ntau_lim = 4e6");
    for key in ["quadratic", "max_stress"] {
        let entry = find::<CriterionEntry>(key).unwrap();
        assert!(!entry.params.is_empty());
        let c = (entry.build)(&t).unwrap();
        assert_eq!(c.key(), key);
        assert_eq!(c.evaluate([0.0, 0.0, 2e6]).index, 1.0);
    }
    let e = match find::<CriterionEntry>("hashin") {
        Ok(_) => panic!("hashin is not registered"),
        Err(e) => e.to_string(),
    };
    assert!(e.contains("quadratic") && e.contains("max_stress"), "{e}");
}
