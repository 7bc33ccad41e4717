//! The one table of curve columns (`junta::CURVE_COLUMNS`) is what every
//! kind of incremental run writes as the header of `curve.csv`, what the
//! run API's curve holds, and the table of `docs/outputs.md`.

mod common;
use common::*;

fn header_of(dir: &std::path::Path) -> String {
    let text = std::fs::read_to_string(dir.join("curve.csv")).unwrap();
    format!("{}\n", text.lines().next().unwrap())
}

/// Load control (a friction block), path following (the coarse DCB,
/// `control = "arc_length"`, three increments), automatic control (the
/// same DCB without `control`) and a fatigue program (the held opening):
/// each writes the table's header, and each row has one cell per column.
#[test]
fn every_kind_of_run_writes_the_table_as_its_header() {
    let dir = tempfile::tempdir().unwrap();
    let auto = write(
        dir.path(),
        "dcb_auto.toml",
        &std::fs::read_to_string(repo().join("examples/delamination/dcb_coarse.toml"))
            .unwrap()
            .replace("control = \"arc_length\"\n", ""),
    );
    std::fs::copy(
        repo().join("examples/delamination/dcb_beam_theory.csv"),
        dir.path().join("dcb_beam_theory.csv"),
    )
    .unwrap();
    let runs = [
        (
            "load",
            repo().join("examples/interface_plasticity/block_friction.toml"),
        ),
        ("arc", repo().join("examples/delamination/dcb_coarse.toml")),
        ("auto", auto),
        ("fatigue", repo().join("examples/fatigue/held_opening.toml")),
    ];
    for (kind, input) in runs {
        let out = dir.path().join(kind);
        run_ok_with(&input, &out, &["--max-increments", "3"]);
        let header = header_of(&out);
        assert_eq!(header, junta::curve_header(), "{kind}");
        let names: Vec<&str> = header.trim_end().split(',').collect();
        let table: Vec<&str> = junta::CURVE_COLUMNS.iter().map(|c| c.name).collect();
        assert_eq!(names, table, "{kind}");
        let text = std::fs::read_to_string(out.join("curve.csv")).unwrap();
        for line in text.lines().skip(1) {
            assert_eq!(line.split(',').count(), table.len(), "{kind}: {line}");
        }
    }
}

/// The run API's curve has every column of the table but `control`
/// (held apart as text), in order.
#[test]
fn the_run_api_curve_has_the_table_columns() {
    let rows = [junta::CurveRow::parse(
        "1,0,1e-1,1e0,1e-2,0,4,2,0,1e-3,0,0e0,0e0,,1,load,0e0,0e0,1e0,0e0,0e0,,,,,0e0,,,",
    )
    .unwrap()];
    let c = junta::Curve::from_rows(&rows);
    let names: Vec<&str> = c.columns.iter().map(|(n, _)| n.as_str()).collect();
    let table: Vec<&str> = junta::CURVE_COLUMNS
        .iter()
        .map(|c| c.name)
        .filter(|n| *n != "control")
        .collect();
    assert_eq!(names, table);
    assert_eq!(c.control, vec!["load".to_string()]);
}

/// `docs/outputs.md` shows the table as the code has it.
#[test]
fn docs_table_is_the_column_table() {
    let page = std::fs::read_to_string(repo().join("docs/outputs.md")).unwrap();
    assert!(
        page.contains(&junta::post::curve_columns::markdown_table()),
        "docs/outputs.md's curve-column table is stale: regenerate it from junta::post::curve_columns::markdown_table()"
    );
}
