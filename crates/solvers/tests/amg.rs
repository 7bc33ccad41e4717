//! Smoothed-aggregation AMG (`cg` with `preconditioner = "amg"`) on H8
//! elasticity: convergence, mesh independence of the iteration count, and
//! exact interpolation of the rigid-body modes.

use junta_core::element::StepInfo;
use junta_core::mesh::generate::{box_mesh, BoxSpec};
use junta_core::topology::CellShape;
use junta_core::{LinearSolver, Model, SymmetricCsc};
use junta_elements::{Integration, Isotropic, SolidElement};
use junta_solvers::amg::{Amg, AmgSettings, NULL_DIM};
use junta_solvers::{CgSettings, CgSolver, Preconditioner};
use std::sync::Arc;

/// Unit cube of `n^3` H8, steel-like, clamped at z = 0, top pulled down.
fn cube(n: usize) -> Model {
    let mesh = box_mesh(
        &BoxSpec::new([1.0; 3], [n; 3], CellShape::Hex8),
        "cube",
        "h8",
        "steel",
    )
    .unwrap();
    let steel = Arc::new(Isotropic::new(210_000.0, 0.3).unwrap());
    let el = Arc::new(SolidElement::new(CellShape::Hex8, Integration::Full, steel).unwrap());
    let mut c = Vec::new();
    for &i in mesh.node_set("z0").unwrap() {
        c.extend((0..3).map(|k| (3 * i + k, 0.0)));
    }
    let mut f = vec![0.0; 3 * mesh.nodes.len()];
    for &i in mesh.node_set("z1").unwrap() {
        f[3 * i] = 1.0;
        f[3 * i + 2] = -2.0;
    }
    Model::new(mesh, vec![el], &c, f, vec![]).unwrap()
}

/// Assembled stiffness (free dofs) and load vector.
fn assemble(model: &Model) -> (SymmetricCsc, Vec<f64>) {
    let asm = model.assembler();
    let mut k = asm.pattern.clone();
    let mut f = vec![0.0; model.dofs.num_dofs()];
    let mut state = model.initial_state();
    let u = model.dofs.expand(None, 0.0);
    asm.assemble(
        &model.mesh,
        &model.elements,
        &model.dofs,
        &u,
        &mut state,
        StepInfo::default(),
        Some(&mut k),
        &mut f,
    )
    .unwrap();
    (k, model.dofs.reduce(&model.f_ext))
}

fn amg_cg() -> CgSolver {
    CgSolver::new(CgSettings {
        preconditioner: Preconditioner::Amg,
        tol: 1e-10,
        ..Default::default()
    })
}

/// Solve with AMG-CG; returns (iterations, true relative residual).
fn solve(model: &Model, s: &mut CgSolver) -> (usize, f64) {
    let (k, b) = assemble(model);
    let coords = model.dofs.equation_coords(&model.mesh.nodes);
    s.set_layout(&model.equation_layout());
    s.analyze(&k, Some(&coords)).unwrap();
    s.factorize(&k).unwrap();
    let mut x = b.clone();
    s.solve_in_place(&k, &mut x).unwrap();
    let mut ax = vec![0.0; k.n];
    k.mul_vec(&x, &mut ax);
    let r: f64 = ax
        .iter()
        .zip(&b)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>()
        .sqrt();
    let bn: f64 = b.iter().map(|v| v * v).sum::<f64>().sqrt();
    (s.report().iterations, r / bn)
}

#[test]
/// Measured: 17 iterations on 8^3 H8 (1944 equations) and 17 on 16^3
/// (13872 equations).
fn amg_cg_solves_the_h8_cube_with_mesh_independent_iterations() {
    let mut counts = Vec::new();
    for n in [8, 16] {
        let mut s = amg_cg();
        let (it, rel) = solve(&cube(n), &mut s);
        eprintln!(
            "n = {n}: {it} iterations, residual {rel:.2e}, {:?}",
            s.report().notes
        );
        assert!(rel <= 1e-10, "n = {n}: relative residual {rel:e}");
        counts.push(it);
    }
    assert!(
        counts[1] as f64 <= 1.5 * counts[0] as f64,
        "iterations grow more than 50 %: {counts:?}"
    );
}

#[test]
fn hierarchy_interpolates_the_rigid_modes_exactly_on_every_level() {
    let model = cube(12);
    let (k, _) = assemble(&model);
    let coords = model.dofs.equation_coords(&model.mesh.nodes);
    let settings = AmgSettings {
        max_coarse: 50,
        ..Default::default()
    };
    let amg = Amg::setup(&k, &coords, &model.equation_layout(), settings).unwrap();
    assert!(amg.num_levels() >= 3, "levels {:?}", amg.sizes());
    // B_0 holds the six rigid modes: K B_0 vanishes away from the supports
    // (rows of equations of nodes not adjacent to the clamped face).
    for l in 0..amg.num_levels() - 1 {
        let (fine, coarse) = (&amg.levels[l], &amg.levels[l + 1]);
        let t = &fine.t;
        for c in 0..NULL_DIM {
            let xc: Vec<f64> = coarse.b.iter().map(|r| r[c]).collect();
            let mut y = vec![0.0; t.n_rows];
            t.mul(&xc, &mut y);
            let scale = fine.b.iter().fold(0.0f64, |m, r| m.max(r[c].abs()));
            let err = y
                .iter()
                .zip(&fine.b)
                .fold(0.0f64, |m, (a, r)| m.max((a - r[c]).abs()));
            assert!(scale > 0.1, "mode {c} vanished on level {l}");
            assert!(
                err <= 1e-12 * scale,
                "level {l}, mode {c}: T B_(l+1) - B_l = {err:e}"
            );
        }
    }
    // Level 0 modes are rigid motions: the stiffness of the same cube
    // without supports annihilates every column of B_0.
    let free = {
        let m = cube(3);
        Model::new(
            m.mesh.clone(),
            m.elements.clone(),
            &[],
            m.f_ext.clone(),
            vec![],
        )
        .unwrap()
    };
    let (kf, _) = assemble(&free);
    let coords = free.dofs.equation_coords(&free.mesh.nodes);
    let amg = Amg::setup(
        &kf,
        &coords,
        &free.equation_layout(),
        AmgSettings::default(),
    );
    // the unsupported stiffness is singular: the coarsest dense Cholesky
    // must refuse it with a typed error, never produce a factor
    assert!(matches!(
        amg,
        Err(junta_core::SolverError::NotPositiveDefinite { .. })
    ));
    let b0 = junta_solvers::amg::rigid_modes(&coords, &free.equation_layout());
    let knorm = kf.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for c in 0..NULL_DIM {
        let x: Vec<f64> = b0.iter().map(|r| r[c]).collect();
        let mut y = vec![0.0; kf.n];
        kf.mul_vec(&x, &mut y);
        let err = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(err <= 1e-12 * knorm, "mode {c}: |K b| = {err:e}");
    }
}

/// MINRES on a symmetric indefinite matrix with a known solution: the
/// 7-point Laplacian of a 12^3 grid (3 dofs per node) shifted by sigma = 3,
/// inside its spectrum, so that it has negative eigenvalues (CG breaks
/// down or diverges on it, LDL^T counts the negative pivots).
#[test]
fn minres_solves_a_symmetric_indefinite_system() {
    use junta_solvers::gallery::{grid_3d, Stencil};
    use junta_solvers::{LdltSolver, MinresSolver};
    let (mut a, coords) = grid_3d(12, 12, 12, 3, Stencil::Point7);
    for j in 0..a.n {
        let p = a.position(j, j).unwrap();
        a.values[p] -= 3.0;
    }
    let xs: Vec<f64> = (0..a.n).map(|i| ((i * 37) % 11) as f64 - 5.0).collect();
    let mut b = vec![0.0; a.n];
    a.mul_vec(&xs, &mut b);
    let mut ldlt = LdltSolver::default();
    ldlt.analyze(&a, Some(&coords)).unwrap();
    ldlt.factorize(&a).unwrap();
    let neg = ldlt.report().negative_pivots.unwrap();
    assert!(neg > 0, "the test matrix must be indefinite");
    let mut s = MinresSolver::default();
    assert!(s.accepts(junta_core::MatrixKind::SymmetricIndefinite));
    s.analyze(&a, None).unwrap();
    s.factorize(&a).unwrap();
    let mut x = b.clone();
    s.solve_in_place(&a, &mut x).unwrap();
    let r = s.report();
    eprintln!(
        "minres: {} iterations, residual {:.2e}, {neg} negative eigenvalues",
        r.iterations, r.residual
    );
    assert!(r.residual <= 1e-10);
    let err = x
        .iter()
        .zip(&xs)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(err < 1e-6, "max error {err:e}");
}
