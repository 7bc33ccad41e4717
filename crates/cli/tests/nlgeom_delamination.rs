//! Delamination under large deformation (issue 37 item 2): a DCB with
//! `nlgeom = true` and no `control` follows the snap-backs of its crack to
//! the end of its program (the dissipation constraint on the interfaces'
//! energy balance, `junta_solvers` module `nonlinear::balance`), and its
//! propagation curve lies on the small-strain run's.

mod common;
use common::*;
use std::path::Path;

/// `(opening, reaction, external work)` of every converged increment.
fn curve(dir: &Path) -> Vec<(f64, f64, f64)> {
    let text = std::fs::read_to_string(dir.join("curve.csv")).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let (d, r, w) = (col("displacement"), col("reaction"), col("external_work"));
    lines
        .map(|row| {
            let v: Vec<&str> = row.split(',').collect();
            (
                v[d].parse().unwrap(),
                v[r].parse().unwrap(),
                v[w].parse().unwrap(),
            )
        })
        .collect()
}

/// The mean load over the openings `[from, to]`: the external work done
/// between the first converged increment at or past `from` and the last at
/// or before `to`, over the opening between them. The work follows the
/// path through every snap-back, so the mean does not depend on where the
/// increments fell on the saw-tooth of the elements letting go one by one.
fn mean_load(c: &[(f64, f64, f64)], from: f64, to: f64) -> f64 {
    let i = c.iter().position(|r| r.0 >= from).unwrap();
    let j = c.iter().rposition(|r| r.0 <= to).unwrap();
    assert!(
        c[j].0 - c[i].0 > 0.5 * (to - from),
        "increments span too little of [{from}, {to}]"
    );
    (c[j].2 - c[i].2) / (c[j].0 - c[i].0)
}

/// tests/data/dcb_nlgeom.toml (the DCB of the delamination examples, pinned
/// at mid-height of each arm's end) under `nlgeom` and under small strain,
/// both with the default control: the nlgeom run reaches the 10 mm opening
/// through the crack's snap-backs, and its peak and its mean loads over
/// the propagation (1 mm windows from 5.5 mm, external work over opening)
/// lie within 2 % of the small-strain run's. The reference is the
/// small-strain run: beam theory with moderate rotations (Williams 1987,
/// large-displacement correction `F = 1 - 0.3 (delta / a)^2` of `G`) puts
/// the large-deformation load about 1 % above it at 10 mm.
#[test]
fn dcb_under_nlgeom_follows_its_crack_to_10_mm_on_the_small_strain_curve() {
    let tmp = tempfile::tempdir().unwrap();
    let text =
        std::fs::read_to_string(repo().join("crates/cli/tests/data/dcb_nlgeom.toml")).unwrap();
    assert!(text.contains("nlgeom = true") && !text.contains("control ="));
    let mut runs = Vec::new();
    for nlgeom in [true, false] {
        let input = tmp.path().join(format!("dcb_{nlgeom}.toml"));
        std::fs::write(
            &input,
            text.replace("nlgeom = true", &format!("nlgeom = {nlgeom}")),
        )
        .unwrap();
        let out = tmp.path().join(format!("out_{nlgeom}"));
        let summary = run_ok(&input, &out);
        assert_eq!(
            summary["status"], "completed",
            "nlgeom = {nlgeom}: {summary}"
        );
        let c = curve(&out);
        let last = c.last().unwrap();
        assert!(
            (last.0 - 10.0).abs() < 1e-9,
            "nlgeom = {nlgeom}: ends at {}",
            last.0
        );
        let csv = std::fs::read_to_string(out.join("curve.csv")).unwrap();
        assert!(
            csv.contains(",dissipation,"),
            "nlgeom = {nlgeom}: the crack was not followed under the dissipation constraint"
        );
        runs.push(c);
    }
    let (large, small) = (&runs[0], &runs[1]);
    let peak = |c: &[(f64, f64, f64)]| c.iter().map(|r| r.1).fold(0.0, f64::max);
    let (p_large, p_small) = (peak(large), peak(small));
    assert!(
        (p_large / p_small - 1.0).abs() < 0.02,
        "peak {p_large} under nlgeom, {p_small} under small strain"
    );
    // past the peak (about 5 mm): the crack runs
    for (from, to) in [(5.5, 6.5), (6.5, 7.5), (7.5, 8.5), (8.5, 10.0)] {
        let (m_large, m_small) = (mean_load(large, from, to), mean_load(small, from, to));
        assert!(
            (m_large / m_small - 1.0).abs() < 0.02,
            "mean load over [{from}, {to}] mm: {m_large} under nlgeom, {m_small} under small strain"
        );
    }
}
