//! CalculiX / Abaqus decks as users write them (issue 12, part 1): each
//! keyword or parameter against a CalculiX run of the same deck.

mod common;
use common::*;

/// `examples/cube.inp` with its `*STATIC` line replaced.
fn cube_with_static(dir: &std::path::Path, static_line: &str) -> std::path::PathBuf {
    let text = std::fs::read_to_string(repo().join("examples/cube.inp")).unwrap();
    let out: Vec<String> = text
        .lines()
        .map(|l| {
            if l.trim().to_uppercase().starts_with("*STATIC") {
                static_line.to_string()
            } else {
                l.to_string()
            }
        })
        .collect();
    write(dir, "cube.inp", &out.join("\n"))
}

/// `*STATIC, SOLVER=SPOOLES` (what the CalculiX manual writes) runs on the
/// direct back end and gives the cube's reaction of CalculiX 2.20
/// (Fz = -2224.553 on TOP, README's examples table); the iterative names go
/// to CG.
#[test]
fn static_solver_parameter_maps_to_back_ends() {
    let dir = tempfile::tempdir().unwrap();
    for (line, key) in [
        ("*STATIC, SOLVER=SPOOLES", "cholesky"),
        ("*static, solver=Pardiso", "cholesky"),
        ("*STATIC, SOLVER=ITERATIVE CHOLESKY, TIME RESET", "cg"),
        ("*STATIC,SOLVER=iterative scaling", "cg"),
    ] {
        let deck = cube_with_static(dir.path(), line);
        let s = run_ok(&deck, &dir.path().join(key));
        let notes = s["notes"].to_string();
        assert!(notes.contains(&format!("`{key}`")), "{line}: {notes}");
        assert_eq!(s["solver"]["name"], key, "{line}");
        let fz = s["reactions"]["TOP"][2].as_f64().unwrap();
        assert!(rel(fz, -2224.553) < 1e-6, "{line}: {fz}");
    }
}

#[test]
fn static_parameters_that_change_the_answer_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let deck = cube_with_static(dir.path(), "*STATIC, RIKS");
    let err = run_err(&deck);
    assert!(err.contains("RIKS") && err.contains(":55:"), "{err}");
    let deck = cube_with_static(dir.path(), "*STATIC, SOLVER=MAGIC");
    let err = run_err(&deck);
    assert!(err.contains("MAGIC") && err.contains("SPOOLES"), "{err}");
    let deck = cube_with_static(dir.path(), "*STATIC, BOGUS=1");
    let err = run_err(&deck);
    assert!(err.contains("BOGUS"), "{err}");
}
