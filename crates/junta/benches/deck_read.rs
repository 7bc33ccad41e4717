//! Criterion bench of the deck reader alone, on the CalculiX unit-cube deck
//! H8 n=40 of `bench/cube_vs_calculix.sh` (133,000 lines, 8 MB; written by
//! `bench/make_cube_deck.py`, which needs `python3`): `read_inp` (lex and
//! parse into the deck's data) and `deck::build_model` (that, then the
//! mesh, elements, sets, constraints and loads of the model, and the
//! element geometry check). The solver choice is not part of either. Run
//! with `cargo bench -p junta --bench deck_read`.

use criterion::{criterion_group, criterion_main, Criterion};
use std::path::{Path, PathBuf};

fn deck() -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = std::env::temp_dir().join("junta_deck_read_bench");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("cube_c3d8_n40.inp");
    if !path.exists() {
        let status = std::process::Command::new("python3")
            .arg(root.join("bench/make_cube_deck.py"))
            .args(["C3D8", "40"])
            .arg(&path)
            .status()
            .expect("python3 runs bench/make_cube_deck.py");
        assert!(status.success(), "bench/make_cube_deck.py failed");
    }
    path
}

fn bench(c: &mut Criterion) {
    let path = deck();
    let mut g = c.benchmark_group("deck_h8_n40");
    g.sample_size(20);
    g.bench_function("read_inp", |b| {
        b.iter(|| junta::input::inp::read_inp(&path).unwrap())
    });
    g.bench_function("build_model", |b| {
        b.iter(|| junta::input::deck::build_model(&path).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
