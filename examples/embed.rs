//! Embedding Junta: the run API from a Rust program. Run with
//!
//! ```sh
//! cargo run --release -p junta --example embed
//! ```
//!
//! 1. The DCB of `examples/delamination/dcb.toml` (AS4/PEEK, mode I; N, mm)
//!    read from its scene, with one law parameter overridden, and run in
//!    memory with an observer that follows the load: it prints the peak
//!    against corrected beam theory (138.5 N at 4.21 mm, BENCHMARKS.md
//!    section 4).
//! 2. A model built in code: the unit-cube benchmark of BENCHMARKS.md
//!    section 1 (H20, n = 2, bottom fixed, top displaced uz = -0.01,
//!    E = 210000, nu = 0.3), run as a linear analysis. Expected top reaction
//!    Fz = -2183.070 (CalculiX 2.20).

use junta::core::mesh::generate::{box_mesh, BoxSpec};
use junta::core::topology::CellShape;
use junta::core::Model;
use junta::elements::{Integration, Isotropic, SolidElement};
use junta::{Flow, FnObserver, Increment, Options, RunSettings, Simulation};
use std::path::Path;
use std::sync::Arc;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    dcb_peak()?;
    cube_built_in_code()?;
    Ok(())
}

/// The DCB through the run API: the peak load and where it is.
fn dcb_peak() -> Result<(), Box<dyn std::error::Error>> {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/delamination/dcb.toml");
    let options = Options {
        // the scene's own value, given again to show the override
        overrides: vec![("laws.cz.G_Ic".into(), toml::Value::Float(0.969))],
        ..Options::default()
    };
    let sim = Simulation::from_file_with(&scene, options)?;
    let check = sim.check()?;
    println!(
        "DCB: {} equations, solver {}",
        check.equations, check.solver
    );
    let mut peak = (0.0_f64, 0.0_f64);
    let mut follow = FnObserver(|inc: &Increment<'_>| {
        if let (Some(p), Some(d)) = (inc.row.reaction, inc.row.displacement) {
            if p > peak.0 {
                peak = (p, d);
            }
        }
        Flow::Continue
    });
    let results = sim.run(&RunSettings::in_memory(), &mut [&mut follow])?;
    println!(
        "DCB: {} after {} increments; peak {:.1} N at {:.2} mm (corrected beam theory: 138.5 N at 4.21 mm)",
        results.status_line,
        results.curve().len(),
        peak.0,
        peak.1
    );
    Ok(())
}

/// A model built in code and run through the same API.
fn cube_built_in_code() -> Result<(), Box<dyn std::error::Error>> {
    // a 2x2x2 box of H20 elements with node sets x0..z1
    let mesh = box_mesh(
        &BoxSpec::new([1.0; 3], [2; 3], CellShape::Hex20),
        "cube",
        "h20",
        "steel",
    )?;
    let steel = Arc::new(Isotropic::new(210_000.0, 0.3)?);
    let h20 = Arc::new(SolidElement::new(
        CellShape::Hex20,
        Integration::Full,
        steel,
    )?);
    // constraints (dof = 3 node + component) and loads
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
    let sim = Simulation::from_model(model, junta::input::scene::AnalysisSpec::default(), "auto")?;
    let results = sim.run(&RunSettings::in_memory(), &mut [])?;
    let fz = results.summary["reactions"]["z1"][2]
        .as_f64()
        .unwrap_or(f64::NAN);
    println!("cube: top reaction Fz = {fz:.3} (CalculiX 2.20: -2183.070)");
    Ok(())
}
