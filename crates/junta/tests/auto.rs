//! `[solver] type = "auto"` above `junta::prepare::auto::DIRECT_ALWAYS` equations:
//! the choice between the direct factor and AMG on the unit cubes of
//! `bench/cube_vs_calculix.sh` (shared/BENCHMARKS.md section 1), and the
//! nested dissection computed for the choice handed to the direct solver
//! instead of computed twice.

use junta::{RunSettings, Simulation};

/// The unit cube of `examples/cube.toml` (clamped at z = 0, pulled at
/// z = 1) with `n^3` `element`s (`h8`, `h20`) and the default solver
/// choice: the model of the bench's CalculiX decks (same mesh, hence the
/// same matrix pattern, which is all the choice reads).
fn cube(element: &str, n: usize) -> String {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let text = std::fs::read_to_string(root.join("examples/cube.toml")).unwrap();
    let edited = text
        .replace(
            "divisions = [2, 2, 2]",
            &format!("divisions = [{n}, {n}, {n}]"),
        )
        .replace("element = \"h8\"", &format!("element = \"{element}\""))
        .replace("type = \"cholesky\"", "type = \"auto\"");
    assert!(edited.contains("type = \"auto\"") && edited.contains(&format!("[{n}, {n}, {n}]")));
    edited
}

/// The cost model of `junta::prepare::auto::predicted_seconds` on the two cubes,
/// whose direct and AMG times were measured on this machine kind
/// (docs/performance.md, 2026-11-26: H20 n=20 direct 3.9 s against AMG-CG
/// 4.2 s; H8 n=40 direct 7.5 s against AMG-CG 3.1 s): `auto` keeps the
/// direct solver on the H20 cube, with the dissection it computed, and
/// takes AMG on the H8 cube. The prediction is booked as its own phase,
/// not as reading.
#[test]
fn auto_picks_the_faster_back_end_on_the_benchmark_cubes() {
    for (element, n, equations, key) in
        [("h20", 20, 102_039, "cholesky"), ("h8", 40, 200_039, "cg")]
    {
        let sim = Simulation::from_scene_text(&cube(element, n), "cube.toml").unwrap();
        let p = sim.prepared();
        assert_eq!(p.model.dofs.num_free, equations, "{element} n={n}");
        assert_eq!(p.solver_key, key, "{element} n={n}: {:?}", p.notes);
        let note = p.notes.join("\n");
        assert_eq!(
            note.contains("AMG-CG is predicted faster than the direct factor"),
            key == "cg",
            "{element} n={n}: {note}"
        );
        assert!(p.choose_solver_seconds > 0.0);
    }
}

/// A plate of 200 x 40 x 5 H8 (123,615 equations) fills its factor far
/// less than a cube: `auto` keeps the direct solver, which takes the
/// nested dissection computed for the choice (one analysis, one
/// dissection: the note says it was reused, and nested dissection and AMD
/// are both among the candidates compared).
#[test]
fn auto_keeps_the_direct_solver_on_a_plate_and_orders_it_once() {
    let text = cube("h8", 1)
        .replace("size = [1.0, 1.0, 1.0]", "size = [200.0, 40.0, 5.0]")
        .replace("divisions = [1, 1, 1]", "divisions = [200, 40, 5]");
    assert!(text.contains("[200, 40, 5]") && text.contains("[200.0, 40.0, 5.0]"));
    let sim = Simulation::from_scene_text(&text, "plate.toml").unwrap();
    assert!(sim.model().dofs.num_free > junta::prepare::auto::DIRECT_ALWAYS);
    assert_eq!(sim.prepared().solver_key, "cholesky");
    let r = sim.run(&RunSettings::in_memory(), &mut []).unwrap();
    let solver = &r.summary["solver"];
    let notes: Vec<&str> = solver["notes"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|n| n.as_str())
        .collect();
    let ordering: Vec<&&str> = notes
        .iter()
        .filter(|n| n.starts_with("ordering "))
        .collect();
    assert_eq!(ordering.len(), 1, "one analysis: {notes:?}");
    assert!(
        ordering[0].contains("nested dissection reused from the solver choice")
            && ordering[0].contains("nested_dissection")
            && ordering[0].contains("amd"),
        "{}",
        ordering[0]
    );
    let t = r.summary.timings.unwrap();
    assert!(t.choose_solver > 0.0, "{t:?}");
}

/// The pattern the choice analysed is the one the run assembles into:
/// `decide` keeps its assembler in the model, the next `Model::assembler`
/// takes it (the same pattern and colouring a fresh build gives, once),
/// and a model whose dof map changed in between gets a new one of its own
/// size.
#[test]
fn the_choice_hands_its_pattern_to_the_run() {
    let sim = Simulation::from_scene_text(&cube("h8", 4), "cube.toml").unwrap();
    let model = sim.model().clone();
    assert!(!model.has_kept_assembler(), "a clone starts without one");
    junta::prepare::auto::decide_above(&model, true, 0);
    assert!(model.has_kept_assembler());
    let kept = model.assembler();
    assert!(!model.has_kept_assembler(), "taken once");
    let fresh = junta::core::assembly::Assembler::new(&model.mesh, &model.dofs);
    assert_eq!(kept.pattern.col_ptr, fresh.pattern.col_ptr);
    assert_eq!(kept.pattern.row_idx, fresh.pattern.row_idx);
    assert_eq!(kept.colors, fresh.colors);
    // the dof map changes after the choice: the kept pattern is not used
    let mut changed = model.clone();
    junta::prepare::auto::decide_above(&changed, true, 0);
    let dofs = 3 * changed.mesh.nodes.len();
    let fixed: Vec<(usize, f64)> = (0..dofs)
        .filter(|&d| changed.dofs.eq[d] == junta::core::dof::CONSTRAINED || d + 30 >= dofs)
        .map(|d| (d, 0.0))
        .collect();
    changed.dofs =
        junta::core::dof::DofMap::new(changed.mesh.nodes.len(), &fixed, &changed.mesh.used_nodes())
            .unwrap();
    let n = changed.dofs.num_free;
    assert!(n < model.dofs.num_free);
    assert_eq!(changed.assembler().pattern.n, n);
}
