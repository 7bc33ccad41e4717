//! Runs over MPI ranks against the same runs in one process: the `junta`
//! binary built with the feature `mpi` (`cargo build -p junta-cli
//! --features mpi`; `JUNTA_MPI_BIN` names another), under `mpirun -np N`
//! with N = 1, 2, 4 (4 oversubscribes a 2-core machine), every `mpirun`
//! wrapped in `timeout`. Without `mpirun` the same binary runs in one
//! process with Junta's own solvers: that is the reference.
//!
//! Parity: the tangents differ only by the order in which PETSc sums the
//! ranks' parts and by MUMPS against Junta's LDL^T, so a run over ranks
//! must take the same increments, iterations and negative pivots, and
//! agree to round-off amplified by the Newton tolerance.

#![cfg(feature = "petsc")]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The MPI-enabled `junta`: `JUNTA_MPI_BIN`, else `junta` next to the
/// test's own target directory.
fn junta() -> PathBuf {
    if let Some(p) = std::env::var_os("JUNTA_MPI_BIN") {
        return PathBuf::from(p);
    }
    let exe = std::env::current_exe().expect("test executable");
    let bin = exe
        .parent()
        .and_then(Path::parent)
        .expect("target/<profile>/deps")
        .join("junta");
    let listed = Command::new(&bin).arg("list").output();
    let ok = listed.is_ok_and(|o| String::from_utf8_lossy(&o.stdout).contains("petsc"));
    assert!(
        ok,
        "{} is not the MPI build: run `cargo build -p junta-cli --features mpi` first (or set JUNTA_MPI_BIN)",
        bin.display()
    );
    bin
}

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path)
}

/// `junta ARGS` in one process (the reference).
fn sequential(args: &[&str]) -> Output {
    let out = Command::new(junta())
        .args(args)
        .arg("-q")
        .output()
        .expect("run junta");
    assert!(
        out.status.success(),
        "junta {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// `timeout SECONDS mpirun -np RANKS junta ARGS` (root allowed,
/// oversubscription allowed, one OpenMP/BLAS thread per rank).
fn mpirun_with(ranks: usize, seconds: u64, args: &[&str]) -> Output {
    timed_mpirun(seconds)
        .args(["-np", &ranks.to_string()])
        .arg(junta())
        .args(args)
        .arg("-q")
        .output()
        .expect("run mpirun")
}

/// `timeout SECONDS mpirun` with the environment of these tests, for the
/// caller to add the ranks and programs.
fn timed_mpirun(seconds: u64) -> Command {
    let mut c = Command::new("timeout");
    c.arg(seconds.to_string())
        .arg("mpirun")
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("OMPI_MCA_rmaps_base_oversubscribe", "1")
        .env("OMP_NUM_THREADS", "1")
        .env("OPENBLAS_NUM_THREADS", "1");
    c
}

fn mpirun(ranks: usize, args: &[&str]) -> Output {
    let out = mpirun_with(ranks, 900, args);
    assert!(
        out.status.success(),
        "mpirun -np {ranks} junta {args:?} ({}): {}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn summary(dir: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("summary.json")).expect("summary.json");
    serde_json::from_str(&text).expect("summary.json is JSON")
}

/// `curve.csv` as (header, rows of numbers; an empty field is NaN).
fn curve(dir: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(dir.join("curve.csv")).expect("curve.csv");
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|l| {
            l.split(',')
                .map(|v| v.parse().unwrap_or(f64::NAN))
                .collect()
        })
        .collect();
    (header, rows)
}

/// The columns a parity check compares: the path and its energies (not
/// the timings).
const CURVE_VALUES: [&str; 5] = [
    "load_factor",
    "reaction",
    "displacement",
    "dissipated_energy",
    "damaged_area",
];
/// Columns that must be equal: the same increments, failed points,
/// cut-backs and negative pivots. (Newton iterations may differ by one
/// where a residual lands on the tolerance: they are checked within one.)
const CURVE_COUNTS: [&str; 4] = ["increment", "failed_points", "cutbacks", "negative_pivots"];

/// Assert that two curves take the same increments and agree to `tol`
/// relative to each column's largest magnitude; return the worst.
fn assert_same_curve(reference: &Path, run: &Path, tol: f64, what: &str) -> f64 {
    let (h, a) = curve(reference);
    let (h2, b) = curve(run);
    assert_eq!(h, h2, "{what}: curve.csv columns");
    assert_eq!(a.len(), b.len(), "{what}: number of increments");
    let col = |name: &str| {
        h.iter()
            .position(|c| c == name)
            .unwrap_or_else(|| panic!("column {name}"))
    };
    for name in CURVE_COUNTS {
        let c = col(name);
        for (i, (ra, rb)) in a.iter().zip(&b).enumerate() {
            // an empty field (NaN: no inertia from an LU factor) on both
            let same = ra[c] == rb[c] || (ra[c].is_nan() && rb[c].is_nan());
            assert!(
                same,
                "{what}: `{name}` of row {i}: {} against {}",
                rb[c], ra[c]
            );
        }
    }
    let c = col("newton_iterations");
    for (i, (ra, rb)) in a.iter().zip(&b).enumerate() {
        assert!(
            (ra[c] - rb[c]).abs() <= 1.0,
            "{what}: Newton iterations of row {i}: {} against {}",
            rb[c],
            ra[c]
        );
    }
    let mut worst: f64 = 0.0;
    for name in CURVE_VALUES {
        let c = col(name);
        let scale = a.iter().map(|r| r[c].abs()).fold(0.0, f64::max).max(1e-300);
        for (i, (ra, rb)) in a.iter().zip(&b).enumerate() {
            let d = (ra[c] - rb[c]).abs() / scale;
            assert!(
                d <= tol,
                "{what}: `{name}` of row {i}: {} against {} ({d:.2e} > {tol:.0e})",
                rb[c],
                ra[c]
            );
            worst = worst.max(d);
        }
    }
    worst
}

/// The cube of BENCHMARKS.md section 1 ([0,1]^3, bottom fixed, top
/// pressed down 0.01, E = 210000, nu = 0.3) as a CalculiX deck of
/// `n x n x n` C3D20 elements.
fn cube_c3d20(n: usize) -> String {
    let m = 2 * n + 1;
    let h = 1.0 / (2 * n) as f64;
    // serendipity: no node where two or three grid indices are odd
    let used = |i: usize, j: usize, k: usize| (i % 2) + (j % 2) + (k % 2) < 2;
    let mut label = vec![0usize; m * m * m];
    let mut deck = String::from("*HEADING\nUnit cube C3D20\n*NODE, NSET=NALL\n");
    let (mut bottom, mut top) = (Vec::new(), Vec::new());
    let mut next = 1;
    for k in 0..m {
        for j in 0..m {
            for i in 0..m {
                if used(i, j, k) {
                    label[i + m * (j + m * k)] = next;
                    deck += &format!(
                        "{next}, {}, {}, {}\n",
                        i as f64 * h,
                        j as f64 * h,
                        k as f64 * h
                    );
                    if k == 0 {
                        bottom.push(next);
                    }
                    if k == m - 1 {
                        top.push(next);
                    }
                    next += 1;
                }
            }
        }
    }
    // Abaqus C3D20: corners of z = 0 then z = 1 (counter-clockwise), the
    // mid-edges of the bottom face, of the top face, then the vertical ones
    let local: [[usize; 3]; 20] = [
        [0, 0, 0],
        [2, 0, 0],
        [2, 2, 0],
        [0, 2, 0],
        [0, 0, 2],
        [2, 0, 2],
        [2, 2, 2],
        [0, 2, 2],
        [1, 0, 0],
        [2, 1, 0],
        [1, 2, 0],
        [0, 1, 0],
        [1, 0, 2],
        [2, 1, 2],
        [1, 2, 2],
        [0, 1, 2],
        [0, 0, 1],
        [2, 0, 1],
        [2, 2, 1],
        [0, 2, 1],
    ];
    deck += "*ELEMENT, TYPE=C3D20, ELSET=EALL\n";
    let mut e = 1;
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let nodes: Vec<String> = local
                    .iter()
                    .map(|l| {
                        label[(2 * i + l[0]) + m * ((2 * j + l[1]) + m * (2 * k + l[2]))]
                            .to_string()
                    })
                    .collect();
                deck += &format!(
                    "{e}, {}\n{}\n",
                    nodes[..15].join(", "),
                    nodes[15..].join(", ")
                );
                e += 1;
            }
        }
    }
    let set = |name: &str, nodes: &[usize]| {
        let mut s = format!("*NSET, NSET={name}\n");
        for chunk in nodes.chunks(10) {
            s += &chunk
                .iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ");
            s += "\n";
        }
        s
    };
    deck += &set("BOTTOM", &bottom);
    deck += &set("TOP", &top);
    deck += "*MATERIAL, NAME=STEEL\n*ELASTIC\n210000., 0.3\n*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n";
    deck += "*BOUNDARY\nBOTTOM, 1, 3\n*STEP\n*STATIC\n*BOUNDARY\nTOP, 3, 3, -0.01\n*END STEP\n";
    deck
}

fn reaction_z(dir: &Path, set: &str) -> f64 {
    summary(dir)["reactions"][set][2]
        .as_f64()
        .expect("reaction")
}

#[test]
fn h20_cube_deck_reactions_match_one_process_on_1_2_4_ranks() {
    let tmp = tempfile::tempdir().unwrap();
    let deck = tmp.path().join("cube20.inp");
    std::fs::write(&deck, cube_c3d20(6)).unwrap();
    let d = deck.to_str().unwrap();
    let seq = tmp.path().join("seq");
    sequential(&["run", d, "-o", seq.to_str().unwrap()]);
    let reference = reaction_z(&seq, "TOP");
    // BENCHMARKS.md section 1: about -2166 N for a fine C3D20 mesh
    assert!(
        (reference / -2165.7 - 1.0).abs() < 5e-3,
        "sequential reaction {reference}"
    );
    for ranks in [1, 2, 4] {
        let out = tmp.path().join(format!("np{ranks}"));
        mpirun(ranks, &["run", d, "-o", out.to_str().unwrap()]);
        let r = reaction_z(&out, "TOP");
        let b = reaction_z(&out, "BOTTOM");
        assert!(
            (r / reference - 1.0).abs() < 1e-10,
            "{ranks} ranks: {r} against {reference}"
        );
        assert!(
            (b / -reference - 1.0).abs() < 1e-10,
            "{ranks} ranks: bottom {b}"
        );
        let s = summary(&out);
        assert_eq!(s["solver"]["name"], "petsc (mumps)");
        assert_partition_adds_up(&s, ranks, 6 * 6 * 6);
    }
}

/// `summary.json` `distributed` of a run on `ranks` ranks of a model of
/// `elements` elements: every element on one rank, every equation owned by
/// one rank, ghosts only where a rank shares nodes, each rank's peak memory.
fn assert_partition_adds_up(s: &serde_json::Value, ranks: usize, elements: u64) {
    let d = &s["distributed"];
    let list = |key: &str| -> Vec<u64> {
        let v: Vec<u64> = d[key]
            .as_array()
            .unwrap_or_else(|| panic!("distributed.{key}: {d}"))
            .iter()
            .map(|x| x.as_f64().unwrap() as u64)
            .collect();
        assert_eq!(v.len(), ranks, "distributed.{key} per rank");
        v
    };
    assert_eq!(list("elements").iter().sum::<u64>(), elements);
    let owned = list("owned_equations");
    assert_eq!(owned.iter().sum::<u64>(), s["equations"].as_u64().unwrap());
    let (ghost, shared) = (list("ghost_equations"), list("shared_nodes"));
    // the lowest rank touching a node owns its equations; the others hold
    // them as ghosts, so rank 0 has none and the ranks that share nodes do
    assert_eq!(ghost[0], 0, "{d}");
    assert_eq!(ghost.iter().sum::<u64>() > 0, ranks > 1, "{d}");
    for r in 0..ranks {
        assert!(owned[r] > 0, "rank {r} owns no equation: {d}");
        assert!(
            ghost[r] <= 3 * shared[r],
            "rank {r}: ghosts beyond its shared nodes: {d}"
        );
    }
    // each rank's peak resident memory: more than one value per owned
    // equation, less than a terabyte
    for (r, p) in list("peak_resident_bytes").into_iter().enumerate() {
        assert!(p > 8 * owned[r] && p < 1 << 40, "rank {r}: peak {p} bytes");
    }
}

#[test]
fn dcb_curve_through_its_peak_matches_one_process_on_1_2_4_ranks() {
    // examples/delamination/dcb.toml (mode I, 11936 equations, viscous
    // regularisation) past its peak load: 60 increments, the crack
    // started. The whole curve (496 increments) is in bench/distributed.py.
    let tmp = tempfile::tempdir().unwrap();
    let scene = repo("examples/delamination/dcb.toml");
    let s = scene.to_str().unwrap();
    let seq = tmp.path().join("seq");
    sequential(&[
        "run",
        s,
        "-o",
        seq.to_str().unwrap(),
        "--max-increments",
        "60",
    ]);
    let (h, rows) = curve(&seq);
    let failed = h.iter().position(|c| c == "failed_points").unwrap();
    assert!(
        rows.last().unwrap()[failed] > 0.0,
        "the crack must have started"
    );
    for ranks in [1, 2, 4] {
        let out = tmp.path().join(format!("np{ranks}"));
        mpirun(
            ranks,
            &[
                "run",
                s,
                "-o",
                out.to_str().unwrap(),
                "--max-increments",
                "60",
            ],
        );
        let worst = assert_same_curve(&seq, &out, 1e-8, &format!("dcb on {ranks} ranks"));
        eprintln!("dcb, {ranks} ranks: worst relative difference {worst:.2e}");
    }
}

/// Plane models over ranks (issue 39): the 2D DCB (CPE8 + LINE_INTER6,
/// two equations per node, the default control through its peak) and the
/// axisymmetric tubular lap joint (linear, CAX8 + axisymmetric line
/// interfaces) on 1 and 2 ranks against one process.
#[test]
fn plane_models_match_one_process_on_1_and_2_ranks() {
    let tmp = tempfile::tempdir().unwrap();
    for (scene, args, tol) in [
        (
            "examples/plane/dcb_plane_strain.toml",
            vec!["--max-increments", "25"],
            1e-7,
        ),
        ("examples/plane/tube_lap_joint.toml", vec![], 1e-8),
    ] {
        let path = repo(scene);
        let s = path.to_str().unwrap();
        let seq = tmp.path().join("seq");
        let mut a = vec!["run", s, "-o", seq.to_str().unwrap()];
        a.extend(&args);
        sequential(&a);
        for ranks in [1, 2] {
            let out = tmp.path().join(format!("np{ranks}"));
            let mut a = vec!["run", s, "-o", out.to_str().unwrap()];
            a.extend(&args);
            mpirun(ranks, &a);
            if scene.contains("dcb") {
                let worst =
                    assert_same_curve(&seq, &out, tol, &format!("{scene} on {ranks} ranks"));
                eprintln!("{scene}, {ranks} ranks: worst relative difference {worst:.2e}");
            } else {
                // the largest displacement and the film's peak shear
                let (s0, s1) = (summary(&seq), summary(&out));
                for (what, v0, v1) in [
                    (
                        "displacement_max",
                        &s0["displacement_max"],
                        &s1["displacement_max"],
                    ),
                    (
                        "traction_max",
                        &s0["interfaces"]["film"]["traction_max"][0],
                        &s1["interfaces"]["film"]["traction_max"][0],
                    ),
                ] {
                    let (v0, v1) = (v0.as_f64().unwrap(), v1.as_f64().unwrap());
                    eprintln!("{scene}, {ranks} ranks: {what} {v1:.12e} against {v0:.12e}");
                    assert!(
                        (v1 - v0).abs() <= tol * v0.abs(),
                        "{scene} on {ranks} ranks: {what} {v1} against {v0}"
                    );
                }
            }
            assert_eq!(summary(&out)["plane"], summary(&seq)["plane"]);
        }
    }
}

#[test]
fn a_fatigue_hold_and_a_laminate_of_seven_interfaces_match_one_process_on_1_2_4_ranks() {
    // dcb_paris: the static opening (100 increments), then the held
    // opening under cycle jumps, 24 increments of fatigue growth with
    // failed points; curved_beam_plane: an L-section of eight plies with
    // an interface between every pair (the lay-up builder, plane strain),
    // under the default control, 10 increments past the first failed point
    // (path following: each increment converged to its tolerance, not to
    // round-off, hence 1e-7 as for the other arc-length runs)
    let tmp = tempfile::tempdir().unwrap();
    for (scene, increments, tol) in [
        ("examples/fatigue/dcb_paris.toml", "125", 1e-8),
        ("examples/laminates/curved_beam_plane.toml", "60", 1e-7),
    ] {
        let path = repo(scene);
        let s = path.to_str().unwrap();
        let seq = tmp.path().join("seq");
        let args = |out: &Path| {
            let o = out.to_str().unwrap().to_string();
            vec![
                "run".to_string(),
                s.to_string(),
                "-o".into(),
                o,
                "--max-increments".into(),
                increments.into(),
            ]
        };
        let a = args(&seq);
        sequential(&a.iter().map(String::as_str).collect::<Vec<_>>());
        let (h, rows) = curve(&seq);
        let col = |name: &str| h.iter().position(|c| c == name).unwrap();
        let last = rows.last().unwrap();
        assert!(
            last[col("failed_points")] > 0.0,
            "{scene}: the parity reaches failed points"
        );
        for ranks in [1, 2, 4] {
            let out = tmp.path().join(format!("np{ranks}"));
            let a = args(&out);
            mpirun(ranks, &a.iter().map(String::as_str).collect::<Vec<_>>());
            let what = format!("{scene} on {ranks} ranks");
            let worst = assert_same_curve(&seq, &out, tol, &what);
            // the cycle count the jumps reach, to the same tolerance
            let (_, other) = curve(&out);
            let c = col("cycles");
            let scale = rows.iter().map(|r| r[c].abs()).fold(1.0, f64::max);
            for (ra, rb) in rows.iter().zip(&other) {
                assert!(
                    (ra[c] - rb[c]).abs() <= 1e-8 * scale,
                    "{what}: cycles {} against {}",
                    rb[c],
                    ra[c]
                );
            }
            eprintln!("{what}: worst relative difference {worst:.2e}");
        }
    }
}

#[test]
fn friction_lu_and_arc_length_snap_back_match_one_process() {
    // bilinear_friction: a nonsymmetric tangent (MUMPS LU); the coarse
    // DCB under arc length: snap-backs, negative pivots (MUMPS inertia)
    let tmp = tempfile::tempdir().unwrap();
    for (scene, tol) in [
        ("examples/interface_plasticity/debond_friction.toml", 1e-8),
        ("examples/delamination/dcb_coarse.toml", 1e-7),
    ] {
        let path = repo(scene);
        let s = path.to_str().unwrap();
        let seq = tmp.path().join("seq");
        sequential(&["run", s, "-o", seq.to_str().unwrap()]);
        let (h, rows) = curve(&seq);
        let neg = h.iter().position(|c| c == "negative_pivots").unwrap();
        let pivots: f64 = rows.iter().map(|r| r[neg]).sum();
        for ranks in [1, 2, 4] {
            let out = tmp.path().join(format!("np{ranks}"));
            mpirun(ranks, &["run", s, "-o", out.to_str().unwrap()]);
            let worst = assert_same_curve(&seq, &out, tol, &format!("{scene} on {ranks} ranks"));
            eprintln!("{scene}, {ranks} ranks: worst {worst:.2e}, negative pivots summed {pivots}");
            let solver = summary(&out)["solver"]["ordering"]
                .as_str()
                .unwrap_or("")
                .to_string();
            let expected = if scene.contains("friction") {
                "lu (mumps)"
            } else {
                "cholesky (mumps)"
            };
            assert!(solver.ends_with(expected), "{scene}: {solver}");
        }
        if scene.contains("coarse") {
            assert!(
                pivots > 10.0,
                "the snap-backs give negative pivots: {pivots}"
            );
        }
    }
}

#[test]
fn gamg_iterations_stay_within_30_percent_from_1_to_4_ranks() {
    // H8 cube, 24^3 elements (46,800 equations), GAMG + CG with the
    // rigid-body near-null space
    let tmp = tempfile::tempdir().unwrap();
    let scene = tmp.path().join("cube.toml");
    let text = std::fs::read_to_string(repo("examples/cube.toml")).unwrap();
    assert!(text.contains("divisions = [2, 2, 2]"));
    std::fs::write(
        &scene,
        text.replace("divisions = [2, 2, 2]", "divisions = [24, 24, 24]"),
    )
    .unwrap();
    let s = scene.to_str().unwrap();
    let mut its = Vec::new();
    for ranks in [1, 2, 4] {
        let out = tmp.path().join(format!("np{ranks}"));
        mpirun(
            ranks,
            &[
                "run",
                s,
                "-o",
                out.to_str().unwrap(),
                "--solver",
                "type=petsc",
                "--solver",
                "method=gamg",
                "--solver",
                "tolerance=1e-8",
            ],
        );
        let sum = summary(&out);
        its.push(sum["solver"]["iterations"].as_f64().unwrap());
        assert!(sum["solver"]["ordering"]
            .as_str()
            .unwrap()
            .contains("cg/gamg"));
    }
    eprintln!("GAMG iterations on 1, 2, 4 ranks: {its:?}");
    for &n in &its[1..] {
        assert!((n / its[0] - 1.0).abs() <= 0.3, "iterations {its:?}");
    }
    assert!(its[0] > 1.0 && its[0] < 200.0, "iterations {its:?}");
}

#[test]
fn a_rank_with_bad_input_or_a_failing_solve_ends_every_rank() {
    let tmp = tempfile::tempdir().unwrap();
    let good = repo("examples/delamination/dcb.toml");
    let bad = tmp.path().join("bad.toml");
    let text = std::fs::read_to_string(&good)
        .unwrap()
        .replace("G_Ic = ", "G_Ic = -");
    std::fs::write(&bad, text).unwrap();
    // every rank reads the bad scene
    let err = failed_run_on_two_ranks(&bad, &tmp.path().join("a"));
    assert!(err.contains("G_Ic"), "the message names the key: {err}");
    // rank 1 alone meets bad input while rank 0 runs the good scene and
    // waits for it in the first collective
    let out = timed_mpirun(120)
        .args(["-np", "1"])
        .arg(junta())
        .args(["run", good.to_str().unwrap(), "-q", "-o"])
        .arg(tmp.path().join("b"))
        .args([":", "-np", "1"])
        .arg(junta())
        .args(["run", bad.to_str().unwrap(), "-q", "-o"])
        .arg(tmp.path().join("c"))
        .output()
        .unwrap();
    let err = assert_every_rank_ended(&out);
    assert!(err.contains("rank 1 of 2") && err.contains("G_Ic"), "{err}");
    // a failing solve: nothing holds the cube (no boundary condition)
    let deck = tmp.path().join("free.inp");
    let free = cube_c3d20(2).replace("*BOUNDARY\nBOTTOM, 1, 3\n", "");
    std::fs::write(
        &deck,
        free.replace("*BOUNDARY\nTOP, 3, 3, -0.01\n", "*CLOAD\nTOP, 3, -1.\n"),
    )
    .unwrap();
    let err = failed_run_on_two_ranks(&deck, &tmp.path().join("d"));
    assert!(err.contains("pivot") || err.contains("singular"), "{err}");
}

#[test]
fn a_rank_out_of_memory_ends_every_rank() {
    // the H8 cube 50^3 (390,000 equations, about 2 GB of address space per
    // rank on 2 ranks) with rank 1 limited to 1.3 GB of address space
    // (`ulimit -v`; a small model starts within 1.2 GB). MUMPS on rank 1
    // runs out of memory in the factorisation, which every rank reports as
    // "not enough memory" (a failed allocation of Junta's own would abort
    // rank 1, and mpirun end rank 0, waiting in a collective, as well)
    let tmp = tempfile::tempdir().unwrap();
    let scene = tmp.path().join("cube.toml");
    let text = std::fs::read_to_string(repo("examples/cube.toml")).unwrap();
    std::fs::write(
        &scene,
        text.replace("divisions = [2, 2, 2]", "divisions = [50, 50, 50]"),
    )
    .unwrap();
    let (bin, s) = (junta(), scene.to_str().unwrap());
    let limited = format!(
        "ulimit -v 1300000; exec {} run {s} -q -o {}",
        bin.display(),
        tmp.path().join("b").display()
    );
    let out = timed_mpirun(300)
        .args(["-np", "1"])
        .arg(&bin)
        .args(["run", s, "-q", "-o"])
        .arg(tmp.path().join("a"))
        .args([":", "-np", "1", "sh", "-c", &limited])
        .output()
        .unwrap();
    let err = assert_every_rank_ended(&out);
    assert!(
        err.contains("not enough memory") || err.contains("memory allocation"),
        "{err}"
    );
}

/// `junta run INPUT -o OUT` on 2 ranks, which must end every rank with an
/// error ([`assert_every_rank_ended`]); its stderr.
fn failed_run_on_two_ranks(input: &Path, out: &Path) -> String {
    let args = ["run", input.to_str().unwrap(), "-o", out.to_str().unwrap()];
    assert_every_rank_ended(&mpirun_with(2, 120, &args))
}

/// The run failed, not by the `timeout` around `mpirun` (exit 124: a rank
/// that hung; no wall clock of the test's own, which a busy machine would
/// trip); its stderr.
fn assert_every_rank_ended(out: &Output) -> String {
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!out.status.success(), "the run must fail: {err}");
    assert_ne!(out.status.code(), Some(124), "timed out: {err}");
    err
}

#[test]
fn restart_on_another_rank_count_continues_the_curve() {
    // dcb_coarse under arc length: 2 ranks for 40 increments, then 2, 4
    // and 1 ranks to the end, against the run in one process. Bit for bit
    // only on one rank: two uninterrupted 2-rank runs differ in the last
    // bits now and then (4 of 54 here, by up to 1.4e-8 after Newton's
    // tolerance; likely MUMPS's dynamic scheduling, docs/distributed.md),
    // and a restart cannot do better than that
    let tmp = tempfile::tempdir().unwrap();
    let path = repo("examples/delamination/dcb_coarse.toml");
    let s = path.to_str().unwrap();
    let seq = tmp.path().join("seq");
    sequential(&["run", s, "-o", seq.to_str().unwrap()]);
    for ranks in [2, 4, 1] {
        let out = tmp.path().join(format!("restart{ranks}"));
        let o = out.to_str().unwrap();
        mpirun(2, &["run", s, "-o", o, "--max-increments", "40"]);
        assert_eq!(curve(&out).1.len(), 40);
        mpirun(ranks, &["run", "--restart", o]);
        let worst = assert_same_curve(&seq, &out, 1e-7, &format!("restart on {ranks} ranks"));
        eprintln!("restart from 2 on {ranks} ranks: worst {worst:.2e}");
    }
    let whole = tmp.path().join("np1");
    mpirun(1, &["run", s, "-o", whole.to_str().unwrap()]);
    let out = tmp.path().join("np1_restart");
    let o = out.to_str().unwrap();
    mpirun(1, &["run", s, "-o", o, "--max-increments", "40"]);
    mpirun(1, &["run", "--restart", o]);
    assert_same_curve(&whole, &out, 0.0, "restart on the same rank");
    let iterations = |d: &Path| {
        let (h, rows) = curve(d);
        let c = h.iter().position(|c| c == "newton_iterations").unwrap();
        rows.iter().map(|r| r[c]).collect::<Vec<_>>()
    };
    assert_eq!(iterations(&whole), iterations(&out));
}
