//! `*SOLID SECTION, COMPOSITE` in decks: plies integrated one by one in a
//! hexahedron ([`junta_elements::layered`]), measured against classical
//! lamination theory.
//!
//! An `L x L` plate (L = 20 mm) of 2 x 2 C3D20 elements, T300/5208 plies
//! `T = 0.125` mm thick, every ply's axes an `*ORIENTATION`; the deck is
//! written here. `abd_of` (tests/support/clt.rs) prescribes CLT's unit
//! fields on the edges and measures `[A B; B D]`. One element through the
//! thickness holds all plies; with two, each holds half of them, and the
//! difference from CLT shrinks (one quadratic element cannot make
//! `sigma_zz` vanish in every ply: its through-thickness strain is one
//! quadratic for the whole stack, CLT's plane stress is ply by ply).

#[path = "support/clt.rs"]
mod clt;
use clt::*;
use junta::input::deck::build_model;
use std::fmt::Write as _;
use std::path::PathBuf;

/// The orientation name of a ply angle.
fn oname(a: f64) -> String {
    if a < 0.0 {
        format!("om{}", -a)
    } else {
        format!("o{a}")
    }
}

/// The deck of the plate: `angles` bottom to top, `nz` elements through
/// the thickness (each holding `angles.len() / nz` plies, 3 Gauss points
/// each), element TYPE `etype`.
fn plate_deck(angles: &[f64], nz: usize, etype: &str) -> String {
    let n = angles.len();
    assert_eq!(n % nz, 0);
    let h = T * n as f64;
    let (ni, nk) = (5usize, 2 * nz + 1);
    let label = |i: usize, j: usize, k: usize| 1 + i + ni * (j + ni * k);
    let used = |i: usize, j: usize, k: usize| (i % 2) + (j % 2) + (k % 2) <= 1;
    let mut d = String::from("*HEADING\ncomposite plate\n*NODE\n");
    for k in 0..nk {
        for j in 0..ni {
            for i in 0..ni {
                if used(i, j, k) {
                    let (x, y, z) = (
                        L * i as f64 / 4.0,
                        L * j as f64 / 4.0,
                        h * k as f64 / (nk - 1) as f64,
                    );
                    writeln!(d, "{}, {x}, {y}, {z}", label(i, j, k)).unwrap();
                }
            }
        }
    }
    const CORNERS: [(usize, usize, usize); 8] = [
        (0, 0, 0),
        (2, 0, 0),
        (2, 2, 0),
        (0, 2, 0),
        (0, 0, 2),
        (2, 0, 2),
        (2, 2, 2),
        (0, 2, 2),
    ];
    const MIDS: [(usize, usize, usize); 12] = [
        (1, 0, 0),
        (2, 1, 0),
        (1, 2, 0),
        (0, 1, 0),
        (1, 0, 2),
        (2, 1, 2),
        (1, 2, 2),
        (0, 1, 2),
        (0, 0, 1),
        (2, 0, 1),
        (2, 2, 1),
        (0, 2, 1),
    ];
    let mut el = 0;
    for ez in 0..nz {
        writeln!(d, "*ELEMENT, TYPE={etype}, ELSET=layer{}", ez + 1).unwrap();
        for ey in 0..2 {
            for ex in 0..2 {
                el += 1;
                let offs: Vec<_> = if etype == "C3D20" {
                    CORNERS.iter().chain(MIDS.iter()).collect()
                } else {
                    CORNERS.iter().collect()
                };
                let nodes: Vec<String> = offs
                    .iter()
                    .map(|&&(a, b, c)| label(2 * ex + a, 2 * ey + b, 2 * ez + c).to_string())
                    .collect();
                let (first, rest) = nodes.split_at(nodes.len().min(15));
                write!(d, "{el}, {}", first.join(", ")).unwrap();
                if rest.is_empty() {
                    d.push('\n');
                } else {
                    writeln!(d, ",\n{}", rest.join(", ")).unwrap();
                }
            }
        }
    }
    for (name, f) in [
        (
            "x0",
            (|i: usize, _j: usize| i == 0) as fn(usize, usize) -> bool,
        ),
        ("x1", |i, _| i == 4),
        ("y0", |_, j| j == 0),
        ("y1", |_, j| j == 4),
    ] {
        writeln!(d, "*NSET, NSET={name}").unwrap();
        for k in 0..nk {
            for j in 0..ni {
                for i in 0..ni {
                    if used(i, j, k) && f(i, j) {
                        writeln!(d, "{}", label(i, j, k)).unwrap();
                    }
                }
            }
        }
    }
    d.push_str(
        "*MATERIAL, NAME=T300\n*ELASTIC, TYPE=ENGINEERING CONSTANTS\n\
         181e3, 10.3e3, 10.3e3, 0.28, 0.28, 0.4, 7.17e3, 7.17e3,\n3.68e3\n",
    );
    let mut seen = Vec::new();
    for &a in angles {
        if !seen.contains(&a) {
            seen.push(a);
            let (s, c) = f64::to_radians(a).sin_cos();
            writeln!(
                d,
                "*ORIENTATION, NAME={}\n{c}, {s}, 0, {}, {c}, 0",
                oname(a),
                -s
            )
            .unwrap();
        }
    }
    let per = n / nz;
    for ez in 0..nz {
        writeln!(d, "*SOLID SECTION, COMPOSITE, ELSET=layer{}", ez + 1).unwrap();
        for (k, &a) in angles[ez * per..(ez + 1) * per].iter().enumerate() {
            writeln!(d, "{T}, 3, T300, {}, ply{}", oname(a), ez * per + k + 1).unwrap();
        }
    }
    d.push_str("*BOUNDARY\nx0, 1, 3\n*STEP\n*STATIC\n*CLOAD\nx1, 1, 1.0\n*END STEP\n");
    d
}

fn write_deck(name: &str, text: &str) -> PathBuf {
    let path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("{name}.inp"));
    std::fs::write(&path, text).unwrap();
    path
}

/// `[dA, dB, dD]` of the plate of `angles` with `nz` elements through.
fn measured(name: &str, angles: &[f64], nz: usize) -> [f64; 3] {
    let path = write_deck(name, &plate_deck(angles, nz, "C3D20"));
    let built = build_model(&path).unwrap_or_else(|e| panic!("{e}"));
    let abd = abd_of(&built.model);
    let r = compare(angles, &abd, &clt_abd(angles));
    eprintln!(
        "{name}: {nz} element(s) through: dA {:.3e}, dB {:.3e}, dD {:.3e}",
        r[0], r[1], r[2]
    );
    r
}

const LAYUPS: [(&str, &[f64]); 4] = [
    ("cross_ply_s", &[0.0, 90.0, 90.0, 0.0]),
    ("angle_ply_s", &[45.0, -45.0, -45.0, 45.0]),
    ("quasi_s", &[0.0, 45.0, -45.0, 90.0, 90.0, -45.0, 45.0, 0.0]),
    ("cross_ply_unsym", &[0.0, 90.0]),
];

#[test]
fn one_element_through_the_thickness_is_clt_within_one_percent() {
    for (name, angles) in LAYUPS {
        let r = measured(name, angles, 1);
        for (what, v) in ["A", "B", "D"].iter().zip(r) {
            assert!(v < 1e-2, "{name}: {what} differs by {v:.3e}");
        }
    }
}

#[test]
fn two_elements_through_the_thickness_come_closer() {
    for (name, angles) in LAYUPS {
        let one = measured(name, angles, 1);
        let two = measured(&format!("{name}_2"), angles, 2);
        for (what, (a, b)) in ["A", "B", "D"].iter().zip(one.iter().zip(two)) {
            assert!(
                b < 1e-2,
                "{name}: {what} with two elements differs by {b:.3e}"
            );
            // equal to round-off where one element is already exact
            assert!(
                b <= a.max(1e-9) * 1.0001,
                "{name}: {what}: two elements {b:.3e} vs one {a:.3e}"
            );
        }
        // D: the through-thickness field of a stack of plies is what one
        // element cannot follow
        assert!(
            two[2] < one[2],
            "{name}: D {:.3e} -> {:.3e}",
            one[2],
            two[2]
        );
    }
}

fn error_of(name: &str, text: &str) -> String {
    match build_model(&write_deck(name, text)) {
        Ok(_) => panic!("{name}: the deck was accepted"),
        Err(e) => e.to_string(),
    }
}

/// The 1-based line of the first line of `text` that starts with `start`.
fn line_of(text: &str, start: &str) -> usize {
    1 + text.lines().position(|l| l.starts_with(start)).unwrap()
}

#[test]
fn composite_on_c3d8i_is_refused_naming_the_line() {
    let text = plate_deck(&[0.0, 90.0], 1, "C3D8I");
    let e = error_of("c3d8i", &text);
    let line = line_of(&text, "*SOLID SECTION");
    assert!(e.contains(&format!(":{line}:")), "{e}");
    assert!(e.contains("C3D8I"), "{e}");
}

#[test]
fn bad_plies_are_refused_naming_the_line() {
    let good = plate_deck(&[0.0, 90.0], 1, "C3D20");
    let ply = line_of(&good, "0.125, 3, T300, o90");
    let cases = [
        ("0.125, 3, NOPE, o90", "material `NOPE` is not defined"),
        ("0.125, 3, T300, o33", "orientation `o33` is not defined"),
        ("0, 3, T300, o90", "must be positive"),
        ("-1, 3, T300, o90", "must be positive"),
        ("0.125, 2.5, T300, o90", "integer from 1 to 5"),
        ("0.125, 7, T300, o90", "integer from 1 to 5"),
    ];
    for (k, (bad, what)) in cases.iter().enumerate() {
        let text = good.replace("0.125, 3, T300, o90", bad);
        let e = error_of(&format!("bad_ply_{k}"), &text);
        assert!(e.contains(&format!(":{ply}:")), "{bad}: {e}");
        assert!(e.contains(what), "{bad}: {e}");
    }
}

#[test]
fn an_angle_in_place_of_the_orientation_is_about_the_section_axis_3() {
    // [0/90] with the plies' angles given as numbers relative to a section
    // orientation turned by 30 degrees, against plies at 30 and 120
    let by_name = plate_deck(&[30.0, 120.0], 1, "C3D20");
    let by_angle = by_name
        .replace(
            "*SOLID SECTION, COMPOSITE, ELSET=layer1",
            "*SOLID SECTION, COMPOSITE, ELSET=layer1, ORIENTATION=o30",
        )
        .replace("0.125, 3, T300, o30, ply1", "0.125, 3, T300, 0, ply1")
        .replace("0.125, 3, T300, o120, ply2", "0.125, 3, T300, 90, ply2");
    assert_ne!(by_name, by_angle);
    let a = abd_of(&build_model(&write_deck("by_name", &by_name)).unwrap().model);
    let b = abd_of(
        &build_model(&write_deck("by_angle", &by_angle))
            .unwrap()
            .model,
    );
    let scale = a[0][0];
    for i in 0..6 {
        for j in 0..6 {
            assert!((a[i][j] - b[i][j]).abs() < 1e-9 * scale, "{i}{j}");
        }
    }
}
