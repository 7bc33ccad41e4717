//! Integration tests of the mesh / deck readers (`junta::input::inp`, `junta::input::gmsh`).

use junta::input::gmsh::{parse_msh, read_msh, GmshError};
use junta::input::inp::{
    parse_inp, read_inp, InpDeck, InpError, InpMaterialKind, InpMixedMode, InpOnset, InpSoftening,
};
use junta_core::mesh::Mesh;
use junta_core::topology::{CellShape, HEX27_NODES, HEX_FACES};
use std::path::PathBuf;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// Every hexahedron of an axis-aligned box mesh has node k at
/// centre + half-size * HEX27_NODES[k]: a geometric check of node orders.
fn check_hex_geometry(mesh: &Mesh) {
    for b in mesh.blocks.iter().filter(|b| b.shape.is_solid()) {
        for e in 0..b.len() {
            let conn = b.element(e);
            let mut lo = [f64::MAX; 3];
            let mut hi = [f64::MIN; 3];
            for &n in &conn[..8] {
                for d in 0..3 {
                    lo[d] = lo[d].min(mesh.nodes[n][d]);
                    hi[d] = hi[d].max(mesh.nodes[n][d]);
                }
            }
            for (k, &n) in conn.iter().enumerate() {
                for d in 0..3 {
                    let want = 0.5 * (lo[d] + hi[d]) + 0.5 * (hi[d] - lo[d]) * HEX27_NODES[k][d];
                    assert!(
                        (mesh.nodes[n][d] - want).abs() < 1e-9,
                        "block {} element {e} local node {k}: {:?}, expected coordinate {d} = {want}",
                        b.name,
                        mesh.nodes[n]
                    );
                }
            }
        }
    }
}

fn err(text: &str) -> InpError {
    parse_inp(text, "test.inp").expect_err("deck should be rejected")
}

// ------------------------------------------------------------------ .inp

#[test]
fn cube_h8_deck() {
    let deck = read_inp(data("cube_h8_n2.inp")).unwrap();
    let m = &deck.mesh;
    assert_eq!(m.nodes.len(), 27);
    assert_eq!(m.node_labels, (1..=27).collect::<Vec<_>>());
    assert_eq!(m.num_elements(), 8);
    assert_eq!(m.blocks.len(), 1);
    let b = &m.blocks[0];
    assert_eq!(
        (
            b.name.as_str(),
            b.shape,
            b.element_type.as_str(),
            b.material.as_str()
        ),
        ("EALL", CellShape::Hex8, "h8", "STEEL")
    );
    check_hex_geometry(m);
    let bottom = m.node_set("BOTTOM").unwrap();
    let top = m.node_set("TOP").unwrap();
    assert_eq!((bottom.len(), top.len()), (9, 9));
    assert!(bottom.iter().all(|&n| m.nodes[n][2] == 0.0));
    assert!(top.iter().all(|&n| m.nodes[n][2] == 1.0));
    assert_eq!(m.node_set("NALL").unwrap().len(), 27);
    assert_eq!(m.element_set("EALL").unwrap().len(), 8);
    assert_eq!(deck.element_labels.len(), 8);

    assert_eq!(deck.materials.len(), 1);
    assert_eq!(
        deck.materials[0].kind,
        InpMaterialKind::Isotropic {
            e: 210000.0,
            nu: 0.3
        }
    );
    assert_eq!(deck.solid_sections.len(), 1);

    assert_eq!(deck.boundaries.len(), 2);
    let fix = &deck.boundaries[0];
    assert_eq!(
        (
            fix.target.as_str(),
            fix.first_dof,
            fix.last_dof,
            fix.value,
            fix.in_step
        ),
        ("BOTTOM", 1, 3, 0.0, false)
    );
    assert_eq!(fix.nodes, bottom);
    let pull = &deck.boundaries[1];
    assert_eq!(
        (
            pull.target.as_str(),
            pull.first_dof,
            pull.last_dof,
            pull.value,
            pull.in_step
        ),
        ("TOP", 3, 3, -0.01, true)
    );
    assert_eq!(pull.nodes, top);
    assert!(deck.cloads.is_empty());

    assert_eq!(deck.steps.len(), 1);
    assert!(!deck.steps[0].nlgeom);
    assert!(deck.steps[0].static_procedure.is_some());
    assert!(deck.heading.contains("2x2x2 C3D8"));
    // *NODE PRINT is kept (the CLI writes it as CSV), no longer a note
    assert_eq!(deck.node_prints.len(), 1, "{:?}", deck.notes);
    let p = &deck.node_prints[0];
    assert_eq!(
        (p.nset.as_str(), p.totals.as_str(), p.step),
        ("TOP", "ONLY", Some(0))
    );
    assert_eq!(p.variables, ["RF"]);
}

#[test]
fn cube_h20_deck_with_continuation_lines() {
    let deck = read_inp(data("cube_h20_n2.inp")).unwrap();
    let m = &deck.mesh;
    assert_eq!(m.nodes.len(), 81);
    assert_eq!(m.num_elements(), 8);
    assert_eq!(m.blocks[0].shape, CellShape::Hex20);
    assert_eq!(m.blocks[0].element_type, "h20");
    check_hex_geometry(m);
    assert_eq!(m.node_set("BOTTOM").unwrap().len(), 21);
    assert_eq!(m.node_set("TOP").unwrap().len(), 21);
    assert_eq!(deck.boundaries[1].value, -0.01);
}

/// One C3D27 on [0,2]x[0,4]x[0,6] with scrambled labels; nodes listed in
/// Abaqus order (21..26 = centres of faces 1..6, 27 = centroid).
fn c3d27_deck() -> String {
    let faces = [
        [1, 2, 3, 4],
        [5, 8, 7, 6],
        [1, 5, 6, 2],
        [2, 6, 7, 3],
        [3, 7, 8, 4],
        [4, 8, 5, 1],
    ];
    let mut nat: Vec<[f64; 3]> = HEX27_NODES[..20].to_vec();
    for f in faces {
        let mut c = [0.0; 3];
        for n in f {
            for d in 0..3 {
                c[d] += 0.25 * HEX27_NODES[n - 1][d];
            }
        }
        nat.push(c);
    }
    nat.push([0.0; 3]);
    let mut s = String::from("*NODE\n");
    // list nodes in reverse to decouple labels from ids
    for (i, x) in nat.iter().enumerate().rev() {
        s += &format!(
            "{}, {}, {}, {}\n",
            1000 + 7 * i,
            1.0 + x[0],
            2.0 + 2.0 * x[1],
            3.0 + 3.0 * x[2]
        );
    }
    s += "*ELEMENT, TYPE=c3d27, ELSET=Q\n5";
    for i in 0..27 {
        s += &format!(", {}", 1000 + 7 * i);
        if i == 14 || i == 26 {
            s += if i == 14 { ",\n" } else { "\n" };
        }
    }
    s.replace(",,", ",").replace("\n,", "\n")
}

#[test]
fn c3d27_node_order_is_converted() {
    let text = c3d27_deck();
    let deck = parse_inp(&text, "c3d27.inp").unwrap();
    let m = &deck.mesh;
    assert_eq!(m.blocks[0].shape, CellShape::Hex27);
    assert_eq!(m.blocks[0].element_type, "h27");
    assert_eq!(m.blocks[0].name, "Q");
    assert_eq!(m.node_label(m.blocks[0].element(0)[0]), 1000);
    check_hex_geometry(m);
    // face S1 (z-) of our table holds Abaqus node 21 at its centre
    let centre = m.blocks[0].element(0)[HEX_FACES[0][8]];
    assert_eq!(m.node_label(centre), 1000 + 7 * 20);
    assert_eq!(m.nodes[centre], [1.0, 2.0, 0.0]);
}

const TWO_BLOCKS_WITH_COHESIVE: &str = "\
*NODE
1, 0, 0, 0
2, 1, 0, 0
3, 1, 1, 0
4, 0, 1, 0
5, 0, 0, 1
6, 1, 0, 1
7, 1, 1, 1
8, 0, 1, 1
11, 0, 0, 1
12, 1, 0, 1
13, 1, 1, 1
14, 0, 1, 1
15, 0, 0, 2
16, 1, 0, 2
17, 1, 1, 2
18, 0, 1, 2
*ELEMENT, TYPE=C3D8, ELSET=LOWER
1, 1, 2, 3, 4, 5, 6, 7, 8
*ELEMENT, TYPE=C3D8, ELSET=UPPER
2, 11, 12, 13, 14, 15, 16, 17, 18
*ELEMENT, TYPE=COH3D8, ELSET=GLUE
3, 5, 6, 7, 8, 11, 12, 13, 14
*ELSET, ELSET=SOLIDS
LOWER, UPPER
*MATERIAL, NAME=Steel
*ELASTIC
210000., 0.3
*DENSITY
7.85e-9
*MATERIAL, NAME=Glue
*ELASTIC, TYPE=TRACTION
1e6, 5e5, 5e5
*SOLID SECTION, ELSET=solids, MATERIAL=steel
*COHESIVE SECTION, ELSET=GLUE, MATERIAL=GLUE, RESPONSE=TRACTION SEPARATION
1.0
";

#[test]
fn coh3d8_bottom_then_top() {
    let deck = parse_inp(TWO_BLOCKS_WITH_COHESIVE, "coh.inp").unwrap();
    let m = &deck.mesh;
    let glue = m.blocks.iter().find(|b| b.name == "GLUE").unwrap();
    assert_eq!(
        (
            glue.shape,
            glue.element_type.as_str(),
            glue.material.as_str()
        ),
        (CellShape::Inter8, "inter8", "Glue")
    );
    let lower = m.blocks.iter().find(|b| b.name == "LOWER").unwrap();
    let upper = m.blocks.iter().find(|b| b.name == "UPPER").unwrap();
    assert_eq!(lower.material, "Steel");
    assert_eq!(upper.material, "Steel");
    let c = glue.element(0);
    // bottom face = top face (z+) of the lower block, top face = bottom of the upper block
    let lower_top: Vec<usize> = HEX_FACES[1][..4]
        .iter()
        .map(|&k| lower.element(0)[k])
        .collect();
    assert_eq!(&c[..4], &lower_top[..]);
    for k in 0..4 {
        assert_eq!(m.nodes[c[k]], m.nodes[c[k + 4]], "pair {k} coincides");
        assert!(upper.element(0).contains(&c[k + 4]));
    }
    // right-hand normal of the bottom quad points from the lower to the upper block
    let p = |i: usize| m.nodes[c[i]];
    let (a, b) = (
        [p(1)[0] - p(0)[0], p(1)[1] - p(0)[1]],
        [p(3)[0] - p(0)[0], p(3)[1] - p(0)[1]],
    );
    assert!(a[0] * b[1] - a[1] * b[0] > 0.0);
    assert_eq!(deck.cohesive_sections.len(), 1);
    assert_eq!(deck.cohesive_sections[0].response, "TRACTION SEPARATION");
    assert_eq!(deck.cohesive_sections[0].thickness, Some(1.0));
    assert_eq!(
        deck.material("glue").unwrap().kind,
        InpMaterialKind::Traction([1e6, 5e5, 5e5])
    );
    assert_eq!(deck.material("STEEL").unwrap().density, Some(7.85e-9));
    assert!(deck.notes.iter().any(|n| n.contains("*DENSITY")));
    assert_eq!(m.element_set("SOLIDS").unwrap().len(), 2);
    assert_eq!(
        deck.element_labels[&3].block,
        m.blocks.iter().position(|b| b.name == "GLUE").unwrap()
    );
}

const TWO_MATERIALS: &str = "\
*NODE
1, 0, 0, 0
2, 1, 0, 0
3, 1, 1, 0
4, 0, 1, 0
5, 0, 0, 1
6, 1, 0, 1
7, 1, 1, 1
8, 0, 1, 1
9, 2, 0, 0
10, 2, 1, 0
11, 2, 0, 1
12, 2, 1, 1
*ELEMENT, TYPE=C3D8, ELSET=EALL
10, 1, 2, 3, 4, 5, 6, 7, 8
20, 2, 9, 10, 3, 6, 11, 12, 7
*ELSET, ELSET=A
10
*ELSET, ELSET=B
20
*MATERIAL, NAME=M1
*ELASTIC, TYPE=ENGINEERING CONSTANTS
100., 10., 10., 0.3, 0.3, 0.4, 5., 5.,
4.
*MATERIAL, NAME=M2
*ELASTIC
200., 0.25
*SOLID SECTION, ELSET=A, MATERIAL=M1
*SOLID SECTION, ELSET=B, MATERIAL=M2
*NSET, NSET=LOADED
11, 12
*CLOAD
LOADED, 1, 5.5
9, 2, -1
";

#[test]
fn sections_split_blocks_and_cloads() {
    let deck = parse_inp(TWO_MATERIALS, "mat.inp").unwrap();
    let m = &deck.mesh;
    assert_eq!(m.blocks.len(), 2);
    assert_eq!(
        (m.blocks[0].name.as_str(), m.blocks[0].material.as_str()),
        ("EALL_M1", "M1")
    );
    assert_eq!(
        (m.blocks[1].name.as_str(), m.blocks[1].material.as_str()),
        ("EALL_M2", "M2")
    );
    assert_eq!(deck.element_labels[&10].block, 0);
    assert_eq!(deck.element_labels[&20].block, 1);
    assert_eq!(m.element_set("EALL").unwrap().len(), 2);
    assert_eq!(
        deck.materials[0].kind,
        InpMaterialKind::EngineeringConstants([100., 10., 10., 0.3, 0.3, 0.4, 5., 5., 4.])
    );
    assert_eq!(deck.cloads.len(), 2);
    assert_eq!(deck.cloads[0].nodes.len(), 2);
    assert_eq!((deck.cloads[0].dof, deck.cloads[0].value), (1, 5.5));
    assert_eq!(m.node_label(deck.cloads[1].nodes[0]), 9);
    assert!(!deck.cloads[1].in_step);
    assert!(deck.steps.is_empty());
}

#[test]
fn generate_ranges_and_case_insensitive_names() {
    let text = std::fs::read_to_string(data("cube_h8_n2.inp")).unwrap().replace(
        "*MATERIAL",
        "*NSET, NSET=Every13, GENERATE\n1, 27, 13\n*ELSET, ELSET=ODD, GENERATE\n1, 8, 2\n*nset, nset=both\nbottom, Top\n*MATERIAL",
    );
    let deck: InpDeck = parse_inp(&text, "gen.inp").unwrap();
    let m = &deck.mesh;
    let g: Vec<usize> = m
        .node_set("Every13")
        .unwrap()
        .iter()
        .map(|&n| m.node_label(n))
        .collect();
    assert_eq!(g, vec![1, 14, 27]);
    assert_eq!(m.element_set("ODD").unwrap().len(), 4);
    assert_eq!(m.node_set("both").unwrap().len(), 18);
}

#[test]
fn error_unsupported_keyword_names_line() {
    let text = "*NODE\n1, 0, 0, 0\n*DYNAMIC\n0.1, 1.\n";
    let e = err(text);
    assert!(
        matches!(&e, InpError::UnknownKeyword { line: 3, keyword, .. } if keyword == "DYNAMIC"),
        "{e:?}"
    );
    let msg = e.to_string();
    assert!(
        msg.contains("test.inp:3") && msg.contains("*DYNAMIC") && msg.contains("*STATIC"),
        "{msg}"
    );
}

#[test]
fn error_unknown_element_type() {
    let e = err("*NODE\n1, 0, 0, 0\n*ELEMENT, TYPE=C3D8R, ELSET=E\n1, 1, 1, 1, 1, 1, 1, 1, 1\n");
    let msg = e.to_string();
    assert!(matches!(e, InpError::ElementType { line: 3, .. }));
    assert!(
        msg.contains("C3D8R")
            && msg.contains("C3D8, C3D8I, C3D20, C3D20R, C3D27, C3D6, C3D15, COH3D8"),
        "{msg}"
    );
}

#[test]
fn error_undefined_node_label() {
    let e = err("*NODE\n1, 0, 0, 0\n*ELEMENT, TYPE=C3D8\n1, 1, 1, 1, 1, 1, 1, 1, 99\n");
    assert!(
        matches!(
            e,
            InpError::UndefinedLabel {
                line: 4,
                label: 99,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(e.to_string().contains("node label 99"));
}

#[test]
fn error_missing_set_lists_defined_sets() {
    let text = std::fs::read_to_string(data("cube_h8_n2.inp"))
        .unwrap()
        .replace("BOTTOM, 1, 3", "BOTOM, 1, 3");
    let e = err(&text);
    let msg = e.to_string();
    assert!(matches!(e, InpError::UnknownName { .. }), "{e:?}");
    assert!(
        msg.contains("BOTOM")
            && msg.contains("BOTTOM")
            && msg.contains("TOP")
            && msg.contains("*BOUNDARY"),
        "{msg}"
    );
    let line = text.lines().position(|l| l == "BOTOM, 1, 3").unwrap() + 1;
    assert!(msg.contains(&format!("test.inp:{line}:")), "{msg}");
}

#[test]
fn error_bad_number() {
    let e = err("*NODE\n1, 0, 0, 0\n2, 1.0, abc, 0\n");
    assert!(
        matches!(&e, InpError::BadNumber { line: 3, text, .. } if text == "abc"),
        "{e:?}"
    );
    assert!(e.to_string().contains("test.inp:3"));
}

#[test]
fn error_short_element_and_continuation() {
    // 20-node element on one line is fine without continuation when complete...
    let ok = std::fs::read_to_string(data("cube_h20_n2.inp")).unwrap();
    assert!(parse_inp(&ok, "x").is_ok());
    // a full line of 16 entries continues (Abaqus rule) even without a comma
    let full16 = ok.replacen(", 40,\n", ", 40\n", 1);
    assert!(parse_inp(&full16, "x").is_ok());
    // ...but a short line cut without a trailing comma leaves the element short
    let broken = ok.replacen(", 32, 37, 40,\n36,", ", 32\n37, 40, 36,", 1);
    let e = err(&broken);
    assert!(
        e.to_string()
            .contains("element 1: TYPE=C3D20 needs 20 nodes, found 13"),
        "{e}"
    );
    let line = broken
        .lines()
        .position(|l| l.starts_with("1, 1, 3, 11"))
        .unwrap()
        + 1;
    assert!(matches!(e, InpError::Invalid { line: l, .. } if l == line));
    // a short line ending with a comma continues
    let split = ok.replacen(", 32, 37, 40,\n36,", ", 32,\n 37, 40, 36,", 1);
    let d = parse_inp(&split, "x").unwrap();
    assert_eq!(
        d.mesh.blocks[0].connectivity,
        parse_inp(&ok, "x").unwrap().mesh.blocks[0].connectivity
    );
}

#[test]
fn error_dofs_and_steps() {
    let base = std::fs::read_to_string(data("cube_h8_n2.inp")).unwrap();
    let e = err(&base.replace("BOTTOM, 1, 3", "BOTTOM, 1, 6"));
    assert!(e.to_string().contains("degree of freedom 6"), "{e}");
    // a second step, with OP=NEW loads and boundaries
    let two = format!(
        "{base}*STEP, NAME=second\n*STATIC\n*CLOAD, OP=NEW\n27, 3, -5.\n*BOUNDARY, OP=NEW\nBOTTOM, 1, 3\n*END STEP\n"
    );
    let d = parse_inp(&two, "x").unwrap();
    assert_eq!(d.steps.len(), 2);
    assert_eq!(d.steps[1].name.as_deref(), Some("second"));
    let last = d.cloads.last().unwrap();
    assert_eq!((last.step, last.op_new, last.value), (Some(1), true, -5.0));
    let bc = d.boundaries.last().unwrap();
    assert_eq!((bc.step, bc.op_new), (Some(1), true));
    assert_eq!(d.boundaries[0].step, None, "model data");
    // OP=NEW is history data only; other OP values are errors
    let e = err(&base.replace("*BOUNDARY\nBOTTOM", "*BOUNDARY, OP=NEW\nBOTTOM"));
    assert!(e.to_string().contains("only valid inside *STEP"), "{e}");
    let e = err(&two.replace("*CLOAD, OP=NEW", "*CLOAD, OP=REPLACE"));
    assert!(e.to_string().contains("OP=MOD, OP=NEW"), "{e}");
    let e = err(&base.replace("*END STEP\n", ""));
    assert!(e.to_string().contains("missing *END STEP"), "{e}");
    let e = err(&base.replace(
        "*SOLID SECTION, ELSET=EALL",
        "*SOLID SECTION, ORIENTATION=OR1, ELSET=EALL",
    ));
    // an orientation that is never defined
    assert!(
        e.to_string().contains("orientation `OR1` is not defined"),
        "{e}"
    );
    let e = err(&base.replace("*STEP", "*STEP, FOO=1"));
    assert!(e.to_string().contains("valid: NAME, NLGEOM, INC"), "{e}");
    let d = parse_inp(&base.replace("*STEP", "*STEP, NLGEOM, INC=50"), "x").unwrap();
    assert!(d.steps[0].nlgeom);
    assert_eq!(d.steps[0].max_increments, Some(50));
}

#[test]
fn error_missing_material_and_wrong_section() {
    let e = err(&TWO_MATERIALS.replace("MATERIAL=M2", "MATERIAL=M3"));
    assert!(
        e.to_string()
            .contains("material `M3` is not defined; defined: M1, M2"),
        "{e}"
    );
    let e = err(&TWO_BLOCKS_WITH_COHESIVE
        .replace("*SOLID SECTION, ELSET=solids", "*SOLID SECTION, ELSET=GLUE"));
    assert!(e.to_string().contains("*COHESIVE SECTION"), "{e}");
}

/// TWO_BLOCKS_WITH_COHESIVE with damage options on the glue.
fn with_damage(damage: &str) -> String {
    TWO_BLOCKS_WITH_COHESIVE.replace("1e6, 5e5, 5e5\n", &format!("1e6, 1e6, 1e6\n{damage}"))
}

const DAMAGE: &str = "*Damage Initiation, criterion=QUADS
80., 100., 100.
*damage evolution , type = energy, mixed mode behavior = bk, power=2.284
0.969, 1.719, 1.719
*DAMAGE STABILIZATION
1e-4
";

/// 1-based line of the first line of `text` that starts with `pat`.
fn line_of(text: &str, pat: &str) -> usize {
    text.lines().position(|l| l.starts_with(pat)).unwrap() + 1
}

#[test]
fn cohesive_damage_keywords_are_read() {
    let text = with_damage(DAMAGE);
    let deck = parse_inp(&text, "coh.inp").unwrap();
    let m = deck.material("glue").unwrap();
    assert!(m.has_damage());
    let i = m.damage_initiation.as_ref().unwrap();
    assert_eq!(i.criterion, InpOnset::Quads);
    assert_eq!(i.strengths, [80.0, 100.0, 100.0]);
    assert_eq!(i.line, line_of(&text, "*Damage Initiation"));
    let e = m.damage_evolution.as_ref().unwrap();
    assert_eq!(e.softening, InpSoftening::Linear);
    assert_eq!(e.mixed_mode, InpMixedMode::Bk { power: 2.284 });
    assert_eq!(e.toughness, [0.969, 1.719, 1.719]);
    assert_eq!(m.damage_stabilization.as_ref().unwrap().viscosity, 1e-4);
    assert_eq!(m.elastic_line, line_of(&text, "1e6, 1e6, 1e6"));
    assert!(!deck.material("steel").unwrap().has_damage());
    // MAXS, exponential, power law
    let text = with_damage(
        "*DAMAGE INITIATION, CRITERION=MAXS\n80, 100, 100\n*DAMAGE EVOLUTION, TYPE=ENERGY, SOFTENING=EXPONENTIAL, MIXED MODE BEHAVIOR=POWER LAW, POWER=1\n1, 2, 2\n",
    );
    let deck = parse_inp(&text, "coh.inp").unwrap();
    let m = deck.material("GLUE").unwrap();
    assert_eq!(
        m.damage_initiation.as_ref().unwrap().criterion,
        InpOnset::Maxs
    );
    let e = m.damage_evolution.as_ref().unwrap();
    assert_eq!(e.softening, InpSoftening::Exponential);
    assert_eq!(e.mixed_mode, InpMixedMode::PowerLaw { power: 1.0 });
}

#[test]
fn cohesive_damage_errors_name_file_and_line() {
    let check = |text: &str, line: usize, needles: &[&str]| {
        let e = err(text).to_string();
        assert!(
            e.starts_with(&format!("test.inp:{line}:")),
            "line {line}: {e}"
        );
        for n in needles {
            assert!(e.contains(n), "`{n}` missing in: {e}");
        }
    };
    // a damage keyword outside a material (after a section)
    let text = format!("{TWO_BLOCKS_WITH_COHESIVE}*DAMAGE STABILIZATION\n1e-4\n");
    check(
        &text,
        line_of(&text, "*DAMAGE STABILIZATION"),
        &["must follow the *MATERIAL"],
    );
    // initiation without evolution: Abaqus would never soften
    let text = with_damage("*DAMAGE INITIATION, CRITERION=QUADS\n80, 100, 100\n");
    check(
        &text,
        line_of(&text, "*DAMAGE INITIATION"),
        &["no *DAMAGE EVOLUTION", "never soften"],
    );
    // evolution before initiation
    let text = with_damage("*DAMAGE EVOLUTION, TYPE=ENERGY\n1\n");
    check(
        &text,
        line_of(&text, "*DAMAGE EVOLUTION"),
        &["must follow its *DAMAGE INITIATION"],
    );
    // unsupported options
    for (from, to, needle) in [
        ("criterion=QUADS", "criterion=MAXE", "CRITERION=MAXE"),
        ("type = energy", "type=DISPLACEMENT", "TYPE=DISPLACEMENT"),
        (
            "type = energy",
            "type=energy, softening=TABULAR",
            "SOFTENING=TABULAR",
        ),
        (
            "mixed mode behavior = bk",
            "mixed mode behavior=TABULAR",
            "MIXED MODE BEHAVIOR=TABULAR",
        ),
        (", power=2.284", "", "needs POWER="),
        (
            "0.969, 1.719, 1.719",
            "0.969, 1.719, 1.719, 20.0",
            "temperature",
        ),
    ] {
        let text = with_damage(&DAMAGE.replace(from, to));
        let pat = if needle == "temperature" {
            "0.969"
        } else if from.starts_with("criterion") {
            "*Damage Initiation"
        } else {
            "*damage evolution"
        };
        check(&text, line_of(&text, pat), &[needle]);
    }
    // a damage material used by a *SOLID SECTION
    let text = with_damage(DAMAGE).replace(
        "*SOLID SECTION, ELSET=solids, MATERIAL=steel",
        "*SOLID SECTION, ELSET=solids, MATERIAL=glue",
    );
    check(
        &text,
        line_of(&text, "*SOLID SECTION"),
        &["damage options", "*COHESIVE SECTION"],
    );
    // a damage material no *COHESIVE SECTION uses
    let text = with_damage(DAMAGE)
        .replace("MATERIAL=GLUE, RESPONSE", "MATERIAL=GLUE2, RESPONSE")
        .replace(
            "*SOLID SECTION",
            "*MATERIAL, NAME=GLUE2\n*ELASTIC, TYPE=TRACTION\n1e6, 1e6, 1e6\n*SOLID SECTION",
        );
    check(
        &text,
        line_of(&text, "*MATERIAL, NAME=Glue"),
        &["no *COHESIVE SECTION uses it"],
    );
    // damage on an isotropic material
    let text = TWO_BLOCKS_WITH_COHESIVE.replace("*DENSITY\n7.85e-9\n", DAMAGE);
    check(
        &text,
        line_of(&text, "*MATERIAL, NAME=Steel"),
        &["not TYPE=TRACTION"],
    );
    // THICKNESS=GEOMETRY
    let text = TWO_BLOCKS_WITH_COHESIVE.replace(
        "RESPONSE=TRACTION SEPARATION",
        "RESPONSE=TRACTION SEPARATION, THICKNESS=GEOMETRY",
    );
    check(
        &text,
        line_of(&text, "*COHESIVE SECTION"),
        &["THICKNESS=GEOMETRY", "SPECIFIED"],
    );
}

#[test]
fn junta_directives() {
    let text = format!(
        "** junta: curve reaction_set=lower reaction_component=Z point_set=LOWER point_component=z\n** junta: output every=5\n{}*NSET, NSET=Lower\n1, 2\n",
        TWO_BLOCKS_WITH_COHESIVE
    );
    let deck = parse_inp(&text, "coh.inp").unwrap();
    let c = deck.curve.unwrap();
    assert_eq!(
        (c.reaction_set.as_str(), c.reaction_component.as_str()),
        ("Lower", "z")
    );
    assert_eq!(c.point_set, "Lower");
    assert_eq!(c.relative_to, None);
    assert_eq!(deck.every, Some(5));
    let bad = text.replace("point_set=LOWER", "point_set=NOPE");
    let e = err(&bad).to_string();
    assert!(e.starts_with("test.inp:1:") && e.contains("NOPE"), "{e}");
    let bad = text.replace("every=5", "every=5 often=1");
    let e = err(&bad).to_string();
    assert!(e.starts_with("test.inp:2:") && e.contains("often"), "{e}");
    let bad = text.replace("** junta: output", "** junta: plot");
    let e = err(&bad).to_string();
    assert!(
        e.starts_with("test.inp:2:") && e.contains("unknown directive"),
        "{e}"
    );
    let bad = text.replace(" point_component=z", "");
    let e = err(&bad).to_string();
    assert!(
        e.starts_with("test.inp:1:") && e.contains("point_component"),
        "{e}"
    );
}

// ------------------------------------------------------------------ Gmsh

#[test]
fn gmsh_hex20_fixture() {
    let m = read_msh(data("box_hex20.msh")).unwrap();
    assert_eq!(m.nodes.len(), 32);
    assert_eq!(m.blocks.len(), 1);
    let b = &m.blocks[0];
    assert_eq!(
        (
            b.name.as_str(),
            b.shape,
            b.element_type.as_str(),
            b.material.as_str()
        ),
        ("solid", CellShape::Hex20, "h20", "solid")
    );
    assert_eq!(b.len(), 2);
    check_hex_geometry(&m);
    assert_eq!(m.element_set("solid").unwrap().len(), 2);
    let origin = m.node_set("origin").unwrap();
    assert_eq!(origin.len(), 1);
    assert_eq!(m.nodes[origin[0]], [0.0, 0.0, 0.0]);
    for (name, z, face) in [("bottom", 0.0, 0), ("top", 1.0, 1)] {
        let nodes = m.node_set(name).unwrap();
        assert_eq!(nodes.len(), 13, "{name}");
        assert!(nodes.iter().all(|&n| m.nodes[n][2] == z));
        let faces = m.face_set(name).unwrap();
        assert_eq!(faces.len(), 2);
        for &f in faces {
            assert_eq!(f.face, face, "{name} is face S{} of its element", face + 1);
            let fnodes = m.face_nodes(f);
            assert_eq!(fnodes.len(), 8);
            assert!(fnodes.iter().all(|&n| m.nodes[n][2] == z));
        }
        assert_eq!(m.nodes_of_faces(faces), nodes);
    }
}

#[test]
fn gmsh_hex27_fixture() {
    let m = read_msh(data("box_hex27.msh")).unwrap();
    assert_eq!(m.nodes.len(), 27);
    assert_eq!(m.blocks[0].shape, CellShape::Hex27);
    assert_eq!(m.blocks[0].element_type, "h27");
    check_hex_geometry(&m);
    let top = m.face_set("top").unwrap();
    assert_eq!(top.len(), 1);
    assert_eq!(m.face_nodes(top[0]).len(), 9);
    assert_eq!(m.node_set("top").unwrap().len(), 9);
}

/// Wedge meshes written by Gmsh 4.15.2 (tests/data/make_prism_msh.py): two
/// physical volumes of prisms, triangles on the physical surfaces `bottom`,
/// `mid` and `top`, quadrangles on `sides`. Each surface element is matched
/// to the face of a wedge: triangles to the end faces S1 (z-) / S2 (z+),
/// the internal `mid` surface to the face whose outward normal agrees with
/// the triangle's right-hand normal (Gmsh orients the extruded top
/// surface along +z, so the lower wedges' S2).
#[test]
fn gmsh_prism_fixtures_match_triangles_to_wedge_faces() {
    for (file, wedge, tri, quad) in [
        (
            "prism_stack_o1.msh",
            CellShape::Wedge6,
            CellShape::Tri3,
            CellShape::Quad4,
        ),
        (
            "prism_stack_o2.msh",
            CellShape::Wedge15,
            CellShape::Tri6,
            CellShape::Quad8,
        ),
    ] {
        let m = read_msh(data(file)).unwrap();
        let names: Vec<&str> = m.blocks.iter().map(|b| b.name.as_str()).collect();
        assert_eq!(names, ["lower", "upper"], "{file}");
        assert!(m.blocks.iter().all(|b| b.shape == wedge), "{file}");
        let lower = m.blocks[0].len();
        assert!(lower >= 4 && m.blocks[1].len() == lower, "{file}");
        // every wedge is right-handed: positive volume of its corner prism
        for b in &m.blocks {
            for e in 0..b.len() {
                let c = b.element(e);
                let p = |k: usize| m.nodes[c[k]];
                let (a, bb, cc, d) = (p(0), p(1), p(2), p(3));
                let u = [bb[0] - a[0], bb[1] - a[1], bb[2] - a[2]];
                let v = [cc[0] - a[0], cc[1] - a[1], cc[2] - a[2]];
                let w = [d[0] - a[0], d[1] - a[1], d[2] - a[2]];
                let det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
                    + u[2] * (v[0] * w[1] - v[1] * w[0]);
                assert!(det > 0.0, "{file}: {} element {e} is inverted", b.name);
            }
        }
        for (name, z, block, face) in [
            ("bottom", 0.0, 0, 0),
            ("mid", 0.5, 0, 1),
            ("top", 1.0, 1, 1),
        ] {
            let faces = m.face_set(name).unwrap();
            assert_eq!(faces.len(), lower, "{file} {name}: one face per wedge");
            for &f in faces {
                assert_eq!((f.block, f.face), (block, face), "{file} {name}");
                let shape = m.blocks[f.block].shape.face_shape_of(f.face).unwrap();
                assert_eq!(shape, tri, "{file} {name}");
                assert!(
                    m.face_nodes(f).iter().all(|&n| m.nodes[n][2] == z),
                    "{file} {name}"
                );
            }
            assert_eq!(
                m.nodes_of_faces(faces),
                m.node_set(name).unwrap(),
                "{file} {name}"
            );
        }
        let sides = m.face_set("sides").unwrap();
        for &f in sides {
            let shape = m.blocks[f.block].shape.face_shape_of(f.face).unwrap();
            assert_eq!(shape, quad, "{file} sides");
            let nodes = m.face_nodes(f);
            let on_side = |d: usize, v: f64| nodes.iter().all(|&n| m.nodes[n][d] == v);
            assert!(
                on_side(0, 0.0) || on_side(0, 1.0) || on_side(1, 0.0) || on_side(1, 1.0),
                "{file}: side face {f:?} is not on the boundary"
            );
        }
        // the sides of the two volumes: as many quadrangles as boundary
        // edges of the triangulated square, twice
        assert_eq!(sides.len() % 2, 0, "{file}");
    }
    // a triangle that is no wedge face is refused with its tag and a hint
    // (the first triangle of the first surface block gets a node of the
    // top surface as its third corner)
    let text = std::fs::read_to_string(data("prism_stack_o1.msh")).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let at = lines.iter().position(|l| l == "$Elements").unwrap();
    let header = (at + 2..lines.len())
        .find(|&i| lines[i].split_whitespace().nth(2) == Some("2"))
        .unwrap();
    let top = m_top_node(&text);
    let mut t: Vec<String> = lines[header + 1]
        .split_whitespace()
        .map(String::from)
        .collect();
    let tag = t[0].clone();
    t[3] = top.to_string();
    lines[header + 1] = t.join(" ");
    let e = parse_msh(&lines.join("\n"), "p.msh")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(&format!("triangle {tag} of surface")) && e.contains("wedge"),
        "{e}"
    );
}

/// Tag of a node at z = 1 in a Gmsh 4.1 file (first one listed).
fn m_top_node(text: &str) -> usize {
    let m = parse_msh(text, "p.msh").unwrap();
    let i = (0..m.nodes.len()).find(|&i| m.nodes[i][2] == 1.0).unwrap();
    m.node_labels[i]
}

const HEX8_MSH: &str = "$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
2
2 7 \"load\"
3 8 \"block\"
$EndPhysicalNames
$Entities
0 0 1 1
3 0 0 1 1 1 1 1 7 0
1 0 0 0 1 1 1 1 8 0
$EndEntities
$Nodes
2 8 1 8
2 3 0 4
5
6
7
8
0 0 1
1 0 1
1 1 1
0 1 1
3 1 0 4
1
2
3
4
0 0 0
1 0 0
1 1 0
0 1 0
$EndNodes
$Elements
2 2 1 2
3 1 5 1
1 1 2 3 4 5 6 7 8
2 3 3 1
2 5 6 7 8
$EndElements
";

#[test]
fn gmsh_hand_written_hex8() {
    let m = parse_msh(HEX8_MSH, "hand.msh").unwrap();
    assert_eq!(m.node_labels, vec![5, 6, 7, 8, 1, 2, 3, 4]);
    assert_eq!(m.blocks[0].name, "block");
    check_hex_geometry(&m);
    let f = m.face_set("load").unwrap();
    assert_eq!(f.len(), 1);
    assert_eq!(f[0].face, 1);
    assert_eq!(m.node_set("load").unwrap().len(), 4);
}

#[test]
fn gmsh_errors() {
    let e = parse_msh(&HEX8_MSH.replace("4.1 0 8", "4.1 1 8"), "bin.msh").unwrap_err();
    assert!(matches!(e, GmshError::Binary { line: 2, .. }), "{e:?}");
    assert!(e.to_string().contains("binary"));
    let e = parse_msh(&HEX8_MSH.replace("4.1 0 8", "2.2 0 8"), "old.msh").unwrap_err();
    assert!(e.to_string().contains("4.1"), "{e}");
    let e = parse_msh(&HEX8_MSH.replace("3 1 5 1", "3 1 4 1"), "tet.msh").unwrap_err();
    assert!(matches!(e, GmshError::ElementType { code: 4, .. }), "{e:?}");
    let e = parse_msh(
        &HEX8_MSH.replace("1 1 2 3 4 5 6 7 8", "1 1 2 3 4 5 6 7 9"),
        "bad.msh",
    )
    .unwrap_err();
    assert!(e.to_string().contains("undefined node tag 9"), "{e}");
}

/// A fresh directory under the system temporary directory.
fn scratch_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("junta-readers-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// `*INCLUDE, INPUT=`: the cube deck split the way users split decks (the
/// mesh in a file of a subdirectory, itself including the sets; the
/// material next to the deck, the name quoted) reads as the single file
/// does; a mistake inside an included file is reported with that file's
/// name and its own line number.
#[test]
fn include_reads_files_in_place_and_errors_name_the_included_file() {
    let whole = std::fs::read_to_string(data("cube_h8_n2.inp")).unwrap();
    let lines: Vec<&str> = whole.lines().collect();
    // lines 4-40: nodes and elements; 41-46: node sets; 47-49: material
    let dir = scratch_dir("include");
    std::fs::create_dir_all(dir.join("parts")).unwrap();
    let mesh = format!("{}\n*include, input=sets.inp\n", lines[3..40].join("\n"));
    std::fs::write(dir.join("parts/mesh.inp"), mesh).unwrap();
    std::fs::write(dir.join("parts/sets.inp"), lines[40..46].join("\n")).unwrap();
    std::fs::write(dir.join("steel.inp"), lines[46..49].join("\n")).unwrap();
    let main = format!(
        "{}\n*INCLUDE, INPUT=parts/mesh.inp\n*Include, Input=\"steel.inp\"\n{}\n",
        lines[..3].join("\n"),
        lines[49..].join("\n")
    );
    std::fs::write(dir.join("main.inp"), &main).unwrap();
    let split = read_inp(dir.join("main.inp")).unwrap();
    let single = read_inp(data("cube_h8_n2.inp")).unwrap();
    assert_eq!(split.mesh.nodes, single.mesh.nodes);
    assert_eq!(split.mesh.blocks, single.mesh.blocks);
    assert_eq!(split.mesh.node_sets, single.mesh.node_sets);
    assert_eq!(split.materials, single.materials);
    assert_eq!(split.steps.len(), single.steps.len());
    // a bad number on line 3 of sets.inp
    let bad = lines[40..46].join("\n").replacen("\n", "\n1, 2, x3\n", 1);
    std::fs::write(dir.join("parts/sets.inp"), bad).unwrap();
    let e = read_inp(dir.join("main.inp")).unwrap_err().to_string();
    assert!(e.contains("sets.inp:2:"), "{e}");
    assert!(e.contains("x3"), "{e}");
    // a missing file: the including file and line, and where it looked
    std::fs::remove_file(dir.join("steel.inp")).unwrap();
    let e = read_inp(dir.join("main.inp")).unwrap_err().to_string();
    assert!(e.contains("main.inp:5: *INCLUDE"), "{e}");
    assert!(e.contains("steel.inp"), "{e}");
    // a cycle and a missing INPUT are errors, not a stack overflow
    std::fs::write(dir.join("a.inp"), "*HEADING\nx\n*INCLUDE, INPUT=b.inp\n").unwrap();
    std::fs::write(dir.join("b.inp"), "*INCLUDE, INPUT=a.inp\n").unwrap();
    let e = read_inp(dir.join("a.inp")).unwrap_err().to_string();
    assert!(
        e.contains("b.inp:1: *INCLUDE") && e.contains("includes itself"),
        "{e}"
    );
    std::fs::write(dir.join("c.inp"), "*HEADING\nx\n*INCLUDE\n").unwrap();
    let e = read_inp(dir.join("c.inp")).unwrap_err().to_string();
    assert!(e.contains("c.inp:3: *INCLUDE: needs INPUT="), "{e}");
    // given as text, without a file to resolve it against
    let e = err("*INCLUDE, INPUT=mesh.inp\n").to_string();
    assert!(e.contains("test.inp:1: *INCLUDE"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A 2D Gmsh mesh (tests/data/plate_quad8.geo: a 4 x 2 plate of 8 x 4
/// serendipity quadrangles, physical surface `plate`, curves `left` and
/// `right`) is a plane model: one block of PlaneQuad8 cells,
/// counter-clockwise, the curves as edge sets. Under a traction on `right`
/// it gives the plane box of the same mesh to round-off, and the reaction
/// is the traction times the edge's length and the thickness.
#[test]
fn gmsh_2d_mesh_is_a_plane_model() {
    use junta::{RunSettings, Simulation};
    let m = read_msh(data("plate_quad8.msh")).unwrap();
    assert_eq!(m.blocks.len(), 1);
    assert_eq!(
        (m.blocks[0].shape, m.blocks[0].element_type.as_str()),
        (CellShape::PlaneQuad8, "cpe8")
    );
    assert_eq!(m.face_sets["right"].len(), 4);
    for e in 0..m.blocks[0].len() {
        let c = m.blocks[0].element(e);
        let area: f64 = (0..4)
            .map(|i| {
                let (p, q) = (m.nodes[c[i]], m.nodes[c[(i + 1) % 4]]);
                p[0] * q[1] - q[0] * p[1]
            })
            .sum();
        assert!(area > 0.0, "cell {e} is clockwise");
    }
    let common = "[model]\nthickness = 0.1\n[materials.steel]\ntype = \"isotropic\"\nE = 200000.0\nnu = 0.3\n\
                  [[load]]\nface_set = \"RIGHT\"\ntraction = [10.0, 5.0, 0.0]\n[[boundary]]\nset = \"LEFT\"\nfixed = [\"x\", \"y\"]\n\
                  [analysis]\ntype = \"linear\"\n";
    let gmsh = format!(
        "{}[mesh]\ntype = \"gmsh\"\nfile = \"{}\"\n[[blocks]]\nname = \"plate\"\nelement = \"cps8\"\nmaterial = \"steel\"\n",
        common.replace("RIGHT", "right").replace("LEFT", "left"),
        data("plate_quad8.msh").display()
    );
    let boxed = format!(
        "{}[mesh]\ntype = \"box\"\nsize = [4.0, 2.0]\ndivisions = [8, 4]\nelement = \"cps8\"\nmaterial = \"steel\"\n",
        common.replace("RIGHT", "x1").replace("LEFT", "x0")
    );
    let run = |text: &str| {
        Simulation::from_scene_text(text, "plate.toml")
            .unwrap()
            .run(&RunSettings::in_memory(), &mut [])
            .unwrap()
            .summary
            .to_json()
    };
    let (a, b) = (run(&gmsh), run(&boxed));
    let umax = |s: &serde_json::Value| s["displacement_max"].as_f64().unwrap();
    assert!(
        (umax(&a) - umax(&b)).abs() < 1e-12 * umax(&b),
        "{} against {}",
        umax(&a),
        umax(&b)
    );
    let r = a["reactions"]["left"].clone();
    assert!(
        (r[0].as_f64().unwrap() + 2.0).abs() < 1e-9 && (r[1].as_f64().unwrap() + 1.0).abs() < 1e-9,
        "{r}"
    );
}
