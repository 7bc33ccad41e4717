//! The AMG back end (`[solver] type = "cg"`, `preconditioner = "amg"`) on
//! layered models with interface elements, run through `junta run`.

mod common;

use common::*;

/// `layers` steel plates 1 x 1 x 0.2 (each `[n, n, m]` H8) stacked in z and
/// joined by INTER8 interfaces with a linear penalty `d`. `bonded`: bottom
/// face clamped, top face pulled in x and z. Otherwise every plate is held
/// on its own x0 face (cantilevers) and loaded by a z displacement of its
/// own x1 edge face, so it needs no interface to be stable.
fn stack(layers: usize, n: usize, m: usize, d: f64, bonded: bool, solver: &str) -> String {
    let mut s = String::from(
        "[model]\ntitle = \"stack\"\nunits = \"N, mm\"\n\n[materials.steel]\ntype = \"isotropic\"\nE = 210000.0\nnu = 0.3\n\n",
    );
    s += &format!(
        "[laws.bond]\ntype = \"linear_penalty\"\nd = {d:e}\n\n[mesh]\ntype = \"boxes\"\n\n"
    );
    for l in 0..layers {
        s += &format!(
            "[[mesh.boxes]]\nname = \"p{l}\"\norigin = [0.0, 0.0, {}]\nsize = [1.0, 1.0, 0.2]\ndivisions = [{n}, {n}, {m}]\nelement = \"h8\"\nmaterial = \"steel\"\n\n",
            0.2 * l as f64
        );
    }
    for l in 1..layers {
        s += &format!(
            "[[interface]]\nname = \"i{l}\"\nbetween = [\"p{}\", \"p{l}\"]\nlaw = \"bond\"\n\n",
            l - 1
        );
    }
    if bonded {
        s += "[[boundary]]\nset = \"p0.z0\"\nfixed = \"all\"\n\n";
        s += &format!(
            "[[boundary]]\nset = \"p{}.z1\"\ndisplacement = {{ x = 0.001, z = 0.002 }}\n\n",
            layers - 1
        );
    } else {
        for l in 0..layers {
            s += &format!("[[boundary]]\nset = \"p{l}.x0\"\nfixed = \"all\"\n\n");
            s += &format!(
                "[[boundary]]\nset = \"p{l}.x1\"\ndisplacement = {{ z = {} }}\n\n",
                0.001 * (l + 1) as f64
            );
        }
    }
    s + "[solver]\n" + solver + "\n"
}

/// Run a scene that must fail; its stderr.
fn scene_err(text: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("s.toml");
    std::fs::write(&p, text).unwrap();
    run_err(&p)
}

fn run_scene(text: &str) -> serde_json::Value {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("s.toml");
    std::fs::write(&p, text).unwrap();
    run_ok(&p, &dir.path().join("out"))
}

const AMG: &str = "type = \"cg\"\npreconditioner = \"amg\"\ntol = 1e-10";

/// Measured: 19 iterations on 3 plates of 8 x 8 x 2 H8 (1782 equations),
/// 17 on 16 x 16 x 4 (8x the elements, 11560 equations).
#[test]
fn amg_cg_solves_a_bonded_stack_with_mesh_independent_iterations() {
    // penalty: 1e7 N/mm^3 (E / h_element = 210000 / 0.05 = 4.2e6 N/mm^3;
    // the advisor recommends 1.3e12 for round-off-limited accuracy, see
    // the penalty sweep in the README for AMG at higher penalties)
    let mut counts = Vec::new();
    for (n, m) in [(8, 2), (16, 4)] {
        let s = run_scene(&stack(3, n, m, 1e7, true, AMG));
        let it = s["solver"]["iterations"].as_u64().unwrap();
        let res = s["solver"]["residual"].as_f64().unwrap();
        eprintln!(
            "n = {n}: {it} iterations, residual {res:.2e}, {}",
            s["solver"]["notes"]
        );
        assert!(res <= 1e-10, "residual {res:e}");
        counts.push(it);
        // the same model solved directly
        let c = run_scene(&stack(3, n, m, 1e7, true, "type = \"cholesky\""));
        let (ra, rc) = (&s["reactions"]["p0.z0"], &c["reactions"]["p0.z0"]);
        for k in 0..3 {
            let (a, b) = (ra[k].as_f64().unwrap(), rc[k].as_f64().unwrap());
            assert!(
                (a - b).abs() <= 1e-7 * b.abs().max(1.0),
                "reaction {k}: amg {a}, cholesky {b}"
            );
        }
    }
    assert!(
        counts[1] as f64 <= 1.5 * counts[0] as f64,
        "iterations {counts:?}"
    );
}

/// The bonded stack (3 plates of 8 x 8 x 2 H8) as the penalty grows from
/// 1e7 to the penalty advisor's recommended d_op (1.34e12 N/mm^3 here, read
/// from the run's `penalty_advice`). Measured: 16, 17, 17 AMG-CG iterations
/// at d = 1e7, 1e9, 1e11 (tol 1e-10) and 15 at d_op (tol 1e-9: at d_op the
/// round-off floor of the residual, eps |||K| |u||| / ||f||, is 2.3e-10, and
/// CG says so when asked for 1e-10). Nodes tied by the bond are one block
/// of the smoother and one aggregate; smoothed node by node
/// (`amg_bonded_clusters = false`) the count grows with the penalty (19,
/// 154, 510), and capped at 60 iterations it stops with its numbers.
#[test]
fn amg_iterations_stay_bounded_up_to_the_advisors_penalty() {
    let first = run_scene(&stack(3, 8, 2, 1e7, true, AMG));
    let d_op = first["penalty_advice"]["i1"]["d_op"].as_f64().unwrap();
    assert!(d_op > 1e11, "advisor's d_op {d_op:e}");
    let base = first["solver"]["iterations"].as_u64().unwrap();
    for d in [1e9, 1e11, d_op] {
        let tol = if d < 1e12 { 1e-10 } else { 1e-9 };
        let solver = format!("type = \"cg\"\npreconditioner = \"amg\"\ntol = {tol:e}");
        let s = run_scene(&stack(3, 8, 2, d, true, &solver));
        let it = s["solver"]["iterations"].as_u64().unwrap();
        let res = s["solver"]["residual"].as_f64().unwrap();
        eprintln!("d = {d:e}: {it} iterations, residual {res:.2e}");
        assert!(res <= tol, "d = {d:e}: residual {res:e}");
        assert!(
            it as f64 <= 1.5 * base as f64,
            "d = {d:e}: {it} iterations against {base} at d = 1e7"
        );
        let c = run_scene(&stack(3, 8, 2, d, true, "type = \"cholesky\""));
        let (ra, rc) = (&s["reactions"]["p0.z0"], &c["reactions"]["p0.z0"]);
        for k in [0, 2] {
            let (a, b) = (ra[k].as_f64().unwrap(), rc[k].as_f64().unwrap());
            assert!(
                (a - b).abs() <= 1e-6 * b.abs(),
                "d = {d:e}, reaction {k}: amg {a}, cholesky {b}"
            );
        }
    }
    // node-by-node smoothing stalls at a stiff penalty, with its numbers
    let solver = format!("{AMG}\nmax_iterations = 60\namg_bonded_clusters = false");
    let err = scene_err(&stack(3, 8, 2, 1e11, true, &solver));
    assert!(
        err.contains("did not converge") && err.contains("after 60 iterations"),
        "{err}"
    );
}

/// At a penalty so stiff that the residual cannot be resolved to the
/// requested tolerance, CG names the round-off floor instead of a bare
/// non-convergence.
#[test]
fn cg_names_the_round_off_floor_of_an_unreachable_tolerance() {
    let err = scene_err(&stack(3, 8, 2, 1e14, true, AMG));
    assert!(
        err.contains("round-off floor") && err.contains("raise it"),
        "{err}"
    );
}

/// A fully failed interface (penalty 1e-3 N/mm^3, 10 orders below the
/// solids' nodal stiffness): three loose plates, each a cantilever held by
/// its own supports. Measured (3 plates of 16 x 16 x 4 H8, 11k equations):
/// 16 AMG-CG iterations with aggregates that stay inside the plates, 48
/// when the model is treated as one body (aggregates straddle the failed
/// interfaces, so the coarse space ties the plates together), and 17 / 22
/// on the 8 x 8 x 2 mesh: without the per-body space the count grows with
/// the mesh. Capped at 30 iterations, the one-body hierarchy stops with a
/// typed non-convergence error that states its numbers.
#[test]
fn failed_interface_needs_per_body_aggregation() {
    let scene = |per_body: bool| {
        stack(
            3,
            16,
            4,
            1e-3,
            false,
            &format!("{AMG}\nmax_iterations = 30\namg_per_body = {per_body}"),
        )
    };
    let s = run_scene(&scene(true));
    let it = s["solver"]["iterations"].as_u64().unwrap();
    assert!(it <= 30, "{it}");
    assert!(s["solver"]["residual"].as_f64().unwrap() <= 1e-10);
    assert!(s["solver"]["notes"].to_string().contains("3 bodies"));
    let err = scene_err(&scene(false));
    assert!(
        err.contains("did not converge") && err.contains("after 30 iterations"),
        "{err}"
    );
}

/// `--export-matrix`: K.mtx read back with sprs equals the stiffness
/// assembled here from the same model (cube of 3^3 H8, bottom clamped, top
/// displaced), b.mtx equals `-K_fc u_c` (the load of the prescribed
/// displacements), and B.mtx holds rigid-body modes (translations).
#[test]
fn export_matrix_reads_back_as_the_assembled_matrix() {
    use junta_core::element::StepInfo;
    use junta_core::mesh::generate::{box_mesh, BoxSpec};
    use junta_core::topology::CellShape;
    use junta_core::Model;
    use junta_elements::{Integration, Isotropic, SolidElement};
    use std::sync::Arc;

    let dir = tempfile::tempdir().unwrap();
    let scene = std::fs::read_to_string(repo().join("examples/cube.toml"))
        .unwrap()
        .replace("divisions = [2, 2, 2]", "divisions = [3, 3, 3]");
    let p = write(dir.path(), "cube.toml", &scene);
    let mx = dir.path().join("mx");
    let out = junta()
        .arg("run")
        .arg(&p)
        .arg("-o")
        .arg(dir.path().join("out"))
        .arg("-q")
        .arg("--export-matrix")
        .arg(&mx)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let kr: sprs::TriMat<f64> = sprs::io::read_matrix_market(mx.join("K.mtx")).unwrap();
    let kr: sprs::CsMat<f64> = kr.to_csr();

    let mesh = box_mesh(
        &BoxSpec::new([1.0; 3], [3; 3], CellShape::Hex8),
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
    for &i in mesh.node_set("z1").unwrap() {
        c.push((3 * i + 2, -0.01));
    }
    let f = vec![0.0; 3 * mesh.nodes.len()];
    let model = Model::new(mesh, vec![el], &c, f, vec![]).unwrap();
    let asm = model.assembler();
    let mut k = asm.pattern.clone();
    let mut f_int = vec![0.0; model.dofs.num_dofs()];
    asm.assemble(
        &model.mesh,
        &model.elements,
        &model.dofs,
        &model.dofs.expand(None, 1.0),
        &mut model.initial_state(),
        StepInfo::default(),
        Some(&mut k),
        &mut f_int,
    )
    .unwrap();
    assert_eq!(kr.rows(), k.n);
    // every entry of both triangles, and nothing else
    let mut count = 0;
    for j in 0..k.n {
        for p in k.col_ptr[j]..k.col_ptr[j + 1] {
            let i = k.row_idx[p];
            for (r, c) in [(i, j), (j, i)] {
                let v = *kr.get(r, c).unwrap_or(&f64::NAN);
                assert!(
                    (v - k.values[p]).abs() <= 1e-14 * k.values[p].abs().max(1.0),
                    "K[{r},{c}]: read {v}, assembled {}",
                    k.values[p]
                );
            }
            count += if i == j { 1 } else { 2 };
        }
    }
    assert_eq!(kr.nnz(), count);
    // b = -f_int(u_c) on the free dofs
    let b: Vec<f64> = std::fs::read_to_string(mx.join("b.mtx"))
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('%'))
        .skip(1)
        .map(|l| l.trim().parse().unwrap())
        .collect();
    let fi = model.dofs.reduce(&f_int);
    assert_eq!(b.len(), k.n);
    assert!(b.iter().any(|v| v.abs() > 1.0));
    for (a, e) in b.iter().zip(&fi) {
        assert!((a + e).abs() <= 1e-12 * e.abs().max(1.0));
    }
    // B: first column is the x translation
    let bm: Vec<f64> = std::fs::read_to_string(mx.join("B.mtx"))
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('%'))
        .skip(1)
        .map(|l| l.trim().parse().unwrap())
        .collect();
    assert_eq!(bm.len(), 6 * k.n);
    let layout = model.equation_layout();
    for (v, &c) in bm.iter().zip(&layout.component) {
        assert_eq!(*v, if c == 0 { 1.0 } else { 0.0 });
    }
}

/// `[solver] type = "auto"` on a model above 150,000 equations whose direct
/// factor would need more than half the memory available (here 0.2 GB, set
/// by `JUNTA_MEMORY_LIMIT`; the factor would need 1.4 GB): the factor is
/// never attempted, AMG is taken, with GMRES when a law can soften (the
/// tangent can be indefinite) and CG otherwise, and `summary.json` says
/// which and why. Two 10 x 10 x 5 mm blocks of 37 x 37 x 18 H8 (158,840
/// equations) joined by a bilinear (softening) or a linear interface.
#[test]
fn auto_takes_amg_when_the_direct_factor_would_not_fit() {
    let scene =
        std::fs::read_to_string(repo().join("crates/cli/tests/data/auto_amg_big.toml")).unwrap();
    let linear = scene
        .replace(
            "type = \"bilinear\"",
            "type = \"linear_penalty\"\nd = 100000.0",
        )
        .lines()
        .filter(|l| {
            !["K =", "N =", "S =", "G_I", "eta ="]
                .iter()
                .any(|k| l.starts_with(k))
        })
        .collect::<Vec<_>>()
        .join("\n");
    for (text, method) in [(scene.as_str(), "gmres"), (linear.as_str(), "cg")] {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("s.toml");
        std::fs::write(&p, text).unwrap();
        let out = junta()
            .args(["run", "-q", "-o"])
            .arg(dir.path().join("out"))
            .arg(&p)
            .env("JUNTA_MEMORY_LIMIT", "2e8")
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let s: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(dir.path().join("out/summary.json")).unwrap(),
        )
        .unwrap();
        let solver = &s["solver"];
        assert_eq!(solver["name"], method, "{solver}");
        let notes = solver["notes"].to_string();
        assert!(
            notes.contains("more than half of the 0.2 GB available")
                && notes.contains(&format!("using {method} with the smoothed-aggregation AMG")),
            "{notes}"
        );
        // equilibrium of the iterative solution: the two reactions balance
        let (lo, up) = (
            s["reactions"]["lower.z0"][2].as_f64().unwrap(),
            s["reactions"]["upper.z1"][2].as_f64().unwrap(),
        );
        assert!(lo < 0.0 && (lo + up).abs() <= 1e-8 * up.abs(), "{lo} {up}");
    }
}
