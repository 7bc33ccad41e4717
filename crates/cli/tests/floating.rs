//! A part held by no support is refused before any factorisation, by
//! `junta check` and by `junta run` under every direct back end, with the
//! block, its elements and the rigid-body modes it leaves free (issue 42,
//! item 4). Before, `lu` sat for minutes in the dense products of a
//! singular factorisation without a word.

mod common;
use common::*;

/// examples/delamination/mmb80_short.toml with the box `lower_bond1`
/// moved 0.1e6 mm up: it touches nothing and nothing holds it.
fn mmb_with_a_floating_box(dir: &std::path::Path) -> std::path::PathBuf {
    let text = std::fs::read_to_string(repo().join("examples/delamination/mmb80_short.toml"))
        .unwrap()
        .replace(
            "name = \"lower_bond1\"\ngroup = \"lower\"\norigin = [20.4, 0.0, 0.0]",
            "name = \"lower_bond1\"\ngroup = \"lower\"\norigin = [20.4, 0.0, 0.1e6]",
        );
    assert!(text.contains("0.1e6"), "the example still has lower_bond1");
    write(dir, "mmb_floating.toml", &text)
}

fn assert_names_the_floating_box(err: &str) {
    assert!(err.contains("held by no support"), "{err}");
    assert!(err.contains("block `lower_bond1` (elements"), "{err}");
    // a free body in 3D: all six modes
    for m in ["translation x", "translation z", "rotation about y"] {
        assert!(err.contains(m), "{m}: {err}");
    }
    // only that box
    assert!(!err.contains("upper_bond"), "{err}");
}

#[test]
fn check_refuses_a_floating_box_and_names_it() {
    let dir = tempfile::tempdir().unwrap();
    let input = mmb_with_a_floating_box(dir.path());
    let out = junta().arg("check").arg(&input).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!out.status.success(), "{err}");
    assert!(err.contains("mmb_floating.toml"), "names the file: {err}");
    assert_names_the_floating_box(&err);
    // the example itself is held
    let ok = junta()
        .arg("check")
        .arg(repo().join("examples/delamination/mmb80_short.toml"))
        .output()
        .unwrap();
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
}

#[test]
fn run_refuses_a_floating_box_under_every_direct_back_end() {
    let dir = tempfile::tempdir().unwrap();
    let input = mmb_with_a_floating_box(dir.path());
    for solver in ["cholesky", "ldlt", "lu"] {
        let out_dir = dir.path().join(solver);
        let out = junta()
            .arg("run")
            .arg(&input)
            .arg("-o")
            .arg(&out_dir)
            .arg("-q")
            .arg("--solver")
            .arg(format!("type={solver}"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(!out.status.success(), "{solver}: {err}");
        assert!(err.starts_with("error: "), "{solver}: {err}");
        assert_names_the_floating_box(&err);
        // refused before the first increment: no curve written
        assert!(!out_dir.join("curve.csv").exists(), "{solver}");
    }
}

/// A block held on one face in x only (a roller face): it can still move
/// in y and z and turn about x. The check names exactly those three
/// modes, from the rank of the rigid-body modes at the held dofs.
#[test]
fn a_roller_face_leaves_three_named_modes_free() {
    let dir = tempfile::tempdir().unwrap();
    let input = write(
        dir.path(),
        "roller.toml",
        r#"
[materials.steel]
type = "isotropic"
E = 210000.0
nu = 0.3

[mesh]
type = "box"
size = [2.0, 1.0, 1.0]
divisions = [2, 1, 1]
element = "h8"
material = "steel"

[[boundary]]
set = "x0"
fixed = ["x"]

[[load]]
set = "x1"
force = [1.0, 0.0, 0.0]
"#,
    );
    let err = run_err(&input);
    assert!(err.contains("held by no support"), "{err}");
    for m in ["translation y", "translation z", "rotation about x"] {
        assert!(err.contains(m), "{m} is free: {err}");
    }
    for m in ["translation x", "rotation about y", "rotation about z"] {
        assert!(!err.contains(m), "{m} is held: {err}");
    }
    // fixing y and z on the same face holds it
    let held = write(
        dir.path(),
        "held.toml",
        &std::fs::read_to_string(&input)
            .unwrap()
            .replace("fixed = [\"x\"]", "fixed = \"all\""),
    );
    let out = junta().arg("check").arg(&held).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
