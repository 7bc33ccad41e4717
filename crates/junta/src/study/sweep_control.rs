//! `junta sweep control <scene>`: one incremental scene under three control
//! methods, to show where each one stops and why.
//!
//! - **arc length** (`[analysis] control = "arc_length"`): path following,
//!   run first; it gives the largest reaction of the path;
//! - **displacement control**: the scene as written, with
//!   `control = "load"` (its prescribed displacements scale with the load
//!   factor);
//! - **load control**: every prescribed (non-zero) displacement of the
//!   scene becomes a total force on the same node set and component, of
//!   magnitude 1.25 times the arc-length peak reaction with the sign of the
//!   displacement (shared by the set's nodes with `split = "consistent"`:
//!   a uniform load over the faces or edges the set spans), so the program
//!   asks for more than the structure can carry and the run must stop at
//!   the load maximum.
//!
//! A scene loaded by forces only is run under load control and arc length
//! (there is no displacement to control). Writes `control.csv` (method,
//! increment, displacement, reaction, load factor), `control_summary.csv`
//! (per method: status, increments, peak, last point, stop message),
//! `control.svg` (the curves, the scene's reference curve, the stop points)
//! and each run's own directory.

use crate::error::{bail, err, Context, Result};
use crate::{input::scene, output::plot};
use std::path::{Path, PathBuf};

/// One method's run.
#[derive(Debug, Clone)]
pub struct ControlRun {
    /// `arc_length`, `displacement` or `load`.
    pub method: &'static str,
    /// `status` of its summary.json.
    pub status: String,
    /// The error that stopped it, if any (first line).
    pub error: Option<String>,
    /// `(displacement, reaction, load factor)` per converged increment.
    pub points: Vec<(f64, f64, f64)>,
}

impl ControlRun {
    /// The point of the largest |load| `(displacement, load)` of the curve.
    pub fn peak(&self) -> Option<(f64, f64)> {
        self.points
            .iter()
            .map(|p| (p.0, p.1))
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
    }
}

fn read_curve(dir: &Path) -> Vec<(f64, f64, f64)> {
    let Ok(text) = std::fs::read_to_string(dir.join("curve.csv")) else {
        return Vec::new();
    };
    let mut lines = text.lines();
    let Some(head) = lines.next() else {
        return Vec::new();
    };
    let head: Vec<&str> = head.split(',').collect();
    let col = |n: &str| head.iter().position(|h| *h == n);
    let (Some(cd), Some(cr), Some(cl)) = (col("displacement"), col("reaction"), col("load_factor"))
    else {
        return Vec::new();
    };
    lines
        .filter_map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            Some((
                f.get(cd)?.parse().ok()?,
                f.get(cr)?.parse().ok()?,
                f.get(cl)?.parse().ok()?,
            ))
        })
        .collect()
}

/// Run `table` (a scene) written to `dir/NAME.toml` into `dir/NAME`.
fn run_variant(table: &toml::Table, dir: &Path, method: &'static str) -> Result<ControlRun> {
    let file = dir.join(format!("{method}.toml"));
    std::fs::write(&file, toml::to_string(table)?)
        .with_context(|| format!("cannot write {}", file.display()))?;
    let out = dir.join(method);
    let _ = std::fs::remove_dir_all(&out);
    tracing::info!("sweep control: {method} ...");
    let error = crate::Simulation::from_file(&file)
        .and_then(|sim| sim.run(&crate::RunSettings::into_dir(&out), &mut []))
        .map_or_else(|e| Some(e.chain()), |r| r.failure.map(|e| e.chain()));
    let status = std::fs::read_to_string(out.join("summary.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .and_then(|v| v["status"].as_str().map(str::to_string))
        .unwrap_or_else(|| "no summary".into());
    Ok(ControlRun {
        method,
        status,
        error,
        points: read_curve(&out),
    })
}

/// Mutable `[analysis]` of a scene table.
fn analysis(t: &mut toml::Table) -> &mut toml::Table {
    t.entry("analysis")
        .or_insert_with(|| toml::Value::Table(toml::Table::new()))
        .as_table_mut()
        .expect("[analysis] is a table")
}

/// Run the three methods on `input` into `out`.
pub fn sweep_control(input: &Path, out: &Path) -> Result<Vec<ControlRun>> {
    // validate as a scene first (clear errors with the file and key)
    let sf = crate::input::validate::read_scene(input)?;
    if !sf.scene.analysis.kind.is_incremental() {
        bail!(
            "{}: key `analysis.type`: `junta sweep control` needs an incremental scene (\"static\")",
            input.display()
        );
    }
    let Some(curve) = sf.scene.output.curve.clone() else {
        bail!(
            "{}: key `output.curve`: `junta sweep control` compares load-displacement curves; give [output] curve = {{ reaction_set, reaction_component, point_set, point_component }}",
            input.display()
        );
    };
    let text = std::fs::read_to_string(input)
        .with_context(|| format!("cannot read {}", input.display()))?;
    let mut base: toml::Table = text.parse().map_err(|e| err!("{}: {e}", input.display()))?;
    // files named relative to the scene (mesh, reference curve) must keep
    // working from the output directory
    let scene_dir = std::fs::canonicalize(input.parent().unwrap_or(Path::new(".")))
        .unwrap_or_else(|_| PathBuf::from("."));
    absolutise_paths(&mut base, &scene_dir);
    if let Some(mut o) = base.remove("output") {
        if let Some(t) = o.as_table_mut() {
            t.remove("directory");
            t.insert("every".into(), toml::Value::Integer(1_000_000));
        }
        base.insert("output".into(), o);
    }
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let mut runs = Vec::new();
    // 1. arc length
    let mut arc = base.clone();
    analysis(&mut arc).insert("control".into(), "arc_length".into());
    runs.push(run_variant(&arc, out, "arc_length")?);
    // 2. the scene's own control (displacement control if it prescribes
    // displacements)
    let mut own = base.clone();
    analysis(&mut own).insert("control".into(), "load".into());
    let boundaries: Vec<toml::Value> = own
        .get("boundary")
        .and_then(|b| b.as_array())
        .cloned()
        .unwrap_or_default();
    let prescribed: Vec<(String, String, f64)> = boundaries
        .iter()
        .filter_map(|b| {
            let set = b.get("set")?.as_str()?.to_string();
            let d = b.get("displacement")?.as_table()?;
            Some(
                d.iter()
                    .filter_map(|(c, v)| {
                        let v = v.as_float().or(v.as_integer().map(|i| i as f64))?;
                        (v != 0.0).then(|| (set.clone(), c.clone(), v))
                    })
                    .collect::<Vec<_>>(),
            )
        })
        .flatten()
        .collect();
    let displacement_driven = !prescribed.is_empty();
    runs.push(run_variant(
        &own,
        out,
        if displacement_driven {
            "displacement"
        } else {
            "load"
        },
    )?);
    // 3. load control of a displacement-driven scene
    if displacement_driven {
        let peak = runs
            .iter()
            .filter_map(|r| r.peak())
            .map(|p| p.1.abs())
            .fold(0.0, f64::max);
        if peak > 0.0 {
            let target = 1.25 * peak;
            let mut load = base.clone();
            analysis(&mut load).insert("control".into(), "load".into());
            let mut bcs = Vec::new();
            for b in boundaries {
                let mut b = b;
                if let Some(t) = b.as_table_mut() {
                    t.remove("displacement");
                    if t.contains_key("fixed") {
                        bcs.push(b);
                    }
                }
            }
            load.insert("boundary".into(), toml::Value::Array(bcs));
            let mut loads = load
                .get("load")
                .and_then(|l| l.as_array())
                .cloned()
                .unwrap_or_default();
            for (set, c, v) in &prescribed {
                let k = match c.as_str() {
                    "x" => 0,
                    "y" => 1,
                    "z" => 2,
                    _ => continue,
                };
                let mut f = [0.0; 3];
                f[k] = target * v.signum();
                let mut t = toml::Table::new();
                t.insert("set".into(), set.clone().into());
                t.insert(
                    "total_force".into(),
                    toml::Value::Array(f.iter().map(|x| toml::Value::Float(*x)).collect()),
                );
                // shared as a uniform load over the faces or edges the set
                // spans (see `split` in docs/scenes.md)
                t.insert("split".into(), "consistent".into());
                loads.push(toml::Value::Table(t));
            }
            load.insert("load".into(), toml::Value::Array(loads));
            runs.push(run_variant(&load, out, "load")?);
        }
    }
    write_outputs(&sf, &curve, &runs, out)?;
    Ok(runs)
}

/// Make the file names a scene reads absolute (`mesh.file`,
/// `output.curve.reference.file`), relative to `dir`.
fn absolutise_paths(t: &mut toml::Table, dir: &Path) {
    let fix = |v: &mut toml::Value| {
        if let Some(s) = v.as_str() {
            let p = Path::new(s);
            if p.is_relative() {
                *v = dir.join(p).display().to_string().into();
            }
        }
    };
    if let Some(f) = t
        .get_mut("mesh")
        .and_then(|m| m.as_table_mut())
        .and_then(|m| m.get_mut("file"))
    {
        fix(f);
    }
    if let Some(f) = t
        .get_mut("output")
        .and_then(|o| o.as_table_mut())
        .and_then(|o| o.get_mut("curve"))
        .and_then(|c| c.as_table_mut())
        .and_then(|c| c.get_mut("reference"))
        .and_then(|r| r.as_table_mut())
        .and_then(|r| r.get_mut("file"))
    {
        fix(f);
    }
}

fn write_outputs(
    sf: &scene::SceneFile,
    curve: &scene::CurveSpec,
    runs: &[ControlRun],
    out: &Path,
) -> Result<()> {
    let mut csv = String::from("method,increment,displacement,reaction,load_factor\n");
    for r in runs {
        for (i, p) in r.points.iter().enumerate() {
            csv += &format!("{},{},{:e},{:e},{:e}\n", r.method, i + 1, p.0, p.1, p.2);
        }
    }
    std::fs::write(out.join("control.csv"), csv)?;
    let mut sum = String::from(
        "method,status,increments,peak_displacement,peak_reaction,last_displacement,last_reaction,stopped_because\n",
    );
    for r in runs {
        let pk = r.peak();
        let last = r.points.last();
        let why = r
            .error
            .as_deref()
            .unwrap_or("")
            .replace(['\n', ','], " ")
            .replace('"', "'");
        sum += &format!(
            "{},\"{}\",{},{},{},{},{},\"{}\"\n",
            r.method,
            r.status.replace('"', "'"),
            r.points.len(),
            pk.map_or(String::new(), |p| format!("{:e}", p.0)),
            pk.map_or(String::new(), |p| format!("{:e}", p.1)),
            last.map_or(String::new(), |p| format!("{:e}", p.0)),
            last.map_or(String::new(), |p| format!("{:e}", p.1)),
            why
        );
    }
    std::fs::write(out.join("control_summary.csv"), sum)?;
    let mut series: Vec<plot::Series> = runs
        .iter()
        .enumerate()
        .map(|(i, r)| plot::Series {
            name: format!(
                "{} ({} increments{})",
                r.method.replace('_', " "),
                r.points.len(),
                if r.error.is_some() { ", stopped" } else { "" }
            ),
            points: r.points.iter().map(|p| (p.0, p.1)).collect(),
            color: i,
            markers_only: false,
        })
        .collect();
    let stops: Vec<(f64, f64)> = runs
        .iter()
        .filter(|r| r.error.is_some())
        .filter_map(|r| r.points.last().map(|p| (p.0, p.1)))
        .collect();
    if !stops.is_empty() {
        series.push(plot::Series {
            name: "where a method stopped".into(),
            points: stops,
            color: 4,
            markers_only: true,
        });
    }
    if let Some(rf) = &curve.reference {
        let path = sf.path.parent().unwrap_or(Path::new(".")).join(&rf.file);
        if let Ok(pts) = crate::post::curve::read_reference_points(&path) {
            series.push(plot::Series {
                name: rf.label.clone(),
                points: pts,
                color: 5,
                markers_only: false,
            });
        }
    }
    plot::write_svg(
        &out.join("control.svg"),
        &[plot::Panel {
            title: format!("{}: control methods", sf.path.display()),
            x_label: format!(
                "displacement of {} ({})",
                curve.point_set, curve.point_component
            ),
            y_label: format!(
                "reaction on {} ({})",
                curve.reaction_set, curve.reaction_component
            ),
            log_x: false,
            log_y: false,
            series,
            vlines: vec![],
        }],
    )
}
