//! Every scene and deck under `examples/` runs to its end as a user runs
//! it: `junta run FILE`, no options. The end is the end of its load
//! program (`status` = `completed`), or the stop the scene itself asks for
//! (`stop_when_separated`: every interface point failed; a path-following
//! scene's own `max_increments`); a linear run has no status and must
//! solve. The Rust plugin example (`examples/plugin_law`) has its own
//! crate and tests.
//!
//! The long ones (release-build seconds in brackets, measured on this
//! machine) are ignored here; run them with
//! `cargo test --release -p junta-cli --test examples -- --ignored`.

mod common;
use common::*;

/// Run `examples/<file>` with no options and check how it ended.
fn runs_to_its_end(file: &str) {
    let dir = tempfile::tempdir().unwrap();
    let s = run_ok(&repo().join("examples").join(file), dir.path());
    let Some(status) = s["status"].as_str() else {
        // a linear run (or its steps): solved, in equilibrium
        assert!(
            s["analysis"].as_str().unwrap().starts_with("linear"),
            "{file}: {s}"
        );
        assert!(!s["displacement_max"].is_null(), "{file}: {s}");
        return;
    };
    let scene_stop = status == "stopped: every interface point has failed"
        || status.contains("[analysis.arc_length] max_increments");
    assert!(
        status.starts_with("completed") || scene_stop,
        "{file}: {status}"
    );
}

macro_rules! examples {
    ($($(#[$attr:meta])* $name:ident => $file:expr;)*) => {
        $(
            #[test]
            $(#[$attr])*
            fn $name() {
                runs_to_its_end($file);
            }
        )*
    };
}

examples! {
    cantilever => "cantilever.toml";
    cube_scene => "cube.toml";
    cube_deck => "cube.inp";
    cube_steps_deck => "cube_steps.inp";
    plane_dcb => "plane/dcb_plane_strain.toml";
    plane_dcb_deck => "plane/dcb_cpe4i.inp";
    plane_enf => "plane/enf_plane_strain.toml";
    plane_mmb => "plane/mmb50_plane_strain.toml";
    plane_tube_joint => "plane/tube_lap_joint.toml";
    /// [run in the suite by plane_joint.rs]
    #[ignore]
    plane_tube_joint_failure => "plane/tube_joint_failure.toml";
    dcb_abaqus_deck => "delamination/dcb_abaqus.inp";
    dcb_arc => "delamination/dcb_arc.toml";
    dcb_coarse => "delamination/dcb_coarse.toml";
    dcb_h8 => "delamination/dcb_h8.toml";
    enf_snapback => "delamination/enf_snapback.toml";
    mmb50 => "delamination/mmb50.toml";
    block_friction => "interface_plasticity/block_friction.toml";
    cross_ply_cure => "laminates/cross_ply_cure.toml";
    cross_ply_tension => "laminates/cross_ply_tension.toml";
    /// [14 s; run in the suite by edge_delamination.rs]
    #[ignore]
    edge_delamination => "laminates/edge_delamination.toml";
    /// [35 s; run in the suite by curved_beam.rs]
    #[ignore]
    curved_beam => "laminates/curved_beam.toml";
    /// [9 s; run in the suite by plane_laminate.rs]
    #[ignore]
    curved_beam_plane => "laminates/curved_beam_plane.toml";
    block_mohr_coulomb => "interface_plasticity/block_mohr_coulomb.toml";
    cyclic_shear => "interface_plasticity/cyclic_shear.toml";
    debond_friction => "interface_plasticity/debond_friction.toml";
    notched_beam => "oscillation/notched_beam.toml";
    beam_peel => "paper/beam_peel.toml";
    beam_shear => "paper/beam_shear.toml";
    penalty_cube => "paper/penalty_cube.toml";
    prism_shear_x => "paper/prism_shear_x.toml";
    prism_shear_y => "paper/prism_shear_y.toml";
    prism_tension => "paper/prism_tension.toml";
    punch_compression => "paper/punch_compression.toml";
    punch_tension => "paper/punch_tension.toml";
    bimetal => "thermal/bimetal.toml";
    cool_down => "thermal/cool_down.toml";
    cure_dcb => "thermal/cure_dcb.toml";
    held_opening => "fatigue/held_opening.toml";
    /// [12 s; run in the suite by fatigue_paris.rs]
    #[ignore]
    dcb_paris => "fatigue/dcb_paris.toml";
    /// [2 s; run in the suite by fatigue_paris.rs]
    #[ignore]
    split_beam_mixed_mode => "fatigue/split_beam_mixed_mode.toml";
    /// [12 s; run in the suite by fatigue_paris.rs]
    #[ignore]
    dcb_cf20 => "fatigue/dcb_cf20.toml";
    /// [126 s: viscous regularisation, small increments]
    #[ignore]
    dcb_viscous => "delamination/dcb.toml";
    /// [13 s]
    #[ignore]
    dcb_plain => "delamination/dcb_plain.toml";
    /// [7 s]
    #[ignore]
    enf => "delamination/enf.toml";
    /// [15 s; run in the suite by r_curve.rs]
    #[ignore]
    dcb_r_curve => "delamination/dcb_r_curve.toml";
    /// [16 s]
    #[ignore]
    mmb80_short => "delamination/mmb80_short.toml";
    /// [3 s]
    #[ignore]
    mmb20 => "delamination/mmb20.toml";
    /// [5 s]
    #[ignore]
    mmb50_short => "delamination/mmb50_short.toml";
    /// [6 s]
    #[ignore]
    mmb80 => "delamination/mmb80.toml";
    /// [106 s: nlgeom, 563 path-following increments]
    #[ignore]
    peel90 => "large_deformation/peel90.toml";
    /// [83 s: nlgeom, 555 path-following increments]
    #[ignore]
    peel45 => "large_deformation/peel45.toml";
}

/// The examples directory holds no scene or deck this file does not run
/// (a new example gets its line above).
#[test]
fn every_example_is_listed() {
    let listed = include_str!("examples.rs");
    let mut missing = Vec::new();
    let root = repo().join("examples");
    let mut dirs = vec![root.clone()];
    while let Some(d) = dirs.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                if !p.ends_with("plugin_law") {
                    dirs.push(p);
                }
                continue;
            }
            let ext = p.extension().and_then(|x| x.to_str()).unwrap_or("");
            if ext == "toml" || ext == "inp" {
                let rel = p
                    .strip_prefix(&root)
                    .unwrap()
                    .to_str()
                    .unwrap()
                    .replace('\\', "/");
                if !listed.contains(&format!("\"{rel}\"")) {
                    missing.push(rel);
                }
            }
        }
    }
    assert!(
        missing.is_empty(),
        "examples not run by examples.rs: {missing:?}"
    );
}
