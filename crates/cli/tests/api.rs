//! The run API (`junta` crate) against the command line on the same
//! inputs: the same curve, an observer's stop as a restart point, scene
//! overrides as edits of the scene, results as typed values.

mod common;
use common::{curve_without_seconds, junta, repo, run_ok};
use junta::{
    Flow, FnObserver, FrameCollector, Increment, Options, RunSettings, Simulation, Status,
};

/// The DCB of the examples, through the API into a directory, writes the
/// CLI's curve.csv to the last bit (wall time aside) over its first 60
/// increments (past the peak; the whole curve is the same code path and
/// costs minutes at the test profile), and the typed curve holds the same
/// numbers as the CSV text.
#[test]
fn dcb_through_the_api_writes_the_cli_curve_bit_for_bit() {
    let scene = repo().join("examples/delamination/dcb.toml");
    let cli = tempfile::tempdir().unwrap();
    common::run_ok_with(&scene, cli.path(), &["--max-increments", "60"]);
    let api = tempfile::tempdir().unwrap();
    let settings = RunSettings {
        max_increments: Some(60),
        ..RunSettings::into_dir(api.path())
    };
    let results = Simulation::from_file(&scene)
        .unwrap()
        .run(&settings, &mut [])
        .unwrap();
    assert_eq!(results.status, Status::Stopped, "{}", results.status_line);
    let (a, b) = (
        curve_without_seconds(cli.path()),
        curve_without_seconds(api.path()),
    );
    assert!(
        a.len() > 20,
        "the DCB converges many increments: {}",
        a.len()
    );
    assert_eq!(a, b);
    // typed columns = the CSV's numbers
    let text = std::fs::read_to_string(cli.path().join("curve.csv")).unwrap();
    let reactions: Vec<f64> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(3).unwrap().parse().unwrap())
        .collect();
    assert_eq!(
        results.curve().get("reaction").unwrap(),
        reactions.as_slice()
    );
    // the peak is the corrected-beam-theory one within the scene's own
    // tolerance (BENCHMARKS.md section 4: 138.5 N)
    let peak = reactions.iter().cloned().fold(0.0, f64::max);
    assert!((peak - 138.5).abs() / 138.5 < 0.03, "peak {peak}");
}

/// An observer that stops at a load factor leaves a run directory that
/// restarts to the same end as the uninterrupted run.
#[test]
fn observer_stop_leaves_a_restartable_run() {
    let scene = repo().join("examples/paper/beam_peel.toml");
    let whole = tempfile::tempdir().unwrap();
    run_ok(&scene, whole.path());
    let parts = tempfile::tempdir().unwrap();
    // the tenth increment, before the interface separates
    let mut stop_at = FnObserver(|inc: &Increment<'_>| {
        if inc.row.increment >= 10 {
            Flow::Stop("increment 10 reached".into())
        } else {
            Flow::Continue
        }
    });
    let first = Simulation::from_file(&scene)
        .unwrap()
        .run(&RunSettings::into_dir(parts.path()), &mut [&mut stop_at])
        .unwrap();
    assert_eq!(first.status, Status::Stopped);
    assert_eq!(first.status_line, "stopped: increment 10 reached");
    assert_eq!(first.rows.len(), 10);
    assert!(
        first.rows.iter().all(|r| r.failed < r.points),
        "not separated yet"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(parts.path().join("summary.json")).unwrap())
            .unwrap();
    assert_eq!(summary["status"], "stopped: increment 10 reached");
    common::restart_ok(parts.path());
    assert_eq!(
        curve_without_seconds(whole.path()),
        curve_without_seconds(parts.path())
    );
}

/// The drivers (and so the observers) run on a thread of rayon's pool, so
/// that the parallel loops they start begin on that thread; with
/// `on_calling_thread` they stay on the caller's thread. The curve is the
/// same to the last bit either way (the paper's peel beam, 12 increments).
#[test]
fn the_drivers_run_on_the_pool_unless_told_to_stay() {
    let scene = repo().join("examples/paper/beam_peel.toml");
    let caller = std::thread::current().id();
    let mut rows = Vec::new();
    for stay in [false, true] {
        let mut threads = Vec::new();
        let mut watch = FnObserver(|_: &Increment<'_>| {
            threads.push((
                std::thread::current().id() == caller,
                rayon::current_thread_index().is_some(),
            ));
            Flow::Continue
        });
        let settings = RunSettings {
            max_increments: Some(12),
            on_calling_thread: stay,
            ..RunSettings::in_memory()
        };
        let r = Simulation::from_file(&scene)
            .unwrap()
            .run(&settings, &mut [&mut watch])
            .unwrap();
        assert_eq!(threads.len(), 12);
        assert!(
            threads.iter().all(|&t| t == (stay, !stay)),
            "on_calling_thread = {stay}: (caller's thread, pool thread) per increment {threads:?}"
        );
        rows.push(
            r.rows
                .iter()
                .map(|r| (r.lambda.to_bits(), r.reaction.map(f64::to_bits)))
                .collect::<Vec<_>>(),
        );
    }
    assert_eq!(rows[0], rows[1]);
}

/// An override gives the result of the edited scene; a key the scene does
/// not have is an error that names it.
#[test]
fn overrides_act_as_edits_of_the_scene() {
    let scene = repo().join("examples/paper/beam_peel.toml");
    let text = std::fs::read_to_string(&scene).unwrap();
    let table: toml::Table = toml::from_str(&text).unwrap();
    let (law, params) = table["laws"].as_table().unwrap().iter().next().unwrap();
    let key = ["d", "K"]
        .into_iter()
        .find(|k| params.get(*k).is_some())
        .expect("a penalty key");
    let old = params[key].as_float().unwrap();
    let path = format!("laws.{law}.{key}");
    // the edited scene, next to the original (its mesh and reference paths)
    let edited_table = {
        let mut t = table.clone();
        junta::prepare::apply_override(&mut t, &path, toml::Value::Float(old * 0.5)).unwrap();
        t
    };
    let dir = tempfile::tempdir().unwrap();
    let edited = scene.with_file_name("beam_peel_edited_for_test.toml");
    std::fs::write(&edited, toml::to_string(&edited_table).unwrap()).unwrap();
    let by_file = Simulation::from_file(&edited)
        .and_then(|s| s.run(&RunSettings::into_dir(dir.path()), &mut []));
    std::fs::remove_file(&edited).unwrap();
    let by_file = by_file.unwrap();
    let options = Options {
        overrides: vec![(path.clone(), toml::Value::Float(old * 0.5))],
        ..Options::default()
    };
    let by_override = Simulation::from_file_with(&scene, options)
        .unwrap()
        .run(&RunSettings::in_memory(), &mut [])
        .unwrap();
    let plain = Simulation::from_file(&scene)
        .unwrap()
        .run(&RunSettings::in_memory(), &mut [])
        .unwrap();
    let r = |x: &junta::RunResults| x.curve().get("reaction").unwrap().to_vec();
    assert_eq!(r(&by_file), r(&by_override));
    assert_ne!(
        r(&plain),
        r(&by_override),
        "halving {path} changes the curve"
    );
    // unknown keys
    for bad in ["laws.no_such_law.d", "nosuchtable.x"] {
        let options = Options {
            overrides: vec![(bad.to_string(), toml::Value::Float(1.0))],
            ..Options::default()
        };
        let e = Simulation::from_file_with(&scene, options).unwrap_err();
        let msg = e.chain();
        assert!(msg.contains(bad) && msg.contains("beam_peel.toml"), "{msg}");
        assert!(e.is_input());
    }
}

/// Typed results: frames kept in memory have the model's shapes, the
/// displacement of the last frame is the one `summary.json` reports, and
/// the check report is the data `junta check` prints.
#[test]
fn frames_and_check_report_are_typed_values() {
    let scene = repo().join("examples/paper/beam_peel.toml");
    let sim = Simulation::from_file(&scene).unwrap();
    let report = sim.check().unwrap();
    let out = junta().arg("check").arg(&scene).output().unwrap();
    assert_eq!(String::from_utf8_lossy(&out.stdout), report.to_string());
    let nodes = sim.model().mesh.nodes.len();
    let mut frames = FrameCollector::every(10);
    let results = sim
        .run(&RunSettings::in_memory(), &mut [&mut frames])
        .unwrap();
    assert!(frames.frames.len() >= 2);
    let last = frames.frames.last().unwrap();
    assert_eq!(last.increment, results.rows.last().unwrap().increment);
    assert_eq!(last.displacement.len(), 3 * nodes);
    let n_solid = last.solid.block.len();
    assert_eq!(last.solid.stress.len(), 6 * n_solid);
    let n_if = last.interface.block.len();
    assert!(n_if > 0);
    assert_eq!(last.interface.traction.len(), 3 * n_if);
    assert_eq!(last.interface.outputs["failed"].len(), n_if);
    // failed points in the frame = the curve's last row
    let failed = last.interface.outputs["failed"]
        .iter()
        .filter(|f| **f > 0.5)
        .count();
    assert_eq!(failed, results.rows.last().unwrap().failed);
    let umax = largest_displacement(&last.displacement);
    let reported = results.summary.displacement_max.unwrap();
    assert!(
        (umax - reported).abs() <= 1e-12 * reported.abs().max(1.0),
        "{umax} {reported}"
    );
}

/// The largest nodal displacement magnitude of a frame's displacement
/// (three components per node), as `summary.json` defines it.
fn largest_displacement(u: &[f64]) -> f64 {
    u.chunks(3)
        .map(|c| (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt())
        .fold(0.0, f64::max)
}

/// A linear run keeps its end fields in `RunResults::frame` unless the
/// caller does without them (`without_end_frame`, as the command line
/// does: they cost about 200 bytes per integration point); the summary is
/// the same either way, and the frame's displacement gives its largest.
#[test]
fn a_linear_run_keeps_its_end_frame_unless_told_not_to() {
    let scene = repo().join("examples/cube.toml");
    let kept = Simulation::from_file(&scene)
        .unwrap()
        .run(&RunSettings::in_memory(), &mut [])
        .unwrap();
    let settings = RunSettings {
        without_end_frame: true,
        ..RunSettings::in_memory()
    };
    let without = Simulation::from_file(&scene)
        .unwrap()
        .run(&settings, &mut [])
        .unwrap();
    assert!(without.frame.is_none());
    let mut a = kept.summary.to_json();
    let mut b = without.summary.to_json();
    for s in [&mut a, &mut b] {
        s["timings"] = serde_json::Value::Null;
    }
    assert_eq!(a, b);
    let frame = kept.frame.expect("a linear run keeps its frame");
    let umax = largest_displacement(&frame.displacement);
    let reported = kept.summary.displacement_max.unwrap();
    assert!(
        umax > 0.0 && (umax - reported).abs() <= 1e-12 * reported,
        "{umax} {reported}"
    );
}

/// A model built in code runs through the same API: the unit cube of
/// BENCHMARKS.md section 1 (H20 n = 2) gives CalculiX 2.20's reaction.
#[test]
fn model_built_in_code_matches_calculix() {
    use junta::core::mesh::generate::{box_mesh, BoxSpec};
    use junta::core::topology::CellShape;
    use junta::elements::{Integration, Isotropic, SolidElement};
    use std::sync::Arc;
    let mesh = box_mesh(
        &BoxSpec::new([1.0; 3], [2; 3], CellShape::Hex20),
        "cube",
        "h20",
        "steel",
    )
    .unwrap();
    let steel = Arc::new(Isotropic::new(210_000.0, 0.3).unwrap());
    let h20 = Arc::new(SolidElement::new(CellShape::Hex20, Integration::Full, steel).unwrap());
    let mut constraints = Vec::new();
    for &n in mesh.node_set("z0").unwrap() {
        constraints.extend((0..3).map(|c| (3 * n + c, 0.0)));
    }
    for &n in mesh.node_set("z1").unwrap() {
        constraints.push((3 * n + 2, -0.01));
    }
    let f_ext = vec![0.0; 3 * mesh.nodes.len()];
    let model = junta::core::Model::new(
        mesh,
        vec![h20],
        &constraints,
        f_ext,
        vec!["z0".into(), "z1".into()],
    )
    .unwrap();
    let sim = Simulation::from_model(model, junta::input::scene::AnalysisSpec::default(), "auto")
        .unwrap();
    let results = sim.run(&RunSettings::in_memory(), &mut []).unwrap();
    let fz = results.summary["reactions"]["z1"][2].as_f64().unwrap();
    assert!((fz - (-2183.070)).abs() < 1e-3, "Fz = {fz}");
    assert!(results.frame.is_some());
}

/// `docs/parameters.md` is what `junta list --markdown` prints today.
#[test]
fn parameter_reference_page_is_current() {
    let page = std::fs::read_to_string(repo().join("docs/parameters.md")).unwrap_or_default();
    let out = junta().args(["list", "--markdown"]).output().unwrap();
    assert!(out.status.success());
    let now = String::from_utf8(out.stdout).unwrap();
    assert!(now.contains("### `bilinear`") && now.contains("| `G_Ic` |"));
    assert!(
        page == now,
        "docs/parameters.md is stale: run `cargo run -p junta-cli -- list --markdown > docs/parameters.md`"
    );
}

/// A law flagged as batched goes through the assembler's block pre-pass
/// (one `evaluate_batch` per interface block and assembly, no per-point
/// call) and gives the per-point law's curve bit for bit.
#[test]
fn batched_law_path_gives_the_per_point_curve_bit_for_bit() {
    use junta::core::element::StepInfo;
    use junta::core::registry::{build_law, register_runtime_law, RuntimeLaw};
    use junta::core::{InterfaceLaw, LawContext, LawError, LawResponse, MatrixKind};
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Arc;

    #[derive(Debug)]
    struct Batched {
        inner: Arc<dyn InterfaceLaw>,
        batches: Arc<AtomicUsize>,
        points: Arc<AtomicUsize>,
    }
    impl InterfaceLaw for Batched {
        fn key(&self) -> &'static str {
            "bilinear_batched_test"
        }
        fn state_len(&self) -> usize {
            self.inner.state_len()
        }
        fn init_state(&self, s: &mut [f64]) {
            self.inner.init_state(s)
        }
        fn evaluate(&self, ctx: &LawContext<'_>, t: &mut [f64]) -> Result<LawResponse, LawError> {
            self.points.fetch_add(1, Ordering::Relaxed);
            self.inner.evaluate(ctx, t)
        }
        fn initial_stiffness(&self) -> [f64; 3] {
            self.inner.initial_stiffness()
        }
        fn wants_small_increments(&self, s: &[f64]) -> bool {
            self.inner.wants_small_increments(s)
        }
        fn stage(&self, s: &[f64]) -> junta_core::PointStage {
            self.inner.stage(s)
        }
        fn failure_index(&self, s: &[f64]) -> Option<f64> {
            self.inner.failure_index(s)
        }
        fn tangent_kind(&self) -> MatrixKind {
            self.inner.tangent_kind()
        }
        fn output_names(&self) -> &'static [&'static str] {
            self.inner.output_names()
        }
        fn outputs(&self, s: &[f64], o: &mut [f64]) {
            self.inner.outputs(s, o)
        }
        fn fracture_properties(&self) -> Option<junta::core::FractureProperties> {
            self.inner.fracture_properties()
        }
        fn is_batched(&self) -> bool {
            true
        }
        fn evaluate_batch(
            &self,
            jumps: &[[f64; 3]],
            committed: &[f64],
            step: StepInfo,
            trial: &mut [f64],
            out: &mut [LawResponse],
        ) -> Result<(), LawError> {
            self.batches.fetch_add(1, Ordering::Relaxed);
            // the inner law is not batched: its evaluate_batch is the
            // default, point by point
            self.inner
                .evaluate_batch(jumps, committed, step, trial, out)
        }
    }
    let (batches, points) = (Arc::new(AtomicUsize::new(0)), Arc::new(AtomicUsize::new(0)));
    let (b2, p2) = (batches.clone(), points.clone());
    register_runtime_law(RuntimeLaw {
        key: "bilinear_batched_test".into(),
        description: "bilinear, evaluated per block (test)".into(),
        build: Arc::new(move |t| {
            Ok(Arc::new(Batched {
                inner: build_law("bilinear", t)?,
                batches: b2.clone(),
                points: p2.clone(),
            }) as Arc<dyn InterfaceLaw>)
        }),
    })
    .unwrap();
    let scene = repo().join("examples/delamination/dcb_coarse.toml");
    let text = std::fs::read_to_string(&scene).unwrap();
    assert_eq!(text.matches("type = \"bilinear\"").count(), 1);
    let batched_text = text.replace("type = \"bilinear\"", "type = \"bilinear_batched_test\"");
    let run = |t: &str| {
        Simulation::from_scene_text(t, &scene)
            .unwrap()
            .run(&RunSettings::in_memory(), &mut [])
            .unwrap()
    };
    let plain = run(&text);
    let batched = run(&batched_text);
    assert!(plain.rows.len() > 10);
    for name in [
        "load_factor",
        "reaction",
        "displacement",
        "dissipated_energy",
    ] {
        assert_eq!(plain.curve().get(name), batched.curve().get(name), "{name}");
    }
    assert_eq!(points.load(Ordering::Relaxed), 0, "no per-point call");
    let n = batches.load(Ordering::Relaxed);
    let solves = batched.summary.driver.unwrap().linear_solves;
    // one batch per assembly; outputs of an increment batch element by
    // element, so at least one call per assembly and no call per point
    assert!(n >= solves, "{n} batches for {solves} solves");
}
