//! Classical lamination theory for the laminate tests, and the model's own
//! `[A B; B D]` measured under CLT's unit fields (see `laminate.rs`).
//!
//! CLT from its textbook formulas (Jones, Mechanics of Composite
//! Materials, 2nd ed., 1999, eqs. 2.84-2.87 for `Q_ij`, 2.93-2.95 for
//! `Q̄_ij` with `m = cos theta, n = sin theta`, 4.28 for `A, B, D`);
//! material T300/5208 (Tsai & Hahn 1980), plies `T` thick on an `L x L`
//! plate.

#![allow(dead_code)]

use junta::input::scene::AnalysisSpec;
use junta::Simulation;
use junta_core::{Model, StepInfo};

pub const E1: f64 = 181.0e3;
pub const E2: f64 = 10.3e3;
pub const G12: f64 = 7.17e3;
pub const NU12: f64 = 0.28;
pub const T: f64 = 0.125;
/// T300/5208 as a scene's `[materials.t300]` (transversely isotropic:
/// E3 = E2, nu13 = nu12, G13 = G12; nu23 = 0.4, G23 = 3.68e3), the
/// constants above.
pub const T300: &str = "[materials.t300]\ntype = \"orthotropic\"\nE1 = 181000\nE2 = 10300\nE3 = 10300\nnu12 = 0.28\nnu13 = 0.28\nnu23 = 0.4\nG12 = 7170\nG13 = 7170\nG23 = 3680";
pub const L: f64 = 20.0;

/// `Q̄` of a ply at `theta` degrees, `[[11, 12, 16], [12, 22, 26], [16, 26, 66]]`.
pub fn q_bar(theta: f64) -> [[f64; 3]; 3] {
    let nu21 = NU12 * E2 / E1;
    let d = 1.0 - NU12 * nu21;
    let (q11, q22, q12, q66) = (E1 / d, E2 / d, NU12 * E2 / d, G12);
    let (n, m) = theta.to_radians().sin_cos();
    let (m2, n2) = (m * m, n * n);
    let b11 = q11 * m2 * m2 + 2.0 * (q12 + 2.0 * q66) * m2 * n2 + q22 * n2 * n2;
    let b12 = (q11 + q22 - 4.0 * q66) * m2 * n2 + q12 * (m2 * m2 + n2 * n2);
    let b22 = q11 * n2 * n2 + 2.0 * (q12 + 2.0 * q66) * m2 * n2 + q22 * m2 * m2;
    let b16 = (q11 - q12 - 2.0 * q66) * m2 * m * n + (q12 - q22 + 2.0 * q66) * m * n2 * n;
    let b26 = (q11 - q12 - 2.0 * q66) * m * n2 * n + (q12 - q22 + 2.0 * q66) * m2 * m * n;
    let b66 = (q11 + q22 - 2.0 * q12 - 2.0 * q66) * m2 * n2 + q66 * (m2 * m2 + n2 * n2);
    [[b11, b12, b16], [b12, b22, b26], [b16, b26, b66]]
}

/// CLT's `[A B; B D]` of plies `angles` (bottom to top, thickness `T`).
pub fn clt_abd(angles: &[f64]) -> [[f64; 6]; 6] {
    let h = T * angles.len() as f64;
    let mut abd = [[0.0; 6]; 6];
    for (k, &theta) in angles.iter().enumerate() {
        let (z0, z1) = (-h / 2.0 + k as f64 * T, -h / 2.0 + (k + 1) as f64 * T);
        let q = q_bar(theta);
        for i in 0..3 {
            for j in 0..3 {
                let a = q[i][j] * (z1 - z0);
                let b = q[i][j] * (z1 * z1 - z0 * z0) / 2.0;
                let d = q[i][j] * (z1.powi(3) - z0.powi(3)) / 3.0;
                abd[i][j] += a;
                abd[i][j + 3] += b;
                abd[i + 3][j] += b;
                abd[i + 3][j + 3] += d;
            }
        }
    }
    abd
}

/// The unit field `phi_i` at a point (`zm`: mid-plane), `[u, v, w]`.
pub fn unit_field(i: usize, p: [f64; 3], zm: f64) -> [f64; 3] {
    let (x, y, z) = (p[0], p[1], p[2] - zm);
    match i {
        0 => [x, 0.0, 0.0],
        1 => [0.0, y, 0.0],
        2 => [y / 2.0, x / 2.0, 0.0],
        3 => [z * x, 0.0, 0.0],
        4 => [0.0, z * y, 0.0],
        _ => [z * y / 2.0, z * x / 2.0, 0.0],
    }
}

/// The `z` of `built`'s mid-plane and the run of unit field `j` prescribed
/// on its edges (node sets `x0`, `x1`, `y0`, `y1`; `w` fixed at one
/// corner only; `built`'s own supports and loads are not used).
pub fn unit_case_of(built: &Model, j: usize) -> (f64, junta::RunResults) {
    let zs = built.mesh.nodes.iter().map(|p| p[2]);
    let (lo, hi) = zs.fold((f64::MAX, f64::MIN), |(a, b), z| (a.min(z), b.max(z)));
    let zm = 0.5 * (lo + hi);
    let sets = &built.mesh.node_sets;
    let mut edges: Vec<usize> = ["x0", "x1", "y0", "y1"]
        .iter()
        .flat_map(|s| sets[*s].clone())
        .collect();
    edges.sort_unstable();
    edges.dedup();
    let corner = sets["x0"]
        .iter()
        .copied()
        .find(|n| sets["y0"].contains(n))
        .unwrap();
    let mut constraints: Vec<(usize, f64)> = Vec::new();
    for &n in &edges {
        let f = unit_field(j, built.mesh.nodes[n], zm);
        constraints.push((3 * n, f[0]));
        constraints.push((3 * n + 1, f[1]));
    }
    constraints.push((3 * corner + 2, 0.0));
    let n3 = 3 * built.mesh.nodes.len();
    let model = Model::new(
        built.mesh.clone(),
        built.elements.clone(),
        &constraints,
        vec![0.0; n3],
        vec![],
    )
    .unwrap();
    let sim = Simulation::from_model(model, AnalysisSpec::default(), "cholesky").unwrap();
    let r = sim.run(&junta::RunSettings::in_memory(), &mut []).unwrap();
    (zm, r)
}

/// `built`'s `[A B; B D]` (a plate `L x L`): column `j` from the run of
/// unit field `j`.
pub fn abd_of(built: &Model) -> [[f64; 6]; 6] {
    let mut abd = [[0.0; 6]; 6];
    for j in 0..6 {
        let m = built;
        let (zm, r) = unit_case_of(built, j);
        let u = r.frame.expect("a linear run keeps its frame").displacement;
        // f_int does not depend on which dofs are prescribed: the unloaded model's
        let mut f = vec![0.0; u.len()];
        let mut state = m.initial_state();
        m.whole_assembler()
            .assemble(
                &m.mesh,
                &m.elements,
                &m.dofs,
                &u,
                &mut state,
                StepInfo::default(),
                None,
                &mut f,
            )
            .unwrap();
        for (i, row) in abd.iter_mut().enumerate() {
            let work: f64 = (0..m.mesh.nodes.len())
                .map(|n| {
                    let phi = unit_field(i, m.mesh.nodes[n], zm);
                    (0..3).map(|c| f[3 * n + c] * phi[c]).sum::<f64>()
                })
                .sum();
            row[j] = work / (L * L);
        }
    }
    abd
}

/// Largest difference of each of A, B, D over the largest entry of A,
/// B's scale `A h`, D respectively (`h` thickness).
pub fn compare(angles: &[f64], measured: &[[f64; 6]; 6], reference: &[[f64; 6]; 6]) -> [f64; 3] {
    let h = T * angles.len() as f64;
    let max_abs = |r: std::ops::Range<usize>, c: std::ops::Range<usize>, m: &[[f64; 6]; 6]| {
        r.clone()
            .flat_map(|i| c.clone().map(move |j| (i, j)))
            .fold(0.0f64, |a, (i, j)| a.max(m[i][j].abs()))
    };
    let diff = |r: std::ops::Range<usize>, c: std::ops::Range<usize>| {
        r.clone()
            .flat_map(|i| c.clone().map(move |j| (i, j)))
            .fold(0.0f64, |a, (i, j)| {
                a.max((measured[i][j] - reference[i][j]).abs())
            })
    };
    let a = max_abs(0..3, 0..3, reference);
    let d = max_abs(3..6, 3..6, reference);
    [
        diff(0..3, 0..3) / a,
        diff(0..3, 3..6) / (a * h),
        diff(3..6, 3..6) / d,
    ]
}
