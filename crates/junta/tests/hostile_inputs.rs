//! Readers against hostile input: huge declared sizes fail at once (before
//! any allocation), input-driven loops are bounded, and mutated files never
//! panic (a bounded, deterministic fuzz of the Gmsh and deck readers).

use junta::input::{gmsh::parse_msh, inp::parse_inp};

const MSH: &str = include_str!("data/box_hex20.msh");
/// Gmsh 4.15.2 meshes of prisms, and of hexahedra and prisms side by side,
/// with triangles and quadrangles on physical surfaces.
const MSH_PRISMS: &str = include_str!("data/prism_stack_o2.msh");
const MSH_MIXED: &str = include_str!("data/mixed_stack_o1.msh");
const INP: &str = include_str!("data/cube_h8_n2.inp");

#[test]
fn gmsh_node_header_declaring_1e12_nodes_is_an_error_naming_the_line() {
    let text = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 1000000000000 1 1000000000000\n3 1 0 1000000000000\n1\n0 0 0\n$EndNodes\n";
    let e = parse_msh(text, "huge.msh").unwrap_err().to_string();
    assert!(
        e.contains("1000000000000") && e.contains("huge.msh:5:"),
        "{e}"
    );
    // the same count on a block header
    let text = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 1 1 1\n3 1 0 1000000000000\n1\n0 0 0\n$EndNodes\n";
    let e = parse_msh(text, "huge.msh").unwrap_err().to_string();
    assert!(
        e.contains("1000000000000") && e.contains("huge.msh:6:"),
        "{e}"
    );
}

#[test]
fn gmsh_element_header_declaring_1e12_elements_is_an_error() {
    let text = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 1 1 1\n3 1 0 1\n1\n0 0 0\n$EndNodes\n$Elements\n1 1000000000000 1 1000000000000\n3 1 5 1000000000000\n1 1 1 1 1 1 1 1 1\n$EndElements\n";
    let e = parse_msh(text, "huge.msh").unwrap_err().to_string();
    assert!(e.contains("1000000000000 elements"), "{e}");
    let text =
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Elements\n1000000000000 1 1 1\n$EndElements\n";
    let e = parse_msh(text, "huge.msh").unwrap_err().to_string();
    assert!(e.contains("element blocks"), "{e}");
}

#[test]
fn generate_over_1e11_labels_is_quick_and_keeps_the_defined_labels() {
    // Before: a loop over 1e11 labels (hours). Now it walks the 27 defined labels.
    let text = INP.replace(
        "*ELEMENT",
        "*NSET, NSET=WIDE, GENERATE\n2, 100000000000, 2\n*ELEMENT",
    );
    let deck = parse_inp(&text, "wide.inp").unwrap();
    let set = deck.mesh.node_set("WIDE").unwrap();
    let labels: Vec<usize> = set.iter().map(|&n| deck.mesh.node_labels[n]).collect();
    assert!(!labels.is_empty());
    assert!(labels.iter().all(|l| l % 2 == 0), "{labels:?}");
    assert!(labels.windows(2).all(|w| w[0] < w[1]), "{labels:?}");
}

/// xorshift64*: a fixed-seed generator, so that a failure reproduces.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// One mutation of a text, line-wise or token-wise: delete, duplicate or
/// swap lines, or replace a token by a hostile number or word.
fn mutate(text: &str, rng: &mut Rng) -> String {
    const TOKENS: &[&str] = &[
        "0",
        "-1",
        "1e300",
        "nan",
        "inf",
        "-0",
        "18446744073709551615",
        "99999999999999999999",
        "1000000000000",
        "4294967296",
        "",
        ",",
        "*",
        "$EndNodes",
        "$Nodes",
        "*STEP",
        "*END STEP",
        "GENERATE",
        "x",
        "1.5",
        "2147483648",
        "3",
    ];
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    for _ in 0..1 + rng.below(4) {
        if lines.is_empty() {
            break;
        }
        let i = rng.below(lines.len());
        match rng.below(5) {
            0 => {
                lines.remove(i);
            }
            1 => {
                let l = lines[i].clone();
                lines.insert(i, l);
            }
            2 => {
                let j = rng.below(lines.len());
                lines.swap(i, j);
            }
            _ => {
                let sep = if lines[i].contains(',') { "," } else { " " };
                let mut t: Vec<String> = lines[i].split(sep).map(String::from).collect();
                let k = rng.below(t.len());
                t[k] = TOKENS[rng.below(TOKENS.len())].to_string();
                lines[i] = t.join(sep);
            }
        }
    }
    lines.join("\n") + "\n"
}

#[test]
fn mutated_gmsh_files_and_decks_never_panic() {
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    for case in 0..2000 {
        let (base, is_msh) = match case % 4 {
            0 => (MSH, true),
            1 => (MSH_PRISMS, true),
            2 => (MSH_MIXED, true),
            _ => (INP, false),
        };
        let text = mutate(base, &mut rng);
        let r = std::panic::catch_unwind(|| {
            if is_msh {
                let _ = parse_msh(&text, "fuzz.msh");
            } else {
                let _ = parse_inp(&text, "fuzz.inp");
            }
        });
        assert!(r.is_ok(), "case {case} panicked on:\n{text}");
    }
}
