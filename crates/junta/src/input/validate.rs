//! Range checks of every numeric scene parameter where it is read, and the
//! checks `junta check` shares with `junta run` (analysis type, curve
//! components, probe / reference / curve sets), so that both refuse the
//! same inputs before solving, with the key in the message.

use crate::error::{bail, Result};
use crate::input::scene::{self, SceneFile};
use std::path::Path;

/// Read a scene file and check its numbers (see [`scene()`]).
pub fn read_scene(path: &Path) -> Result<SceneFile> {
    let sf = SceneFile::read(path)?;
    scene(&sf)?;
    Ok(sf)
}

fn finite(file: &str, key: &str, v: &[f64]) -> Result<()> {
    if let Some(x) = v.iter().find(|x| !x.is_finite()) {
        bail!("{file}: key `{key}`: {x} is not a finite number");
    }
    Ok(())
}

/// Numbers of the scene text itself (no mesh needed): loads, prescribed
/// displacements, reference value, output fractions, interface thickness,
/// solver type, load program.
pub fn scene(sf: &SceneFile) -> Result<()> {
    let s = &sf.scene;
    let file = &sf.path.display().to_string();
    for (i, l) in s.load.iter().enumerate() {
        for (k, v) in [
            ("force", l.force),
            ("total_force", l.total_force),
            ("traction", l.traction),
        ] {
            if let Some(v) = v {
                finite(file, &format!("load[{i}].{k}"), &v)?;
            }
        }
        if let Some(p) = l.pressure {
            finite(file, &format!("load[{i}].pressure"), &[p])?;
        }
    }
    for (i, b) in s.boundary.iter().enumerate() {
        if let Some(d) = b.displacement {
            for (c, v) in [("x", d.x), ("y", d.y), ("z", d.z)] {
                if let Some(v) = v {
                    finite(file, &format!("boundary[{i}].displacement.{c}"), &[v])?;
                }
            }
        }
    }
    if let Some(r) = &s.reference {
        if !r.value.is_finite() || r.value == 0.0 {
            bail!(
                "{file}: key `reference.value`: {} is not valid; give the finite, nonzero reference reaction",
                r.value
            );
        }
        r.component_index(&sf.path)?;
    }
    for f in &s.output.fractions {
        if !(f.is_finite() && *f > 0.0 && *f <= 1.0) {
            bail!("{file}: key `output.fractions`: {f} is not valid; fractions of the load lie in (0, 1]");
        }
    }
    if s.output.every == 0 {
        bail!("{file}: key `output.every`: 0 is not valid; write a frame every n >= 1 increments");
    }
    for (i, f) in s.interface.iter().enumerate() {
        if let Some(t) = f.thickness {
            if !(t.is_finite() && t > 0.0) {
                bail!("{file}: key `interface[{i}].thickness`: {t} is not valid; give a positive thickness");
            }
        }
        for (k, w) in [
            ("within", &f.within),
            (
                "precrack.within",
                &f.precrack.as_ref().map(|p| p.within.clone()),
            ),
        ] {
            if let Some(w) = w {
                finite(
                    file,
                    &format!("interface[{i}].{k}"),
                    w.get_ref().as_flattened(),
                )?;
            }
        }
    }
    for (i, n) in s.node_set.iter().enumerate() {
        finite(
            file,
            &format!("node_set[{i}].within"),
            n.within.get_ref().as_flattened(),
        )?;
    }
    if let Some(t) = &s.solver {
        if let Some(v) = t.get("type") {
            if !v.is_str() {
                bail!("{file}: key `solver.type`: {v} is not valid; give a solver name such as \"cholesky\" or \"cg\" (see `junta list`)");
            }
        }
    }
    analysis(file, &s.analysis)
}

/// The analysis type, load program and Newton settings.
pub fn analysis(file: &str, a: &scene::AnalysisSpec) -> Result<()> {
    if a.steps.is_empty() {
        bail!("{file}: key `analysis.steps`: the load program is empty; give the load factor at the end of each step, e.g. [1.0]");
    }
    finite(file, "analysis.steps", &a.steps)?;
    if !a.kind.is_incremental() {
        return Ok(());
    }
    let n = &a.newton;
    let positive = |k: &str, v: f64, max: f64| -> Result<()> {
        if !(v.is_finite() && v > 0.0 && v <= max) {
            bail!("{file}: key `analysis.newton.{k}`: {v} is not valid; it must lie in (0, {max}]");
        }
        Ok(())
    };
    positive("initial_increment", n.initial_increment, 1.0)?;
    positive("min_increment", n.min_increment, 1.0)?;
    positive("max_increment", n.max_increment, 1.0)?;
    if n.min_increment > n.max_increment {
        bail!(
            "{file}: key `analysis.newton.min_increment`: {} is above max_increment = {}",
            n.min_increment,
            n.max_increment
        );
    }
    positive("tol_force", n.tol_force, 1.0)?;
    if !(n.tol_energy.is_finite() && n.tol_energy >= 0.0) {
        bail!(
            "{file}: key `analysis.newton.tol_energy`: {} is not valid; give a finite value >= 0",
            n.tol_energy
        );
    }
    if n.max_iterations == 0 || n.max_iterations > 10_000 {
        bail!(
            "{file}: key `analysis.newton.max_iterations`: {} is not valid; it must lie in [1, 10000]",
            n.max_iterations
        );
    }
    if !(n.cutback.is_finite() && n.cutback > 0.0 && n.cutback < 1.0) {
        bail!(
            "{file}: key `analysis.newton.cutback`: {} is not valid; it must lie in (0, 1)",
            n.cutback
        );
    }
    if !(n.growth.is_finite() && n.growth >= 1.0 && n.growth <= 100.0) {
        bail!(
            "{file}: key `analysis.newton.growth`: {} is not valid; it must lie in [1, 100]",
            n.growth
        );
    }
    Ok(())
}
