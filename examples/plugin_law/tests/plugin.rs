//! The plugin crate's own `junta` lists its law next to Junta's own plugins
//! and runs a scene with it.

use std::path::Path;
use std::process::Command;

fn junta() -> Command {
    Command::new(env!("CARGO_BIN_EXE_junta-bimodular"))
}

#[test]
fn list_shows_the_plugin_law_and_every_builtin_plugin_crate() {
    let out = junta().arg("list").output().unwrap();
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    // The plugin, then one key per Junta plugin crate: the linker kept every
    // crate's registrations although this binary names none of them.
    for key in [
        "bimodular_penalty",
        "linear_penalty",
        "h27",
        "inter18",
        "isotropic",
        "quadratic",
        "cholesky",
    ] {
        assert!(text.contains(key), "`list` lacks {key}:\n{text}");
    }
}

#[test]
fn scene_with_the_plugin_law_matches_the_closed_form() {
    let dir = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scene.toml");
    let out = junta()
        .args(["run", "-q"])
        .arg(&scene)
        .arg("-o")
        .arg(dir.path())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("summary.json")).unwrap())
            .unwrap();
    // Closed form of the scene header: sigma = Delta / (H / M + 1 / kt).
    let (e, nu) = (2.1e11, 0.3);
    let m = e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let sigma = 1.25e-5 / (0.01 / m + 1.0 / 1e13);
    let reaction = summary["reactions"]["upper.z1"][2].as_f64().unwrap();
    assert!(
        (reaction - sigma * 0.04).abs() <= 1e-6 * sigma * 0.04,
        "reaction {reaction} vs closed form {}",
        sigma * 0.04
    );
}
