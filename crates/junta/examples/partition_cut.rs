//! The cut of the partition a run over MPI ranks would use
//! ([`junta_core::distributed::partition_elements`]), for 2 to 64 ranks,
//! without MPI: one JSON line per rank count with the elements, nodes
//! and shared nodes of the most loaded rank and the mean shared nodes.
//! `bench/distributed.py` turns it into communication volumes.
//!
//! ```text
//! cargo run --release -p junta --example partition_cut -- examples/delamination/dcb.toml
//! ```

use junta_core::distributed::{partition_cut, partition_elements};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let input = std::env::args()
        .nth(1)
        .ok_or("usage: partition_cut SCENE_OR_DECK [RANKS...]")?;
    let ranks: Vec<usize> = std::env::args()
        .skip(2)
        .map(|r| r.parse())
        .collect::<Result<_, _>>()?;
    let ranks = if ranks.is_empty() {
        vec![2, 4, 8, 16, 32, 64]
    } else {
        ranks
    };
    let sim = junta::Simulation::from_file(&input)?;
    let model = sim.model();
    for p in ranks {
        let cut = partition_cut(&model.mesh, &partition_elements(&model.mesh, p), p);
        let max = |v: &[usize]| v.iter().copied().max().unwrap_or(0);
        let mean = cut.shared_nodes.iter().sum::<usize>() as f64 / p as f64;
        println!(
            "{{\"ranks\": {p}, \"equations\": {}, \"nodes\": {}, \"elements_max\": {}, \"nodes_max\": {}, \"shared_nodes_max\": {}, \"shared_nodes_mean\": {mean}}}",
            model.dofs.num_free,
            model.mesh.nodes.len(),
            max(&cut.elements),
            max(&cut.nodes),
            max(&cut.shared_nodes)
        );
    }
    Ok(())
}
