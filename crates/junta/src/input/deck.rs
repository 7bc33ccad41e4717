//! Abaqus/CalculiX decks (`.inp`) to a [`Model`]: the reader lives in
//! `crate::input::inp`; here its materials become registry materials
//! (`*ELASTIC` isotropic -> `isotropic`, ENGINEERING CONSTANTS ->
//! `orthotropic`), its cohesive materials interface laws (below), its
//! `*BOUNDARY` lines constraints and its `*CLOAD` lines nodal forces.
//! Reactions are reported for every `*BOUNDARY` target.
//!
//! # Cohesive materials
//!
//! A `COH3D8` or `COH3D6` block takes the material of its `*COHESIVE SECTION,
//! RESPONSE=TRACTION SEPARATION`. Abaqus divides the separation by the
//! section's constitutive thickness `T0` (data line; 1 when not given, the
//! usual choice for zero-thickness elements) to get the nominal strain, so
//! the traction is `(K / T0) delta`: Junta's penalties are `K_nn / T0` etc.
//! (with `T0 = 1`, traction = K * separation). Strengths (nominal
//! stresses) and fracture energies are used as given.
//!
//! - `*ELASTIC, TYPE=TRACTION` alone -> `linear_penalty` with `d3 = K_nn /
//!   T0`, `d1 = K_ss / T0`, `d2 = K_tt / T0`.
//! - With `*DAMAGE INITIATION` + `*DAMAGE EVOLUTION, TYPE=ENERGY` ->
//!   `bilinear` (`SOFTENING=LINEAR`, the default) or `exponential`
//!   (`SOFTENING=EXPONENTIAL`; Junta's exponential shape has the same onset
//!   and fracture energy, its curve is not Abaqus' energy-defined one, so
//!   only the linear case matches Abaqus increment for increment), with
//!   `K = K_nn / T0`, `N = t_n^0`, `S = t_s^0`, `G_Ic`, `G_IIc`;
//!   `CRITERION=QUADS` -> `onset = "quadratic"`, `MAXS` -> `"max_stress"`;
//!   `MIXED MODE BEHAVIOR=BK, POWER=eta` -> `propagation = "bk"`, `eta`;
//!   `POWER LAW, POWER=alpha` -> `"power_law"`, `alpha`; `MODE INDEPENDENT`
//!   -> `bk` with `G_IIc = G_Ic` (then `G_c` does not depend on the mode).
//!   Junta's laws have one shear penalty, strength and toughness: `K_ss =
//!   K_tt`, `t_s^0 = t_t^0` and `G_IIc = G_IIIc` are required (an error
//!   names the line otherwise); `K_ss = K_nn` gives `shear_penalty =
//!   "equal"`, `K_ss = K_nn (G_Ic/G_IIc)(S/N)^2` (to 1e-6) gives
//!   `"turon2018"` (with a note: Abaqus' effective separation with unequal
//!   penalties is not Turon's energy-based one, so mixed-mode curves differ),
//!   any other `K_ss` is an error.
//! - `*DAMAGE STABILIZATION` `mu` -> `viscosity = mu / T` (Abaqus' viscosity
//!   is in step-time units; Junta's in load-factor units, and the load
//!   factor runs 0 -> 1 over the step period `T`).
//!
//! # Incremental runs
//!
//! A deck whose model has a softening law (a material with damage), or a
//! step with NLGEOM, runs as an incremental static analysis
//! (`junta_solvers::newton`). NLGEOM makes every element large-deformation
//! (total-Lagrangian solids, interfaces on their current mid-surface) for
//! the whole run. Each
//! `*STEP` is one step of the proportional load program: Abaqus ramps the
//! loads and prescribed displacements linearly over the step, and the load
//! factor runs over the step as `t / T`, so the first step goes 0 -> 1 with
//! the first step's loads as the pattern; a later step must prescribe the
//! same dofs with values that are a multiple `c` of the first step's (the
//! program is then `[1, c, ...]`), anything else is an error (the driver
//! scales one load pattern). `*STATIC` data `dt0, T, dtmin, dtmax` give the
//! Newton settings as fractions of the period: `initial_increment = dt0 /
//! T` (default 1, Abaqus' default dt0 = T), `max_increment = dtmax / T`
//! (default 1), `min_increment = dtmin / T` (default `min(dt0 / T, 1e-5)`,
//! Abaqus' default); `DIRECT` fixes the increment at `dt0` (no growth, no
//! cut-back). The settings are global in Junta: steps with other fractions
//! are an error. `*STEP, INC=n` stops the run after `n` increments of that
//! step (status in summary.json; Abaqus' default of 100 when INC is not
//! given is not applied, a note says so).
//!
//! # Linear decks
//!
//! Several `*STEP`s are several linear load cases, with CalculiX's rules
//! (checked against `ccx` 2.20 on a 4-step deck):
//! - boundary conditions and loads of earlier steps (and the model data)
//!   stay; a step's value on a dof replaces the earlier one (`OP=MOD`, the
//!   default);
//! - `OP=NEW` on a keyword removes everything of its kind given before it;
//! - several `*CLOAD` values on one dof within a step add up; two different
//!   `*BOUNDARY` values on one dof within a step are an error;
//! - each step is solved from the unloaded state (linear analysis: the
//!   result of a step is the response to its loads, not an increment).
//!
//! (The same rules give each step's loads in an incremental run.)
//!
//! # Temperatures
//!
//! `*EXPANSION` becomes the material's `alpha` (`alpha1..3`, `alpha`);
//! each step's temperature change from the initial temperatures
//! ([`DeckStep::temperature`]) is its thermal load in a linear run; an
//! incremental run scales the first change by a temperature factor per
//! program step (`temperature_pattern`), ramped over the step like the
//! loads (docs/decks.md, "Thermal loads").
//!
//! # Amplitudes
//!
//! A load or prescribed displacement with `AMPLITUDE=` is multiplied by the
//! amplitude ([`crate::input::inp::InpAmplitude`]) at the end of the
//! step it is given in (step time, or total time: the sum of the periods
//! up to that step's end); carried into a later step that does not give it
//! again, it keeps that value (CalculiX 2.20 does the same). In an
//! incremental run, a step whose loads name an amplitude contributes one
//! program step per segment between the amplitude's points inside the
//! step: load factors `c a(t_i)`, then `c a(T)`, with `c` the step's
//! loads at amplitude 1 as a multiple of the pattern (segments that do not
//! move the load factor are dropped). All loads and non-zero prescribed
//! displacements given in such a step share the amplitude, and none may be
//! carried from an earlier step (it would stay constant while the others
//! vary: not one pattern); errors name the line otherwise. Newton's
//! increment fractions apply to each segment; `INC=n` counts the
//! increments of all segments of the step.

use crate::error::{bail, err, Result};
use crate::input::inp::{
    read_inp, InpDeck, InpExpansion, InpMaterial, InpMaterialKind, InpMixedMode, InpOnset,
    InpSoftening, InpStep,
};
use crate::input::scene::{AnalysisKind, AnalysisSpec, CurveSpec};
use junta_core::registry::{self, ElementBuild, ElementEntry, LawEntry, MaterialEntry};
use junta_core::{Element, Kinematics, Model};
use junta_elements::Orientation;
use junta_solvers::arc_length::ArcLengthSettings;
use junta_solvers::newton::NewtonSettings;
use std::path::Path;
use std::sync::Arc;

fn table(pairs: &[(&str, f64)]) -> toml::Table {
    pairs
        .iter()
        .map(|(k, v)| (k.to_string(), toml::Value::Float(*v)))
        .collect()
}

/// A deck turned into a model, with what `junta run` needs besides.
pub struct DeckModel {
    /// The model, with the loads of the first step.
    pub model: Model,
    /// The reader's notes and the builder's.
    pub notes: Vec<String>,
    /// Every step's load case.
    pub steps: Vec<DeckStep>,
    /// First line of `*HEADING`.
    pub title: String,
    /// The incremental program of a deck with a softening law.
    pub incremental: Option<DeckIncremental>,
    /// `** junta: curve` directive.
    pub curve: Option<CurveSpec>,
    /// `** junta: output every=N` directive.
    pub every: Option<usize>,
    /// The linear solver the deck's `*STATIC, SOLVER=` asks for (a
    /// registry key), if any.
    pub solver: Option<String>,
    /// `*NODE PRINT` / `*EL PRINT` requests and the tables they fill.
    pub prints: crate::output::deck_print::PrintTables,
}

/// Map a `*STATIC, SOLVER=` name to a Junta back end, with a note.
///
/// Direct solvers (CalculiX SPOOLES, PARDISO, PASTIX; Abaqus DIRECT or
/// DEFAULT) -> `cholesky` (SPD, the linear and hardening case) or `ldlt`
/// (a softening cohesive law); CalculiX ITERATIVE SCALING / ITERATIVE
/// CHOLESKY (and Abaqus ITERATIVE) -> `cg`. Anything else is an error.
pub fn solver_of_deck(
    name: &str,
    softening: bool,
    at: &str,
    notes: &mut Vec<String>,
) -> Result<String> {
    let n = name.split_whitespace().collect::<Vec<_>>().join(" ");
    let key = match n.as_str() {
        "SPOOLES" | "PARDISO" | "PASTIX" | "DIRECT" | "DEFAULT" | "SGI" | "TAUCS" => {
            if softening {
                "ldlt"
            } else {
                "cholesky"
            }
        }
        "ITERATIVE SCALING" | "ITERATIVE CHOLESKY" | "ITERATIVE" => "cg",
        _ => {
            return Err(err!(
                "{at}: *STATIC, SOLVER={name}: unknown solver; valid: SPOOLES, PARDISO, PASTIX, ITERATIVE SCALING, ITERATIVE CHOLESKY"
            ))
        }
    };
    notes.push(format!(
        "{at}: *STATIC, SOLVER={name} -> Junta's `{key}` back end (override with --solver type=...)"
    ));
    Ok(key.to_string())
}

/// The incremental analysis of a deck (see the module docs).
#[derive(Debug, Clone)]
pub struct DeckIncremental {
    /// `type = "static"`, the load program and the Newton settings.
    pub analysis: AnalysisSpec,
    /// Per program step: `*STEP, INC=n` and the line of that `*STEP` (a
    /// deck step with an amplitude makes one program step per segment
    /// between its points, all with the deck step's limit: the limit counts
    /// the increments of all of them).
    pub increment_limits: Vec<Option<(usize, usize)>>,
    /// Per program step: the deck step (0-based) it belongs to.
    pub deck_steps: Vec<usize>,
    /// The load pattern the load factor scales (the first step's loads, at
    /// amplitude 1 when it has one).
    pub pattern: DeckStep,
    /// The temperature change the temperature factor scales and the
    /// factor at the end of each program step ([`junta_core::Model::temperature_steps`]),
    /// when the deck changes temperatures.
    pub temperature: Option<(Vec<f64>, Vec<f64>)>,
}

/// The interface law of a cohesive material: registry key and parameters
/// (see the module docs); `thickness` is the constitutive thickness `T0`,
/// `period` the step period `T` (for the viscosity).
pub fn cohesive_law_table(
    mat: &InpMaterial,
    thickness: f64,
    period: f64,
    file: &str,
    notes: &mut Vec<String>,
) -> Result<(&'static str, toml::Table)> {
    let InpMaterialKind::Traction([enn, ess, ett]) = mat.kind else {
        bail!(
            "{file}:{}: *MATERIAL, NAME={}: cohesive elements need *ELASTIC, TYPE=TRACTION",
            mat.line,
            mat.name
        );
    };
    let (kn, ks, kt) = (enn / thickness, ess / thickness, ett / thickness);
    let (Some(init), Some(evo)) = (&mat.damage_initiation, &mat.damage_evolution) else {
        return Ok((
            "linear_penalty",
            table(&[("d1", ks), ("d2", kt), ("d3", kn)]),
        ));
    };
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-6 * a.abs().max(b.abs());
    let el = mat.elastic_line;
    if !close(ess, ett) {
        bail!(
            "{file}:{el}: *ELASTIC, TYPE=TRACTION: K_ss = {ess} and K_tt = {ett} differ; Junta's damage laws have one shear penalty: give K_ss = K_tt"
        );
    }
    let [tn, ts, tt] = init.strengths;
    if !close(ts, tt) {
        bail!(
            "{file}:{}: *DAMAGE INITIATION: t_s^0 = {ts} and t_t^0 = {tt} differ; Junta's damage laws have one shear strength: give t_s^0 = t_t^0",
            init.data_line
        );
    }
    let [g1, g2, g3] = evo.toughness;
    if !close(g2, g3) {
        bail!(
            "{file}:{}: *DAMAGE EVOLUTION: G_IIc = {g2} and G_IIIc = {g3} differ; Junta's damage laws have one shear toughness: give G_IIc = G_IIIc",
            evo.data_line
        );
    }
    let mut t = table(&[("K", kn), ("N", tn), ("S", ts), ("G_Ic", g1), ("G_IIc", g2)]);
    let turon = kn * (g1 / g2) * (ts / tn).powi(2);
    if close(ks, kn) {
        // shear_penalty = "equal" is the default
    } else if close(ks, turon) {
        t.insert("shear_penalty".into(), "turon2018".into());
        notes.push(format!(
            "{file}:{el}: K_ss = K_nn (G_Ic/G_IIc)(t_s^0/t_n^0)^2: shear_penalty = \"turon2018\"; Junta's equivalent jump with two penalties is Turon's energy-based one, Abaqus' effective separation is geometric, so mixed-mode curves can differ from Abaqus'"
        ));
    } else {
        bail!(
            "{file}:{el}: *ELASTIC, TYPE=TRACTION: K_ss = {ess} is neither K_nn = {enn} nor Turon's K_nn (G_Ic/G_IIc)(t_s^0/t_n^0)^2 = {:.6e}; Junta's damage laws take K_s = K_n or Turon's rule",
            turon * thickness
        );
    }
    match evo.mixed_mode {
        InpMixedMode::Bk { power } => {
            t.insert("propagation".into(), "bk".into());
            t.insert("eta".into(), power.into());
        }
        InpMixedMode::PowerLaw { power } => {
            t.insert("propagation".into(), "power_law".into());
            t.insert("alpha".into(), power.into());
        }
        InpMixedMode::ModeIndependent => {
            t.insert("propagation".into(), "bk".into());
            t.insert("eta".into(), 1.0.into());
        }
    }
    let onset = match init.criterion {
        InpOnset::Quads => "quadratic",
        InpOnset::Maxs => "max_stress",
    };
    t.insert("onset".into(), onset.into());
    if let Some(st) = &mat.damage_stabilization {
        if st.viscosity > 0.0 {
            t.insert("viscosity".into(), (st.viscosity / period).into());
        }
    }
    let key = match evo.softening {
        InpSoftening::Linear => "bilinear",
        InpSoftening::Exponential => {
            notes.push(format!(
                "{file}:{}: SOFTENING=EXPONENTIAL -> law `exponential`: same onset and fracture energy as Abaqus, but Junta's exponential curve (traction decaying exponentially after onset) is not Abaqus' energy-defined one",
                evo.line
            ));
            "exponential"
        }
    };
    Ok((key, t))
}

/// The constitutive thickness of the cohesive sections that use `mat`
/// (1 when not given); sections with different thicknesses are an error.
fn section_thickness(deck: &InpDeck, mat: &InpMaterial, file: &str) -> Result<f64> {
    let mut out: Option<(f64, usize)> = None;
    for c in deck
        .cohesive_sections
        .iter()
        .filter(|c| c.material.eq_ignore_ascii_case(&mat.name))
    {
        let t = c.thickness.unwrap_or(1.0);
        match out {
            Some((t0, l0)) if t0 != t => bail!(
                "{file}:{}: *COHESIVE SECTION: material `{}` is used with constitutive thickness {t} here and {t0} at line {l0}; give each thickness its own material",
                c.line,
                mat.name
            ),
            _ => out = Some((t, c.line)),
        }
    }
    Ok(out.map_or(1.0, |o| o.0))
}

/// Step period `T` of step `k` (1 when not given).
fn period(deck: &InpDeck, k: usize) -> f64 {
    deck.steps
        .get(k)
        .and_then(|s| s.static_procedure.as_ref())
        .and_then(|p| p.period)
        .unwrap_or(1.0)
}

/// Read a deck and build the model (with the boundary conditions and loads
/// of its first step), every step's load case, and for a deck with a
/// softening law its incremental program.
///
/// Stages: `read_deck`, `build_elements` (one element set per block,
/// with its material or cohesive law), `deck_solver`, the load cases
/// ([`deck_steps`]) and, with a softening law, the load program
/// (`incremental_program`); then what the run reports (reaction sets,
/// curve, print tables) and the model itself (`model_of_deck`).
pub fn build_model(path: &Path) -> Result<DeckModel> {
    let file = path.display().to_string();
    let mut deck = read_deck(path, &file)?;
    let mut notes = deck.notes.clone();
    let (elements, softening) = build_elements(&deck, &file, &mut notes)?;
    let solver = deck_solver(&deck, softening, &file, &mut notes)?;
    let steps = deck_steps(&deck, &file)?;
    if !softening {
        note_linear_riks(&deck, &file, &mut notes);
    }
    // a softening law or NLGEOM: an incremental run (a linear deck with
    // NLGEOM runs incrementally, as in CalculiX)
    note_nlgeom_pressures(&deck, &file, &mut notes);
    let incremental = if softening || deck_kinematics(&deck) == Kinematics::Finite {
        Some(incremental_program(&deck, &steps, &file, &mut notes)?)
    } else {
        None
    };
    let reaction_sets = reaction_sets(&mut deck);
    let first = incremental.as_ref().map_or(&steps[0], |i| &i.pattern);
    let curve = curve_spec(&deck, incremental.is_some(), &file, &mut notes);
    let title = deck.heading.lines().next().unwrap_or("").trim().to_string();
    let every = deck.every;
    let prints = print_tables(&mut deck);
    // the temperature change: the first step's (linear), or the pattern
    // the program's temperature factor scales (incremental)
    let (temperature, temperature_steps) = match &incremental {
        Some(inc) => match &inc.temperature {
            Some((field, factors)) => (Some(field.clone()), factors.clone()),
            None => (None, Vec::new()),
        },
        None => (steps[0].temperature.clone(), Vec::new()),
    };
    if steps.iter().any(|s| s.temperature.is_some())
        && !deck.temperatures.iter().any(|t| t.step.is_none())
    {
        notes.push(format!(
            "{file}: *TEMPERATURE without *INITIAL CONDITIONS, TYPE=TEMPERATURE: the initial (stress-free) temperature is 0"
        ));
    }
    let mut model = model_of_deck(deck, elements, first, reaction_sets, &file, &mut notes)?;
    model
        .set_temperature(temperature)
        .map_err(|e| err!("{file}: *TEMPERATURE: {e}"))?;
    model.temperature_steps = temperature_steps;
    Ok(DeckModel {
        model,
        notes,
        steps,
        title,
        incremental,
        curve,
        every,
        solver,
        prints,
    })
}

/// Read the deck (`*INCLUDE` files in place: errors name the file they are
/// in) and refuse one with nothing to solve.
fn read_deck(path: &Path, file: &str) -> Result<InpDeck> {
    let deck = read_inp(path).map_err(|e| err!("{e}"))?;
    if deck.mesh.nodes.is_empty() && deck.mesh.blocks.is_empty() {
        bail!("{file}: the deck is empty: no *NODE and no *ELEMENT");
    }
    if deck.mesh.num_elements() == 0 {
        bail!("{file}: the deck has no *ELEMENT: nothing to solve");
    }
    if deck.steps.is_empty() {
        bail!("{file}: the deck has no *STEP: nothing to solve; add *STEP, *STATIC, the loads and *END STEP");
    }
    Ok(deck)
}

/// The elements of every block, in block order, and whether any cohesive
/// law softens (then the deck runs incremental).
fn build_elements(
    deck: &InpDeck,
    file: &str,
    notes: &mut Vec<String>,
) -> Result<(Vec<Arc<dyn Element>>, bool)> {
    let mut elements = Vec::new();
    let mut softening = false;
    for bi in 0..deck.mesh.blocks.len() {
        let (element, softens) = block_element(deck, bi, file, notes)?;
        softening |= softens;
        elements.push(element);
    }
    Ok((elements, softening))
}

/// Finite kinematics when a step asks for NLGEOM. Abaqus keeps NLGEOM on
/// for the rest of the analysis once a step sets it; Junta takes it for the
/// whole run (a small-strain first step before an NLGEOM step is noted in
/// [`step_notes`]).
fn deck_kinematics(deck: &InpDeck) -> Kinematics {
    if deck.steps.iter().any(|s| s.nlgeom) {
        Kinematics::Finite
    } else {
        Kinematics::Small
    }
}

/// Under NLGEOM, a note on the first face pressure: Junta applies it on
/// the reference face (a dead load), CalculiX and Abaqus make it follow the
/// deformed face.
fn note_nlgeom_pressures(deck: &InpDeck, file: &str, notes: &mut Vec<String>) {
    use crate::input::inp::InpDloadKind;
    if deck_kinematics(deck) != Kinematics::Finite {
        return;
    }
    if let Some(d) = deck
        .dloads
        .iter()
        .find(|d| matches!(d.kind, InpDloadKind::Pressure(_)))
    {
        notes.push(format!(
            "{file}:{}: under NLGEOM this pressure acts on the reference face, in its reference direction (a dead load); CalculiX and Abaqus make a pressure follow the deformed face, so their answers differ once the face turns",
            d.line
        ));
    }
}

/// The material axes of block `bi` from its `*SOLID SECTION, ORIENTATION=`
/// (none without one): `a`, `b`, and for a cylindrical system (two points
/// of the axis) `system = "cylindrical"`; the elements then take the axes
/// at each integration point.
fn orientation_axes(deck: &InpDeck, bi: usize) -> Vec<(&'static str, toml::Value)> {
    match deck.block_orientations.get(bi).copied().flatten() {
        Some(o) => axes_of(&deck.orientations[o]),
        None => Vec::new(),
    }
}

/// The elements of block `bi`: its registry element type with the block's
/// material (isotropic, orthotropic or anisotropic, with the section's
/// axes) or, for cohesive elements, its interface law
/// ([`cohesive_law_table`]); `true` with them when that law softens.
fn block_element(
    deck: &InpDeck,
    bi: usize,
    file: &str,
    notes: &mut Vec<String>,
) -> Result<(Arc<dyn Element>, bool)> {
    let b = &deck.mesh.blocks[bi];
    if let Some(si) = deck.block_composites.get(bi).copied().flatten() {
        return Ok((composite_element(deck, bi, si, file)?, false));
    }
    let axes = orientation_axes(deck, bi);
    let mat = deck.material(&b.material).ok_or_else(|| {
        err!(
            "{file}: elements of block `{}` have no material: add a *SOLID SECTION (or *COHESIVE SECTION) for their ELSET",
            b.name
        )
    })?;
    let entry = registry::find::<ElementEntry>(&b.element_type).map_err(|e| err!("{file}: {e}"))?;
    let mut softening = false;
    let options = plane_options(deck, bi);
    let mut build = ElementBuild {
        material: None,
        law: None,
        options: &options,
        kinematics: deck_kinematics(deck),
    };
    let at = format!("{file}:{}: *MATERIAL, NAME={}", mat.line, mat.name);
    if b.shape.is_interface() {
        match &mat.kind {
            InpMaterialKind::Traction(_) => {
                if mat.expansion.is_some() {
                    notes.push(format!(
                        "{at}: *EXPANSION of a cohesive material ignored: interfaces carry no thermal strain (they see the jump the solids' expansion makes)"
                    ));
                }
                let thickness = section_thickness(deck, mat, file)?;
                let (key, t) = cohesive_law_table(mat, thickness, period(deck, 0), file, notes)?;
                softening = key != "linear_penalty";
                let l = registry::find::<LawEntry>(key)?;
                let law = (l.build)(&t).map_err(|e| err!("{at}: law `{key}`: {e}"))?;
                notes.extend(law.warnings().into_iter().map(|w| format!("{at}: {w}")));
                build.law = Some(law);
            }
            _ => {
                return Err(err!(
                    "{at}: cohesive elements of block `{}` need *ELASTIC, TYPE=TRACTION",
                    b.name
                ))
            }
        }
    } else {
        build.material = Some(solid_material(mat, &axes, &at, &b.name)?);
    }
    let element = (entry.build)(&build).map_err(|e| err!("{file}: block `{}`: {e}", b.name))?;
    Ok((element, softening))
}

/// The width a plane block's elements stand for: the full ring in an
/// axisymmetric model (CAX elements; a 2D cohesive block too), else the
/// section's thickness (default 1); `None` for 3D blocks.
pub(crate) fn block_width(deck: &InpDeck, bi: usize) -> Option<junta_core::element::PlaneWidth> {
    use junta_core::element::PlaneWidth;
    let b = &deck.mesh.blocks[bi];
    if b.shape.dimension() != 2 {
        return None;
    }
    let axisymmetric = if b.shape.is_interface() {
        deck.mesh
            .blocks
            .iter()
            .any(|o| o.element_type.starts_with("cax"))
    } else {
        b.element_type.starts_with("cax")
    };
    Some(if axisymmetric {
        PlaneWidth::Axisymmetric
    } else {
        PlaneWidth::Thickness(
            deck.block_thickness
                .get(bi)
                .copied()
                .flatten()
                .unwrap_or(1.0),
        )
    })
}

/// The element options of a plane block ([`block_width`]): `thickness`,
/// or for a 2D cohesive block of an axisymmetric model `axisymmetric`.
fn plane_options(deck: &InpDeck, bi: usize) -> toml::Table {
    use junta_core::element::PlaneWidth;
    let mut t = toml::Table::new();
    match block_width(deck, bi) {
        Some(PlaneWidth::Thickness(w)) => {
            t.insert("thickness".into(), w.into());
        }
        Some(PlaneWidth::Axisymmetric) if deck.mesh.blocks[bi].shape.is_interface() => {
            t.insert("axisymmetric".into(), true.into());
        }
        _ => {}
    }
    t
}

/// The solid material of `mat` (isotropic, orthotropic or anisotropic)
/// with the material axes `axes` (`a`, `b`, `system` of
/// [`orientation_axes`]; none: the global axes); `at` names the material
/// in errors, `block` the block.
fn solid_material(
    mat: &InpMaterial,
    axes: &[(&'static str, toml::Value)],
    at: &str,
    block: &str,
) -> Result<Arc<dyn junta_core::Material>> {
    let with_axes = |mut t: toml::Table| {
        for (k, v) in axes {
            t.insert((*k).into(), v.clone());
        }
        t
    };
    let material = match &mat.kind {
        InpMaterialKind::Isotropic { e, nu } => match &mat.expansion {
            // orthotropic expansion: an orthotropic material with
            // isotropic constants, in the section's axes
            Some(InpExpansion::Orthotropic(a)) => {
                let g = e / (2.0 * (1.0 + nu));
                let t = table(&[
                    ("E1", *e),
                    ("E2", *e),
                    ("E3", *e),
                    ("nu12", *nu),
                    ("nu13", *nu),
                    ("nu23", *nu),
                    ("G12", g),
                    ("G13", g),
                    ("G23", g),
                    ("alpha1", a[0]),
                    ("alpha2", a[1]),
                    ("alpha3", a[2]),
                ]);
                let m = registry::find::<MaterialEntry>("orthotropic")?;
                (m.build)(&with_axes(t)).map_err(|e| err!("{at}: {e}"))?
            }
            Some(InpExpansion::Anisotropic(_)) => {
                return Err(err!(
                    "{at}: *EXPANSION, TYPE=ANISO needs *ELASTIC, TYPE=ANISO (or give TYPE=ISO or ORTHO)"
                ))
            }
            iso => {
                let mut pairs = vec![("E", *e), ("nu", *nu)];
                if let Some(InpExpansion::Isotropic(a)) = iso {
                    pairs.push(("alpha", *a));
                }
                let m = registry::find::<MaterialEntry>("isotropic")?;
                (m.build)(&table(&pairs)).map_err(|e| err!("{at}: {e}"))?
            }
        },
        InpMaterialKind::EngineeringConstants(c) => {
            let names = ["E1", "E2", "E3", "nu12", "nu13", "nu23", "G12", "G13", "G23"];
            let mut pairs: Vec<(&str, f64)> =
                names.iter().copied().zip(c.iter().copied()).collect();
            let a = match &mat.expansion {
                None => None,
                Some(InpExpansion::Isotropic(a)) => Some([*a; 3]),
                Some(InpExpansion::Orthotropic(a)) => Some(*a),
                Some(InpExpansion::Anisotropic(_)) => {
                    return Err(err!(
                        "{at}: *EXPANSION, TYPE=ANISO needs *ELASTIC, TYPE=ANISO (or give TYPE=ISO or ORTHO)"
                    ))
                }
            };
            if let Some(a) = a {
                pairs.extend([("alpha1", a[0]), ("alpha2", a[1]), ("alpha3", a[2])]);
            }
            let m = registry::find::<MaterialEntry>("orthotropic")?;
            (m.build)(&with_axes(table(&pairs))).map_err(|e| err!("{at}: {e}"))?
        }
        InpMaterialKind::Anisotropic(d) => {
            let mut t = toml::Table::new();
            let floats = |v: &[f64]| toml::Value::Array(v.iter().map(|&x| toml::Value::Float(x)).collect());
            t.insert("D".into(), floats(&d[..]));
            let a = match &mat.expansion {
                None => None,
                Some(InpExpansion::Isotropic(a)) => Some([*a, *a, *a, 0.0, 0.0, 0.0]),
                Some(InpExpansion::Orthotropic(a)) => Some([a[0], a[1], a[2], 0.0, 0.0, 0.0]),
                Some(InpExpansion::Anisotropic(a)) => Some(*a),
            };
            if let Some(a) = a {
                t.insert("alpha".into(), floats(&a));
            }
            let m = registry::find::<MaterialEntry>("anisotropic")?;
            (m.build)(&with_axes(t)).map_err(|e| err!("{at}: {e}"))?
        }
        _ => {
            return Err(err!(
                "{at}: solid elements of block `{block}` need *ELASTIC (ISOTROPIC, ENGINEERING CONSTANTS, ORTHO or ANISO)"
            ))
        }
    };
    Ok(material)
}

/// The material axes of an `*ORIENTATION` as the table keys of a
/// material (`a`, `b`, and `system = "cylindrical"` for a cylindrical one).
fn axes_of(o: &crate::input::inp::InpOrientation) -> Vec<(&'static str, toml::Value)> {
    let arr = |v: [f64; 3]| toml::Value::Array(v.iter().map(|&x| toml::Value::Float(x)).collect());
    let mut axes = vec![("a", arr(o.a)), ("b", arr(o.b))];
    if o.cylindrical {
        axes.push(("system", toml::Value::String("cylindrical".into())));
    }
    axes
}

/// The layered element of block `bi`, whose `*SOLID SECTION, COMPOSITE`
/// is `deck.solid_sections[si]`: each ply's material ([`solid_material`])
/// in its axes — its `*ORIENTATION`; or an angle `theta` about axis 3 of
/// the section's orientation (`a' = cos theta e1 + sin theta e2`, `b' =
/// -sin theta e1 + cos theta e2`, with `e1`, `e2` the section's axes 1, 2,
/// the global x, y without one); or the section's orientation; or the
/// global axes — integrated ply by ply ([`junta_elements::layered`]).
fn composite_element(deck: &InpDeck, bi: usize, si: usize, file: &str) -> Result<Arc<dyn Element>> {
    use crate::input::inp::InpPlyAxes;
    use junta_elements::{Integration, Ply, SolidElement};
    let b = &deck.mesh.blocks[bi];
    let s = &deck.solid_sections[si];
    let c = s.composite.as_ref().expect("a composite section");
    let integration = match b.element_type.as_str() {
        "h20r" => Integration::Reduced,
        _ => Integration::Full,
    };
    let section_axes = |o: Option<usize>| -> Result<[[f64; 3]; 2]> {
        let Some(o) = o else {
            return Ok([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
        };
        let o = &deck.orientations[o];
        let q = Orientation::rectangular(o.a, o.b)
            .axes()
            .map_err(|e| err!("{file}:{}: *ORIENTATION, NAME={}: {e}", o.line, o.name))?
            .reference();
        Ok([
            [q[(0, 0)], q[(1, 0)], q[(2, 0)]],
            [q[(0, 1)], q[(1, 1)], q[(2, 1)]],
        ])
    };
    let mut plies = Vec::with_capacity(c.plies.len());
    for (k, ply) in c.plies.iter().enumerate() {
        let mat = deck.material(&ply.material).ok_or_else(|| {
            err!(
                "{file}:{}: *SOLID SECTION: material `{}` is not defined",
                ply.line,
                ply.material
            )
        })?;
        let axes = match ply.axes {
            InpPlyAxes::Named { index, .. } => axes_of(&deck.orientations[index]),
            InpPlyAxes::Section => match c.orientation {
                Some(o) => axes_of(&deck.orientations[o]),
                None => Vec::new(),
            },
            InpPlyAxes::Angle(theta) => {
                let [e1, e2] = section_axes(c.orientation)?;
                let (sn, cs) = theta.to_radians().sin_cos();
                let a: [f64; 3] = std::array::from_fn(|i| cs * e1[i] + sn * e2[i]);
                let bb: [f64; 3] = std::array::from_fn(|i| -sn * e1[i] + cs * e2[i]);
                let arr = |v: [f64; 3]| {
                    toml::Value::Array(v.iter().map(|&x| toml::Value::Float(x)).collect())
                };
                vec![("a", arr(a)), ("b", arr(bb))]
            }
        };
        let at = format!(
            "{file}:{}: *SOLID SECTION, COMPOSITE: ply {} (*MATERIAL, NAME={})",
            ply.line,
            k + 1,
            mat.name
        );
        plies.push(Ply {
            material: solid_material(mat, &axes, &at, &b.name)?,
            thickness: ply.thickness,
            points: ply.points,
        });
    }
    let el = SolidElement::layered(b.shape, integration, c.stack_direction - 1, &plies)
        .map_err(|e| {
            err!(
                "{file}:{}: *SOLID SECTION, COMPOSITE: block `{}`: {e}",
                s.line,
                b.name
            )
        })?
        .with_kinematics(deck_kinematics(deck));
    Ok(Arc::new(el))
}

/// The back end the steps' `*STATIC, SOLVER=` ask for ([`solver_of_deck`]),
/// if any; steps asking for different ones are an error.
fn deck_solver(
    deck: &InpDeck,
    softening: bool,
    file: &str,
    notes: &mut Vec<String>,
) -> Result<Option<String>> {
    let mut solver = None;
    for st in &deck.steps {
        if let Some(p) = &st.static_procedure {
            if let Some(name) = &p.solver {
                let at = format!("{file}:{}", p.line);
                let key = solver_of_deck(name, softening, &at, notes)?;
                if solver.as_ref().is_some_and(|k| k != &key) {
                    return Err(err!(
                        "{at}: *STATIC, SOLVER={name} differs from an earlier step's solver; Junta uses one back end per run"
                    ));
                }
                solver = Some(key);
            }
        }
    }
    Ok(solver)
}

/// A note for `*STATIC, RIKS` on a deck without a softening law: its path
/// is linear, solved in one step.
fn note_linear_riks(deck: &InpDeck, file: &str, notes: &mut Vec<String>) {
    if let Some(p) = deck
        .steps
        .iter()
        .filter_map(|st| st.static_procedure.as_ref())
        .find(|p| p.riks.is_some())
    {
        notes.push(format!(
            "{file}:{}: *STATIC, RIKS on a model without a softening law: its path is linear, solved in one linear step",
            p.line
        ));
    }
}

/// The node sets whose reactions are reported: every `*BOUNDARY` target,
/// once, in order (a target given by node gets a node set `node_N`, added
/// to the mesh).
fn reaction_sets(deck: &mut InpDeck) -> Vec<String> {
    let mut reaction_sets: Vec<String> = Vec::new();
    for bc in &deck.boundaries {
        let name = match deck
            .mesh
            .node_sets
            .keys()
            .find(|k| k.eq_ignore_ascii_case(&bc.target))
        {
            Some(k) => k.clone(),
            None => {
                let k = format!("node_{}", bc.target);
                deck.mesh.node_sets.insert(k.clone(), bc.nodes.clone());
                k
            }
        };
        if !reaction_sets.contains(&name) {
            reaction_sets.push(name);
        }
    }
    reaction_sets
}

/// The `** junta: curve` directive as a curve spec; on a deck that runs
/// linear (`incremental` false) a note that it is not used.
fn curve_spec(
    deck: &InpDeck,
    incremental: bool,
    file: &str,
    notes: &mut Vec<String>,
) -> Option<CurveSpec> {
    let curve = deck.curve.as_ref().map(|c| CurveSpec {
        reaction_set: c.reaction_set.clone(),
        reaction_component: c.reaction_component.clone(),
        point_set: c.point_set.clone(),
        point_component: c.point_component.clone(),
        relative_to: c.relative_to.clone(),
        negate: false,
        reference: None,
        conjugate: false,
    });
    if let (Some(c), false) = (&deck.curve, incremental) {
        notes.push(format!(
            "{file}:{}: the curve directive is used by incremental runs only (a deck with a softening cohesive law); this deck runs linear",
            c.line
        ));
    }
    curve
}

/// The deck's `*NODE PRINT` / `*EL PRINT` requests (taken from it), with
/// the material axes of each block with an orientation (for `*EL PRINT`).
fn print_tables(deck: &mut InpDeck) -> crate::output::deck_print::PrintTables {
    let block_axes = deck
        .block_orientations
        .iter()
        .map(|o| {
            o.and_then(|o| {
                let o = &deck.orientations[o];
                let o = if o.cylindrical {
                    Orientation::cylindrical(o.a, o.b)
                } else {
                    Orientation::rectangular(o.a, o.b)
                };
                o.axes().ok()
            })
        })
        .collect();
    crate::output::deck_print::PrintTables::new(
        std::mem::take(&mut deck.node_prints),
        std::mem::take(&mut deck.el_prints),
    )
    .with_axes(block_axes)
}

/// The model of the deck's mesh and elements, loaded by `first` (the first
/// step, or the incremental run's pattern), with its `*EQUATION`s
/// eliminated; element errors name the deck's own element label.
fn model_of_deck(
    deck: InpDeck,
    elements: Vec<Arc<dyn Element>>,
    first: &DeckStep,
    reaction_sets: Vec<String>,
    file: &str,
    notes: &mut Vec<String>,
) -> Result<Model> {
    crate::prepare::limits::check_memory(
        &format!("{file}: the model ({} nodes)", deck.mesh.nodes.len()),
        crate::prepare::limits::model_bytes(&deck.mesh),
    )?;
    // element errors name the deck's own element label, not the index
    let labels: std::collections::HashMap<(usize, usize), usize> = deck
        .element_labels
        .iter()
        .map(|(&l, r)| ((r.block, r.element), l))
        .collect();
    let block_names: Vec<String> = deck.mesh.blocks.iter().map(|b| b.name.clone()).collect();
    let equations: Vec<junta_core::dof::LinearEquation> = deck
        .equations
        .iter()
        .map(|e| junta_core::dof::LinearEquation {
            terms: e
                .terms
                .iter()
                .map(|&(node, dof, a)| (3 * node + dof - 1, a))
                .collect(),
            origin: format!("{file}:{}", e.line),
        })
        .collect();
    let mut model = Model::new(
        deck.mesh,
        elements,
        &first.constraints,
        first.f_ext.clone(),
        reaction_sets,
    )
    .map_err(|e| match e {
        junta_core::CoreError::Element {
            block,
            element,
            source,
        } => {
            let label = block_names
                .iter()
                .position(|n| *n == block)
                .and_then(|b| labels.get(&(b, element)));
            match label {
                Some(label) => {
                    err!("{file}: element {label} (*ELEMENT label) of ELSET `{block}`: {source}")
                }
                None => err!(
                    "{file}: element {} of block `{block}`: {source}",
                    element + 1
                ),
            }
        }
        e => err!("{file}: {e}"),
    })?;
    model.add_equations(&equations).map_err(|e| err!("{e}"))?;
    if !equations.is_empty() {
        notes.push(format!(
            "{} linear equations (*EQUATION) eliminated: {} dependent dofs",
            equations.len(),
            model.dofs.dependents.dofs.len()
        ));
    }
    Ok(model)
}

/// `c` with `s = c * pattern` (same constrained dofs, values and forces in
/// proportion, to 1e-12 of the largest), if any.
fn proportional(pattern: &DeckStep, s: &DeckStep) -> Option<f64> {
    if pattern.constraints.len() != s.constraints.len()
        || pattern
            .constraints
            .iter()
            .zip(&s.constraints)
            .any(|(a, b)| a.0 != b.0)
    {
        return None;
    }
    let p: Vec<f64> = pattern
        .constraints
        .iter()
        .map(|c| c.1)
        .chain(pattern.f_ext.iter().copied())
        .collect();
    let v: Vec<f64> = s
        .constraints
        .iter()
        .map(|c| c.1)
        .chain(s.f_ext.iter().copied())
        .collect();
    let (imax, pmax) = p
        .iter()
        .enumerate()
        .map(|(i, x)| (i, x.abs()))
        .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
    if pmax == 0.0 {
        return None;
    }
    let c = v[imax] / p[imax];
    let scale = pmax.max(v.iter().fold(0.0f64, |m, x| m.max(x.abs())));
    p.iter()
        .zip(&v)
        .all(|(a, b)| (b - c * a).abs() <= 1e-12 * scale)
        .then_some(c)
}

/// The amplitude of the loads and prescribed displacements given in step
/// `k` of an incremental run (`None`: they ramp linearly): one for all of
/// them (fixed supports, value 0, aside), or an error naming the line.
fn step_amplitude(deck: &InpDeck, k: usize, file: &str) -> Result<Option<usize>> {
    let given = deck
        .boundaries
        .iter()
        .filter(|b| b.step == Some(k) && b.value != 0.0)
        .map(|b| (b.amplitude, b.line))
        .chain(
            deck.cloads
                .iter()
                .filter(|c| c.step == Some(k) && c.value != 0.0)
                .map(|c| (c.amplitude, c.line)),
        )
        .chain(
            deck.dloads
                .iter()
                .filter(|d| d.step == Some(k))
                .map(|d| (d.amplitude, d.line)),
        );
    let mut first: Option<(Option<usize>, usize)> = None;
    for (a, line) in given {
        match first {
            None => first = Some((a, line)),
            Some((b, l)) if a != b => {
                let name = |x: Option<usize>| {
                    x.map_or("none (a linear ramp)".to_string(), |i| {
                        format!("`{}`", deck.amplitudes[i].name)
                    })
                };
                bail!(
                    "{file}:{line}: amplitude {} here, {} at line {l} of the same step: Junta's incremental runs scale one load pattern, so every load and prescribed displacement of a step must use the same AMPLITUDE= (or none)",
                    name(a),
                    name(b)
                );
            }
            _ => {}
        }
    }
    Ok(first.and_then(|f| f.0))
}

/// The load program and Newton settings of a deck with a softening law
/// (module docs).
///
/// Stages: the load pattern ([`ProgramSteps::pattern`]); per deck step,
/// the load factors it passes through ([`ProgramSteps::targets`], segments
/// that do not move the load dropped), its notes ([`step_notes`]) and its
/// Newton settings ([`step_newton`], the same for every step); the checks
/// of amplitudes against viscosity and Riks ([`check_amplitudes`]); and
/// `*STATIC, RIKS` as path following ([`riks_path`]).
fn incremental_program(
    deck: &InpDeck,
    steps: &[DeckStep],
    file: &str,
    notes: &mut Vec<String>,
) -> Result<DeckIncremental> {
    let mut program = Vec::with_capacity(steps.len());
    let mut limits = Vec::with_capacity(steps.len());
    let mut deck_steps = Vec::with_capacity(steps.len());
    let mut settings: Option<(NewtonSettings, usize)> = None;
    let ps = ProgramSteps::new(deck, steps.len(), file)?;
    let pattern = ps.pattern(steps)?;
    let temperature = temperature_pattern(steps, file)?;
    let mut temperature_steps = Vec::with_capacity(steps.len());
    let (mut lambda, mut theta) = (0.0, 0.0);
    for (k, s) in steps.iter().enumerate() {
        let targets = ps.targets(&pattern, k, s, lambda, notes)?;
        let step = deck.steps.get(k);
        let limit = step.and_then(|st| st.max_increments.map(|n| (n, st.line)));
        let before = program.len();
        let c = temperature.as_ref().map_or(0.0, |(_, f)| f[k]);
        if c != theta && targets.len() > 1 {
            bail!(
                "{file}:{}: {}: its temperatures change in a step whose loads follow an amplitude; Junta ramps the temperature linearly over a step: give the temperature change its own step",
                s.line,
                s.name
            );
        }
        for t in targets {
            // a segment that moves neither the load nor the temperature is
            // no step at all
            if t != lambda || c != theta {
                program.push(t);
                limits.push(limit);
                deck_steps.push(k);
                temperature_steps.push(c);
                lambda = t;
                theta = c;
            }
        }
        let deck_has_nlgeom = deck_kinematics(deck) == Kinematics::Finite;
        step_notes(
            file,
            s,
            step,
            program.len() == before,
            deck_has_nlgeom,
            notes,
        );
        let (n, pline) = step_newton(file, s, step)?;
        match &settings {
            None => settings = Some((n, pline)),
            Some((first, l)) => {
                if first.initial_increment != n.initial_increment
                    || first.max_increment != n.max_increment
                    || first.min_increment != n.min_increment
                    || first.growth != n.growth
                {
                    bail!(
                        "{file}:{pline}: *STATIC: the increments of this step, as fractions of its period, differ from those of the *STATIC at line {l}; Junta's Newton settings are the same for every step: give every step the same fractions"
                    );
                }
            }
        }
    }
    check_amplitudes(deck, steps.len(), &ps.amps, file)?;
    let (mut newton, _) = settings.expect("at least one step");
    let (control, arc_length) =
        riks_path(deck, steps.len(), file, &mut program, &mut newton, notes)?;
    Ok(DeckIncremental {
        analysis: AnalysisSpec {
            kind: AnalysisKind::Static,
            steps: program,
            stop_when_separated: false,
            newton,
            control,
            arc_length,
            nlgeom: deck_kinematics(deck) == Kinematics::Finite,
        },
        increment_limits: limits,
        deck_steps,
        pattern,
        temperature: temperature.map(|(field, _)| (field, temperature_steps)),
    })
}

/// The deck's steps as the load program sees them: the amplitude of each
/// step's loads ([`step_amplitude`]) and the total time at each step's end
/// ([`step_ends`]).
struct ProgramSteps<'a> {
    deck: &'a InpDeck,
    file: &'a str,
    amps: Vec<Option<usize>>,
    ends: Vec<f64>,
}

impl<'a> ProgramSteps<'a> {
    fn new(deck: &'a InpDeck, steps: usize, file: &'a str) -> Result<Self> {
        let amps = (0..steps)
            .map(|k| step_amplitude(deck, k, file))
            .collect::<Result<Vec<_>>>()?;
        let ends = step_ends(deck);
        Ok(ProgramSteps {
            deck,
            file,
            amps,
            ends,
        })
    }

    /// The loads of step `k` (a step with an amplitude) at amplitude 1;
    /// loads carried from earlier steps (at their value) are an error.
    fn unit(&self, k: usize) -> Result<DeckStep> {
        let (deck, file, ends) = (self.deck, self.file, &self.ends);
        let carried = deck_steps_scaled(deck, file, k..k + 1, &|amp, st| {
            if st == Some(k) {
                0.0
            } else {
                amplitude_at_end(deck, ends, amp, st)
            }
        })?;
        let c = &carried[0];
        if c.constraints.iter().any(|c| c.1 != 0.0) || c.f_ext.iter().any(|f| *f != 0.0) {
            bail!(
                "{file}:{}: {}: loads or prescribed displacements carried over from earlier steps stay constant while this step's amplitude varies: not one load pattern; give them again in this step with the same AMPLITUDE=",
                c.line,
                c.name
            );
        }
        let mut u = deck_steps_scaled(deck, file, k..k + 1, &|amp, st| {
            if st == Some(k) {
                1.0
            } else {
                amplitude_at_end(deck, ends, amp, st)
            }
        })?;
        Ok(u.remove(0))
    }

    /// The load pattern the load factor scales: the first step's loads (at
    /// amplitude 1 when it has one); an error when nothing loads the model.
    fn pattern(&self, steps: &[DeckStep]) -> Result<DeckStep> {
        let pattern = match self.amps.first().copied().flatten() {
            Some(_) => self.unit(0)?,
            None => steps[0].clone(),
        };
        if pattern.constraints.iter().all(|c| c.1 == 0.0) && pattern.f_ext.iter().all(|f| *f == 0.0)
        {
            bail!(
                "{}:{}: {}: nothing loads the model (no *CLOAD, no non-zero *BOUNDARY): the incremental run of a softening deck scales the first step's loads",
                self.file,
                pattern.line,
                pattern.name
            );
        }
        Ok(pattern)
    }

    /// The load factors step `k` (`s`) passes through, from `lambda`: its
    /// multiple `c` of the pattern (1 for the first step); with an
    /// amplitude `a`, `c a(t_i)` at the amplitude's points inside the step,
    /// then `c a(T)` (a note when `c a(0)` is not where the loads stand).
    fn targets(
        &self,
        pattern: &DeckStep,
        k: usize,
        s: &DeckStep,
        lambda: f64,
        notes: &mut Vec<String>,
    ) -> Result<Vec<f64>> {
        let (deck, file) = (self.deck, self.file);
        let not_proportional = || {
            err!(
                "{file}:{}: {}: its loads and prescribed displacements are not a multiple of the first step's; Junta's incremental runs scale one load pattern over the steps (a proportional program), so multi-step softening decks must keep the same loaded dofs with proportional values (or be split into several decks)",
                s.line,
                s.name
            )
        };
        let a = match self.amps[k] {
            None if k == 0 => return Ok(vec![1.0]),
            None => return Ok(vec![proportional(pattern, s).ok_or_else(not_proportional)?]),
            Some(a) => a,
        };
        let c = if k == 0 {
            1.0
        } else {
            proportional(pattern, &self.unit(k)?).ok_or_else(not_proportional)?
        };
        let amp = &deck.amplitudes[a];
        let start = if amp.total_time {
            step_end_time(deck, &self.ends, k, true) - period(deck, k)
        } else {
            0.0
        };
        let end = start + period(deck, k);
        let mut t: Vec<f64> = amp
            .points
            .iter()
            .filter(|p| p.0 > start && p.0 < end)
            .map(|p| c * p.1)
            .collect();
        t.push(c * amp.value(end));
        if c != 0.0 && (c * amp.value(start) - lambda).abs() > 1e-12 * c.abs() {
            notes.push(format!(
                "{file}:{}: {}: amplitude `{}` starts at {} but the loads stand at {} of it: the jump is ramped over the step's first segment",
                s.line,
                s.name,
                amp.name,
                amp.value(start),
                lambda / c
            ));
        }
        Ok(t)
    }
}

/// The notes of one step of an incremental run: skipped (`skipped`: the
/// load factor does not change), a step without the NLGEOM of another, no `INC=`.
fn step_notes(
    file: &str,
    s: &DeckStep,
    step: Option<&InpStep>,
    skipped: bool,
    deck_has_nlgeom: bool,
    notes: &mut Vec<String>,
) {
    if skipped {
        notes.push(format!(
            "{file}:{}: {}: the load factor does not change in this step: nothing to solve, skipped",
            s.line, s.name
        ));
    }
    if step.is_some_and(|st| !st.nlgeom) && deck_has_nlgeom {
        notes.push(format!(
            "{file}:{}: this step has no NLGEOM but another step has: Junta runs the whole analysis with large deformation",
            s.line
        ));
    }
    if step.is_some_and(|st| st.max_increments.is_none()) {
        notes.push(format!(
            "{file}:{}: no INC= on *STEP: Abaqus would stop this step after 100 increments; Junta does not limit it",
            s.line
        ));
    }
}

/// The Newton settings of one step's `*STATIC` data `dt0, T, dtmin, dtmax`
/// as fractions of the period `T`: `initial_increment = min(dt0 / T, 1)`,
/// `max_increment = min(dtmax / T, 1)`, `min_increment = dtmin / T`
/// (default `min(dt0 / T, 1e-5)`); `DIRECT` fixes the increment at `dt0`.
/// With the line of the `*STATIC` (of the `*STEP` without one).
fn step_newton(
    file: &str,
    s: &DeckStep,
    step: Option<&InpStep>,
) -> Result<(NewtonSettings, usize)> {
    let proc = step.and_then(|st| st.static_procedure.as_ref());
    let t = proc.and_then(|p| p.period).unwrap_or(1.0);
    let pline = proc.map_or(s.line, |p| p.line);
    if t <= 0.0 {
        bail!("{file}:{pline}: *STATIC: the time period {t} must be positive");
    }
    let dt0 = (proc.and_then(|p| p.initial_increment).unwrap_or(t) / t).min(1.0);
    let mut n = NewtonSettings {
        initial_increment: dt0,
        max_increment: (proc.and_then(|p| p.max_increment).unwrap_or(t) / t).min(1.0),
        min_increment: proc
            .and_then(|p| p.min_increment)
            .map_or(dt0.min(1e-5), |m| m / t),
        ..NewtonSettings::default()
    };
    if proc.is_some_and(|p| p.direct) {
        n.max_increment = dt0;
        n.min_increment = dt0;
        n.growth = 1.0;
    }
    if !(n.initial_increment > 0.0 && n.max_increment > 0.0 && n.min_increment > 0.0) {
        bail!("{file}:{pline}: *STATIC: increments must be positive (data line `initial increment, time period, minimum increment, maximum increment`)");
    }
    if n.min_increment > n.initial_increment.min(n.max_increment) {
        bail!("{file}:{pline}: *STATIC: the minimum increment exceeds the initial or the maximum increment");
    }
    Ok((n, pline))
}

/// What an incremental program cannot combine: an amplitude (`amps`, per
/// step) with `*DAMAGE STABILIZATION` or `*STATIC, RIKS`, and the
/// stabilization with steps of different periods.
fn check_amplitudes(
    deck: &InpDeck,
    steps: usize,
    amps: &[Option<usize>],
    file: &str,
) -> Result<()> {
    let viscous = deck.materials.iter().any(|m| {
        m.damage_stabilization
            .as_ref()
            .is_some_and(|s| s.viscosity > 0.0)
    });
    if let Some(a) = amps.iter().flatten().next() {
        let amp = &deck.amplitudes[*a];
        if viscous {
            bail!(
                "{file}:{}: *AMPLITUDE {}: with *DAMAGE STABILIZATION: Junta's viscosity is in load-factor units (the load factor running linearly over the step), which an amplitude would make time-dependent; remove the amplitude or the stabilization",
                amp.line,
                amp.name
            );
        }
        if deck.steps.iter().any(|st| {
            st.static_procedure
                .as_ref()
                .is_some_and(|p| p.riks.is_some())
        }) {
            bail!(
                "{file}:{}: *AMPLITUDE {}: with *STATIC, RIKS: the arc length finds the load factor itself (Abaqus ignores amplitudes in a Riks step); remove AMPLITUDE=",
                amp.line,
                amp.name
            );
        }
    }
    if viscous && (1..steps).any(|k| period(deck, k) != period(deck, 0)) {
        bail!(
            "{file}: *DAMAGE STABILIZATION with steps of different periods: Junta's viscosity is in load-factor units, one value per law; give the steps the same period"
        );
    }
    Ok(())
}

/// `*STATIC, RIKS`: Abaqus's arc length, run with path following; the load
/// factor is the load proportionality factor (LPF) of the step's loads, the
/// 5th data value its maximum (the program becomes `[LPF_max]`, 1e6
/// without one), the first increment `dt0 / T` as a fraction of it, and
/// `INC` (default 100) the number of increments. Without Riks: load
/// control with path following at limit points (`control = "auto"`),
/// `program` and `newton` as they are.
fn riks_path(
    deck: &InpDeck,
    steps: usize,
    file: &str,
    program: &mut Vec<f64>,
    newton: &mut NewtonSettings,
    notes: &mut Vec<String>,
) -> Result<(crate::input::scene::Control, ArcLengthSettings)> {
    let mut control = crate::input::scene::Control::Auto;
    let mut arc_length = ArcLengthSettings::default();
    let riks = deck.steps.iter().find_map(|st| {
        let p = st.static_procedure.as_ref()?;
        Some((p.riks.as_ref()?, p, st))
    });
    if let Some((r, p, st)) = riks {
        if steps != 1 {
            bail!(
                "{file}:{}: *STATIC, RIKS: path following runs one step; this deck has {} steps",
                p.line,
                steps
            );
        }
        let t = p.period.unwrap_or(1.0);
        let first = p.initial_increment.unwrap_or(0.1 * t) / t;
        let end = match r.max_load_factor {
            Some(m) if m > 0.0 && m.is_finite() => m,
            Some(m) => bail!(
                "{file}:{}: *STATIC, RIKS: the maximum load proportionality factor {m} must be positive",
                p.line
            ),
            None => 1e6,
        };
        *program = vec![end];
        newton.initial_increment = (first / end).min(1.0);
        newton.max_increment = 1.0;
        newton.min_increment = newton.min_increment.min(1e-3 * newton.initial_increment);
        control = crate::input::scene::Control::ArcLength;
        // Abaqus ends a Riks step after INC increments (default 100)
        arc_length.max_increments = st.max_increments.unwrap_or(100);
        notes.push(format!(
            "{file}:{}: *STATIC, RIKS: path following (`control = \"arc_length\"`): the load factor is the load proportionality factor of the step's loads, first increment {first:e}, {}; arc lengths and their limits are Junta's own (cylindrical, then the dissipated energy)",
            p.line,
            match r.max_load_factor {
                Some(m) => format!("up to LPF = {m}"),
                None => format!("no maximum LPF: up to {} increments", arc_length.max_increments),
            }
        ));
    }
    Ok((control, arc_length))
}

/// The boundary conditions and loads in force in one step of a deck.
#[derive(Debug, Clone)]
pub struct DeckStep {
    /// `*STEP, NAME=` or `step N` (1-based).
    pub name: String,
    /// Line of `*STEP` (0 for a deck without steps).
    pub line: usize,
    /// `(dof, value)`, sorted by dof.
    pub constraints: Vec<(usize, f64)>,
    /// Nodal forces (length = dofs).
    pub f_ext: Vec<f64>,
    /// Temperature change of every node from its initial temperature
    /// (`*INITIAL CONDITIONS, TYPE=TEMPERATURE`, 0 where none is given) at
    /// the end of the step (`*TEMPERATURE` of this and earlier steps);
    /// `None` when nothing changes.
    pub temperature: Option<Vec<f64>>,
}

/// The temperature change of every node at the end of step `k`: the
/// initial temperatures, then every `*TEMPERATURE` of steps up to `k` in
/// order (`OP=NEW` goes back to the initial ones first; a node not given
/// keeps its earlier value, as in CalculiX and Abaqus). `None` when no node
/// changes.
fn step_temperature(deck: &InpDeck, k: usize) -> Option<Vec<f64>> {
    if deck.temperatures.is_empty() {
        return None;
    }
    let mut t0 = vec![0.0; deck.mesh.nodes.len()];
    for t in deck.temperatures.iter().filter(|t| t.step.is_none()) {
        for &n in &t.nodes {
            t0[n] = t.value;
        }
    }
    let mut t = t0.clone();
    let mut cleared = None;
    for tl in deck
        .temperatures
        .iter()
        .filter(|t| t.step.is_some_and(|s| s <= k))
    {
        if tl.op_new && cleared != tl.step {
            t.clone_from(&t0);
            cleared = tl.step;
        }
        for &n in &tl.nodes {
            t[n] = tl.value;
        }
    }
    let d: Vec<f64> = t.iter().zip(&t0).map(|(a, b)| a - b).collect();
    d.iter().any(|x| *x != 0.0).then_some(d)
}

/// The temperature changes of an incremental deck as one pattern: the
/// first step's non-zero change, and per deck step the multiple of it
/// reached at the step's end (the temperature factor, ramped over the step
/// like the loads). A change that is not a multiple of the pattern is an
/// error naming the step (Junta scales one temperature field).
fn temperature_pattern(steps: &[DeckStep], file: &str) -> Result<Option<(Vec<f64>, Vec<f64>)>> {
    let Some(pattern) = steps.iter().find_map(|s| s.temperature.clone()) else {
        return Ok(None);
    };
    let (imax, pmax) = pattern
        .iter()
        .enumerate()
        .fold(
            (0, 0.0f64),
            |(i, m), (j, v)| if v.abs() > m { (j, v.abs()) } else { (i, m) },
        );
    let mut factors = Vec::with_capacity(steps.len());
    for s in steps {
        let c = match &s.temperature {
            None => 0.0,
            Some(d) => {
                let c = d[imax] / pattern[imax];
                if d.iter()
                    .zip(&pattern)
                    .any(|(a, p)| (a - c * p).abs() > 1e-12 * pmax)
                {
                    bail!(
                        "{file}:{}: {}: its temperatures (*TEMPERATURE) are not a multiple of the first temperature change; an incremental run scales one temperature field (give the same nodes proportional values, or split the deck)",
                        s.line,
                        s.name
                    );
                }
                c
            }
        };
        factors.push(c);
    }
    Ok(Some((pattern, factors)))
}

/// Add the consistent nodal forces of the `*DLOAD` / `*DSLOAD` loads
/// active in step `k` to `f_ext`. A load on an element with the same label
/// (`P3`, `GRAV`, ...) as an earlier one replaces it (in the same step or a
/// later one, as CalculiX and Abaqus do); `OP=NEW` removes every earlier
/// distributed load. `GRAV` and `CENTRIF` use the density of the element's
/// material (`*DENSITY`, an error naming the material when missing).
fn add_distributed_loads(
    deck: &InpDeck,
    file: &str,
    k: usize,
    scale: &dyn Fn(Option<usize>, Option<usize>) -> f64,
    f_ext: &mut [f64],
) -> Result<()> {
    use crate::input::inp::InpDloadKind;
    use junta_core::mesh::{ElementRef, FaceRef};
    use junta_elements::body_load::{add_body_load_with, BodyLoad};
    use junta_elements::face_load::{add_face_load_with, FaceLoad};
    // (element, label) -> (load index, face)
    let mut active: std::collections::BTreeMap<(ElementRef, &str), (usize, usize)> =
        std::collections::BTreeMap::new();
    let mut cleared_at = None;
    for (i, d) in deck.dloads.iter().enumerate() {
        if d.step.is_some_and(|s| s > k) {
            continue;
        }
        if d.op_new && cleared_at != Some(d.keyword_line) {
            active.clear();
            cleared_at = Some(d.keyword_line);
        }
        for &(e, face) in &d.elements {
            // a *DSLOAD pressure is keyed by its face, as a *DLOAD Pn
            let label: &str = match d.kind {
                InpDloadKind::Pressure(_) => ["P1", "P2", "P3", "P4", "P5", "P6"][face],
                _ => &d.label,
            };
            active.insert((e, label), (i, face));
        }
    }
    // one call per load and block (a block has one material, one density)
    let mut groups: std::collections::BTreeMap<(usize, usize), Vec<(ElementRef, usize)>> =
        std::collections::BTreeMap::new();
    for ((e, _), (i, face)) in active {
        groups.entry((i, e.block)).or_default().push((e, face));
    }
    for ((i, block), members) in groups {
        let d = &deck.dloads[i];
        let c = scale(d.amplitude, d.step);
        let at = |err: junta_core::CoreError| {
            let kw = if d.label == "P" { "DSLOAD" } else { "DLOAD" };
            err!("{file}:{}: *{kw}: {err}", d.line)
        };
        let elements: Vec<ElementRef> = members.iter().map(|m| m.0).collect();
        let density = || -> Result<f64> {
            let b = &deck.mesh.blocks[block];
            match deck.material(&b.material).and_then(|m| m.density) {
                Some(rho) => Ok(rho),
                None => Err(err!(
                    "{file}:{}: *DLOAD: {} needs the density of material `{}` (element {}): add *DENSITY to it",
                    d.line,
                    d.label,
                    b.material,
                    deck.mesh.element_label(block, elements[0].element)
                )),
            }
        };
        let width = |b: usize| block_width(deck, b);
        let body = |rho: f64, load: BodyLoad, f: &mut [f64]| {
            add_body_load_with(&deck.mesh, &elements, rho, load, &width, f).map_err(at)
        };
        match d.kind {
            InpDloadKind::Pressure(p) => {
                let faces: Vec<FaceRef> = members
                    .iter()
                    .map(|&(e, face)| FaceRef {
                        block: e.block,
                        element: e.element,
                        face,
                    })
                    .collect();
                add_face_load_with(&deck.mesh, &faces, FaceLoad::Pressure(c * p), &width, f_ext)
                    .map_err(at)?
            }
            InpDloadKind::Gravity(g) => {
                body(density()?, BodyLoad::Gravity(g.map(|x| c * x)), f_ext)?
            }
            // the amplitude scales the load's magnitude, omega^2
            InpDloadKind::Centrifugal {
                omega2,
                point,
                axis,
            } => body(
                density()?,
                BodyLoad::Centrifugal {
                    omega2: c * omega2,
                    point,
                    axis,
                },
                f_ext,
            )?,
            InpDloadKind::BodyForce(b) => body(1.0, BodyLoad::Gravity(b.map(|x| c * x)), f_ext)?,
        }
    }
    Ok(())
}

/// The load cases of a deck: one per `*STEP` (one in all for a deck
/// without steps), by the rules of the module docs.
pub fn deck_steps(deck: &InpDeck, file: &str) -> Result<Vec<DeckStep>> {
    let all = 0..deck.steps.len().max(1);
    let ends = step_ends(deck);
    deck_steps_scaled(deck, file, all, &|amp, step| {
        amplitude_at_end(deck, &ends, amp, step)
    })
}

/// End of step `s` (0-based) in step time (its period) or total time (the
/// periods of the steps up to it, `ends` from [`step_ends`]).
fn step_end_time(deck: &InpDeck, ends: &[f64], s: usize, total: bool) -> f64 {
    if total {
        ends[s]
    } else {
        period(deck, s)
    }
}

/// Total time at the end of each step.
fn step_ends(deck: &InpDeck) -> Vec<f64> {
    (0..deck.steps.len().max(1))
        .scan(0.0, |t, k| {
            *t += period(deck, k);
            Some(*t)
        })
        .collect()
}

/// The factor of a load or prescribed displacement with amplitude `amp`
/// given in step `step`: the amplitude at the end of that step (a load
/// carried into later steps keeps that value, as in Abaqus and CalculiX
/// (checked with ccx 2.20: a `*CLOAD, AMPLITUDE=` of step 1 stays at its
/// step-1 end value through a step 2 that does not give it again); 1
/// without an amplitude.
fn amplitude_at_end(deck: &InpDeck, ends: &[f64], amp: Option<usize>, step: Option<usize>) -> f64 {
    match (amp, step) {
        (Some(a), Some(s)) => {
            let a = &deck.amplitudes[a];
            a.value(step_end_time(deck, ends, s, a.total_time))
        }
        _ => 1.0,
    }
}

/// [`deck_steps`] with each value (force, pressure, body load, prescribed
/// displacement) multiplied by `scale(amplitude, step it was given in)`.
fn deck_steps_scaled(
    deck: &InpDeck,
    file: &str,
    which: std::ops::Range<usize>,
    scale: &dyn Fn(Option<usize>, Option<usize>) -> f64,
) -> Result<Vec<DeckStep>> {
    use std::collections::BTreeMap;
    let ndof = 3 * deck.mesh.nodes.len();
    let mut out = Vec::with_capacity(which.len());
    for k in which {
        let upto = |s: Option<usize>| s.is_none_or(|s| s <= k);
        // dof -> (value, step it was set in, line)
        let mut bcs: BTreeMap<usize, (f64, Option<usize>, usize)> = BTreeMap::new();
        let mut cleared_at = None;
        for bc in deck.boundaries.iter().filter(|b| upto(b.step)) {
            if bc.op_new && cleared_at != Some(bc.keyword_line) {
                bcs.clear();
                cleared_at = Some(bc.keyword_line);
            }
            for &n in &bc.nodes {
                for dof in bc.first_dof..=bc.last_dof {
                    let d = 3 * n + dof - 1;
                    let value = bc.value * scale(bc.amplitude, bc.step);
                    if let Some(&(v, s, line)) = bcs.get(&d) {
                        if s == bc.step && v != value {
                            return Err(err!(
                                "{file}:{}: *BOUNDARY: node {} dof {dof} is given {} here and {v} at line {line} of the same {}",
                                bc.line,
                                deck.mesh.node_labels.get(n).copied().unwrap_or(n + 1),
                                value,
                                if bc.step.is_some() { "step" } else { "model data" }
                            ));
                        }
                    }
                    bcs.insert(d, (value, bc.step, bc.line));
                }
            }
        }
        // dof -> (value, step it was set in)
        let mut loads: BTreeMap<usize, (f64, Option<usize>)> = BTreeMap::new();
        let mut cleared_at = None;
        for c in deck.cloads.iter().filter(|c| upto(c.step)) {
            if c.op_new && cleared_at != Some(c.keyword_line) {
                loads.clear();
                cleared_at = Some(c.keyword_line);
            }
            let value = c.value * scale(c.amplitude, c.step);
            for &n in &c.nodes {
                let d = 3 * n + c.dof - 1;
                match loads.get_mut(&d) {
                    // within one step (or the model data) loads add up
                    Some((v, s)) if *s == c.step => *v += value,
                    // a later step replaces the value
                    _ => {
                        loads.insert(d, (value, c.step));
                    }
                }
            }
        }
        let mut f_ext = vec![0.0; ndof];
        for (d, (v, _)) in loads {
            f_ext[d] = v;
        }
        add_distributed_loads(deck, file, k, scale, &mut f_ext)?;
        let step = deck.steps.get(k);
        out.push(DeckStep {
            name: step
                .and_then(|s| s.name.clone())
                .unwrap_or_else(|| format!("step {}", k + 1)),
            line: step.map_or(0, |s| s.line),
            constraints: bcs.into_iter().map(|(d, (v, _, _))| (d, v)).collect(),
            f_ext,
            temperature: step_temperature(deck, k),
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::inp::parse_inp;

    /// Two bricks glued by one COH3D8 with cohesive material `material`
    /// (the lines after `*MATERIAL, NAME=CZ`) and section data `section`.
    fn glued(material: &str, section: &str) -> String {
        format!(
            "*NODE
1, 0, 0, 0
2, 1, 0, 0
3, 1, 1, 0
4, 0, 1, 0
5, 0, 0, 1
6, 1, 0, 1
7, 1, 1, 1
8, 0, 1, 1
11, 0, 0, 1
12, 1, 0, 1
13, 1, 1, 1
14, 0, 1, 1
15, 0, 0, 2
16, 1, 0, 2
17, 1, 1, 2
18, 0, 1, 2
*ELEMENT, TYPE=C3D8, ELSET=ARMS
1, 1, 2, 3, 4, 5, 6, 7, 8
2, 11, 12, 13, 14, 15, 16, 17, 18
*ELEMENT, TYPE=COH3D8, ELSET=GLUE
3, 5, 6, 7, 8, 11, 12, 13, 14
*MATERIAL, NAME=STEEL
*ELASTIC
210000., 0.3
*MATERIAL, NAME=CZ
{material}*SOLID SECTION, ELSET=ARMS, MATERIAL=STEEL
*COHESIVE SECTION, ELSET=GLUE, MATERIAL=CZ, RESPONSE=TRACTION SEPARATION
{section}"
        )
    }

    fn law_of(text: &str) -> Result<(&'static str, toml::Table, Vec<String>)> {
        let deck = parse_inp(text, "t.inp").map_err(|e| err!("{e}"))?;
        let mat = deck.material("CZ").unwrap();
        let mut notes = Vec::new();
        let t = section_thickness(&deck, mat, "t.inp")?;
        let (k, table) = cohesive_law_table(mat, t, period(&deck, 0), "t.inp", &mut notes)?;
        Ok((k, table, notes))
    }

    /// The cohesive material of the Abaqus DCB deck maps to exactly the law
    /// of its twin scene (both written by make_dcb_deck.py from the same
    /// numbers).
    #[test]
    fn dcb_deck_law_equals_scene_law() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/delamination");
        let text = std::fs::read_to_string(root.join("dcb_abaqus.inp")).unwrap();
        let (key, table, _) = law_of(&text).unwrap();
        let scene: toml::Table =
            toml::from_str(&std::fs::read_to_string(root.join("dcb_h8.toml")).unwrap()).unwrap();
        let mut expected = scene["laws"]["cz"].as_table().unwrap().clone();
        assert_eq!(expected.remove("type").unwrap().as_str(), Some(key));
        // propagation = "bk" is the scene's default
        let mut table = table;
        assert_eq!(table.remove("propagation").unwrap().as_str(), Some("bk"));
        assert_eq!(table, expected);
    }

    const ELASTIC: &str = "*ELASTIC, TYPE=TRACTION\n1e6, 1e6, 1e6\n";

    #[test]
    fn damage_options_map_to_law_parameters() {
        // MAXS, POWER LAW, EXPONENTIAL, stabilization over a period of 2,
        // constitutive thickness 0.5
        let text = glued(
            &format!(
                "{ELASTIC}*damage initiation, criterion = maxs\n80, 100, 100\n\
*Damage Evolution, type=ENERGY, softening=EXPONENTIAL, mixed mode behavior=POWER LAW, power=2\n0.969, 1.719, 1.719\n\
*DAMAGE STABILIZATION\n1e-3\n"
            ),
            "0.5\n*STEP\n*STATIC\n0.1, 2.0\n*END STEP\n",
        );
        let (key, t, notes) = law_of(&text).unwrap();
        assert_eq!(key, "exponential");
        assert_eq!(t["K"].as_float(), Some(2e6));
        assert_eq!(t["N"].as_float(), Some(80.0));
        assert_eq!(t["S"].as_float(), Some(100.0));
        assert_eq!(t["onset"].as_str(), Some("max_stress"));
        assert_eq!(t["propagation"].as_str(), Some("power_law"));
        assert_eq!(t["alpha"].as_float(), Some(2.0));
        assert_eq!(t["viscosity"].as_float(), Some(5e-4));
        assert!(notes.iter().any(|n| n.contains("EXPONENTIAL")), "{notes:?}");
        // mode independent: one toughness for all modes
        let text = glued(
            &format!("{ELASTIC}*DAMAGE INITIATION, CRITERION=QUADS\n80, 100, 100\n*DAMAGE EVOLUTION, TYPE=ENERGY\n1.5\n"),
            "\n",
        );
        let (key, t, _) = law_of(&text).unwrap();
        assert_eq!(key, "bilinear");
        assert_eq!(t["G_Ic"].as_float(), Some(1.5));
        assert_eq!(t["G_IIc"].as_float(), Some(1.5));
        assert_eq!(t["K"].as_float(), Some(1e6));
        // Turon's shear penalty K_s = K (G_Ic/G_IIc)(S/N)^2
        let ks = 1e6 * (0.969 / 1.719) * (100.0f64 / 80.0).powi(2);
        let text = glued(
            &format!("*ELASTIC, TYPE=TRACTION\n1e6, {ks:e}, {ks:e}\n*DAMAGE INITIATION, CRITERION=QUADS\n80, 100, 100\n*DAMAGE EVOLUTION, TYPE=ENERGY, MIXED MODE BEHAVIOR=BK, POWER=2.284\n0.969, 1.719, 1.719\n"),
            "\n",
        );
        let (_, t, notes) = law_of(&text).unwrap();
        assert_eq!(t["shear_penalty"].as_str(), Some("turon2018"));
        assert!(notes.iter().any(|n| n.contains("turon2018")), "{notes:?}");
        // no damage: linear penalty, divided by the thickness
        let (key, t, _) = law_of(&glued(ELASTIC, "2.0\n")).unwrap();
        assert_eq!(key, "linear_penalty");
        assert_eq!(t["d3"].as_float(), Some(5e5));
    }

    #[test]
    fn unequal_shear_data_is_an_error_naming_the_line() {
        let damage = "*DAMAGE INITIATION, CRITERION=QUADS\n80, 100, 100\n*DAMAGE EVOLUTION, TYPE=ENERGY, MIXED MODE BEHAVIOR=BK, POWER=2\n0.969, 1.719, 1.719\n";
        let base = glued(&format!("{ELASTIC}{damage}"), "\n");
        let line_of = |text: &str, pat: &str| text.lines().position(|l| l == pat).unwrap() + 1;
        for (from, to, what) in [
            ("1e6, 1e6, 1e6", "1e6, 1e6, 2e6", "K_tt"),
            ("1e6, 1e6, 1e6", "1e6, 3e6, 3e6", "K_ss"),
            ("80, 100, 100", "80, 100, 90", "t_t^0"),
            ("0.969, 1.719, 1.719", "0.969, 1.719, 2.0", "G_IIIc"),
        ] {
            let text = base.replace(from, to);
            let e = law_of(&text).unwrap_err().to_string();
            let line = line_of(&text, to);
            assert!(
                e.contains(&format!("t.inp:{line}:")) && e.contains(what),
                "{e}"
            );
        }
    }

    #[test]
    fn program_of_steps() {
        let deck_text = |steps: &str| {
            glued(
                &format!("{ELASTIC}*DAMAGE INITIATION, CRITERION=QUADS\n80, 100, 100\n*DAMAGE EVOLUTION, TYPE=ENERGY\n1.5\n"),
                &format!("\n*NSET, NSET=TOP\n15, 16, 17, 18\n*BOUNDARY\n1, 1, 3\n2, 1, 3\n3, 1, 3\n4, 1, 3\n{steps}"),
            )
        };
        let program = |steps: &str| -> Result<DeckIncremental> {
            let deck = parse_inp(&deck_text(steps), "t.inp").map_err(|e| err!("{e}"))?;
            let s = deck_steps(&deck, "t.inp")?;
            incremental_program(&deck, &s, "t.inp", &mut Vec::new())
        };
        let one =
            "*STEP, INC=7\n*STATIC\n0.1, 2.0, 0.001, 0.5\n*BOUNDARY\nTOP, 3, 3, 0.2\n*END STEP\n";
        let p = program(one).unwrap();
        assert_eq!(p.analysis.kind, AnalysisKind::Static);
        assert_eq!(p.analysis.steps, vec![1.0]);
        let n = &p.analysis.newton;
        assert_eq!(
            (n.initial_increment, n.min_increment, n.max_increment),
            (0.05, 0.0005, 0.25)
        );
        assert_eq!(
            p.increment_limits,
            vec![Some((
                7,
                deck_text(one)
                    .lines()
                    .position(|l| l.starts_with("*STEP"))
                    .unwrap()
                    + 1
            ))]
        );
        // a second step that unloads to 40 %: program [1, 0.4]
        let two = format!(
            "{one}*STEP\n*STATIC\n0.1, 2.0, 0.001, 0.5\n*BOUNDARY\nTOP, 3, 3, 0.08\n*END STEP\n"
        );
        let p = program(&two).unwrap();
        assert_eq!(p.analysis.steps.len(), 2);
        assert!((p.analysis.steps[1] - 0.4).abs() < 1e-12);
        // a second step that loads another dof: not a proportional program
        let other =
            format!("{one}*STEP\n*STATIC\n0.1, 2.0\n*BOUNDARY\nTOP, 1, 1, 0.1\n*END STEP\n");
        let e = program(&other).unwrap_err().to_string();
        assert!(e.contains("not a multiple of the first step"), "{e}");
        // other increment fractions
        let frac = format!(
            "{one}*STEP\n*STATIC\n0.2, 2.0, 0.001, 0.5\n*BOUNDARY\nTOP, 3, 3, 0.4\n*END STEP\n"
        );
        let e = program(&frac).unwrap_err().to_string();
        assert!(e.contains("same fractions"), "{e}");
        // DIRECT: fixed increments
        let p = program(&one.replace("*STATIC", "*STATIC, DIRECT")).unwrap();
        let n = &p.analysis.newton;
        assert_eq!(
            (
                n.initial_increment,
                n.min_increment,
                n.max_increment,
                n.growth
            ),
            (0.05, 0.05, 0.05, 1.0)
        );
    }

    /// `*AMPLITUDE` in an incremental run: the load factor passes through
    /// the amplitude's points inside each step (step or total time), the
    /// step's INC limit on each segment, and the errors of what one load
    /// pattern cannot express.
    #[test]
    fn amplitudes_in_the_program() {
        let deck_text = |steps: &str| {
            glued(
                &format!("{ELASTIC}*DAMAGE INITIATION, CRITERION=QUADS\n80, 100, 100\n*DAMAGE EVOLUTION, TYPE=ENERGY\n1.5\n"),
                &format!("\n*NSET, NSET=TOP\n15, 16, 17, 18\n*AMPLITUDE, NAME=CYC\n0, 0, 1, 1, 2, 0.5\n3, 1.2\n*AMPLITUDE, NAME=TOT, TIME=TOTAL TIME\n0, 0, 3, 1.2, 4, 2.0, 5, 0.0\n*BOUNDARY\n1, 1, 3\n2, 1, 3\n3, 1, 3\n4, 1, 3\n{steps}"),
            )
        };
        let program = |steps: &str| -> Result<DeckIncremental> {
            let deck = parse_inp(&deck_text(steps), "t.inp").map_err(|e| err!("{e}"))?;
            let s = deck_steps(&deck, "t.inp")?;
            incremental_program(&deck, &s, "t.inp", &mut Vec::new())
        };
        let one = "*STEP, INC=7\n*STATIC\n0.1, 3.0\n*BOUNDARY, AMPLITUDE=CYC\nTOP, 3, 3, 0.2\n*END STEP\n";
        let p = program(one).unwrap();
        // points at t = 1, 2 inside the step, then a(3)
        assert_eq!(p.analysis.steps, vec![1.0, 0.5, 1.2]);
        let line = deck_text(one)
            .lines()
            .position(|l| l.starts_with("*STEP"))
            .unwrap()
            + 1;
        assert_eq!(p.increment_limits, vec![Some((7, line)); 3]);
        // the pattern is the step's load at amplitude 1
        assert!(p.pattern.constraints.iter().any(|c| c.1 == 0.2));
        // a second step with a total-time amplitude (steps span 0-3, 3-6):
        // its points at t = 4 and 5, then a(6) = 0 (no change: no segment);
        // its value 0.1 is half the pattern's
        let two = format!(
            "{one}*STEP\n*STATIC\n0.1, 3.0\n*BOUNDARY, AMPLITUDE=TOT\nTOP, 3, 3, 0.1\n*END STEP\n"
        );
        let p = program(&two).unwrap();
        assert_eq!(p.analysis.steps, vec![1.0, 0.5, 1.2, 1.0, 0.0]);
        // a later step without an amplitude ramps from the last value to
        // its own (a carried value keeps its amplitude's end value)
        let three = format!("{one}*STEP\n*STATIC\n0.1, 3.0\n*END STEP\n");
        let e = program(&three).unwrap();
        assert_eq!(e.analysis.steps, vec![1.0, 0.5, 1.2]);
        // two amplitudes in one step
        let mixed = "*STEP\n*STATIC\n0.1, 3.0\n*BOUNDARY, AMPLITUDE=CYC\nTOP, 3, 3, 0.2\n*CLOAD, AMPLITUDE=TOT\n15, 1, 5.0\n*END STEP\n";
        let e = program(mixed).unwrap_err().to_string();
        assert!(e.contains("same AMPLITUDE=") && e.contains("`CYC`"), "{e}");
        // a load carried into a step whose amplitude varies
        let carried = format!(
            "{one}*STEP\n*STATIC\n0.1, 3.0\n*CLOAD, AMPLITUDE=CYC\n15, 1, 5.0\n*END STEP\n"
        );
        let e = program(&carried).unwrap_err().to_string();
        assert!(e.contains("carried over"), "{e}");
    }
}
