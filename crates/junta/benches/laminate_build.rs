//! Criterion bench of the lay-up builder: a 32-ply quasi-isotropic
//! `[0/45/90/-45]4s` laminate of H8I, 0.125 mm plies on a 100 x 100 mm
//! plate of 71 x 71 elements, with an interface between every pair of plies
//! (31 INTER8 layers): 331,776 nodes, 981,504 equations. `build_mesh`
//! stacks, merges and inserts the interfaces; `build_model` adds the ply
//! materials, the elements, the supports and the element geometry check
//! (what `summary.json` `timings.build` reports). Run with
//! `cargo bench -p junta --bench laminate_build`.

use criterion::{criterion_group, criterion_main, Criterion};
use junta::input::scene::{build_mesh, build_model, SceneFile};

const SCENE: &str = r#"
[materials.t300]
type = "orthotropic"
E1 = 181.0e3
E2 = 10.3e3
E3 = 10.3e3
nu12 = 0.28
nu13 = 0.28
nu23 = 0.4
G12 = 7.17e3
G13 = 7.17e3
G23 = 3.68e3
[laws.cz]
type = "linear_penalty"
d = 1.0e9
[laminate]
base = { type = "rectangle", size = [100.0, 100.0], divisions = [71, 71] }
element = "h8i"
material = "t300"
ply_thickness = 0.125
layup = "[0/45/90/-45]4s"
interface_law = "cz"
interfaces = "all"
[[boundary]]
set = "x0"
fixed = "all"
"#;

fn bench(c: &mut Criterion) {
    let sf = SceneFile::parse(std::path::Path::new("laminate32.toml"), SCENE.into()).unwrap();
    let model = build_model(&sf).unwrap();
    assert_eq!(model.mesh.blocks.len(), 32 + 31);
    assert!(model.dofs.num_free > 950_000);
    drop(model);
    let mut g = c.benchmark_group("laminate_32_plies");
    g.sample_size(10);
    g.bench_function("build_mesh", |b| b.iter(|| build_mesh(&sf).unwrap()));
    g.bench_function("build_model", |b| b.iter(|| build_model(&sf).unwrap()));
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
