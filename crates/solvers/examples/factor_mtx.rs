//! Time the direct solver on a matrix written by `junta run --export-matrix
//! DIR` (`K.mtx` and `layout.csv`, whose coordinates feed nested dissection).
//!
//! `cargo run --release -p junta-solvers --example factor_mtx -- DIR [double|mixed] [repeats]`
//! prints the analysis, factor and solve times, the factor's stored
//! non-zeros and its multiply-add rate (the factor's flops over its time).

use junta_core::{LinearSolver, SymmetricCsc};
use junta_solvers::{CholeskySettings, CholeskySolver, Precision};
use std::time::Instant;

fn read_matrix(path: &str) -> SymmetricCsc {
    let text = std::fs::read_to_string(path).expect("K.mtx");
    let mut lines = text.lines().filter(|l| !l.starts_with('%'));
    let head: Vec<usize> = lines
        .next()
        .unwrap()
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect();
    let n = head[0];
    let mut cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
    for l in lines {
        let mut it = l.split_whitespace();
        let i: usize = it.next().unwrap().parse().unwrap();
        let j: usize = it.next().unwrap().parse().unwrap();
        let v: f64 = it.next().unwrap().parse().unwrap();
        let (r, c) = if i <= j {
            (i - 1, j - 1)
        } else {
            (j - 1, i - 1)
        };
        cols[c].push((r, v));
    }
    let mut a = SymmetricCsc::from_columns(
        cols.iter_mut()
            .map(|c| {
                c.sort_by_key(|e| e.0);
                c.iter().map(|e| e.0).collect()
            })
            .collect(),
    );
    a.values = cols.iter().flat_map(|c| c.iter().map(|e| e.1)).collect();
    a
}

fn read_coords(path: &str, n: usize) -> Vec<[f64; 3]> {
    let text = std::fs::read_to_string(path).expect("layout.csv");
    let mut xyz = vec![[0.0; 3]; n];
    for l in text.lines().skip(1) {
        let f: Vec<&str> = l.split(',').collect();
        let e: usize = f[0].parse().unwrap();
        for k in 0..3 {
            xyz[e][k] = f[4 + k].parse().unwrap();
        }
    }
    xyz
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let dir = args.get(1).expect("DIR");
    let precision = match args.get(2).map(String::as_str) {
        Some("double") => Precision::Double,
        _ => Precision::Mixed,
    };
    let repeats: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(3);
    let a = read_matrix(&format!("{dir}/K.mtx"));
    let coords = read_coords(&format!("{dir}/layout.csv"), a.n);
    let mut s = CholeskySolver::new(CholeskySettings {
        precision,
        ..Default::default()
    });
    let t = Instant::now();
    s.analyze(&a, Some(&coords)).unwrap();
    println!("n = {}, analyze {:.3} s", a.n, t.elapsed().as_secs_f64());
    for _ in 0..repeats {
        let t = Instant::now();
        s.factorize(&a).unwrap();
        let tf = t.elapsed().as_secs_f64();
        let mut x = vec![1.0; a.n];
        let t = Instant::now();
        s.solve_in_place(&a, &mut x).unwrap();
        let ts = t.elapsed().as_secs_f64();
        println!("factor {tf:.3} s, solve {ts:.3} s");
    }
    println!("{:?}", s.report());
}
