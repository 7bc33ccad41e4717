//! The lay-up builder against classical lamination theory.
//!
//! Each built laminate (`[laminate]` in a scene, interfaces between its
//! plies) is loaded by the displacement field of a mid-plane strain
//! `eps0 = (eps_x, eps_y, gamma_xy)` and curvature `kappa = (k_x, k_y,
//! k_xy)` prescribed on its four edges (in-plane components only; `w` is
//! free but at one corner):
//!
//! ```text
//! u = eps_x x + gamma_xy y / 2 + z' (k_x x + k_xy y / 2)
//! v = gamma_xy x / 2 + eps_y y + z' (k_y y + k_xy x / 2)      z' = z - z_mid
//! ```
//!
//! The 3D solution is then the CLT state itself (uniform in x and y,
//! `sigma_zz = tau_xz = tau_yz = 0`, every ply in plane stress), which
//! quadratic hexahedra represent exactly, so the model's generalised forces
//! `F_i = sum f_int . phi_i` (the work-conjugates of the six unit fields
//! `phi_i`) divided by the area are the columns of `[A B; B D]`.
//!
//! The reference is CLT written from its textbook formulas (Jones,
//! Mechanics of Composite Materials, 2nd ed., 1999, eqs. 2.84-2.87 for
//! `Q_ij`, 2.93-2.95 for `Q̄_ij` with `m = cos theta, n = sin theta`,
//! 4.28 for `A, B, D`), independently of the builder's Voigt rotation:
//! material T300/5208 (Tsai & Hahn 1980: E1 = 181 GPa, E2 = 10.3 GPa,
//! G12 = 7.17 GPa, nu12 = 0.28), plies 0.125 mm, a 20 x 20 mm plate.

#[path = "support/clt.rs"]
mod clt;
#[path = "support/lekhnitskii.rs"]
mod lekhnitskii;
use clt::*;
use junta::input::scene::{build_model, AnalysisSpec, SceneFile};
use junta::Simulation;
use junta_core::{Model, StepInfo};

/// The laminate of scene `text`, built.
fn built(text: &str) -> Model {
    let sf = SceneFile::parse(std::path::Path::new("laminate.toml"), text.to_string()).unwrap();
    build_model(&sf).unwrap()
}

/// The built laminate of `text`, the `z` of its mid-plane, and the run of
/// unit field `j` on its edges.
fn unit_case(text: &str, j: usize) -> (Model, f64, junta::RunResults) {
    let m = built(text);
    let (zm, r) = unit_case_of(&m, j);
    (m, zm, r)
}

/// The `[A B; B D]` of the laminate of scene `text`.
fn measured_abd(text: &str) -> [[f64; 6]; 6] {
    abd_of(&built(text))
}

fn scene(layup: &str, element: &str, extra: &str) -> String {
    format!(
        r#"
{T300}

[laws.glue]
type = "linear_penalty"
d = 1.0e6

[laminate]
base = {{ type = "rectangle", size = [{L}, {L}], divisions = [2, 2] }}
element = "{element}"
material = "t300"
ply_thickness = {T}
layup = "{layup}"
interface_law = "glue"
interfaces = "all"
{extra}
"#
    )
}

fn check(code: &str, angles: &[f64], element: &str, extra: &str) -> [[f64; 6]; 6] {
    let measured = measured_abd(&scene(code, element, extra));
    let reference = clt_abd(angles);
    let [ea, eb, ed] = compare(angles, &measured, &reference);
    eprintln!("{code} ({element}): A {ea:.2e}, B {eb:.2e}, D {ed:.2e}");
    // the issue asks 1 %; the CLT field is exact in H20, so the test holds 1e-6
    for (what, e) in [("A", ea), ("B", eb), ("D", ed)] {
        assert!(e < 1e-6, "{code}: {what} differs from CLT by {e:.3e}");
    }
    measured
}

#[test]
fn cross_ply_symmetric_has_no_coupling() {
    let m = check("[0/90]s", &[0.0, 90.0, 90.0, 0.0], "h20", "");
    // A16 = D16 = 0 and B = 0 to round-off, D11 > D22 (0 plies outside)
    assert!(m[3][3] > 3.0 * m[4][4]);
}

#[test]
fn angle_ply_has_bend_twist_coupling() {
    let m = check("[±45]s", &[45.0, -45.0, -45.0, 45.0], "h20", "");
    // D16 = D26 != 0 (the +45 plies are outside), A16 = 0
    assert!(m[3][5] > 0.05 * m[3][3], "D16 {} D11 {}", m[3][5], m[3][3]);
    assert!(m[0][2].abs() < 1e-8 * m[0][0]);
}

#[test]
fn quasi_isotropic() {
    let angles = [0.0, 45.0, -45.0, 90.0, 90.0, -45.0, 45.0, 0.0];
    let m = check("[0/±45/90]s", &angles, "h20", "");
    // quasi-isotropic in-plane: A11 = A22, A66 = (A11 - A12) / 2
    assert!((m[0][0] - m[1][1]).abs() < 1e-6 * m[0][0]);
    assert!((m[2][2] - 0.5 * (m[0][0] - m[0][1])).abs() < 1e-6 * m[0][0]);
}

#[test]
fn unsymmetric_cross_ply_couples_stretching_and_bending() {
    let m = check("[0/90]", &[0.0, 90.0], "h20", "");
    // the 0 ply at the bottom: B11 = (Q22 - Q11) h^2 / 8 < 0, B22 = -B11
    assert!(m[0][3] < 0.0 && (m[0][3] + m[1][4]).abs() < 1e-6 * m[0][3].abs());
}

/// `[0_2/90]s`: six plies in three blocks; `interfaces = "all"` puts one
/// between every pair, the default (`"blocks"`) only between blocks; the
/// documented sets exist.
#[test]
fn merged_blocks_equal_separate_plies_and_the_blocks_have_their_sets() {
    let merged = scene("[0_2/90]s", "h20", "");
    let sf = SceneFile::parse(std::path::Path::new("m.toml"), merged.clone()).unwrap();
    let mesh = junta::input::scene::build_mesh(&sf).unwrap();
    // 6 plies, blocks 0 0 | 90 90 | 0 0, interfaces between all 5 pairs
    for s in ["ply_1", "ply_6", "block_1", "block_3", "interface_5_6"] {
        assert!(mesh.element_sets.contains_key(s), "{s}");
    }
    assert!(!mesh.element_sets.contains_key("block_4"));
    for s in ["top", "bottom", "x0", "y1", "interface_3_4.top"] {
        assert!(mesh.node_sets.contains_key(s), "{s}");
    }
    let interfaces = mesh
        .blocks
        .iter()
        .filter(|b| b.shape.is_interface())
        .count();
    assert_eq!(interfaces, 5);
    let blocks_only = scene("[0_2/90]s", "h20", "").replace("interfaces = \"all\"", "");
    let sf = SceneFile::parse(std::path::Path::new("b.toml"), blocks_only).unwrap();
    let mesh = junta::input::scene::build_mesh(&sf).unwrap();
    let names: Vec<&str> = mesh
        .blocks
        .iter()
        .filter(|b| b.shape.is_interface())
        .map(|b| b.name.as_str())
        .collect();
    assert_eq!(names, ["interface_2_3", "interface_4_5"]);
}
/// H8I (incompatible modes), H27 and the reduced H20R hold the bending
/// field too; plain H8 locks in shear (D several times too stiff on plies
/// 80 times thinner than wide: see docs/laminates.md).
#[test]
fn other_bending_elements() {
    let angles = [0.0, 45.0, -45.0, 90.0, 90.0, -45.0, 45.0, 0.0];
    for el in ["h8i", "h27", "h20r"] {
        check("[0/±45/90]s", &angles, el, "");
    }
}

/// T300/5208's expansion along and across the fibre (Tsai & Hahn 1980).
const ALPHA: [f64; 2] = [0.02e-6, 22.5e-6];

/// CLT's free thermal response `[eps0; kappa] = [A B; B D]^-1 [N_T; M_T]`
/// of plies `angles` cooled by `dt` (Jones 1999, eqs. 4.94-4.96; the
/// expansion of a ply at theta: `alpha_x = a1 m^2 + a2 n^2`, `alpha_y = a1
/// n^2 + a2 m^2`, `alpha_xy = 2 (a1 - a2) m n`, engineering shear).
fn clt_thermal(angles: &[f64], dt: f64) -> [f64; 6] {
    let h = T * angles.len() as f64;
    let mut load = [0.0; 6];
    for (k, &theta) in angles.iter().enumerate() {
        let (z0, z1) = (-h / 2.0 + k as f64 * T, -h / 2.0 + (k + 1) as f64 * T);
        let (n, m) = theta.to_radians().sin_cos();
        let [a1, a2] = ALPHA;
        let alpha = [
            a1 * m * m + a2 * n * n,
            a1 * n * n + a2 * m * m,
            2.0 * (a1 - a2) * m * n,
        ];
        let q = q_bar(theta);
        for i in 0..3 {
            let qa: f64 = (0..3).map(|j| q[i][j] * alpha[j] * dt).sum();
            load[i] += qa * (z1 - z0);
            load[i + 3] += qa * (z1 * z1 - z0 * z0) / 2.0;
        }
    }
    let abd = clt_abd(angles);
    let m = nalgebra::Matrix6::from_fn(|i, j| abd[i][j]);
    let x = m.lu().solve(&nalgebra::Vector6::from(load)).unwrap();
    [x[0], x[1], x[2], x[3], x[4], x[5]]
}

/// `examples/laminates/cross_ply_cure.toml`: the [0/90] plate cooled by
/// 150 K warps into CLT's saddle, `kappa_x = -kappa_y`, measured from the
/// three probes on the bottom face of its centre line (0.04 % on 8 x 8
/// H20; the free edges' boundary layer is the rest).
#[test]
fn cross_ply_cure_saddle_matches_clt() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/laminates/cross_ply_cure.toml");
    let sim = Simulation::from_file(&path).unwrap();
    let mesh = sim.model().mesh.clone();
    let r = sim.run(&junta::RunSettings::in_memory(), &mut []).unwrap();
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    // the build's cost is reported, inside the reading time
    let t = r.summary.timings.expect("a run reports its timings");
    let build = t.build.expect("a scene reports its build");
    assert!(build > 0.0 && build <= t.read, "{t:?}");
    assert!(t.build_peak_bytes.is_some_and(|b| b > 1_000_000), "{t:?}");
    let u = r.frame.unwrap().displacement;
    let w = |x: f64, y: f64| {
        let n = mesh
            .nodes
            .iter()
            .position(|p| (p[0] - x).abs() < 1e-9 && (p[1] - y).abs() < 1e-9 && p[2].abs() < 1e-9)
            .unwrap();
        u[3 * n + 2]
    };
    let kx = -(w(2.5, 5.0) - 2.0 * w(5.0, 5.0) + w(7.5, 5.0)) / 2.5f64.powi(2);
    let ky = -(w(5.0, 2.5) - 2.0 * w(5.0, 5.0) + w(5.0, 7.5)) / 2.5f64.powi(2);
    let clt = clt_thermal(&[0.0, 90.0], -150.0);
    eprintln!(
        "kappa_x {kx:.6e} ky {ky:.6e}, CLT {:.6e} {:.6e}",
        clt[3], clt[4]
    );
    assert!(clt[3] < 0.0 && (clt[3] + clt[4]).abs() < 1e-12);
    assert!(
        (kx - clt[3]).abs() < 2e-3 * clt[3].abs(),
        "{kx} vs {}",
        clt[3]
    );
    assert!(
        (ky - clt[4]).abs() < 2e-3 * clt[4].abs(),
        "{ky} vs {}",
        clt[4]
    );
}

/// Ply stresses in the material axes: under the unit stretch `eps_x = 1`
/// every ply of angle theta has the strain `eps_1 = m^2`, `eps_2 = n^2`,
/// `gamma_12 = -2 m n` in its axes (the strain transformation, Jones 1999
/// eq. 2.80), so `sigma_1 = Q11 m^2 + Q12 n^2`, `sigma_2 = Q12 m^2 + Q22
/// n^2`, `tau_12 = -2 Q66 m n`, and no out-of-plane stress.
#[test]
fn ply_stresses_in_material_axes() {
    let angles: [f64; 8] = [0.0, 45.0, -45.0, 90.0, 90.0, -45.0, 45.0, 0.0];
    let (m, _, r) = unit_case(&scene("[0/±45/90]s", "h20", ""), 0);
    let solid = r.frame.unwrap().solid;
    let nu21 = NU12 * E2 / E1;
    let d = 1.0 - NU12 * nu21;
    let (q11, q22, q12) = (E1 / d, E2 / d, NU12 * E2 / d);
    let z0 = m.mesh.nodes.iter().fold(f64::MAX, |a, p| a.min(p[2]));
    let points = solid.block.len();
    assert!(points > 0);
    let mut worst = 0.0f64;
    for p in 0..points {
        let ply = ((solid.position[3 * p + 2] - z0) / T).floor() as usize;
        let (n, mm) = angles[ply].to_radians().sin_cos();
        let expected = [
            q11 * mm * mm + q12 * n * n,
            q12 * mm * mm + q22 * n * n,
            0.0,
            -2.0 * G12 * mm * n,
            0.0,
            0.0,
        ];
        for k in 0..6 {
            worst = worst.max((solid.material_stress[6 * p + k] - expected[k]).abs() / q11);
        }
    }
    assert!(
        worst < 1e-8,
        "ply stress differs from CLT by {worst:.3e} of Q11"
    );
}

/// T300/5208's strengths (Tsai & Hahn 1980, MPa).
const STRENGTHS: &str = "Xt = 1500.0\nXc = 1500.0\nYt = 40.0\nYc = 246.0\nS12 = 68.0\nS23 = 123.0";

/// First-ply failure of `[0/90]s` stretched by `eps_x` (the CLT state, no
/// free edge): the 90 plies fail first, in matrix tension, at `sigma_2 =
/// Q22 eps_x = Yt` (their axis 2 is x), so the strength ratio of the unit
/// field is `Yt / Q22` for maximum stress and Hashin alike (Hashin's
/// matrix tension `(s22 / Yt)^2 = 1` with no shear); Tsai-Wu's is the
/// positive root of its quadratic in the 90 ply's `(sigma_1, sigma_2) =
/// (Q12, Q22) R`, written here from Tsai & Wu 1971 with `F12 = -1/2
/// sqrt(F11 F22)`.
#[test]
fn first_ply_failure_of_a_cross_ply_matches_clt() {
    let crit = format!(
        "[[ply_failure]]\ntype = \"ply_max_stress\"\n{STRENGTHS}\n[[ply_failure]]\ntype = \"hashin\"\n{STRENGTHS}\n[[ply_failure]]\ntype = \"tsai_wu\"\n{STRENGTHS}"
    );
    let text = scene("[0/90]s", "h20", &crit);
    let (m, _, r) = unit_case(&text, 0);
    let u = r.frame.unwrap().displacement;
    let sf = SceneFile::parse(std::path::Path::new("laminate.toml"), text).unwrap();
    let uses = junta::post::ply_failure::from_scene(&sf, &m).unwrap();
    let state = m.initial_state();
    let res =
        junta::post::ply_failure::evaluate(&m, &u, &state, StepInfo::default(), &uses).unwrap();
    let nu21 = NU12 * E2 / E1;
    let d = 1.0 - NU12 * nu21;
    let (q22, q12) = (E2 / d, NU12 * E2 / d);
    let (xt, xc, yt, yc) = (1500.0f64, 1500.0f64, 40.0f64, 246.0f64);
    let (f1, f2) = (1.0 / xt - 1.0 / xc, 1.0 / yt - 1.0 / yc);
    let (f11, f22) = (1.0 / (xt * xc), 1.0 / (yt * yc));
    let f12 = -0.5 * (f11 * f22).sqrt();
    let (s1, s2) = (q12, q22);
    let a = f11 * s1 * s1 + f22 * s2 * s2 + 2.0 * f12 * s1 * s2;
    let b = f1 * s1 + f2 * s2;
    let tsai_wu = (-b + (b * b + 4.0 * a).sqrt()) / (2.0 * a);
    for (name, expected) in [
        ("ply_max_stress", yt / q22),
        ("hashin", yt / q22),
        ("tsai_wu", tsai_wu),
    ] {
        let r = res.iter().find(|r| r.name == name).unwrap();
        let w = r.weakest.as_ref().unwrap();
        eprintln!(
            "{name}: R {:.6e} (CLT {expected:.6e}) in {} {}",
            r.strength_ratio, w.block, w.mode
        );
        assert!(
            (r.strength_ratio - expected).abs() < 1e-6 * expected,
            "{name}: {} vs {expected}",
            r.strength_ratio
        );
        assert!(
            w.block == "ply_2" || w.block == "ply_3",
            "{name}: {}",
            w.block
        );
        if name != "tsai_wu" {
            assert_eq!(w.mode, "matrix_tension");
        }
        // the unit field is far past failure: index > 1 everywhere it was evaluated
        assert!(r.max_index > 1.0);
        assert_eq!(
            r.cell_index.len(),
            m.mesh
                .blocks
                .iter()
                .filter(|b| b.shape.is_solid())
                .map(|b| b.len())
                .sum::<usize>()
        );
    }
}

/// `examples/laminates/cross_ply_tension.toml`: the `[0/90]s` coupon
/// stretched by 1e-3. Away from its edges the state is CLT's (`N_y = 0`:
/// `eps_y = -2 Q12 / (Q11 + Q22) eps_x`), so the Hashin index of a 90 ply
/// cell at the centre is `(sigma_2 / Yt)^2` with `sigma_2 = Q22 eps_x +
/// Q12 eps_y`; the free edges only raise the stress, so the model's
/// first-ply-failure factor is at most CLT's `Yt / sigma_2`.
#[test]
fn cross_ply_coupon_first_ply_failure() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/laminates/cross_ply_tension.toml");
    let sf = SceneFile::read(&path).unwrap();
    let built = build_model(&sf).unwrap();
    let sim = Simulation::from_file(&path).unwrap();
    let r = sim.run(&junta::RunSettings::in_memory(), &mut []).unwrap();
    let u = r.frame.unwrap().displacement;
    let uses = junta::post::ply_failure::from_scene(&sf, &built).unwrap();
    let state = built.initial_state();
    let res =
        junta::post::ply_failure::evaluate(&built, &u, &state, StepInfo::default(), &uses).unwrap();
    let nu21 = NU12 * E2 / E1;
    let d = 1.0 - NU12 * nu21;
    let (q11, q22, q12) = (E1 / d, E2 / d, NU12 * E2 / d);
    let eps_x = 1e-3;
    let eps_y = -2.0 * q12 / (q11 + q22) * eps_x;
    let sigma_2 = q22 * eps_x + q12 * eps_y;
    let hashin = res.iter().find(|r| r.name == "hashin").unwrap();
    // the ply_2 cell whose centre is (11.25, 5.625): cells of a box run x fastest
    let mesh = &built.mesh;
    let solid: Vec<usize> = (0..mesh.blocks.len())
        .filter(|&b| mesh.blocks[b].shape.is_solid())
        .collect();
    let ply2 = mesh.blocks.iter().position(|b| b.name == "ply_2").unwrap();
    let offset: usize = solid
        .iter()
        .take_while(|&&b| b != ply2)
        .map(|&b| mesh.blocks[b].len())
        .sum();
    let centre = (0..mesh.blocks[ply2].len())
        .find(|&e| {
            let c = mesh.blocks[ply2].element(e).iter().fold([0.0; 2], |a, &n| {
                [
                    a[0] + mesh.nodes[n][0] / 20.0,
                    a[1] + mesh.nodes[n][1] / 20.0,
                ]
            });
            (c[0] - 11.25).abs() < 1e-6 && (c[1] - 5.625).abs() < 1e-6
        })
        .unwrap();
    let index = hashin.cell_index[offset + centre];
    let clt = (sigma_2 / 40.0).powi(2);
    eprintln!(
        "centre 90 cell: Hashin {index:.6e}, CLT {clt:.6e}; FPF factor {:.4} (CLT {:.4})",
        hashin.strength_ratio,
        40.0 / sigma_2
    );
    assert!((index - clt).abs() < 0.01 * clt, "{index} vs {clt}");
    assert!(hashin.strength_ratio <= 40.0 / sigma_2);
    // the summary carries it
    let s = r
        .summary
        .section("ply_failure")
        .expect("summary.json ply_failure");
    assert_eq!(
        s["hashin"]["first_ply_failure_load_factor"].as_f64(),
        Some(hashin.strength_ratio)
    );
    // the same coupon as an incremental run: the indices of its last state, no load factor
    let text = std::fs::read_to_string(&path).unwrap().replacen(
        "\n[[ply_failure]]\ntype = \"hashin\"",
        "\n[analysis]\ntype = \"static\"\n\n[[ply_failure]]\ntype = \"hashin\"",
        1,
    );
    let r = Simulation::from_scene_text(&text, &path)
        .unwrap()
        .run(&junta::RunSettings::in_memory(), &mut [])
        .unwrap();
    let s = r
        .summary
        .section("ply_failure")
        .expect("an incremental run's ply_failure");
    let max = s["hashin"]["max_index"].as_f64().unwrap();
    assert!(
        (max - hashin.max_index).abs() < 1e-9 * hashin.max_index,
        "{max} vs {}",
        hashin.max_index
    );
    assert!(s["hashin"].get("first_ply_failure_load_factor").is_none());
}

/// The unsymmetric `[0/45/-45/90]` plate of the parity tests on `base`
/// (a `[laminate.base]` inline table) with `element`: 20 x 5 mm, an
/// interface between each pair of plies, clamped at `x0`, a force on every
/// node of `x1`.
fn plate_scene(base: &str, element: &str) -> String {
    format!(
        r#"
{T300}
[laws.glue]
type = "linear_penalty"
d = 1.0e5
[laminate]
base = {base}
element = "{element}"
material = "t300"
ply_thickness = {T}
layup = "[0/45/-45/90]"
interface_law = "glue"
[[boundary]]
set = "x0"
fixed = "all"
[[load]]
set = "x1"
force = [0.0, 0.0, -0.01]
[solver]
type = "cholesky"
"#
    )
}

/// The Abaqus/CalculiX deck of a built laminate written out ply by ply:
/// C3D8I layers with an `*ORIENTATION` each, COH3D8 between them with an
/// `*ELASTIC, TYPE=TRACTION` material, the edge `x0` clamped and a force on
/// every node of `x1`. `angles` are the plies' (bottom to top).
fn ply_by_ply_deck(m: &Model, angles: &[f64], k: f64, force: f64) -> String {
    let mut d = String::from("*HEADING\nthe built laminate, ply by ply\n*NODE\n");
    for (i, p) in m.mesh.nodes.iter().enumerate() {
        d += &format!("{}, {:.17e}, {:.17e}, {:.17e}\n", i + 1, p[0], p[1], p[2]);
    }
    let mut label = 1;
    for b in &m.mesh.blocks {
        let (kind, set) = if b.shape.is_interface() {
            ("COH3D8", b.name.to_uppercase())
        } else {
            ("C3D8I", b.name.to_uppercase())
        };
        d += &format!("*ELEMENT, TYPE={kind}, ELSET={set}\n");
        for e in 0..b.len() {
            let nodes: Vec<String> = b.element(e).iter().map(|n| (n + 1).to_string()).collect();
            d += &format!("{label}, {}\n", nodes.join(", "));
            label += 1;
        }
    }
    for (name, set) in [("X0", "x0"), ("X1", "x1")] {
        d += &format!("*NSET, NSET={name}\n");
        for n in &m.mesh.node_sets[set] {
            d += &format!("{}\n", n + 1);
        }
    }
    d += &format!(
        "*MATERIAL, NAME=T300\n*ELASTIC, TYPE=ENGINEERING CONSTANTS\n{E1}, {E2}, {E2}, {NU12}, {NU12}, 0.4, {G12}, {G12}\n3.68e3\n*MATERIAL, NAME=GLUE\n*ELASTIC, TYPE=TRACTION\n{k}, {k}, {k}\n"
    );
    for (i, theta) in angles.iter().enumerate() {
        let (s, c) = theta.to_radians().sin_cos();
        d += &format!(
            "*ORIENTATION, NAME=OR{n}\n{c:.17e}, {s:.17e}, 0.0, {:.17e}, {c:.17e}, 0.0\n*SOLID SECTION, ELSET=PLY_{n}, MATERIAL=T300, ORIENTATION=OR{n}\n",
            -s,
            n = i + 1
        );
    }
    for b in m.mesh.blocks.iter().filter(|b| b.shape.is_interface()) {
        d += &format!(
            "*COHESIVE SECTION, ELSET={}, MATERIAL=GLUE, RESPONSE=TRACTION SEPARATION\n1.0\n",
            b.name.to_uppercase()
        );
    }
    d += &format!("*BOUNDARY\nX0, 1, 3\n*STEP\n*STATIC\n*CLOAD\nX1, 3, {force}\n*END STEP\n");
    d
}

/// The same laminate two ways: `[laminate]` (the builder's plies, rotated
/// materials and inserted INTER8) and the deck written ply by ply from its
/// mesh (C3D8I with `*ORIENTATION`, COH3D8 with `*ELASTIC, TYPE=TRACTION`)
/// give the same displacements to round-off: an unsymmetric
/// `[0/45/-45/90]` plate clamped at x0 under an end load (bending, twist
/// and the stretching coupling all loaded).
#[test]
fn the_laminate_as_a_scene_and_as_a_ply_by_ply_deck() {
    let text = plate_scene(
        "{ type = \"rectangle\", size = [20.0, 5.0], divisions = [8, 2] }",
        "h8i",
    );
    let dir = tempfile::tempdir().unwrap();
    let scene_path = dir.path().join("plate.toml");
    std::fs::write(&scene_path, &text).unwrap();
    let sf = SceneFile::read(&scene_path).unwrap();
    let built = build_model(&sf).unwrap();
    assert_eq!(
        built
            .mesh
            .blocks
            .iter()
            .filter(|b| b.shape.is_interface())
            .count(),
        3
    );
    let deck_path = dir.path().join("plate.inp");
    std::fs::write(
        &deck_path,
        ply_by_ply_deck(&built, &[0.0, 45.0, -45.0, 90.0], 1.0e5, -0.01),
    )
    .unwrap();
    let run = |p: &std::path::Path| {
        let r = Simulation::from_file(p)
            .unwrap()
            .run(&junta::RunSettings::in_memory(), &mut [])
            .unwrap();
        r.frame.unwrap().displacement
    };
    let (us, ud) = (run(&scene_path), run(&deck_path));
    assert_eq!(us.len(), ud.len());
    let scale = us.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let diff = us
        .iter()
        .zip(&ud)
        .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
    eprintln!(
        "max |u| {scale:.6e}, scene - deck {:.3e} relative",
        diff / scale
    );
    assert!(scale > 1e-3, "the plate bends: {scale}");
    assert!(
        diff < 1e-8 * scale,
        "scene and deck differ by {:.3e} of max |u|",
        diff / scale
    );
}

/// `k = sqrt(b_rr / b_tt)` of a 0-degree ply curved about its axis 2 (1
/// the hoop, 3 the radius) in plane strain along 2: the compliances `b_ij
/// = S_ij - S_i2 S_j2 / S_22` of T300/5208 (nu23 = 0.4).
fn hoop_ply_k() -> f64 {
    lekhnitskii::hoop_ply_k(E1, E2, NU12, 0.4)
}

/// A quarter of a ring of 0-degree plies (fibres around the hoop) under an
/// internal pressure, axially held (plane strain): the cylindrically
/// orthotropic thick tube (Lekhnitskii, Anisotropic Plates, 1968, sec. 30;
/// derived here). With the stress function `F`, `sigma_r = F / r`,
/// `sigma_theta = F'`, and the plane-strain compliances `b_ij = S_ij -
/// S_iz S_jz / S_zz`, compatibility `d(r eps_theta)/dr = eps_r` gives `r^2
/// F'' + r F' - k^2 F = 0`, `k = sqrt(b_rr / b_tt)`, so
///
/// ```text
/// sigma_r = A r^(k-1) + B r^(-k-1),   sigma_theta = k (A r^(k-1) - B r^(-k-1)),
/// ```
///
/// `A`, `B` from `sigma_r(a) = -p`, `sigma_r(b) = 0` (k = 1 is Lamé's
/// tube). In the ply axes the hoop is 1, the axis 2 and the radius 3.
#[test]
fn ring_of_hoop_plies_matches_the_anisotropic_tube() {
    let (a, t, n, p) = (10.0, 0.5, 8usize, 1.0);
    let base = format!(
        "{{ type = \"ring\", inner_radius = {a}, width = 1.0, sweep = 90.0, divisions = [24, 1] }}"
    );
    let text = hoop_ring_scene(&base, ["end0", "end1", "side0", "side1"], t, n, p);
    let sim = Simulation::from_scene_text(&text, "ring.toml").unwrap();
    assert_eq!(
        sim.model()
            .mesh
            .blocks
            .iter()
            .filter(|b| b.shape.is_interface())
            .count(),
        n - 1
    );
    let r = sim.run(&junta::RunSettings::in_memory(), &mut []).unwrap();
    let (err_r, err_t, k) = tube_errors(&r.frame.unwrap().solid, a, a + n as f64 * t, p);
    eprintln!(
        "k = {k:.4}; largest error: sigma_r {err_r:.3e} of p, sigma_theta {err_t:.3e} of its peak"
    );
    assert!(k > 3.0, "strongly anisotropic: k = {k}");
    assert!(
        err_r < 1e-2 && err_t < 1e-2,
        "sigma_r {err_r:.3e}, sigma_theta {err_t:.3e}"
    );
}

/// A `[0/90]s` cross-section on a `line` base (cpe8 plies in plane
/// strain, glued by stiff line interfaces) stretched along `x`: with `eps_z
/// = 0` and `sigma_y = 0` through the thickness every ply carries `sigma_x
/// = E~ eps`, with `E~ = 1 / (S_xx - S_xz^2 / S_zz)` of its compliance in
/// `(x, z)`: `E1 / (1 - nu12^2 E2 / E1)` for the 0-degree ply (fibre along
/// `x`) and `1 / (1 / E2 - nu12^2 / E1)` for the 90-degree ply (fibre
/// along `z`, out of the plane). The reaction against that closed form,
/// and the sets of the line base.
#[test]
fn cross_section_line_base_stretches_as_its_plane_strain_plies() {
    let (length, eps) = (10.0, 1e-3);
    let text = format!(
        r#"
[model]
thickness = 2.0
{T300}
[laws.glue]
type = "linear_penalty"
d = 1.0e8
[laminate]
base = {{ type = "line", length = {length}, divisions = [10], origin = [1.0, -0.5] }}
element = "cpe8"
material = "t300"
ply_thickness = {T}
layup = "[0/90]s"
interface_law = "glue"
[[node_set]]
name = "pin"
within = [[0.99, -0.51, -1.0], [1.01, -0.49, 1.0]]
[[boundary]]
set = "x0"
fixed = ["x"]
[[boundary]]
set = "pin"
fixed = ["y"]
[[boundary]]
set = "x1"
displacement = {{ x = {u} }}
"#,
        u = eps * length
    );
    let sim = Simulation::from_scene_text(&text, "line.toml").unwrap();
    let mesh = &sim.model().mesh;
    // the sets of a line base: the ends every ply, the bottom and top faces
    let h = 4.0 * T;
    for (set, axis, at) in [
        ("x0", 0, 1.0),
        ("x1", 0, 1.0 + length),
        ("bottom", 1, -0.5),
        ("top", 1, -0.5 + h),
    ] {
        let nodes = &mesh.node_sets[set];
        assert!(
            !nodes.is_empty()
                && nodes
                    .iter()
                    .all(|&i| (mesh.nodes[i][axis] - at).abs() < 1e-9),
            "{set}"
        );
    }
    // blocks 0 / 90 90 / 0: two interfaces
    assert_eq!(
        mesh.element_sets
            .keys()
            .filter(|k| k.starts_with("interface_"))
            .count(),
        2
    );
    let r = sim.run(&junta::RunSettings::in_memory(), &mut []).unwrap();
    let reaction = r.summary.section("reactions").unwrap()["x1"][0]
        .as_f64()
        .unwrap();
    let e0 = E1 / (1.0 - NU12 * NU12 * E2 / E1);
    let e90 = 1.0 / (1.0 / E2 - NU12 * NU12 / E1);
    let expected = 2.0 * (2.0 * T) * (e0 + e90) * eps;
    eprintln!(
        "[0/90]s in plane strain: reaction {reaction:.6e}, closed form {expected:.6e} ({:+.2e})",
        reaction / expected - 1.0
    );
    assert!(
        (reaction / expected - 1.0).abs() < 1e-6,
        "{reaction} vs {expected}"
    );
}

/// The same quarter ring as a cross-section: `cpe8` plies in plane strain
/// on a `ring` base of the `x`-`y` plane (clockwise from `+x` to `-y`,
/// docs/laminates.md "Cross-sections"), `line_inter6` interfaces between
/// them, against the same anisotropic tube.
#[test]
fn cross_section_ring_of_hoop_plies_matches_the_anisotropic_tube() {
    let (a, t, n, p) = (10.0, 0.5, 8usize, 1.0);
    let base = format!("{{ type = \"ring\", inner_radius = {a}, sweep = 90.0, divisions = [24] }}");
    let text = hoop_ring_scene(&base, ["end0", "end1", "", ""], t, n, p)
        .replace("element = \"h20\"", "element = \"cpe8\"")
        .replace("[[boundary]]\nset = \"\"\nfixed = [\"z\"]\n", "");
    let text = format!("[model]\nthickness = 1.0\n{text}");
    let sim = Simulation::from_scene_text(&text, "ring.toml").unwrap();
    let model = sim.model();
    let lines = model
        .mesh
        .blocks
        .iter()
        .filter(|b| b.shape == junta::core::topology::CellShape::LineInter6)
        .count();
    assert_eq!(lines, n - 1);
    // the sector ends where the docs say: end0 on +x, end1 on -y
    for (set, axis) in [("end0", 1), ("end1", 0)] {
        assert!(
            model.mesh.node_sets[set]
                .iter()
                .all(|&i| model.mesh.nodes[i][axis].abs() < 1e-9),
            "{set}"
        );
    }
    let r = sim.run(&junta::RunSettings::in_memory(), &mut []).unwrap();
    let (err_r, err_t, k) = tube_errors(&r.frame.unwrap().solid, a, a + n as f64 * t, p);
    eprintln!(
        "cross-section: k = {k:.4}; largest error: sigma_r {err_r:.3e} of p, sigma_theta {err_t:.3e} of its peak"
    );
    assert!(
        err_r < 1e-2 && err_t < 1e-2,
        "sigma_r {err_r:.3e}, sigma_theta {err_t:.3e}"
    );
}

/// The scene of the quarter ring of hoop plies of
/// `ring_of_hoop_plies_matches_the_anisotropic_tube` on `base`, with the
/// names of its sets at `theta = 0`, `theta = 90` degrees and its two
/// axial faces.
fn hoop_ring_scene(base: &str, sets: [&str; 4], t: f64, n: usize, p: f64) -> String {
    let [e0, e1, s0, s1] = sets;
    format!(
        r#"
{T300}
[laws.glue]
type = "linear_penalty"
d = 1.0e8
[laminate]
base = {base}
element = "h20"
material = "t300"
ply_thickness = {t}
layup = "[0_{n}]"
interface_law = "glue"
interfaces = "all"
[[boundary]]
set = "{e0}"
fixed = ["y"]
[[boundary]]
set = "{e1}"
fixed = ["x"]
[[boundary]]
set = "{s0}"
fixed = ["z"]
[[boundary]]
set = "{s1}"
fixed = ["z"]
[[load]]
face_set = "bottom"
pressure = {p}
[solver]
type = "cholesky"
"#
    )
}

/// The largest errors of `sigma_r` (of `p`) and `sigma_theta` (of its
/// peak) at the integration points of a ring of hoop plies about `z`,
/// radii `a` to `b`, under the internal pressure `p`, against the
/// cylindrically orthotropic tube (see
/// `ring_of_hoop_plies_matches_the_anisotropic_tube`); and `k`.
fn tube_errors(solid: &junta::SolidPoints, a: f64, b: f64, p: f64) -> (f64, f64, f64) {
    // plane-strain compliances: 1 hoop, 2 axis, 3 radius
    let k = hoop_ply_k();
    // sigma_r(a) = -p, sigma_r(b) = 0
    let m = nalgebra::Matrix2::new(
        a.powf(k - 1.0),
        a.powf(-k - 1.0),
        b.powf(k - 1.0),
        b.powf(-k - 1.0),
    );
    let c = m.lu().solve(&nalgebra::Vector2::new(-p, 0.0)).unwrap();
    let sigma_r = |r: f64| c[0] * r.powf(k - 1.0) + c[1] * r.powf(-k - 1.0);
    let sigma_t = |r: f64| k * (c[0] * r.powf(k - 1.0) - c[1] * r.powf(-k - 1.0));
    let peak_t = sigma_t(a).abs().max(sigma_t(b).abs());
    let (mut err_r, mut err_t) = (0.0f64, 0.0f64);
    for q in 0..solid.block.len() {
        let x = &solid.position[3 * q..3 * q + 3];
        let rad = x[0].hypot(x[1]);
        let s = &solid.material_stress[6 * q..6 * q + 6];
        err_r = err_r.max((s[2] - sigma_r(rad)).abs() / p);
        err_t = err_t.max((s[0] - sigma_t(rad)).abs() / peak_t);
    }
    (err_r, err_t, k)
}

/// A quarter cylinder about `z` (radius `a`, from `theta = 0` at `+x` to
/// 90 degrees, `z` from 0 to `w`) in MSH 4.1 ASCII, `n` Quad8 cells around
/// and one along `z`, every node on the circle, the cells alternately
/// clockwise and counter-clockwise seen from outside; physical curves
/// `cut0` (`theta = 0`), `cut1` (90 degrees), `face0` (`z = 0`), `face1`
/// (`z = w`).
fn quarter_cylinder_msh(a: f64, w: f64, n: usize) -> String {
    // lattice (i around 0..=2n, j along z 0..=2): corner i, j even
    let id = |i: usize, j: usize| j * (2 * n + 1) + i + 1;
    let nn = 3 * (2 * n + 1);
    let mut m = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n5\n1 1 \"cut0\"\n1 2 \"cut1\"\n1 3 \"face0\"\n1 4 \"face1\"\n2 5 \"shell\"\n$EndPhysicalNames\n");
    m += &format!("$Entities\n0 4 1 0\n1 {a} 0 0 {a} 0 {w} 1 1 0\n2 0 {a} 0 0 {a} {w} 1 2 0\n3 0 0 0 {a} {a} 0 1 3 0\n4 0 0 {w} {a} {a} {w} 1 4 0\n1 0 0 0 {a} {a} {w} 1 5 0\n$EndEntities\n");
    m += &format!("$Nodes\n1 {nn} 1 {nn}\n2 1 0 {nn}\n");
    for k in 1..=nn {
        m += &format!("{k}\n");
    }
    for j in 0..3 {
        for i in 0..=2 * n {
            let th = std::f64::consts::FRAC_PI_2 * i as f64 / (2 * n) as f64;
            m += &format!(
                "{:.17e} {:.17e} {:.17e}\n",
                a * th.cos(),
                a * th.sin(),
                0.5 * w * j as f64
            );
        }
    }
    m += &format!(
        "$EndNodes\n$Elements\n5 {} 1 {}\n",
        2 + 2 * n + n,
        2 + 2 * n + n
    );
    let mut tag = 1;
    // cut0 and cut1: one line element along z each
    for (e, i) in [0usize, 2 * n].into_iter().enumerate() {
        m += &format!(
            "1 {} 8 1\n{tag} {} {} {}\n",
            e + 1,
            id(i, 0),
            id(i, 2),
            id(i, 1)
        );
        tag += 1;
    }
    for (e, j) in [(3usize, 0usize), (4, 2)] {
        m += &format!("1 {e} 8 {n}\n");
        for c in 0..n {
            m += &format!(
                "{tag} {} {} {}\n",
                id(2 * c, j),
                id(2 * c + 2, j),
                id(2 * c + 1, j)
            );
            tag += 1;
        }
    }
    m += &format!("2 1 16 {n}\n");
    for c in 0..n {
        let (i0, i1) = (2 * c, 2 * c + 2);
        let q = [
            id(i0, 0),
            id(i1, 0),
            id(i1, 2),
            id(i0, 2),
            id(i0 + 1, 0),
            id(i1, 1),
            id(i0 + 1, 2),
            id(i0, 1),
        ];
        let q = if c % 2 == 1 {
            [q[0], q[3], q[2], q[1], q[7], q[6], q[5], q[4]]
        } else {
            q
        };
        let q: Vec<String> = q.iter().map(|v| v.to_string()).collect();
        m += &format!("{tag} {}\n", q.join(" "));
        tag += 1;
    }
    m + "$EndElements\n"
}

/// The quarter ring of hoop plies extruded from a curved Gmsh surface (a
/// quarter cylinder of Quad8, every node on the circle), plies outward
/// (`normal_away_from` a point of the axis), fibres around the axis
/// (`transverse_direction` the axis): the extrusion along the averaged
/// normals puts every node where the ring generator does, so the two
/// models are the same mesh, and their material frames differ only by the
/// interpolation of the normal (the field's; the ring's is exactly radial).
/// The displacements must agree to 1e-5 of max |u|, the stresses match
/// the anisotropic tube as the ring's do, and the field's normal is radial
/// at points inside the laminate.
#[test]
fn hoop_ring_on_a_curved_gmsh_surface_is_the_ring() {
    let (a, t, n, p) = (10.0, 0.5, 8usize, 1.0);
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("shell.msh"),
        quarter_cylinder_msh(a, 1.0, 24),
    )
    .unwrap();
    let run = |name: &str, text: String| {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        let sim = Simulation::from_file(&path).unwrap();
        let nodes = sim.model().mesh.nodes.clone();
        let r = sim.run(&junta::RunSettings::in_memory(), &mut []).unwrap();
        let frame = r.frame.unwrap();
        (nodes, frame.displacement, frame.solid)
    };
    let ring_base = format!(
        "{{ type = \"ring\", inner_radius = {a}, width = 1.0, sweep = 90.0, divisions = [24, 1] }}"
    );
    let (nr, ur, _) = run(
        "ring.toml",
        hoop_ring_scene(&ring_base, ["end0", "end1", "side0", "side1"], t, n, p),
    );
    let gmsh_base = "{ type = \"gmsh\", file = \"shell.msh\", normal_away_from = [0.0, 0.0, 0.5], transverse_direction = [0.0, 0.0, 1.0] }";
    let (ng, ug, solid) = run(
        "shell.toml",
        hoop_ring_scene(gmsh_base, ["cut0", "cut1", "face0", "face1"], t, n, p),
    );
    let (diff, compared, scale) = largest_difference((&nr, &ur), (&ng, &ug), 1e-4);
    let (err_r, err_t, _) = tube_errors(&solid, a, a + n as f64 * t, p);
    eprintln!("hoop ring on a Gmsh cylinder: {compared} nodes, largest difference from the ring generator's {:.3e} of max |u|; against the tube sigma_r {err_r:.3e} of p, sigma_theta {err_t:.3e} of its peak", diff / scale);
    assert!(diff < 1e-5 * scale, "{:.3e}", diff / scale);
    assert!(
        err_r < 1e-2 && err_t < 1e-2,
        "sigma_r {err_r:.3e}, sigma_theta {err_t:.3e}"
    );
    // the default 0-degree direction, x, is the surface's normal at theta = 0
    let default_fibre = hoop_ring_scene(
        "{ type = \"gmsh\", file = \"shell.msh\", normal_away_from = [0.0, 0.0, 0.5] }",
        ["cut0", "cut1", "face0", "face1"],
        t,
        n,
        p,
    );
    let path = dir.path().join("default.toml");
    std::fs::write(&path, default_fibre).unwrap();
    let e = Simulation::from_file(&path).unwrap_err().to_string();
    assert!(
        e.contains("default.toml")
            && e.contains("laminate.base.fibre_direction")
            && e.contains("transverse_direction"),
        "{e}"
    );
    // a cylinder about z faces neither +z nor -z: the side must be given
    let no_side = hoop_ring_scene(
        "{ type = \"gmsh\", file = \"shell.msh\", transverse_direction = [0.0, 0.0, 1.0] }",
        ["cut0", "cut1", "face0", "face1"],
        t,
        n,
        p,
    );
    std::fs::write(&path, no_side).unwrap();
    let e = Simulation::from_file(&path).unwrap_err().to_string();
    assert!(
        e.contains("shell.msh") && e.contains("normal_away_from"),
        "{e}"
    );
}

/// An L-section of 0-degree plies (fibres around the bend) opened by a
/// pure couple, held in plane strain across its width: the radial stress
/// through the bend against Lekhnitskii's curved beam under pure bending
/// (Anisotropic Plates, 1968, sec. 31; ASTM D6415's basis), derived here
/// with `sigma_r = psi / r`, `sigma_theta = psi'`: compatibility with a
/// rigid rotation of the sections gives `r^2 psi'' + r psi' - k^2 psi = C
/// r / b_tt`, so
///
/// ```text
/// sigma_r = A r^(k-1) + B r^(-k-1) + E,   sigma_theta = k A r^(k-1) - k B r^(-k-1) + E,
/// ```
///
/// with `sigma_r(a) = sigma_r(b) = 0` and the section's moment about the
/// bend's centre `int sigma_theta r dr = -int psi dr = M / w`.
#[test]
fn l_section_radial_stress_matches_lekhnitskii() {
    let (a, t, n, w) = (6.0, 0.25, 8usize, 2.0);
    let b = a + n as f64 * t;
    let text = format!(
        r#"
{T300}
[laminate]
base = {{ type = "l_section", inner_radius = {a}, arms = [20.0, 20.0], width = {w}, divisions = [20, 24, 20, 1] }}
element = "h20"
material = "t300"
ply_thickness = {t}
layup = "[0_{n}]"
[[boundary]]
set = "end0"
fixed = "all"
[[boundary]]
set = "side0"
fixed = ["y"]
[[boundary]]
set = "side1"
fixed = ["y"]
"#
    );
    let sf = SceneFile::parse(std::path::Path::new("l.toml"), text).unwrap();
    let mut model = build_model(&sf).unwrap();
    // a couple on arm b's end (x = -20): f_x = c (z - z_m), no net force
    let zm = 0.5 * (a + b);
    let c = 1.0;
    let mut moment = 0.0;
    for &i in &model.mesh.node_sets["end1"] {
        let z = model.mesh.nodes[i][2];
        model.f_ext[3 * i] = c * (z - zm);
        moment += (z - zm) * c * (z - zm);
    }
    let sim = Simulation::from_model(model, AnalysisSpec::default(), "cholesky").unwrap();
    let r = sim.run(&junta::RunSettings::in_memory(), &mut []).unwrap();
    let solid = r.frame.unwrap().solid;
    let k = hoop_ply_k();
    let solve = |m: f64| lekhnitskii::CurvedBeam::new(a, b, k, m);
    // points of the bend's mid-section (45 degrees, x = z)
    let pts: Vec<usize> = (0..solid.block.len())
        .filter(|&q| {
            let x = &solid.position[3 * q..3 * q + 3];
            (x[2].atan2(x[0]).to_degrees() - 45.0).abs() < 2.0 && x[0] > 0.0 && x[2] > 0.0
        })
        .collect();
    assert!(pts.len() >= 2 * n, "{} points near 45 degrees", pts.len());
    let hoop_inner = pts
        .iter()
        .min_by(|&&p, &&q| {
            let r = |i: usize| solid.position[3 * i].hypot(solid.position[3 * i + 2]);
            r(p).total_cmp(&r(q))
        })
        .map(|&q| solid.material_stress[6 * q])
        .unwrap();
    // the sign of the moment: the hoop stress at the inner radius says which way it bends
    let mut beam = solve(moment / w);
    if beam.sigma_theta(a).signum() != hoop_inner.signum() {
        beam = solve(-moment / w);
    }
    let sigma_r = |r: f64| beam.sigma_r(r);
    let peak = (0..=200)
        .map(|i| sigma_r(a + (b - a) * i as f64 / 200.0))
        .fold(0.0f64, |m, s| if s.abs() > m.abs() { s } else { m });
    let (mut err, mut fe_peak) = (0.0f64, 0.0f64);
    for &q in &pts {
        let x = &solid.position[3 * q..3 * q + 3];
        let rad = x[0].hypot(x[2]);
        let s = solid.material_stress[6 * q + 2];
        err = err.max((s - sigma_r(rad)).abs());
        if s.abs() > fe_peak.abs() {
            fe_peak = s;
        }
    }
    let astm = 3.0 * moment / (2.0 * w * (b - a) * (a * b).sqrt());
    eprintln!(
        "k = {k:.4}; Lekhnitskii peak sigma_r {peak:.5e}, model {fe_peak:.5e} ({:+.2} %); largest difference {:.2} % of the peak; ASTM D6415 3M/(2wt sqrt(r_i r_o)) = {astm:.5e} ({:+.2} %)",
        100.0 * (fe_peak / peak - 1.0),
        100.0 * err / peak.abs(),
        100.0 * (astm / peak.abs() - 1.0)
    );
    assert!(
        (fe_peak - peak).abs() < 0.02 * peak.abs(),
        "peak {fe_peak} vs {peak}"
    );
    assert!(err < 0.03 * peak.abs());
}

/// A full ring is two halves merged at both seams: no node is left
/// doubled (two H20 plies, 16 elements around, 2 along: per corner level
/// 16 x 3 corners and 16 x 3 mid-edges around, 16 x 2 along the axis, on
/// three levels, and 16 x 3 radial mid-edges per ply: 480 nodes), and
/// under internal pressure in plane strain it is Lamé's tube: `sigma_r =
/// p a^2 / (b^2 - a^2) (1 - b^2 / r^2)` at the integration points.
#[test]
fn full_ring_is_closed_and_is_lames_tube() {
    let (a, b, p) = (10.0, 12.0, 1.0);
    let text = format!(
        r#"
[materials.steel]
type = "isotropic"
E = 200.0e3
nu = 0.3
[laminate]
base = {{ type = "ring", inner_radius = {a}, width = 1.0, divisions = [16, 2] }}
element = "h20"
material = "steel"
ply_thickness = 1.0
layup = "[0/0]"
[[node_set]]
name = "axis_x"
within = [[10.0, 0.0, 0.0], [12.0, 0.0, 1.0]]
[[node_set]]
name = "axis_y"
within = [[0.0, 10.0, 0.0], [0.0, 12.0, 1.0]]
[[boundary]]
set = "side0"
fixed = ["z"]
[[boundary]]
set = "side1"
fixed = ["z"]
[[boundary]]
set = "axis_x"
fixed = ["y"]
[[boundary]]
set = "axis_y"
fixed = ["x"]
[[load]]
face_set = "inner"
pressure = {p}
"#
    );
    let sim = Simulation::from_scene_text(&text, "ring.toml").unwrap();
    assert_eq!(
        sim.model().mesh.nodes.len(),
        3 * (16 * 3 + 16 * 3 + 16 * 2) + 2 * 16 * 3
    );
    assert!(!sim.model().mesh.node_sets.contains_key("end0"));
    let r = sim.run(&junta::RunSettings::in_memory(), &mut []).unwrap();
    let solid = r.frame.unwrap().solid;
    let lame = |r: f64| p * a * a / (b * b - a * a) * (1.0 - b * b / (r * r));
    let mut err = 0.0f64;
    for q in 0..solid.block.len() {
        let x = &solid.position[3 * q..3 * q + 3];
        let rad = x[0].hypot(x[1]);
        let (c, s) = (x[0] / rad, x[1] / rad);
        let st = &solid.stress[6 * q..6 * q + 6];
        let sr = c * c * st[0] + s * s * st[1] + 2.0 * c * s * st[3];
        err = err.max((sr - lame(rad)).abs() / p);
    }
    eprintln!("full ring: sigma_r within {err:.3e} of p");
    assert!(err < 0.02, "{err}");
}

/// A plane quadrilateral mesh of the rectangle `[0, lx] x [0, ly]`, `nx x
/// ny` Quad4 (`quadratic`: Quad8) in MSH 4.1 ASCII, with the physical
/// curves `x0` and `x1` (its two short edges) and the physical surface
/// `plate`; the cells alternate counter-clockwise and clockwise to exercise
/// the reorientation.
fn rectangle_msh(lx: f64, ly: f64, nx: usize, ny: usize, quadratic: bool) -> String {
    let p = if quadratic { 2 } else { 1 };
    let (gx, gy) = (p * nx + 1, p * ny + 1);
    // lattice points, without the cell centres of a Quad8 mesh
    let keep = |i: usize, j: usize| !(quadratic && i % 2 == 1 && j % 2 == 1);
    let mut tag_of = std::collections::HashMap::new();
    let mut coords = Vec::new();
    for j in 0..gy {
        for i in 0..gx {
            if keep(i, j) {
                coords.push([
                    lx * i as f64 / (gx - 1) as f64,
                    ly * j as f64 / (gy - 1) as f64,
                ]);
                tag_of.insert((i, j), coords.len());
            }
        }
    }
    let id = |i: usize, j: usize| tag_of[&(i, j)];
    let nn = coords.len();
    let mut m = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n3\n1 1 \"x0\"\n1 2 \"x1\"\n2 3 \"plate\"\n$EndPhysicalNames\n");
    m += &format!("$Entities\n0 2 1 0\n1 0 0 0 0 {ly} 0 1 1 0\n2 {lx} 0 0 {lx} {ly} 0 1 2 0\n1 0 0 0 {lx} {ly} 0 1 3 0\n$EndEntities\n");
    m += &format!("$Nodes\n1 {nn} 1 {nn}\n2 1 0 {nn}\n");
    for k in 1..=nn {
        m += &format!("{k}\n");
    }
    for c in &coords {
        m += &format!("{} {} 0\n", c[0], c[1]);
    }
    let ne = nx * ny + 2 * ny;
    let (line, quad) = if quadratic { (8, 16) } else { (1, 3) };
    m += &format!("$EndNodes\n$Elements\n3 {ne} 1 {ne}\n");
    let mut tag = 1;
    for (entity, i) in [(1, 0), (2, p * nx)] {
        m += &format!("1 {entity} {line} {ny}\n");
        for j in 0..ny {
            let (a, b) = (id(i, p * j), id(i, p * (j + 1)));
            m += &if quadratic {
                format!("{tag} {a} {b} {}\n", id(i, 2 * j + 1))
            } else {
                format!("{tag} {a} {b}\n")
            };
            tag += 1;
        }
    }
    m += &format!("2 1 {quad} {}\n", nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let (i0, j0, i1, j1) = (p * i, p * j, p * (i + 1), p * (j + 1));
            let mut q = vec![id(i0, j0), id(i1, j0), id(i1, j1), id(i0, j1)];
            if quadratic {
                q.extend([
                    id(i0 + 1, j0),
                    id(i1, j0 + 1),
                    id(i0 + 1, j1),
                    id(i0, j0 + 1),
                ]);
            }
            if (i + j) % 2 == 1 {
                q = if quadratic {
                    vec![q[0], q[3], q[2], q[1], q[7], q[6], q[5], q[4]]
                } else {
                    vec![q[0], q[3], q[2], q[1]]
                };
            }
            let q: Vec<String> = q.iter().map(|v| v.to_string()).collect();
            m += &format!("{tag} {}\n", q.join(" "));
            tag += 1;
        }
    }
    m + "$EndElements\n"
}

/// The same laminate three ways: the box base, the Gmsh 2D mesh of the
/// same rectangle extruded (and the ply-by-ply deck, the test above):
/// displacements equal to 1e-9 at every node (matched by position; the
/// two nodes an interface puts at one position matched as a pair, in the
/// order that fits).
#[test]
fn the_laminate_on_a_box_and_on_an_extruded_gmsh_mesh() {
    for (element, quadratic) in [("h8i", false), ("h20", true)] {
        same_on_box_and_gmsh(element, quadratic);
    }
}

fn same_on_box_and_gmsh(element: &str, quadratic: bool) {
    let scene = |base: &str| plate_scene(base, element);
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("plate.msh"),
        rectangle_msh(20.0, 5.0, 8, 2, quadratic),
    )
    .unwrap();
    let box_scene = dir.path().join("box.toml");
    std::fs::write(
        &box_scene,
        scene("{ type = \"rectangle\", size = [20.0, 5.0], divisions = [8, 2] }"),
    )
    .unwrap();
    let gmsh_scene = dir.path().join("gmsh.toml");
    std::fs::write(
        &gmsh_scene,
        scene("{ type = \"gmsh\", file = \"plate.msh\" }"),
    )
    .unwrap();
    let run = |p: &std::path::Path| {
        let sim = Simulation::from_file(p).unwrap();
        let nodes = sim.model().mesh.nodes.clone();
        let r = sim.run(&junta::RunSettings::in_memory(), &mut []).unwrap();
        (nodes, r.frame.unwrap().displacement)
    };
    let (nb, ub) = run(&box_scene);
    let (ng, ug) = run(&gmsh_scene);
    let (diff, compared, scale) = largest_difference((&nb, &ub), (&ng, &ug), 1e-9);
    eprintln!("{element}: box and extruded Gmsh base: {compared} positions compared, largest difference {:.3e} of max |u| {scale:.4e}", diff / scale);
    assert_eq!(compared, nb.len());
    assert!(diff < 1e-9 * scale, "{:.3e}", diff / scale);
}

/// The largest difference between two displacement fields on meshes of
/// the same node positions to `tol` of the mesh's extent (nodes an
/// interface doubles matched either way), the number of nodes compared
/// and max `|u|` of the first.
fn largest_difference(
    (nb, ub): (&[[f64; 3]], &[f64]),
    (ng, ug): (&[[f64; 3]], &[f64]),
    tol: f64,
) -> (f64, usize, f64) {
    assert_eq!(nb.len(), ng.len());
    let key = |p: &[f64; 3]| [p[0], p[1], p[2]].map(|c| (c * 1e6).round() as i64);
    let group = |nodes: &[[f64; 3]]| {
        let mut by: std::collections::BTreeMap<[i64; 3], Vec<usize>> = Default::default();
        for (i, p) in nodes.iter().enumerate() {
            by.entry(key(p)).or_default().push(i);
        }
        by
    };
    let (gb, gg) = (group(nb), group(ng));
    assert_eq!(gb.len(), gg.len());
    let scale = ub.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let d = |i: usize, j: usize| {
        (0..3).fold(0.0f64, |a, c| a.max((ub[3 * i + c] - ug[3 * j + c]).abs()))
    };
    let extent = nb.iter().flatten().fold(0.0f64, |m, c| m.max(c.abs()));
    let far = |p: &[f64; 3], q: &[f64; 3]| (0..3).fold(0.0f64, |m, c| m.max((p[c] - q[c]).abs()));
    let (mut diff, mut compared) = (0.0f64, 0);
    for (k, a) in &gb {
        // the same position in the other mesh, to round-off
        let b = gg
            .get(k)
            .or_else(|| {
                gg.values()
                    .find(|b| far(&nb[a[0]], &ng[b[0]]) < tol * extent)
            })
            .unwrap_or_else(|| panic!("no node of the second mesh at {:?}", nb[a[0]]));
        let worst = match (a.as_slice(), b.as_slice()) {
            ([i], [j]) => d(*i, *j),
            ([i1, i2], [j1, j2]) => d(*i1, *j1)
                .max(d(*i2, *j2))
                .min(d(*i1, *j2).max(d(*i2, *j1))),
            _ => panic!("position {k:?}: {a:?} against {b:?}"),
        };
        compared += a.len();
        diff = diff.max(worst);
    }
    (diff, compared, scale)
}

/// Ply failure through an incremental run. A `[0/90]s` plate stretched
/// along `x` with its `y` sides held (sliding) is in a uniform state that
/// CLT gives exactly, free edges nowhere: every ply has `eps_x = eps`,
/// `eps_y = gamma_xy = 0` and is in plane stress. The 90 plies then carry
/// `(sigma_1, sigma_2) = (Q12, Q22) eps` and fail by maximum stress at
/// `eps = Yt / Q22`, by Tsai-Wu at the root of its quadratic (as in
/// `first_ply_failure_of_a_cross_ply_matches_clt`). The run takes 7
/// increments to twice the maximum-stress failure; the first failure's load
/// factor, interpolated in the inverse strength ratio (exact for a linear
/// response), must be CLT's, and `ply_failure.csv` and the frames carry
/// the indices of every increment, across a restart after the third.
#[test]
fn first_ply_failure_of_an_incremental_run_matches_clt() {
    let nu21 = NU12 * E2 / E1;
    let d = 1.0 - NU12 * nu21;
    let (q22, q12) = (E2 / d, NU12 * E2 / d);
    let (xt, xc, yt, yc) = (1500.0f64, 1500.0f64, 40.0f64, 246.0f64);
    let max_stress = yt / q22;
    let (f1, f2) = (1.0 / xt - 1.0 / xc, 1.0 / yt - 1.0 / yc);
    let (f11, f22) = (1.0 / (xt * xc), 1.0 / (yt * yc));
    let f12 = -0.5 * (f11 * f22).sqrt();
    let a = f11 * q12 * q12 + f22 * q22 * q22 + 2.0 * f12 * q12 * q22;
    let b = f1 * q12 + f2 * q22;
    let tsai_wu = (-b + (b * b + 4.0 * a).sqrt()) / (2.0 * a);
    let length = 4.0;
    let stretch = 1e-3; // the load factor's unit: eps = 1e-3 lambda
    let end = 2.0 * max_stress / stretch;
    let text = format!(
        r#"
{T300}
[laminate]
base = {{ type = "rectangle", size = [{length}, {length}], divisions = [2, 2] }}
element = "h20"
material = "t300"
ply_thickness = {T}
layup = "[0/90]s"
[[boundary]]
set = "x0"
fixed = ["x"]
[[boundary]]
set = "x1"
displacement = {{ x = {dx} }}
[[boundary]]
set = "y0"
fixed = ["y"]
[[boundary]]
set = "y1"
fixed = ["y"]
[[boundary]]
set = "bottom"
fixed = ["z"]
[analysis]
type = "static"
steps = [{end}]
[analysis.newton]
initial_increment = {inc}
max_increment = {inc}
[[ply_failure]]
type = "ply_max_stress"
{STRENGTHS}
[[ply_failure]]
type = "tsai_wu"
{STRENGTHS}
"#,
        dx = stretch * length,
        inc = 1.0 / 7.0,
    );
    let dir = std::env::temp_dir().join(format!("junta_ply_history_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let input = dir.join("plate.toml");
    std::fs::write(&input, &text).unwrap();
    // three increments (before the failure), then a restart to the end:
    // the course of the criteria crosses the restart
    let first = junta::RunSettings {
        max_increments: Some(3),
        ..junta::RunSettings::into_dir(&dir)
    };
    Simulation::from_file(&input)
        .unwrap()
        .run(&first, &mut [])
        .unwrap();
    let restart = junta::run::simulation::read_checkpoint(&dir, false)
        .unwrap()
        .unwrap();
    let r = junta::run::simulation::restart(
        &dir,
        restart,
        &junta::RunSettings::into_dir(&dir),
        &mut [],
    )
    .unwrap();
    let s = r.summary.section("ply_failure").expect("ply_failure");
    for (name, expected) in [("ply_max_stress", max_stress), ("tsai_wu", tsai_wu)] {
        let f = &s[name]["first_failure"];
        let strain = f["load_factor"].as_f64().unwrap() * stretch;
        eprintln!(
            "{name}: first failure at eps {strain:.6e} (CLT {expected:.6e}), increment {}",
            f["increment"]
        );
        assert!(
            (strain - expected).abs() < 1e-6 * expected,
            "{name}: {strain} vs {expected}"
        );
        assert_eq!(f["interpolated"].as_bool(), Some(true));
        let block = f["weakest"]["block"].as_str().unwrap();
        assert!(block == "ply_2" || block == "ply_3", "{block}");
        // 7 increments to twice the failure: it fails in the 4th
        assert_eq!(f["increment"].as_u64(), Some(4));
    }
    // one line per increment; the maximum-stress index grows with the load
    let csv = std::fs::read_to_string(dir.join("ply_failure.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(
        lines[0],
        "increment,step,load_factor,ply_max_stress_max_index,ply_max_stress_strength_ratio,tsai_wu_max_index,tsai_wu_strength_ratio"
    );
    assert_eq!(lines.len(), 8);
    let last: Vec<f64> = lines[7].split(',').map(|v| v.parse().unwrap()).collect();
    assert!(
        (last[3] - 2.0).abs() < 1e-6,
        "index at twice the failure: {}",
        last[3]
    );
    let frame = std::fs::read_dir(dir.join("frames"))
        .unwrap()
        .filter_map(|e| e.ok())
        .find(|e| e.file_name().to_string_lossy().starts_with("results_"))
        .unwrap();
    let vtu = std::fs::read_to_string(frame.path()).unwrap();
    assert!(vtu.contains("Name=\"tsai_wu_index\""));
    let _ = std::fs::remove_dir_all(&dir);
}

/// A plane mesh of the square `[0, l]^2` in MSH 4.1 ASCII, `n x n` grid
/// cells, with the physical curves `x0`, `x1`, `y0`, `y1` on its edges:
/// with `mixed` the cells of the left half are quadrilaterals (Quad4 /
/// Quad8), every other cell is cut into two triangles (Tri3 / Tri6) along
/// alternating diagonals; every other cell is written clockwise, to
/// exercise the reorientation. `z` is the plane's height.
fn square_msh(l: f64, n: usize, quadratic: bool, mixed: bool, z: f64) -> String {
    let p = if quadratic { 2 } else { 1 };
    let g = p * n + 1;
    let id = |i: usize, j: usize| j * g + i + 1;
    let nn = g * g;
    let mut m = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n5\n1 1 \"x0\"\n1 2 \"x1\"\n1 3 \"y0\"\n1 4 \"y1\"\n2 5 \"plate\"\n$EndPhysicalNames\n");
    m += &format!("$Entities\n0 4 1 0\n1 0 0 {z} 0 {l} {z} 1 1 0\n2 {l} 0 {z} {l} {l} {z} 1 2 0\n3 0 0 {z} {l} 0 {z} 1 3 0\n4 0 {l} {z} {l} {l} {z} 1 4 0\n1 0 0 {z} {l} {l} {z} 1 5 0\n$EndEntities\n");
    m += &format!("$Nodes\n1 {nn} 1 {nn}\n2 1 0 {nn}\n");
    for k in 1..=nn {
        m += &format!("{k}\n");
    }
    for j in 0..g {
        for i in 0..g {
            let c = |k: usize| l * k as f64 / (g - 1) as f64;
            m += &format!("{} {} {z}\n", c(i), c(j));
        }
    }
    let (mut quads, mut tris) = (Vec::new(), Vec::new());
    for j in 0..n {
        for i in 0..n {
            let (i0, j0, i1, j1) = (p * i, p * j, p * (i + 1), p * (j + 1));
            let h = p / 2; // a mid-side step (quadratic only)
            let cw = (i + j) % 2 == 1;
            if mixed && i < n / 2 {
                let mut q = vec![id(i0, j0), id(i1, j0), id(i1, j1), id(i0, j1)];
                if quadratic {
                    q.extend([
                        id(i0 + h, j0),
                        id(i1, j0 + h),
                        id(i0 + h, j1),
                        id(i0, j0 + h),
                    ]);
                }
                if cw {
                    q = if quadratic {
                        vec![q[0], q[3], q[2], q[1], q[7], q[6], q[5], q[4]]
                    } else {
                        vec![q[0], q[3], q[2], q[1]]
                    };
                }
                quads.push(q);
                continue;
            }
            // corners (lattice indices) of the two triangles
            let cut: [[(usize, usize); 3]; 2] = if (i + 2 * j) % 3 == 0 {
                [
                    [(i0, j0), (i1, j0), (i1, j1)],
                    [(i0, j0), (i1, j1), (i0, j1)],
                ]
            } else {
                [
                    [(i0, j0), (i1, j0), (i0, j1)],
                    [(i1, j0), (i1, j1), (i0, j1)],
                ]
            };
            for mut t in cut {
                if cw {
                    t.swap(1, 2);
                }
                let mut v: Vec<usize> = t.iter().map(|&(a, b)| id(a, b)).collect();
                if quadratic {
                    for k in 0..3 {
                        let (a, b) = (t[k], t[(k + 1) % 3]);
                        v.push(id((a.0 + b.0) / 2, (a.1 + b.1) / 2));
                    }
                }
                tris.push(v);
            }
        }
    }
    let edges: [Vec<(usize, usize)>; 4] = [
        (0..g).map(|j| (0, j)).collect(),
        (0..g).map(|j| (p * n, j)).collect(),
        (0..g).map(|i| (i, 0)).collect(),
        (0..g).map(|i| (i, p * n)).collect(),
    ];
    let blocks = 4 + usize::from(!quads.is_empty()) + usize::from(!tris.is_empty());
    let ne = 4 * n + quads.len() + tris.len();
    m += &format!("$EndNodes\n$Elements\n{blocks} {ne} 1 {ne}\n");
    let mut tag = 1;
    let line = if quadratic { 8 } else { 1 };
    for (e, pts) in edges.iter().enumerate() {
        m += &format!("1 {} {line} {n}\n", e + 1);
        for k in 0..n {
            let (a, b) = (pts[p * k], pts[p * (k + 1)]);
            m += &format!("{tag} {} {}", id(a.0, a.1), id(b.0, b.1));
            if quadratic {
                let c = pts[p * k + 1];
                m += &format!(" {}", id(c.0, c.1));
            }
            m += "\n";
            tag += 1;
        }
    }
    for (cells, code) in [
        (&quads, if quadratic { 16 } else { 3 }),
        (&tris, if quadratic { 9 } else { 2 }),
    ] {
        if cells.is_empty() {
            continue;
        }
        m += &format!("2 1 {code} {}\n", cells.len());
        for c in cells {
            let c: Vec<String> = c.iter().map(|v| v.to_string()).collect();
            m += &format!("{tag} {}\n", c.join(" "));
            tag += 1;
        }
    }
    m + "$EndElements\n"
}

/// The `[A B; B D]` of a laminate on a Gmsh base file written by `msh`.
fn gmsh_abd(msh: &str, code: &str, element: &str, extra: &str) -> [[f64; 6]; 6] {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("plate.msh"), msh).unwrap();
    let text = scene(code, element, extra).replace(
        &format!("base = {{ type = \"rectangle\", size = [{L}, {L}], divisions = [2, 2] }}"),
        "base = { type = \"gmsh\", file = \"plate.msh\" }",
    );
    let path = dir.path().join("plate.toml");
    std::fs::write(&path, &text).unwrap();
    let sf = SceneFile::read(&path).unwrap();
    abd_of(&build_model(&sf).unwrap())
}

/// Triangles in a Gmsh base: Tri6 -> Wedge15 (alone and beside Quad8 ->
/// Hex20), interfaces between every ply (INTER12 on the triangles, INTER16
/// on the quadrilaterals), give CLT's `[A B; B D]` (the CLT field lies in
/// the Wedge15 and Hex20 spaces, so to round-off); Tri3 -> Wedge6 beside
/// Quad4 -> Hex8 give CLT's `A` (the membrane fields are linear), the
/// linear elements lock in bending, as plain H8 does.
#[test]
fn triangles_in_a_gmsh_base_give_clt() {
    let angles = [0.0, 45.0, -45.0, 90.0];
    let reference = clt_abd(&angles);
    for (quadratic, mixed, element) in [
        (true, false, "wedge15"),
        (true, true, "h20"),
        (false, true, "h8"),
        (false, false, "wedge6"),
    ] {
        let msh = square_msh(L, 4, quadratic, mixed, 1.5);
        let measured = gmsh_abd(&msh, "[0/45/-45/90]", element, "");
        let [ea, eb, ed] = compare(&angles, &measured, &reference);
        eprintln!("triangles (quadratic {quadratic}, with quads {mixed}, {element}): A {ea:.2e}, B {eb:.2e}, D {ed:.2e}");
        assert!(ea < 1e-6, "A {ea:.3e}");
        if quadratic {
            assert!(eb < 1e-6 && ed < 1e-6, "B {eb:.3e}, D {ed:.3e}");
        }
    }
}

/// A cross-section's base is a line, an L-section or a ring: the 3D bases
/// and the 3D counts of divisions are refused by key, with what is valid.
#[test]
fn cross_section_mistakes_name_the_key() {
    for (base, says) in [
        ("{ type = \"rectangle\", size = [1.0, 1.0], divisions = [1, 1] }", "takes \"line\", \"l_section\" or \"ring\""),
        ("{ type = \"line\", length = 1.0, divisions = [1, 1] }", "give 1 number,"),
        ("{ type = \"line\", divisions = [2] }", "`laminate.base.length` is required"),
        ("{ type = \"l_section\", inner_radius = 1.0, arms = [1.0, 1.0], divisions = [1, 2, 1, 1] }", "give 3 numbers"),
        ("{ type = \"ring\", inner_radius = 1.0, divisions = [3] }", "even number"),
        ("{ type = \"line\", length = 1.0, divisions = [2], grading = [2.0, 1.0] }", "give one ratio"),
        ("{ type = \"ring\", inner_radius = 1.0, width = 2.0, divisions = [4] }", "`laminate.base.width` is not read with type = \"ring\" in a cross-section (a cross-section's width is `[model] thickness`)"),
    ] {
        let text = format!("{T300}\n[laminate]\nbase = {base}\nelement = \"cpe4\"\nmaterial = \"t300\"\nply_thickness = 0.1\nlayup = \"[0/90]\"\n");
        let sf = SceneFile::parse(std::path::Path::new("cut.toml"), text).unwrap();
        let e = build_model(&sf).err().expect(base).to_string();
        assert!(e.contains(says) && e.contains("cut.toml") && e.contains("laminate.base"), "{base}: {e}");
    }
    // a line under solid plies: says what `line` is for
    let text = format!("{T300}\n[laminate]\nbase = {{ type = \"line\", length = 1.0, divisions = [2] }}\nelement = \"h8\"\nmaterial = \"t300\"\nply_thickness = 0.1\nlayup = \"[0/90]\"\n");
    let sf = SceneFile::parse(std::path::Path::new("cut.toml"), text).unwrap();
    let e = build_model(&sf).err().expect("line with h8").to_string();
    assert!(e.contains("cross-section of plane elements"), "{e}");
}

/// A base key that its type does not read (one written for another type)
/// is refused, naming it and the keys that type reads, rather than
/// ignored.
#[test]
fn base_keys_of_another_type_are_refused() {
    for (base, key, reads) in [
        ("{ type = \"rectangle\", size = [1.0, 1.0], divisions = [1, 1], inner_radius = 2.0 }", "inner_radius", "`size`, `divisions`, `origin`"),
        ("{ type = \"ring\", inner_radius = 1.0, width = 1.0, divisions = [4, 1], size = [1.0, 1.0] }", "size", "`inner_radius`, `width`, `sweep`, `divisions`"),
        ("{ type = \"l_section\", inner_radius = 1.0, arms = [1.0, 1.0], width = 1.0, divisions = [1, 2, 1, 1], origin = [1.0, 0.0, 0.0] }", "origin", "`inner_radius`, `arms`, `width`, `divisions`"),
        ("{ type = \"rectangle\", size = [1.0, 1.0], divisions = [1, 1], flip = true }", "flip", "`size`, `divisions`, `origin`"),
    ] {
        let text = format!("{T300}\n[laminate]\nbase = {base}\nelement = \"h8\"\nmaterial = \"t300\"\nply_thickness = 0.1\nlayup = \"[0/90]\"\n");
        let sf = SceneFile::parse(std::path::Path::new("cut.toml"), text).unwrap();
        let e = build_model(&sf).err().expect(base).to_string();
        assert!(
            e.contains("cut.toml") && e.contains(&format!("`laminate.base.{key}` is not read")) && e.contains(reads),
            "{base}: {e}"
        );
    }
}
