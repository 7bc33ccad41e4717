//! The typed run contract: `summary.json` reads back into the typed
//! `junta::Summary` equal to the run's own, for a linear run, an
//! incremental run and one that stopped early; its typed fields say what
//! the file says.

mod common;
use common::*;
use junta::{RunSettings, Simulation, Status, Summary, SummaryAnalysis};

fn round_trip(input: &std::path::Path, max_increments: Option<usize>) -> (Summary, Status) {
    let (s, status, _) = run_and_read(input, max_increments);
    (s, status)
}

fn run_and_read(
    input: &std::path::Path,
    max_increments: Option<usize>,
) -> (Summary, Status, junta::RunResults) {
    let dir = tempfile::tempdir().unwrap();
    let settings = RunSettings {
        max_increments,
        ..RunSettings::into_dir(dir.path())
    };
    let results = Simulation::from_file(input)
        .unwrap()
        .run(&settings, &mut [])
        .unwrap();
    let read = Summary::read(&dir.path().join("summary.json")).unwrap();
    assert_eq!(read, results.summary, "{}", input.display());
    // and the file is that summary as JSON
    let text = std::fs::read_to_string(dir.path().join("summary.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(v, results.summary.to_json());
    let status = results.status;
    (read, status, results)
}

#[test]
fn a_linear_summary_round_trips() {
    let (s, status) = round_trip(&repo().join("examples/cube.toml"), None);
    assert_eq!(status, Status::Completed);
    assert_eq!(s.analysis, SummaryAnalysis::LinearStatic);
    assert_eq!(s.status, None);
    assert_eq!(s.increments, None);
    // 45 equations: `junta run examples/cube.toml` prints them
    assert_eq!(s.equations, 45);
    assert_eq!(s.dofs, 3 * s.nodes);
    assert!(s.section("reactions").is_some());
    assert!(s.energy.is_none() && s.newton_iterations.is_none());
    let t = s.timings.expect("a linear run has timings");
    assert!(t.pattern.is_some() && t.driver_total.is_none());
}

/// The typed end-of-run sections say what the run's own curve says.
#[test]
fn the_typed_sections_agree_with_the_curve() {
    let input = repo().join("examples/fatigue/held_opening.toml");
    let (s, _, results) = run_and_read(&input, None);
    let last = results.rows.last().unwrap();
    let energy = s.energy.unwrap();
    assert_eq!(energy.dissipated_energy, last.dissipated);
    assert_eq!(energy.external_work, last.external_work);
    let it = s.newton_iterations.unwrap();
    let per: Vec<usize> = results.rows.iter().map(|r| r.iterations).collect();
    assert_eq!(it.per_increment, per);
    assert_eq!(it.total, per.iter().sum::<usize>());
    assert_eq!(Some(it.per_increment.len()), s.increments);
    let driver = s.driver.unwrap();
    assert!(driver.newton_iterations_with_failed_attempts >= it.total);
    assert!(s.timings.unwrap().driver_total.is_some());
}

#[test]
fn an_incremental_summary_round_trips() {
    let input = repo().join("examples/fatigue/held_opening.toml");
    let (s, status) = round_trip(&input, None);
    assert_eq!(status, Status::Completed);
    assert_eq!(s.analysis, SummaryAnalysis::Static);
    assert_eq!(s.status.as_deref(), Some("completed"));
    assert!(s.increments.unwrap() > 0);
    assert!(s["fatigue"].is_object());
    // stopped early: the status line says so, typed and in the file
    let (s, status) = round_trip(&input, Some(2));
    assert_eq!(status, Status::Stopped);
    assert_eq!(s.increments, Some(2));
    assert_eq!(
        s.status.as_deref(),
        Some("stopped after the requested number of increments")
    );
}
