//! The restart point of an incremental run (`checkpoint.json`) and what it
//! must prove before a restart continues it: the inputs are the ones the
//! run started from (a hash of the scene and of every file it reads, with
//! the scene's text to name the keys that changed), the run has not
//! already finished, and the driver's fields are in range.

use crate::error::{bail, Context, Result};
use junta_solvers::newton::Checkpoint;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// What `checkpoint.json` holds.
#[derive(Debug, Serialize, Deserialize)]
pub struct RestartFile {
    /// The scene that was run.
    pub input: PathBuf,
    /// The driver's restart point.
    pub checkpoint: Checkpoint,
    /// First failure so far, if any.
    pub first_failure: Option<FirstFailure>,
    /// Changes of control at limit points so far.
    #[serde(default)]
    pub path_switches: Vec<junta_solvers::path_switch::PathSwitch>,
    /// Frames written so far `(load factor, file)`.
    pub frames: Vec<(f64, String)>,
    /// The run's `--solver KEY=VALUE` overrides (applied again on restart).
    #[serde(default)]
    pub solver_overrides: Vec<String>,
    /// Hashes of the scene and every file it reads (a restart refuses
    /// edited inputs).
    #[serde(default)]
    pub inputs: Vec<InputHash>,
    /// The scene's text, to name the keys an edit changed.
    #[serde(default)]
    pub scene_text: Option<String>,
    /// The status of a run that ended for good (end of the program, or
    /// every interface point failed): a restart has nothing to do.
    #[serde(default)]
    pub finished: Option<String>,
    /// External forces of the checkpoint's increment
    /// ([`crate::run::observer::RunLog::external_force`]); empty in files of
    /// older runs.
    #[serde(default, with = "junta_solvers::nonlinear::packed")]
    pub external_force: Vec<f64>,
    /// The ply failure criteria's course so far (empty in files of older
    /// runs).
    #[serde(default)]
    pub ply_failure: crate::post::ply_failure_history::PlyFailureHistory,
}

/// When the first interface point failed.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct FirstFailure {
    /// Increment (global, 1-based) in which it failed.
    pub increment: usize,
    /// Load factor of that increment.
    pub load_factor: f64,
    /// The curve's reaction then (`None` without a curve).
    pub reaction: Option<f64>,
    /// The curve's displacement then (`None` without a curve).
    pub displacement: Option<f64>,
}

/// Write `path` atomically (temporary file, then rename).
pub(crate) fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let tmp = path.with_extension("tmp");
    std::fs::write(&tmp, bytes).with_context(|| format!("cannot write {}", tmp.display()))?;
    std::fs::rename(&tmp, path).with_context(|| format!("cannot write {}", path.display()))
}

/// Read `DIR/checkpoint.json`.
pub fn read_restart(dir: &Path) -> Result<RestartFile> {
    let path = dir.join("checkpoint.json");
    let text = std::fs::read_to_string(&path).with_context(|| {
        format!(
            "cannot read {} (is {} the output directory of an incremental run?)",
            path.display(),
            dir.display()
        )
    })?;
    serde_json::from_str(&text)
        .with_context(|| format!("{}: not a Junta checkpoint", path.display()))
}

/// One input file of a run and its hash.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InputHash {
    /// The file: canonical (absolute) path, or the path as found (relative
    /// to the scene's directory) when it could not be resolved.
    pub path: PathBuf,
    /// FNV-1a 64 of the file's bytes, hex.
    pub fnv1a: String,
}

/// FNV-1a, 64 bits: stable across Rust versions and platforms.
fn fnv1a(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// The files a scene or deck reads: itself, its mesh file, its reference
/// curve; a deck's `*INCLUDE, INPUT=` files.
pub fn input_files(input: &Path) -> Vec<PathBuf> {
    let mut files = vec![input.to_path_buf()];
    let dir = input.parent().unwrap_or(Path::new(".")).to_path_buf();
    let Ok(text) = std::fs::read_to_string(input) else {
        return files;
    };
    let is_toml = input
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("toml"));
    if is_toml {
        if let Ok(v) = toml::from_str::<toml::Table>(&text) {
            let get = |path: &[&str]| {
                let mut cur = toml::Value::Table(v.clone());
                for k in path {
                    cur = cur.get(k)?.clone();
                }
                cur.as_str().map(|s| dir.join(s))
            };
            files.extend(get(&["mesh", "file"]));
            files.extend(get(&["output", "curve", "reference", "file"]));
        }
    } else {
        for line in text.lines() {
            let up = line.trim().to_ascii_uppercase();
            if up.starts_with("*INCLUDE") {
                if let Some(i) = up.find("INPUT") {
                    let rest = &line.trim()[i..];
                    if let Some(eq) = rest.find('=') {
                        let name = rest[eq + 1..].split(',').next().unwrap_or("").trim();
                        files.push(dir.join(name.trim_matches('"')));
                    }
                }
            }
        }
    }
    files
}

/// Hashes of [`input_files`] (files that cannot be read hash as empty).
pub fn hash_inputs(input: &Path) -> Vec<InputHash> {
    input_files(input)
        .into_iter()
        .map(|p| InputHash {
            fnv1a: fnv1a(&std::fs::read(&p).unwrap_or_default()),
            path: std::fs::canonicalize(&p).unwrap_or(p),
        })
        .collect()
}

/// Keys whose values differ between two TOML tables (`a.b.c: old -> new`).
fn toml_diff(prefix: &str, a: &toml::Value, b: &toml::Value, out: &mut Vec<String>) {
    match (a, b) {
        (toml::Value::Table(x), toml::Value::Table(y)) => {
            let keys: std::collections::BTreeSet<&String> = x.keys().chain(y.keys()).collect();
            for k in keys {
                let p = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                match (x.get(k), y.get(k)) {
                    (Some(u), Some(v)) => toml_diff(&p, u, v, out),
                    (Some(u), None) => out.push(format!("`{p}` removed (was {u})")),
                    (None, Some(v)) => out.push(format!("`{p}` added ({v})")),
                    (None, None) => {}
                }
            }
        }
        (toml::Value::Array(x), toml::Value::Array(y)) if x.len() == y.len() => {
            for (i, (u, v)) in x.iter().zip(y).enumerate() {
                toml_diff(&format!("{prefix}[{i}]"), u, v, out);
            }
        }
        _ if a != b => out.push(format!("`{prefix}`: {a} -> {b}")),
        _ => {}
    }
}

/// Refuse a restart whose inputs changed since the checkpoint, naming what
/// changed, unless `allow_edited`. Checkpoints written before hashes were
/// kept pass.
pub fn check_inputs(r: &RestartFile, allow_edited: bool) -> Result<Vec<String>> {
    let mut changes = Vec::new();
    for old in &r.inputs {
        let now = fnv1a(&std::fs::read(&old.path).unwrap_or_default());
        if now == old.fnv1a {
            continue;
        }
        let mut keys = Vec::new();
        if let (Some(before), Ok(after)) = (&r.scene_text, std::fs::read_to_string(&old.path)) {
            if old.path == r.input {
                if let (Ok(a), Ok(b)) = (
                    toml::from_str::<toml::Table>(before),
                    toml::from_str::<toml::Table>(&after),
                ) {
                    toml_diff(
                        "",
                        &toml::Value::Table(a),
                        &toml::Value::Table(b),
                        &mut keys,
                    );
                }
            }
        }
        changes.push(if keys.is_empty() {
            format!("{} changed", old.path.display())
        } else {
            format!("{} changed: {}", old.path.display(), keys.join(", "))
        });
    }
    if !changes.is_empty() && !allow_edited {
        bail!(
            "the input changed since the run stopped, so the restart would not continue the same run:\n  {}\nrestore it, start a new run, or pass --allow-edited to continue with the edited input",
            changes.join("\n  ")
        );
    }
    Ok(changes)
}

/// Range checks of the driver's fields of a checkpoint.
pub fn check_fields(r: &RestartFile, path: &Path, steps: usize, dofs: usize) -> Result<()> {
    let c = &r.checkpoint;
    let at = path.display();
    if !(c.increment_size.is_finite() && c.increment_size > 0.0 && c.increment_size <= 1.0) {
        bail!(
            "{at}: checkpoint field `increment_size` = {} is out of range (0, 1]",
            c.increment_size
        );
    }
    if !(c.step_fraction.is_finite() && (0.0..=1.0).contains(&c.step_fraction)) {
        bail!(
            "{at}: checkpoint field `step_fraction` = {} is out of range [0, 1]",
            c.step_fraction
        );
    }
    if c.increment_index > 1 << 40 {
        bail!(
            "{at}: checkpoint field `increment_index` = {} is out of range",
            c.increment_index
        );
    }
    if c.step >= steps {
        bail!(
            "{at}: checkpoint field `step` = {} but the load program has {steps} steps",
            c.step
        );
    }
    if !c.lambda.is_finite() || !c.force_peak.is_finite() {
        bail!("{at}: checkpoint fields `lambda`, `force_peak` must be finite");
    }
    if c.u.len() != dofs || !c.u.iter().all(|x| x.is_finite()) {
        bail!(
            "{at}: checkpoint field `u` has {} values (finite: {}), the model has {dofs} dofs",
            c.u.len(),
            c.u.iter().all(|x| x.is_finite())
        );
    }
    Ok(())
}
