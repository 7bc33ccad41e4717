//! Embedding Junta without the CLI: build a mesh, elements and a model in
//! code, solve, and read the results. Run with
//!
//! ```sh
//! cargo run --release -p junta-cli --example embed
//! ```
//!
//! The model is the unit-cube benchmark of shared/BENCHMARKS.md section 1
//! (H20, n = 2): bottom fixed, top displaced uz = -0.01, E = 210000,
//! nu = 0.3. Expected top reaction Fz = -2183.070 (CalculiX 2.20).

use junta_core::mesh::generate::{box_mesh, BoxSpec};
use junta_core::topology::CellShape;
use junta_core::Model;
use junta_elements::{Integration, Isotropic, SolidElement};
use junta_solvers::cholesky::{CholeskySettings, CholeskySolver};
use junta_solvers::linear_static::solve_linear_static;
use std::sync::Arc;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // 1. mesh: a 2x2x2 box of H20 elements with sets x0..z1
    let mesh = box_mesh(
        &BoxSpec::new([1.0; 3], [2; 3], CellShape::Hex20),
        "cube",
        "h20",
        "steel",
    )?;
    // 2. one element object per block: H20, full integration, isotropic steel
    let steel = Arc::new(Isotropic::new(210_000.0, 0.3)?);
    let h20 = Arc::new(SolidElement::new(
        CellShape::Hex20,
        Integration::Full,
        steel,
    )?);
    // 3. constraints (dof = 3 node + component) and loads
    let mut constraints = Vec::new();
    for &n in mesh.node_set("z0")? {
        constraints.extend((0..3).map(|c| (3 * n + c, 0.0)));
    }
    for &n in mesh.node_set("z1")? {
        constraints.push((3 * n + 2, -0.01));
    }
    let f_ext = vec![0.0; 3 * mesh.nodes.len()];
    let model = Model::new(
        mesh,
        vec![h20],
        &constraints,
        f_ext,
        vec!["z0".into(), "z1".into()],
    )?;
    // 4. solve with the direct back end
    let mut solver = CholeskySolver::new(CholeskySettings::default());
    let result = solve_linear_static(&model, &mut solver)?;
    // 5. results: reactions are f_int - f_ext on the constrained dofs
    let fz = model.set_total("z1", &result.residual)?[2];
    println!("equations: {}", model.dofs.num_free);
    println!("top reaction Fz = {fz:.3} (CalculiX 2.20: -2183.070)");
    println!("timings: {:?}", result.timings);
    Ok(())
}
