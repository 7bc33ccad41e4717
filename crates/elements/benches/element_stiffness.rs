//! Element stiffness (tangent + internal force) of H8, H20 and H27 on a
//! distorted element, small strain and total-Lagrangian (`_nlgeom`):
//! `cargo bench -p junta-elements --bench element_stiffness`.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use junta_core::element::{ElementContext, StepInfo};
use junta_core::topology::{CellShape, HEX27_NODES};
use junta_core::{Element, Kinematics};
use junta_elements::{Integration, Isotropic, SolidElement};
use std::sync::Arc;

fn coords(shape: CellShape) -> Vec<[f64; 3]> {
    HEX27_NODES[..shape.num_nodes()]
        .iter()
        .enumerate()
        .map(|(a, p)| {
            let w = 0.03 * ((a as f64) * 1.7).sin();
            [p[0] + w, 0.8 * p[1] - w, 1.2 * p[2] + 0.5 * w]
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let steel = Arc::new(Isotropic::new(210e9, 0.3).unwrap());
    let mut group = c.benchmark_group("element_stiffness");
    for (name, shape, integration, kinematics) in [
        ("h8", CellShape::Hex8, Integration::Full, Kinematics::Small),
        (
            "h20",
            CellShape::Hex20,
            Integration::Full,
            Kinematics::Small,
        ),
        (
            "h20r",
            CellShape::Hex20,
            Integration::Reduced,
            Kinematics::Small,
        ),
        (
            "h27",
            CellShape::Hex27,
            Integration::Full,
            Kinematics::Small,
        ),
        (
            "h8_nlgeom",
            CellShape::Hex8,
            Integration::Full,
            Kinematics::Finite,
        ),
        (
            "h20_nlgeom",
            CellShape::Hex20,
            Integration::Full,
            Kinematics::Finite,
        ),
    ] {
        let el = SolidElement::new(shape, integration, steel.clone())
            .unwrap()
            .with_kinematics(kinematics);
        let x = coords(shape);
        let n = 3 * x.len();
        let u: Vec<f64> = (0..n).map(|i| 1e-4 * (i as f64).cos()).collect();
        let mut f = vec![0.0; n];
        let mut k = vec![0.0; n * n];
        let ctx = ElementContext {
            coords: &x,
            disp: &u,
            state_committed: &[],
            step: StepInfo::default(),
            law_responses: None,
            temperature: None,
        };
        group.bench_function(name, |b| {
            b.iter(|| {
                el.compute(black_box(&ctx), &mut [], &mut f, Some(&mut k))
                    .unwrap();
                black_box(&k);
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
