//! `[[load]] set = ... total_force = [...]`: the consistent split (the
//! default) gives each node of the set the integral of its shape function
//! over the element faces, or else edges, the set spans; `split = "equal"`
//! the same share per node.
//!
//! The references are independent of the split's code: a face set is
//! compared with the same load as a `traction` on the face set (the face
//! integrator of `junta_elements::face_load`), an edge set with nodal
//! forces written out by hand from the closed-form edge weights (a
//! straight quadratic edge of length L: L/6, 2L/3, L/6; linear: L/2,
//! L/2), and the weights themselves with the closed forms of a flat face
//! (8-node: -A/12 per corner, A/3 per mid-side; 4-node: A/4 per corner).

use junta::elements::face_load::{set_weights, SetSpan};
use junta::{RunSettings, Simulation};

/// A cantilever 2 x 1 x 1, `nx x 2 x 1` cells of `element`, clamped at
/// x = 0, with `loads` (TOML `[[load]]` tables and extra node sets).
fn scene(element: &str, nx: usize, extra: &str) -> String {
    format!(
        r#"
[materials.steel]
type = "isotropic"
E = 1000.0
nu = 0.3

[mesh]
type = "box"
size = [2.0, 1.0, 1.0]
divisions = [{nx}, 2, 1]
element = "{element}"
material = "steel"

[[boundary]]
set = "x0"
fixed = "all"

{extra}

[solver]
type = "cholesky"
"#
    )
}

fn displacement(text: &str) -> (Vec<f64>, Vec<String>) {
    let sim = Simulation::from_scene_text(text, "total_force.toml").unwrap();
    let notes = sim.notes().to_vec();
    let r = sim.run(&RunSettings::in_memory(), &mut []).unwrap();
    (
        r.frame.expect("a linear run keeps its frame").displacement,
        notes,
    )
}

/// max |a - b| / max |b|
fn rel_diff(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(scale > 0.0);
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / scale
}

/// Nodal forces on single points, as `[[load]]` tables with `force`.
fn point_forces(points: &[([f64; 3], [f64; 3])]) -> String {
    let mut s = String::new();
    for (k, (x, f)) in points.iter().enumerate() {
        s += &format!(
            "[[node_set]]\nname = \"p{k}\"\nwithin = [{x:?}, {x:?}]\n[[load]]\nset = \"p{k}\"\nforce = {f:?}\n"
        );
    }
    s
}

const EDGE: &str = "[[node_set]]\nname = \"edge\"\nwithin = [[2.0, 0.0, 1.0], [2.0, 1.0, 1.0]]\n";

/// A total force on the end face x = 2 (area 1) equals the traction of
/// the same total on that face, for every solid element kind; the
/// force-per-node weights of a single flat H20 face are the closed forms
/// (-1/12 per corner, 1/3 per mid-side) and of a single H8 face 1/4.
#[test]
fn total_force_on_a_face_set_equals_the_traction() {
    let f = [0.3, -0.2, -1.0];
    for element in ["h8", "h8i", "h20", "h27", "wedge6", "wedge15"] {
        let (u, notes) = displacement(&scene(
            element,
            2,
            &format!("[[load]]\nset = \"x1\"\ntotal_force = {f:?}\n"),
        ));
        let (t, _) = displacement(&scene(
            element,
            2,
            &format!("[[load]]\nface_set = \"x1\"\ntraction = {f:?}\n"),
        ));
        let d = rel_diff(&u, &t);
        assert!(d < 1e-10, "{element}: relative difference {d:e}");
        assert!(
            notes.iter().all(|n| !n.contains("total_force")),
            "{notes:?}"
        );
    }
    // the weights on one face of one cell
    for (element, corner, mid) in [("h20", -1.0 / 12.0, 1.0 / 3.0), ("h8", 0.25, 0.0)] {
        let text = scene(
            element,
            1,
            "[[node_set]]\nname = \"face\"\nwithin = [[2.0, 0.0, 0.0], [2.0, 0.5, 1.0]]\n",
        );
        let sim = Simulation::from_scene_text(&text, "w.toml").unwrap();
        let mesh = &sim.model().mesh;
        let set = mesh.node_set("face").unwrap();
        assert_eq!(set.len(), if element == "h20" { 8 } else { 4 });
        let w = set_weights(mesh, set).unwrap();
        assert!(matches!(&w.span, SetSpan::Faces(f) if f.len() == 1));
        assert!((w.measure - 0.5).abs() < 1e-14, "{}", w.measure);
        for (&n, &wn) in set.iter().zip(&w.weights) {
            let x = mesh.nodes[n];
            let is_corner = (x[1] == 0.0 || x[1] == 0.5) && (x[2] == 0.0 || x[2] == 1.0);
            let want = if is_corner { corner } else { mid };
            assert!(
                (wn - want).abs() < 1e-14,
                "{element} node {x:?}: {wn} vs {want}"
            );
        }
        assert!((w.weights.iter().sum::<f64>() - 1.0).abs() < 1e-14);
    }
}

/// A total force on the edge x = 2, z = 1 (length 1, two cells along y)
/// equals the nodal forces of the consistent line load written out by
/// hand: quadratic edges of length 1/2 give the nodes at y = 0, 1/4, 1/2,
/// 3/4, 1 the shares 1/12, 1/3, 1/6, 1/3, 1/12; linear edges give y = 0,
/// 1/2, 1 the shares 1/4, 1/2, 1/4. `split = "equal"` gives the hand-made
/// equal shares instead (1/5 or 1/3 each) and a field that differs.
#[test]
fn total_force_on_an_edge_set_equals_the_consistent_line_load() {
    let f = [0.0, 0.4, -1.0];
    let cases: [(&str, &[(f64, f64)]); 4] = [
        (
            "h20",
            &[
                (0.0, 1.0 / 12.0),
                (0.25, 1.0 / 3.0),
                (0.5, 1.0 / 6.0),
                (0.75, 1.0 / 3.0),
                (1.0, 1.0 / 12.0),
            ],
        ),
        (
            "h27",
            &[
                (0.0, 1.0 / 12.0),
                (0.25, 1.0 / 3.0),
                (0.5, 1.0 / 6.0),
                (0.75, 1.0 / 3.0),
                (1.0, 1.0 / 12.0),
            ],
        ),
        ("h8", &[(0.0, 0.25), (0.5, 0.5), (1.0, 0.25)]),
        ("h8i", &[(0.0, 0.25), (0.5, 0.5), (1.0, 0.25)]),
    ];
    for (element, shares) in cases {
        let total = format!("{EDGE}[[load]]\nset = \"edge\"\ntotal_force = {f:?}\n");
        let (u, _) = displacement(&scene(element, 2, &total));
        let by_hand: Vec<([f64; 3], [f64; 3])> = shares
            .iter()
            .map(|&(y, w)| ([2.0, y, 1.0], f.map(|c| w * c)))
            .collect();
        let (h, _) = displacement(&scene(element, 2, &point_forces(&by_hand)));
        let d = rel_diff(&u, &h);
        assert!(d < 1e-10, "{element} consistent: relative difference {d:e}");

        let equal = format!("{total}split = \"equal\"\n");
        let (e, _) = displacement(&scene(element, 2, &equal));
        let n = shares.len() as f64;
        let by_hand: Vec<([f64; 3], [f64; 3])> = shares
            .iter()
            .map(|&(y, _)| ([2.0, y, 1.0], f.map(|c| c / n)))
            .collect();
        let (he, _) = displacement(&scene(element, 2, &point_forces(&by_hand)));
        let d = rel_diff(&e, &he);
        assert!(d < 1e-10, "{element} equal: relative difference {d:e}");
        let d = rel_diff(&e, &u);
        assert!(d > 1e-3, "{element}: the equal split should differ, {d:e}");

        // `split = "consistent"` is the default
        let (c, _) = displacement(&scene(
            element,
            2,
            &format!("{total}split = \"consistent\"\n"),
        ));
        assert_eq!(c, u);
    }
}

/// A set that spans no face or edge (here one corner node) shares
/// equally, with a note that says so; a node set that spans a face plus
/// stray nodes gives those nothing, with a note.
#[test]
fn points_share_equally_and_stray_nodes_get_nothing_with_a_note() {
    let f = [0.0, 0.0, -1.0];
    let text = scene(
        "h8",
        2,
        &format!(
            "[[node_set]]\nname = \"ends\"\nwithin = [[2.0, 0.0, 1.0], [2.0, 0.0, 1.0]]\n\
             [[load]]\nset = \"ends\"\ntotal_force = {f:?}\n"
        ),
    );
    // a one-node set: a point
    let (_, notes) = displacement(&text);
    assert!(
        notes
            .iter()
            .any(|n| n.contains("holds no complete element face or edge")
                && n.contains("`ends`")
                && n.contains("total_force.toml")),
        "{notes:?}"
    );
    // H20, the x = 2 end: the face y in [0, 1/2] (8 nodes) and the two
    // mid-edge nodes at y = 3/4, z = 0 and z = 1 of the next face
    let stray = scene(
        "h20",
        1,
        &format!(
            "[[node_set]]\nname = \"face_and_two\"\nwithin = [[2.0, 0.0, 0.0], [2.0, 0.75, 1.0]]\n\
             [[load]]\nset = \"face_and_two\"\ntotal_force = {f:?}\n"
        ),
    );
    let sim = Simulation::from_scene_text(&stray, "s.toml").unwrap();
    assert!(
        sim.notes()
            .iter()
            .any(|n| n.contains("2 of the 10 nodes of set `face_and_two`")
                && n.contains("get no share")),
        "{:?}",
        sim.notes()
    );
    let mesh = &sim.model().mesh;
    let set = mesh.node_set("face_and_two").unwrap();
    assert_eq!(set.len(), 10);
    let w = set_weights(mesh, set).unwrap();
    assert!(matches!(&w.span, SetSpan::Faces(f) if f.len() == 1));
    assert_eq!(w.off_span, 2);
    for (&n, &wn) in set.iter().zip(&w.weights) {
        if mesh.nodes[n][1] == 0.75 {
            assert_eq!(wn, 0.0);
        }
    }
    assert!((w.weights.iter().sum::<f64>() - 1.0).abs() < 1e-14);
}

/// `split` with a bad value, with `force`, or on a face set: errors that
/// name the file, the key and what is valid.
#[test]
fn bad_split_keys_are_errors_naming_the_key() {
    let f = "[0.0, 0.0, -1.0]";
    for (extra, needles) in [
        (
            format!("[[load]]\nset = \"x1\"\ntotal_force = {f}\nsplit = \"lumped\"\n"),
            &[
                "bad.toml",
                "key `load[0].split`",
                "`lumped` is not valid",
                "\"consistent\"",
                "\"equal\"",
            ][..],
        ),
        (
            format!("[[load]]\nset = \"x1\"\nforce = {f}\nsplit = \"equal\"\n"),
            &["bad.toml", "key `load[0].split`", "with `total_force`"][..],
        ),
        (
            format!("[[load]]\nface_set = \"x1\"\ntraction = {f}\nsplit = \"equal\"\n"),
            &["bad.toml", "key `load[0].split`", "not with `face_set`"][..],
        ),
    ] {
        let e = match Simulation::from_scene_text(&scene("h8", 1, &extra), "bad.toml") {
            Ok(_) => panic!("{extra}: accepted"),
            Err(e) => e.to_string(),
        };
        for n in needles {
            assert!(e.contains(n), "{extra}: `{n}` not in: {e}");
        }
    }
}
