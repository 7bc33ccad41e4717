//! The advice of `junta check` per law and per mesh: the penalty advisor
//! judges a cohesive law's penalty against the solids (Turon's bound), a
//! constraint penalty by the paper's error analysis; thin blocks of fully
//! integrated H8 get a shear-locking warning.

mod common;
use common::{junta, repo, run_ok};

fn check(path: &std::path::Path) -> String {
    let out = junta().arg("check").arg(path).output().unwrap();
    assert!(
        out.status.success(),
        "junta check {} failed:\n{}",
        path.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn check_text(dir: &std::path::Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    // the DCB's reference curve is read relative to the scene
    let csv = repo().join("examples/delamination/dcb_beam_theory.csv");
    std::fs::copy(csv, dir.join("dcb_beam_theory.csv")).unwrap();
    check(&p)
}

fn penalty_line(s: &str) -> &str {
    s.lines()
        .find(|l| l.contains("penalty advisor:"))
        .unwrap_or_else(|| panic!("no penalty advisor line:\n{s}"))
}

/// dcb.toml: bilinear law, K = 1e6 N/mm^3, arms of AS4/PEEK 1.56 mm thick
/// with E3 = 10100 MPa across the interface. By hand (Turon, Davila,
/// Camanho & Costa 2007): K >= 50 E_33 / t = 50 x 10100 / 1.56 =
/// 3.2372e5 N/mm^3; the interface adds 1/K / (t / E_33) = 10100 / (1e6 x
/// 1.56) = 0.65 % compliance. K is 3.09 x the bound: good, and no
/// recommendation of the constraint optimum d_op.
#[test]
fn dcb_cohesive_penalty_is_judged_by_turons_bound() {
    let s = check(&repo().join("examples/delamination/dcb.toml"));
    let l = penalty_line(&s);
    let turon = 50.0 * 10100.0 / 1.56;
    assert!(!l.contains("too low") && !l.contains("d_op"), "{l}");
    assert!(l.contains("cohesive law"), "{l}");
    assert!(l.contains(&format!("50 E_33/t = {turon:.3e}")), "{l}");
    assert!(l.contains("0.65%"), "{l}");
    assert!(l.contains("good: K is 3.089 x Turon's bound"), "{l}");
    // the same on the H8 mesh
    let s = check(&repo().join("examples/delamination/dcb_h8.toml"));
    let l = penalty_line(&s);
    assert!(!l.contains("too low") && l.contains("good"), "{l}");
    assert!(l.contains(&format!("{turon:.3e}")), "{l}");
}

/// K = 1e5 < 3.237e5: the interface adds 10100 / (1e5 x 1.56) = 6.47 %
/// compliance: warned, with the bound to raise K to. K = 1e9 > 1e3 x the
/// bound (3.237e8): too stiff.
#[test]
fn cohesive_penalty_below_turons_bound_is_warned() {
    let dir = tempfile::tempdir().unwrap();
    let base = std::fs::read_to_string(repo().join("examples/delamination/dcb.toml")).unwrap();
    assert!(base.contains("K = 1.0e6"));
    let s = check_text(
        dir.path(),
        "low.toml",
        &base.replace("K = 1.0e6", "K = 1.0e5"),
    );
    let l = penalty_line(&s);
    assert!(l.contains("6.47%"), "{l}");
    assert!(
        l.contains("too compliant: the penalty adds more than 2% compliance")
            && l.contains(&format!(
                "raise K to at least Turon's bound {:.3e}",
                50.0 * 10100.0 / 1.56
            )),
        "{l}"
    );
    let s = check_text(
        dir.path(),
        "stiff.toml",
        &base.replace("K = 1.0e6", "K = 1.0e9"),
    );
    let l = penalty_line(&s);
    assert!(l.contains("too stiff") && l.contains("oscillations"), "{l}");
    assert!(!l.contains("recommended"), "{l}");
}

/// linear_penalty (the paper's prism in tension, d = 1e25 N/m^3): the
/// paper's error analysis and its recommended d_op, as before.
#[test]
fn constraint_penalty_keeps_the_papers_recommendation() {
    let s = check(&repo().join("examples/paper/prism_tension.toml"));
    let l = penalty_line(&s);
    assert!(
        l.contains("eps_op = k_min/sqrt(n e_c)") && l.contains("recommended d_op"),
        "{l}"
    );
    assert!(
        !l.contains("cohesive") && !l.contains("Turon's bound"),
        "{l}"
    );
}

fn h8_warnings(s: &str) -> Vec<&str> {
    s.lines()
        .filter(|l| l.contains("warning: block") && l.contains("fully integrated h8"))
        .collect()
}

/// dcb_h8.toml: H8 arms 1.56 mm thick with two elements through each;
/// along the first 35 mm of the bond 0.5 mm long (l/t = 0.32): the
/// measured table of junta::prepare::bending gives 17.2 + (9.6 - 17.2) x
/// log2(0.5 / 0.3205) = 12 %; the far field's 2.006 mm (l/t = 1.29) is past
/// the table's l/t = 1 column: at least 47.1 %. The same mesh with h8i or h20 and a thick
/// block of h8 (the 1 m cube of examples/cube.toml) get no warning.
#[test]
fn thin_h8_blocks_get_the_locking_warning() {
    let dcb_h8 = std::fs::read_to_string(repo().join("examples/delamination/dcb_h8.toml")).unwrap();
    let s = check(&repo().join("examples/delamination/dcb_h8.toml"));
    let w = h8_warnings(&s);
    // one warning for the model: the worst block's numbers (the 2 mm far
    // field, l/t = 1.29: at least 47 %), the others named with theirs
    assert_eq!(w.len(), 1, "{s}");
    assert!(
        w[0].contains("2 elements through its 1.5600e0 thickness (z)")
            && w[0].contains("at least 47% too stiff")
            && w[0].contains("`lower_near` (12%)")
            && w[0].contains("h8i")
            && w[0].contains("h20"),
        "{}",
        w[0]
    );
    let dir = tempfile::tempdir().unwrap();
    for el in ["h8i", "h20"] {
        let s = check_text(
            dir.path(),
            &format!("{el}.toml"),
            &dcb_h8.replace("element = \"h8\"", &format!("element = \"{el}\"")),
        );
        assert!(h8_warnings(&s).is_empty(), "{el}: {s}");
    }
    let s = check(&repo().join("examples/cube.toml"));
    assert!(s.contains("h8: 8") && h8_warnings(&s).is_empty(), "{s}");
}

/// The cantilever of examples/cantilever.toml with element = "h8" (10 x 1 x
/// 1: one layer, l/t = 1): 55.6 % too stiff by the table (the run gives
/// 1.234e-4 m against Timoshenko's 1.920e-4: 1.920 / 1.234 - 1 = 55.6 %);
/// the warning is in summary.json.
#[test]
fn h8_warning_is_in_the_run_summary() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(repo().join("examples/cantilever.toml"))
        .unwrap()
        .replace("element = \"h20\"", "element = \"h8\"");
    let p = dir.path().join("c.toml");
    std::fs::write(&p, text).unwrap();
    let s = run_ok(&p, &dir.path().join("out"));
    let w = s["warnings"].to_string();
    assert!(
        w.contains("fully integrated h8, 1 element through") && w.contains("about 56% too stiff"),
        "{w}"
    );
    let uz = -s["probes"]["x1"][2].as_f64().unwrap();
    assert!(((1.920e-4 / uz - 1.0) - 0.556).abs() < 1e-3, "{uz:e}");
}

/// examples/fatigue/dcb_paris.toml: an H8 DCB 25.4 mm wide with one
/// element across, opened along z. The old check judged each block alone
/// and warned for blocks whose longest side is the width ("elements
/// 2.5400e1 long (y), l/t = 16.28", eight lines); the arms bend in x-z, so
/// at most one warning, through z, and none along the width. Its mesh is
/// judged where the crack runs (0.125 mm elements at the front, not the
/// 2 mm far field): not "too coarse".
#[test]
fn wide_h8_dcb_is_judged_in_its_bending_plane_and_at_its_front() {
    let s = check(&repo().join("examples/fatigue/dcb_paris.toml"));
    let w = h8_warnings(&s);
    assert!(w.len() <= 1, "{s}");
    for l in &w {
        assert!(
            l.contains("thickness (z)")
                && !l.contains("thickness (y)")
                && !l.contains("2.5400e1 long"),
            "{l}"
        );
    }
    let locking = s.lines().filter(|l| l.contains("locks")).count();
    assert!(locking <= 1, "{s}");
    assert!(!s.contains("too coarse"), "{s}");
    let advice = s
        .lines()
        .find(|l| l.contains("mesh advice: interface `bond`"))
        .unwrap_or_else(|| panic!("{s}"));
    assert!(
        advice.contains("where the crack runs") && advice.contains("1.250e-1 .. 1.250e-1 long"),
        "{advice}"
    );
}

/// A real locking case: a steel beam 1 x 0.1 x 0.02 m of h8, 20 x 1 x 1,
/// clamped at x = 0 and bent through its 0.02 m thickness (z) by an end
/// shear: one element through it, l/t = 0.05 / 0.02 = 2.5 (past the
/// table's first column): "at least 56% too stiff", once. The same beam
/// pulled along its axis (a bar in tension) gets no warning.
#[test]
fn slender_h8_beam_bent_through_one_layer_warns_once() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(repo().join("examples/cantilever.toml"))
        .unwrap()
        .replace("size = [1.0, 0.1, 0.1]", "size = [1.0, 0.1, 0.02]")
        .replace("divisions = [10, 1, 1]", "divisions = [20, 1, 1]")
        .replace("element = \"h20\"", "element = \"h8\"");
    let s = check_text(dir.path(), "bent.toml", &text);
    let w = h8_warnings(&s);
    assert_eq!(w.len(), 1, "{s}");
    assert!(
        w[0].contains("1 element through its 2.0000e-2 thickness (z)")
            && w[0].contains("l/t = 2.50")
            && w[0].contains("at least 56% too stiff"),
        "{}",
        w[0]
    );
    let pulled = text.replace(
        "traction = [0.0, 0.0, -1.0e5]",
        "traction = [1.0e5, 0.0, 0.0]",
    );
    let s = check_text(dir.path(), "pulled.toml", &pulled);
    assert!(h8_warnings(&s).is_empty(), "{s}");
}

/// The peel examples' H8 substrate is fixed on its base (every node of
/// `substrate.z0`, half of its nodes, fixed in all directions): it is held
/// along a face and does not bend, so it gets no locking warning (it got
/// one, judged through its thickness, before bodies held along a face
/// were set aside).
#[test]
fn a_substrate_held_on_its_base_gets_no_locking_warning() {
    for name in ["peel45.toml", "peel90.toml"] {
        let path = repo().join("examples/large_deformation").join(name);
        let s = check(&path);
        assert!(h8_warnings(&s).is_empty(), "{name}: {s}");
        assert!(!s.contains("locks"), "{name}: {s}");
    }
}
