//! Criterion bench of assembly: sparsity pattern construction and parallel
//! numeric assembly (tangent + internal force) into the fixed pattern, on
//! the unit-cube deck of shared/BENCHMARKS.md section 1 at a size that runs
//! in seconds (H8 10^3, H20 6^3 elements). Run with
//! `cargo bench -p junta-solvers --bench assembly`.

use criterion::{criterion_group, criterion_main, Criterion};
use junta_core::element::StepInfo;
use junta_core::mesh::generate::{box_mesh, BoxSpec};
use junta_core::topology::CellShape;
use junta_core::Model;
use junta_elements::{Integration, Isotropic, SolidElement};
use std::sync::Arc;

fn cube(shape: CellShape, n: usize) -> Model {
    let mesh = box_mesh(&BoxSpec::new([1.0; 3], [n; 3], shape), "cube", "h", "steel").unwrap();
    let steel = Arc::new(Isotropic::new(210_000.0, 0.3).unwrap());
    let el = Arc::new(SolidElement::new(shape, Integration::Full, steel).unwrap());
    let mut c = Vec::new();
    for &i in mesh.node_set("z0").unwrap() {
        c.extend((0..3).map(|k| (3 * i + k, 0.0)));
    }
    for &i in mesh.node_set("z1").unwrap() {
        c.push((3 * i + 2, -0.01));
    }
    let f = vec![0.0; 3 * mesh.nodes.len()];
    Model::new(mesh, vec![el], &c, f, vec![]).unwrap()
}

fn bench(c: &mut Criterion) {
    for (name, shape, n) in [
        ("h8_10", CellShape::Hex8, 10),
        ("h20_6", CellShape::Hex20, 6),
    ] {
        let model = cube(shape, n);
        c.bench_function(&format!("pattern_{name}"), |b| b.iter(|| model.assembler()));
        let asm = model.assembler();
        let mut k = asm.pattern.clone();
        let mut f = vec![0.0; model.dofs.num_dofs()];
        let mut state = model.initial_state();
        let u = model.dofs.expand(None, 1.0);
        c.bench_function(&format!("assemble_{name}"), |b| {
            b.iter(|| {
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
                .unwrap()
            })
        });
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = bench
}
criterion_main!(benches);
