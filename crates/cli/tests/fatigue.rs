//! The cycle-jump driver (issue 26, part 2): `[fatigue]` after the load
//! program, on `examples/fatigue/held_opening.toml` (two stiff blocks bonded
//! by a `fatigue_bilinear` interface, the opening held). Under a held jump
//! the law's closed form is linear in the cycles (Turon et al. 2007's
//! rate at a constant G_max), so every row of the fatigue step is checked
//! against it.

mod common;
use common::*;
use std::path::Path;

// the example's law and load (mm, N, MPa)
const K: f64 = 1.0e6;
const N: f64 = 80.0;
const G_C: f64 = 0.969;
const C_I: f64 = 0.02;
const M_I: f64 = 5.0;
const L_CZ: f64 = 1.0;
const DELTA: f64 = 0.001;
const R: f64 = 0.1;
const AREA: f64 = 1.0;

/// `(D_0, r)`: the energy damage the static opening leaves and the
/// fatigue rate per cycle at the held jump, from the bilinear curve
/// (onset `N / K`, final jump `2 G_c / N`) and the Paris law of Turon et
/// al. 2007: `r = C (DG / G_c)^m / l_cz`, `DG = (1 - R^2) G_max`, `G_max`
/// the area under the static curve up to the jump.
fn closed_form() -> (f64, f64) {
    closed_form_at(DELTA, R)
}

/// [`closed_form`] at the opening `delta` and load ratio `r`.
fn closed_form_at(delta: f64, r: f64) -> (f64, f64) {
    let (l0, lf) = (N / K, 2.0 * G_C / N);
    let d0 = (delta - l0) / (lf - l0);
    let g_max =
        0.5 * N * l0 + N * (lf * (delta - l0) - 0.5 * (delta * delta - l0 * l0)) / (lf - l0);
    let dg = (1.0 - r * r) * g_max;
    (d0, C_I * (dg / G_C).powf(M_I) / L_CZ)
}

/// `(step, cycles, dissipated energy)` of every row.
fn rows(dir: &Path) -> Vec<(usize, f64, f64)> {
    let text = std::fs::read_to_string(dir.join("curve.csv")).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| head.iter().position(|h| *h == n).unwrap();
    let (s, c, d) = (col("step"), col("cycles"), col("dissipated_energy"));
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (
                f[s].parse().unwrap(),
                f[c].parse().unwrap(),
                f[d].parse().unwrap(),
            )
        })
        .collect()
}

fn scene_with(dir: &Path, name: &str, edit: impl Fn(String) -> String) -> std::path::PathBuf {
    let text = std::fs::read_to_string(repo().join("examples/fatigue/held_opening.toml")).unwrap();
    write(dir, name, &edit(text))
}

/// Every row of the fatigue step dissipates `G_c A min(1, D_0 + r N)`
/// (1e-4: the blocks' compliance moves the jump by 1e-6 of it), the
/// cycles run to the end of the step, the jumps are bounded by
/// `max_damage_increment`, and halving it gives the same curve at the
/// cycles both reach (1e-5). Measured: within 2.3e-6 of the closed form;
/// N_f = 1.7732e7 cycles.
#[test]
fn held_opening_grows_damage_at_the_closed_form_rate() {
    let (d0, r) = closed_form();
    let dir = tempfile::tempdir().unwrap();
    let mut curves = Vec::new();
    for (name, increment) in [("coarse", 0.05), ("fine", 0.025)] {
        let input = scene_with(dir.path(), &format!("{name}.toml"), |t| {
            t.replace(
                "max_damage_increment = 0.05",
                &format!("max_damage_increment = {increment}"),
            )
        });
        let out = dir.path().join(name);
        let s = run_ok(&input, &out);
        assert_eq!(s["status"], "completed", "{s}");
        assert_eq!(
            s["fatigue"]["cycles"].as_f64(),
            Some(2.0e7),
            "{}",
            s["fatigue"]
        );
        assert_eq!(s["fatigue"]["load_ratio"].as_f64(), Some(R));
        let rows = rows(&out);
        let fatigue: Vec<_> = rows.iter().filter(|r| r.0 == 1).collect();
        assert_eq!(fatigue.last().unwrap().1, 2.0e7);
        let mut last = 0.0;
        for &&(_, cycles, dissipated) in &fatigue {
            let expect = G_C * AREA * (d0 + r * cycles).min(1.0);
            assert!(
                (dissipated - expect).abs() <= 1e-4 * expect,
                "{name}: N = {cycles}: {dissipated} against {expect}"
            );
            // one jump grows the damage by at most the allowed amount
            assert!(
                dissipated - last <= increment * G_C * AREA * (1.0 + 1e-4) || last == 0.0,
                "{name}: N = {cycles}: a jump of {}",
                dissipated - last
            );
            last = dissipated;
        }
        curves.push(fatigue.iter().map(|r| (r.1, r.2)).collect::<Vec<_>>());
    }
    println!("N_f = {:.6e} cycles (closed form)", (1.0 - d0) / r);
    // the fine run passes through the coarse run's cycles: same energy
    for (cycles, d) in &curves[0] {
        if let Some((_, e)) = curves[1]
            .iter()
            .find(|(c, _)| (c - cycles).abs() < 1e-6 * cycles)
        {
            // the blocks' compliance lets the jump drift by 1e-6 with the
            // damage, so the rate is constant to that only
            assert!(
                (d - e).abs() <= 1e-5 * d.abs(),
                "N = {cycles}: {d} against {e}"
            );
        }
    }
    assert!(curves[1].len() > curves[0].len() + 10);
}

/// A run stopped inside the fatigue step and restarted gives the
/// uninterrupted curve bit for bit (the cycle count is part of the
/// cursor).
#[test]
fn restart_inside_the_fatigue_step_repeats_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let input = repo().join("examples/fatigue/held_opening.toml");
    let whole = dir.path().join("whole");
    run_ok(&input, &whole);
    let parts = dir.path().join("parts");
    let first = run_ok_with(&input, &parts, &["--max-increments", "12"]);
    assert_ne!(first["status"], "completed");
    let stopped = rows(&parts);
    assert!(
        stopped.last().unwrap().0 == 1 && stopped.last().unwrap().1 > 0.0,
        "{stopped:?}"
    );
    restart_ok(&parts);
    assert_eq!(curve_without_seconds(&whole), curve_without_seconds(&parts));
}

/// Block loading: 5e6 cycles at the example's opening (R = 0.1), then the
/// opening raised by a fifth (a static step, the cycles held) and 1e7
/// cycles at R = 0.2. The energy damage grows at the first block's rate,
/// keeps its value through the ramp (above the static damage of the new
/// opening), then grows at the second block's rate until the point fails:
/// every row against that piecewise closed form.
#[test]
fn blocks_of_different_amplitude_grow_damage_block_by_block() {
    let dir = tempfile::tempdir().unwrap();
    let input = scene_with(dir.path(), "blocks.toml", |t| {
        t.replace(
            "cycles = 2.0e7",
            "blocks = [{ load = 1.0, cycles = 5.0e6 }, { load = 1.2, cycles = 1.0e7, load_ratio = 0.2 }]",
        )
    });
    let out = dir.path().join("blocks");
    let s = run_ok(&input, &out);
    assert_eq!(s["status"], "completed", "{s}");
    let blocks = s["fatigue"]["blocks"].as_array().unwrap();
    assert_eq!(blocks.len(), 2, "{s}");
    // steps: 0 loading, 1 first block, 2 the ramp to 1.2, 3 second block
    assert_eq!(blocks[1]["step"], 3);
    let (d1, r1) = closed_form_at(DELTA, R);
    let (d2_static, r2) = closed_form_at(1.2 * DELTA, 0.2);
    let d_switch = d1 + r1 * 5.0e6;
    assert!(d_switch > d2_static);
    let rows = rows(&out);
    let mut checked = [0usize; 3];
    for &(step, cycles, dissipated) in &rows {
        let expect = match step {
            1 => d1 + r1 * cycles,
            2 => d_switch,
            3 => (d_switch + r2 * (cycles - 5.0e6)).min(1.0),
            _ => continue,
        };
        checked[step - 1] += 1;
        let expect = G_C * AREA * expect;
        assert!(
            (dissipated - expect).abs() <= 1e-4 * expect,
            "step {step}, N = {cycles}: {dissipated} against {expect}"
        );
    }
    assert!(checked.iter().all(|&n| n > 0), "{checked:?}");
    assert_eq!(rows.last().unwrap().1, 1.5e7);
    // a bad block, or both cycles and blocks: the key is named
    for (fatigue, expect) in [
        (
            "blocks = [{ load = 1.0, cycles = -5.0 }]",
            "fatigue.blocks[0].cycles",
        ),
        (
            "cycles = 2.0e7\nblocks = [{ load = 1.0, cycles = 5.0 }]",
            "not both",
        ),
    ] {
        let bad = scene_with(dir.path(), "bad.toml", |t| {
            t.replace("cycles = 2.0e7", fatigue)
        });
        let err = run_err(&bad);
        assert!(
            err.contains("bad.toml") && err.contains(expect),
            "{expect}: {err}"
        );
    }
}

/// `[fatigue]` mistakes name the file and key and what is valid.
#[test]
fn fatigue_input_errors_name_the_key() {
    let dir = tempfile::tempdir().unwrap();
    for (edit, expect) in [
        (("cycles = 2.0e7", "cycles = -1.0"), "fatigue.cycles"),
        (
            ("load_ratio = 0.1", "load_ratio = 1.0"),
            "fatigue.load_ratio",
        ),
        (("type = \"static\"", "type = \"linear\""), "key `fatigue`"),
        (
            ("steps = [1.0]", "steps = [1.0]\ncontrol = \"arc_length\""),
            "arc_length",
        ),
        (
            ("max_damage_increment = 0.05", "max_damage_increment = 0.0"),
            "fatigue.max_damage_increment",
        ),
        (
            ("max_damage_increment = 0.05", "max_damage = 0.05"),
            "max_damage",
        ),
        (("\"local\"", "\"global\""), "fatigue.energy_release_rate"),
        (
            ("\"local\"", "\"crack_front\"\ndirection = [0.0, 0.0, 0.0]"),
            "fatigue.direction",
        ),
    ] {
        let input = scene_with(dir.path(), "bad.toml", |t| {
            assert!(t.contains(edit.0), "{}", edit.0);
            t.replace(edit.0, edit.1)
        });
        let err = run_err(&input);
        assert!(
            err.contains("bad.toml") && err.contains(expect),
            "{expect}: {err}"
        );
    }
}
