//! The delamination benchmarks of examples/delamination/ on their own
//! meshes, cut short so that the suite stays fast: the DCB to just before
//! its peak, the ENF up to 2 mm. References: beam theory, BENCHMARKS.md
//! section 4 (corrected beam theory for the DCB: compliance
//! 2 a_e^3 / (3 E11 I), peak 138.5 N at 4.21 mm; ENF: C(a0) =
//! (3 a0^3 + 2 L^3) / (8 E11 b h^3) = 4.313e-3 mm/N).

mod common;
use common::*;
use std::path::Path;

/// Columns of curve.csv by name.
fn curve(dir: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(dir.join("curve.csv")).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    (header, rows)
}

fn column(c: &(Vec<String>, Vec<Vec<String>>), name: &str) -> Vec<f64> {
    let k =
        c.0.iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name}"));
    c.1.iter()
        .map(|r| r[k].parse().unwrap_or(f64::NAN))
        .collect()
}

fn run_incremental(input: &Path, dir: &Path, max_increments: usize) -> serde_json::Value {
    run_ok_with(
        input,
        dir,
        &["--max-increments", &max_increments.to_string()],
    )
}

#[test]
fn dcb_follows_corrected_beam_theory_to_the_peak() {
    let dir = tempfile::tempdir().unwrap();
    let ex = repo().join("examples/delamination/dcb.toml");
    // 42 increments of 0.1 mm: delta = 4.2 mm, just before the peak
    let s = run_incremental(&ex, dir.path(), 42);
    // the solver auto choice for a softening law, with its inertia
    assert_eq!(s["solver"]["name"], "ldlt", "{}", s["solver"]);
    let c = curve(dir.path());
    let delta = column(&c, "displacement");
    let p = column(&c, "reaction");
    let np = column(&c, "negative_pivots");
    assert!((delta[41] - 4.2).abs() < 1e-9, "opening {}", delta[41]);
    // linear branch: corrected beam theory stiffness 3 E11 I / (2 a_e^3)
    let (e11, b, h, a0) = (122700.0f64, 25.4f64, 1.56f64, 32.9f64);
    let gamma = 1.18 * (e11 * 10100.0f64).sqrt() / 5500.0;
    let chi = (e11 / (11.0 * 5500.0) * (3.0 - 2.0 * (gamma / (1.0 + gamma)).powi(2))).sqrt();
    let ae = a0 + chi * h;
    let ei = e11 * b * h.powi(3) / 12.0;
    let k_cbt = 3.0 * ei / (2.0 * ae.powi(3));
    let k = p[9] / delta[9]; // delta = 1 mm
    assert!(
        (k / k_cbt - 1.0).abs() < 0.05,
        "DCB stiffness {k:.3} N/mm against corrected beam theory {k_cbt:.3} N/mm"
    );
    // load at 4.2 mm against the CBT curve there (linear branch, the peak
    // is at 4.21 mm): the cohesive zone makes it a little more compliant
    let p_cbt = k_cbt * 4.2;
    assert!(
        (p[41] / p_cbt - 1.0).abs() < 0.05,
        "P(4.2 mm) = {:.2} N against corrected beam theory {p_cbt:.2} N",
        p[41]
    );
    // stable branch: the tangent stays positive definite (ldlt's inertia)
    assert!(np.iter().all(|&n| n == 0.0), "negative pivots {np:?}");
    // energy: no point dissipates more than G_Ic per unit area (the
    // damage >= 0.99 of the damaged area is reached long before the end of
    // the softening branch when K is large: lam_f / lam_0 = 303 here)
    let bond = &s["interfaces"]["bond"];
    let (w, a_d, a_pz) = (
        bond["dissipated_energy"].as_f64().unwrap(),
        bond["damaged_area"].as_f64().unwrap(),
        bond["process_zone_area"].as_f64().unwrap(),
    );
    assert!(a_pz > 0.0, "a process zone exists before the peak");
    assert!(w > 0.0 && w <= 0.969 * (a_d + a_pz), "{w} {a_d} {a_pz}");
    let v = bond["viscous_energy"].as_f64().unwrap();
    // the regularisation dissipates what the small element-by-element
    // snap-backs release (about a quarter of the fracture energy here)
    assert!(v >= 0.0 && v < 0.5 * w, "viscous {v} against fracture {w}");
    // mesh advice: the example's mesh is the coarsest the advice accepts
    let advice = &s["mesh_advice"]["bond"];
    assert_eq!(advice["verdict"], "adequate", "{advice}");
    let n_e = advice["elements_in_zone"].as_f64().unwrap();
    assert!((3.0..3.5).contains(&n_e), "{n_e}");
    // Rice's length for AS4/PEEK mode I: 0.88 E22 G_Ic / N^2 (BENCHMARKS 4)
    let l = advice["mode_i"]["rice"].as_f64().unwrap();
    assert!((l - 0.88 * 10100.0 * 0.969 / 6400.0).abs() < 1e-9 * l);
    // the law warns about Turon's consistency condition
    let warnings = s["warnings"].to_string();
    assert!(warnings.contains("turon2018"), "{warnings}");
}

#[test]
fn enf_compliance_against_beam_theory_and_precrack_contact() {
    let dir = tempfile::tempdir().unwrap();
    let ex = repo().join("examples/delamination/enf.toml");
    // 0.045 mm per increment: 2.0 mm of deflection in 45 increments
    let s = run_incremental(&ex, dir.path(), 45);
    let c = curve(dir.path());
    let delta = column(&c, "displacement");
    let p = column(&c, "reaction");
    let last = delta.len() - 1;
    assert!(
        (delta[last] - 2.025).abs() < 1e-6,
        "deflection {}",
        delta[last]
    );
    let (e11, b, h, a0, l) = (122700.0f64, 25.4f64, 1.56f64, 37.5f64, 50.0f64);
    let c_bt = (3.0 * a0.powi(3) + 2.0 * l.powi(3)) / (8.0 * e11 * b * h.powi(3));
    let compliance = delta[last] / p[last];
    // beam theory leaves out shear deformation (E11/G13 = 22): the 3D model
    // is 4-6 % more compliant
    let ratio = compliance / c_bt;
    assert!(
        (1.0..1.07).contains(&ratio),
        "ENF compliance {compliance:.4e} mm/N against beam theory {c_bt:.4e} (ratio {ratio:.4})"
    );
    // the precracked faces press on each other through the contact law:
    // they do not interpenetrate by more than the penalty allows
    let pre = &s["interfaces"]["bond.precrack"];
    let jmin = pre["jump_min"][2].as_f64().unwrap();
    assert!(jmin > -1e-4, "precrack interpenetration {jmin}");
    assert!(
        pre["traction_min"][2].as_f64().unwrap() < 0.0,
        "no contact pressure"
    );
}

/// Without regularisation, displacement control stops just past the DCB's
/// peak (the first elements to separate snap back): the run says so, with
/// the peak, instead of a bare non-convergence.
#[test]
fn dcb_without_regularisation_stops_past_the_peak_and_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let ex = repo().join("examples/delamination");
    let text = std::fs::read_to_string(ex.join("dcb.toml")).unwrap();
    let text: String = text
        .lines()
        .filter(|l| !l.starts_with("viscosity"))
        .map(|l| {
            l.replace(
                "dcb_beam_theory.csv",
                &ex.join("dcb_beam_theory.csv").display().to_string(),
            ) + "\n"
        })
        .collect();
    // displacement control alone (the default `auto` would take over)
    let text = text.replacen(
        "type = \"static\"",
        "type = \"static\"\ncontrol = \"displacement\"",
        1,
    );
    let scene = dir.path().join("dcb_plain.toml");
    std::fs::write(&scene, text).unwrap();
    let out = junta()
        .arg("run")
        .arg(&scene)
        .arg("-o")
        .arg(dir.path().join("out"))
        .arg("-q")
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("snap-back") && err.contains("viscosity"),
        "{err}"
    );
    // the peak it names is the corrected-beam-theory peak within 3 %
    let peak: f64 = err
        .split("peaked at ")
        .nth(1)
        .and_then(|s| s.split_whitespace().next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no peak in: {err}"));
    assert!((peak / 138.51 - 1.0).abs() < 0.03, "peak {peak}");
    // the converged increments are on disk, the last one as a frame
    assert!(dir.path().join("out/checkpoint.json").exists());
}

/// The cohesive-zone mesh advice sizes a triangle by its shortest edge:
/// on the T3 prism cut into 4 x 2 cells of 0.05 x 0.1 (a bilinear law),
/// the wedge6 + INTER6 mesh gets the same advice as the h8 + INTER8 mesh
/// of the same cells (element length 0.05, the quadrilateral's shorter
/// side; same moduli and arm thickness), `junta check`'s advice line.
#[test]
fn mesh_advice_sizes_triangles_like_their_cells() {
    let text = std::fs::read_to_string(repo().join("examples/paper/prism_tension.toml"))
        .unwrap()
        .replace(
            "type = \"linear_penalty\"\nd = 1.0e25",
            "type = \"bilinear\"\nK = 1.0e14\nN = 8.0e7\nS = 1.0e8\nG_Ic = 500.0\nG_IIc = 1000.0\neta = 2.0",
        )
        .replace("divisions = [1, 1, 1]", "divisions = [4, 2, 1]");
    assert!(text.contains("bilinear"));
    let dir = tempfile::tempdir().unwrap();
    let advice = |element: &str| {
        let scene = write(
            dir.path(),
            &format!("{element}.toml"),
            &text.replace("element = \"h27\"", &format!("element = \"{element}\"")),
        );
        let out = junta().arg("check").arg(&scene).output().unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let s = String::from_utf8_lossy(&out.stdout).to_string();
        s.lines()
            .find(|l| l.contains("mesh advice"))
            .unwrap_or_else(|| panic!("no advice in {s}"))
            .to_string()
    };
    let (w, h) = (advice("wedge6"), advice("h8"));
    assert!(w.contains("5.000e-2 .. 5.000e-2 long"), "{w}");
    assert_eq!(w, h);
}
