//! Helpers shared by the CLI test programs.
#![allow(dead_code)]

use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

pub fn junta() -> Command {
    Command::new(env!("CARGO_BIN_EXE_junta"))
}

pub fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Run `junta run input -o dir`, return summary.json.
pub fn run_ok(input: &Path, dir: &Path) -> Value {
    run_ok_with(input, dir, &[])
}

/// [`run_ok`] with extra arguments (e.g. `--max-increments 40`).
pub fn run_ok_with(input: &Path, dir: &Path, args: &[&str]) -> Value {
    let out = junta()
        .arg("run")
        .arg(input)
        .arg("-o")
        .arg(dir)
        .arg("-q")
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "junta run {} failed:\n{}",
        input.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

/// `junta run --restart dir -q`, which must succeed.
pub fn restart_ok(dir: &Path) {
    let out = junta()
        .args(["run", "-q", "--restart"])
        .arg(dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "junta run --restart {} failed:\n{}",
        dir.display(),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Run and expect failure; return stderr.
pub fn run_err(input: &Path) -> String {
    let dir = tempfile::tempdir().unwrap();
    let out = junta()
        .arg("run")
        .arg(input)
        .arg("-o")
        .arg(dir.path())
        .arg("-q")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(
        !out.status.success(),
        "expected failure for {}",
        input.display()
    );
    assert!(!err.contains("panicked"), "panic on bad input:\n{err}");
    assert!(
        err.starts_with("error: "),
        "error message should start with `error: `:\n{err}"
    );
    err
}

pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

pub fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// The named columns of `DIR/curve.csv`, row by row, as numbers (an
/// empty field reads as NaN); panics naming a column the file lacks.
pub fn curve_columns<const N: usize>(dir: &Path, names: [&str; N]) -> Vec<[f64; N]> {
    let text = std::fs::read_to_string(dir.join("curve.csv")).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let cols = names.map(|n| {
        head.iter()
            .position(|h| *h == n)
            .unwrap_or_else(|| panic!("curve.csv has no column {n}"))
    });
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            cols.map(|c| f[c].parse().unwrap_or(f64::NAN))
        })
        .collect()
}

/// The lines of `DIR/curve.csv` (header included) without the wall-clock
/// column `seconds`, found by its name: what a repeated or restarted run
/// must reproduce bit for bit.
pub fn curve_without_seconds(dir: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(dir.join("curve.csv")).unwrap();
    let head: Vec<&str> = text.lines().next().unwrap_or("").split(',').collect();
    let seconds = head
        .iter()
        .position(|h| *h == "seconds")
        .expect("curve.csv has a seconds column");
    text.lines()
        .map(|l| {
            let mut f: Vec<&str> = l.split(',').collect();
            f.remove(seconds);
            f.join(",")
        })
        .collect()
}

/// The blocks of a CalculiX `.dat` (`displacements`, `forces`, `total
/// force`, `stresses` for a set): per (what, set) the rows by label (node,
/// `elem.point` for stresses, `total` for totals). Set names are upper
/// case (as CalculiX prints them, and as [`junta_blocks`] gives them).
pub fn dat_blocks(text: &str) -> BTreeMap<(String, String), BTreeMap<String, Vec<f64>>> {
    let mut out: BTreeMap<(String, String), BTreeMap<String, Vec<f64>>> = BTreeMap::new();
    let mut cur: Option<(String, String)> = None;
    for l in text.lines() {
        let t = l.trim();
        if let Some(at) = t.find(" for set ") {
            let what = t.split(' ').next().unwrap();
            let what = if t.starts_with("total force") {
                "total"
            } else {
                what
            };
            let set = t[at + 9..].split_whitespace().next().unwrap();
            cur = Some((what.to_string(), set.to_uppercase()));
            continue;
        }
        if t.starts_with(|c: char| c.is_ascii_alphabetic()) {
            // another table (CalculiX's `strains ... forset`): not read
            cur = None;
            continue;
        }
        let Some(key) = &cur else { continue };
        let f: Vec<&str> = t.split_whitespace().filter(|x| *x != "CYL").collect();
        if f.is_empty() {
            continue;
        }
        let nums: Vec<f64> = f.iter().filter_map(|x| x.parse().ok()).collect();
        if nums.len() != f.len() {
            continue;
        }
        let (label, vals) = match key.0.as_str() {
            "total" => ("total".to_string(), nums),
            "stresses" => (format!("{}.{}", f[0], f[1]), nums[2..].to_vec()),
            _ => (f[0].to_string(), nums[1..].to_vec()),
        };
        out.entry(key.clone()).or_default().insert(label, vals);
    }
    out
}

/// Junta's `node_print.csv` / `el_print.csv` rows as the same blocks.
pub fn junta_blocks(dir: &Path) -> BTreeMap<(String, String), BTreeMap<String, Vec<f64>>> {
    let mut out: BTreeMap<(String, String), BTreeMap<String, Vec<f64>>> = BTreeMap::new();
    let vals = |f: &[&str]| -> Vec<f64> { f.iter().filter_map(|x| x.parse().ok()).collect() };
    if let Ok(t) = std::fs::read_to_string(dir.join("node_print.csv")) {
        for l in t.lines().skip(1) {
            let f: Vec<&str> = l.split(',').collect();
            let what = match (f[2], f[3]) {
                (_, "total") => "total",
                ("U", _) => "displacements",
                _ => "forces",
            };
            out.entry((what.into(), f[1].to_uppercase()))
                .or_default()
                .insert(f[3].into(), vals(&f[4..7]));
        }
    }
    if let Ok(t) = std::fs::read_to_string(dir.join("el_print.csv")) {
        for l in t.lines().skip(1) {
            let f: Vec<&str> = l.split(',').collect();
            if f[2] == "S" {
                out.entry(("stresses".into(), f[1].to_uppercase()))
                    .or_default()
                    .insert(format!("{}.{}", f[3], f[4]), vals(&f[5..11]));
            }
        }
    }
    out
}

/// Largest difference between Junta's rows and CalculiX's over every block
/// of the `.dat`, relative to the block's largest value (as
/// `bench/calculix_suite.py` measures).
pub fn worst_against_dat(dat: &str, dir: &Path) -> f64 {
    worst_against_dat_of(dat, dir, false)
        .into_values()
        .fold(0.0, f64::max)
}

/// Per block of the `.dat`, the largest difference between Junta's rows
/// and CalculiX's relative to the block's largest value. `plane`: the deck
/// is a plane (2D) one that CalculiX expanded into a layer or a sector of
/// 3D elements, whose integration points repeat the plane cell's through
/// the layer (point `p` of the 3D element is Junta's point `(p - 1) mod n
/// + 1`, `n` the plane cell's count), and whose out-of-plane shear
/// stresses `sxz`, `syz` come from the expansion (in a sector, the hoop
/// direction turns across its 2 degrees): stresses compare `sxx, syy,
/// szz, sxy` only.
pub fn worst_against_dat_of(dat: &str, dir: &Path, plane: bool) -> BTreeMap<(String, String), f64> {
    let (refs, got) = (dat_blocks(dat), junta_blocks(dir));
    assert!(!refs.is_empty());
    let mut out = BTreeMap::new();
    for (key, rows) in &refs {
        let g = got
            .get(key)
            .unwrap_or_else(|| panic!("no Junta rows for {key:?}"));
        let scale = rows.values().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        let mut worst = 0.0f64;
        for (label, want) in rows {
            let label = match (plane, label.split_once('.')) {
                (true, Some((e, p))) => {
                    let n = (1..)
                        .take_while(|k| g.contains_key(&format!("{e}.{k}")))
                        .count();
                    let p: usize = p.parse().unwrap();
                    format!("{e}.{}", (p - 1) % n.max(1) + 1)
                }
                _ => label.clone(),
            };
            let have = g
                .get(&label)
                .unwrap_or_else(|| panic!("{key:?}: no row {label}"));
            let m = if plane && key.0 == "stresses" {
                4
            } else {
                have.len()
            };
            for (a, b) in have.iter().zip(want).take(m) {
                worst = worst.max((a - b).abs() / scale);
            }
        }
        out.insert(key.clone(), worst);
    }
    out
}
