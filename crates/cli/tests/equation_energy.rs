//! Reactions and energies when a prescribed dof is the independent dof of
//! `*EQUATION`s (issue 42, item 2): the master node of a face or of a
//! periodic pair carries its own elements' share as `RF` (CalculiX's
//! value), while the work of the prescribed motion, and the summary's
//! `generalized_reactions`, take the whole constraint force (`r_p + sum_d
//! c_dp r_d`, see `junta_core::dof::DofMap::generalized_reactions_into`).

mod common;
use common::*;
use serde_json::Value;

/// A unit C3D8 brick (E = 1000 MPa, nu = 0) clamped on x = 0 and
/// stretched by 0.01 mm through node 2 alone, the other nodes of the face
/// x = 1 (3, 6, 7) tied to it in x by `u_n - u_2 = 0`.
const ONE_ELEMENT: &str = "\
*NODE
1, 0, 0, 0
2, 1, 0, 0
3, 1, 1, 0
4, 0, 1, 0
5, 0, 0, 1
6, 1, 0, 1
7, 1, 1, 1
8, 0, 1, 1
*ELEMENT, TYPE=C3D8, ELSET=BRICK
1, 1, 2, 3, 4, 5, 6, 7, 8
*NSET, NSET=LEFT
1, 4, 5, 8
*NSET, NSET=MASTER
2
*MATERIAL, NAME=M
*ELASTIC
1000., 0.
*SOLID SECTION, ELSET=BRICK, MATERIAL=M
*BOUNDARY
LEFT, 1, 3
*EQUATION
2
3, 1, 1.0, 2, 1, -1.0
2
6, 1, 1.0, 2, 1, -1.0
2
7, 1, 1.0, 2, 1, -1.0
*STEP
*STATIC
*BOUNDARY
MASTER, 1, 1, 0.01
*NODE PRINT, NSET=MASTER
RF
*END STEP
";

/// The one-element deck: uniaxial stress `E delta / L = 10` MPa on a
/// unit face, so the face carries 10 N and each of its four corner nodes
/// `sigma A / 4 = 2.5` N (a uniformly stressed linear hexahedron). The
/// master's printed reaction (`RF` in node_print.csv, and `reactions` in
/// summary.json) is its own elements' share, 2.5 N, as CalculiX prints it
/// (issue 42); `generalized_reactions` holds the total constraint force
/// on the face, 10 N.
#[test]
fn master_node_prints_its_share_and_reports_the_face_total() {
    let dir = tempfile::tempdir().unwrap();
    let deck = write(dir.path(), "one.inp", ONE_ELEMENT);
    let out = dir.path().join("out");
    let s = run_ok(&deck, &out);
    let share = s["reactions"]["MASTER"][0].as_f64().unwrap();
    let total = s["generalized_reactions"]["MASTER"][0].as_f64().unwrap();
    assert!((share - 2.5).abs() < 1e-9, "RF share {share}");
    assert!((total - 10.0).abs() < 1e-9, "total {total}");
    // the clamped face's reaction is the same 10 N, opposite; it has no
    // dependents, so both entries agree there
    let left = s["reactions"]["LEFT"][0].as_f64().unwrap();
    let left_g = s["generalized_reactions"]["LEFT"][0].as_f64().unwrap();
    assert!((left + 10.0).abs() < 1e-9 && (left_g - left).abs() < 1e-12);
    let table = std::fs::read_to_string(out.join("node_print.csv")).unwrap();
    let row = table
        .lines()
        .find(|l| l.starts_with("1,MASTER,RF,2,"))
        .unwrap_or_else(|| panic!("no RF row of node 2:\n{table}"));
    let rf: f64 = row.split(',').nth(4).unwrap().parse().unwrap();
    assert!((rf - 2.5).abs() < 1e-9, "{row}");
    // a model without equations has no `generalized_reactions`
    let plain = ONE_ELEMENT
        .replace("*EQUATION\n2\n3, 1, 1.0, 2, 1, -1.0\n2\n6, 1, 1.0, 2, 1, -1.0\n2\n7, 1, 1.0, 2, 1, -1.0\n", "")
        .replace("MASTER, 1, 1, 0.01", "2, 1, 1, 0.01\n3, 1, 1, 0.01\n6, 1, 1, 0.01\n7, 1, 1, 0.01");
    assert_ne!(plain, ONE_ELEMENT);
    let p = run_ok(
        &write(dir.path(), "plain.inp", &plain),
        &dir.path().join("plain"),
    );
    assert!(p.get("generalized_reactions").is_none());
}

/// Two unit steel bricks stacked in z and glued by one COH3D8 (the mesh
/// and law of tests/data/amplitude_cohesive.inp: K = 1e5, N = 80, G_c =
/// 1.5), opened to 0.03 mm (past the peak, into softening), written two
/// ways: `face`, the top face prescribed; `master`, a periodic slice
/// whose stretch is prescribed on top node 15 alone, every other top node
/// tied to its bottom partner by `u_T - u_B - u_15 + u_1 = 0` (z), the
/// bottom free in z but at node 1 (`u_L - u_0 - u_ML + u_M0 = 0` of
/// generalized plane strain decks).
fn slice(master: bool) -> String {
    let text = std::fs::read_to_string(repo().join("crates/cli/tests/data/amplitude_cohesive.inp"))
        .unwrap();
    let start = text.find("*AMPLITUDE").unwrap();
    let mut deck = text[..start].to_string();
    if master {
        deck += "*NSET, NSET=MASTER\n15\n*BOUNDARY\nBOT, 1, 2\n1, 3, 3\nTOP, 1, 2\n*EQUATION\n";
        for (t, b) in [(16, 2), (17, 3), (18, 4)] {
            deck += &format!("4\n{t}, 3, 1.0, {b}, 3, -1.0, 15, 3, -1.0, 1, 3, 1.0\n");
        }
        deck += "*STEP, INC=200\n*STATIC\n0.05, 1.0\n*BOUNDARY\nMASTER, 3, 3, 0.03\n*END STEP\n";
    } else {
        deck += "*BOUNDARY\nBOT, 1, 3\nTOP, 1, 2\n";
        deck += "*STEP, INC=200\n*STATIC\n0.05, 1.0\n*BOUNDARY\nTOP, 3, 3, 0.03\n*END STEP\n";
    }
    deck
}

fn energy(s: &Value, key: &str) -> f64 {
    s["energy"][key]
        .as_f64()
        .unwrap_or_else(|| panic!("energy.{key}: {s}"))
}

/// The periodic slice with a master node does the same external work as
/// the slice with its whole top face prescribed (1e-6 relative), and the
/// work balances the stored plus the dissipated energy: the model is
/// linear elastic at fixed damage and the bilinear law unloads to the
/// origin, so the stored energy is `F delta / 2` (Clapeyron, docs/outputs.md
/// "Energies"), `F` the total force on the top face. Before the fix the
/// master's work took its elements' share only (a quarter of the face's
/// force here).
#[test]
fn periodic_master_node_does_the_work_of_the_whole_face() {
    let dir = tempfile::tempdir().unwrap();
    let mut sums = Vec::new();
    for (name, master) in [("face", false), ("master", true)] {
        let deck = write(dir.path(), &format!("{name}.inp"), &slice(master));
        let s = run_ok(&deck, &dir.path().join(name));
        assert!(
            s["status"].as_str().unwrap().starts_with("completed"),
            "{name}: {}",
            s["status"]
        );
        sums.push(s);
    }
    let (face, master) = (&sums[0], &sums[1]);
    let w_face = energy(face, "external_work");
    let w_master = energy(master, "external_work");
    let dissipated = energy(master, "dissipated_energy");
    assert!(dissipated > 0.1, "nothing dissipated: {dissipated}");
    assert!(
        (w_master - w_face).abs() <= 1e-6 * w_face.abs(),
        "master {w_master} vs face {w_face}"
    );
    // the total force on the top face: the face run's reaction, the
    // master run's generalized reaction at node 15
    let f_face = face["reactions"]["TOP"][2].as_f64().unwrap();
    let f_master = master["generalized_reactions"]["MASTER"][2]
        .as_f64()
        .unwrap();
    let share = master["reactions"]["MASTER"][2].as_f64().unwrap();
    assert!(
        (f_master - f_face).abs() <= 1e-6 * f_face.abs(),
        "{f_master} vs {f_face}"
    );
    assert!(
        (share - f_face / 4.0).abs() <= 1e-6 * f_face.abs(),
        "share {share}"
    );
    let stored = 0.5 * f_face * 0.03;
    let balance = (w_master - stored - dissipated).abs() / w_master;
    assert!(
        balance < 1e-3,
        "W {w_master} vs stored {stored} + dissipated {dissipated}: {balance:e}"
    );
}
