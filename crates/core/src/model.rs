//! [`Model`]: everything a solver needs, independent of where it came from
//! (a TOML scene, an `.inp` deck or an embedding program): the mesh, one
//! element object per block, the dof map with the prescribed values, and the
//! reference external force vector (scaled by the load factor in
//! incremental analyses).

use crate::assembly::{check_geometry, Assembler};
use crate::dof::DofMap;
use crate::element::Element;
use crate::error::CoreError;
use crate::mesh::Mesh;
use crate::state::StateStore;
use std::sync::Arc;

/// A model ready to solve.
#[derive(Debug, Clone)]
pub struct Model {
    /// The mesh.
    pub mesh: Mesh,
    /// Element object of each block (index-aligned with `mesh.blocks`).
    pub elements: Vec<Arc<dyn Element>>,
    /// Dof map with the prescribed values at load factor 1.
    pub dofs: DofMap,
    /// External nodal forces at load factor 1 (length = number of dofs).
    pub f_ext: Vec<f64>,
    /// Named node sets whose reactions are reported.
    pub reaction_sets: Vec<String>,
    /// Linear equations eliminated in `dofs` ([`Model::add_equations`]).
    pub equations: Vec<crate::dof::LinearEquation>,
    /// Thermal load: the temperature change of every node from the
    /// stress-free temperature at temperature factor 1 (length = number of
    /// nodes), or `None` (no thermal strain anywhere). Element kernels get
    /// it scaled by [`crate::element::StepInfo::temperature_factor`].
    pub temperature: Option<Vec<f64>>,
    /// Temperature factor at the end of each step of an incremental load
    /// program ([`Model::temperature_factor`]): inside step `s` it goes
    /// linearly from the previous step's value (0 before the first step)
    /// to `temperature_steps[s]`, as the load factor does; steps past the
    /// end keep the last value. Empty: 1 throughout (the whole change from
    /// the first increment). A cool-down before a mechanical load is the
    /// program `[0, lambda_1, ...]` with `temperature_steps = [1]`.
    pub temperature_steps: Vec<f64>,
    /// The cycle program of a high-cycle fatigue run, or `None` (no
    /// cycles: every increment has `delta_cycles = 0`).
    pub fatigue: Option<FatigueProgram>,
    /// An assembler built before the run (the solver choice needs its
    /// pattern), handed to the first [`Model::assembler`] call.
    kept_assembler: KeptAssembler,
}

/// An assembler kept for the run's first [`Model::assembler`] call, with
/// the fingerprint of the dof map and connectivity it was built from (a
/// model changed since gets a new one). A clone of the model starts
/// without it.
#[derive(Default)]
struct KeptAssembler(std::sync::Mutex<Option<(u64, Assembler)>>);

impl Clone for KeptAssembler {
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl std::fmt::Debug for KeptAssembler {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let kept = self.0.lock().map(|k| k.is_some()).unwrap_or(false);
        write!(f, "KeptAssembler({kept})")
    }
}

/// High-cycle fatigue as a program quantity, like the temperature: the
/// cycle count `N` goes linearly over each step from the previous step's
/// end value (0 before the first step) to `cycle_steps[s]`, so a step with
/// the load factor held and `N` moving is a fatigue step (the envelope
/// maximum of a constant-amplitude load held while the cycles run, Turon
/// et al. 2007's cycle jump). `N` is a function of the cursor (step,
/// fraction), so checkpoints need nothing more; a program of several
/// blocks is several such steps, each with its load ratio, with static
/// steps between blocks of different maxima. The drivers pass `N`, the
/// increment's `delta_cycles` and the step's load ratio to the laws
/// ([`crate::element::StepInfo`]) and size a fatigue step's increments so
/// that no point's damage grows by more than `max_damage_increment` (from
/// the laws' committed `damage_rate`, [`Model::max_law_output`]).
#[derive(Debug, Clone, PartialEq)]
pub struct FatigueProgram {
    /// Cycles at the end of each step of the program.
    pub cycle_steps: Vec<f64>,
    /// Load ratio `R = min / max` of the cycle in each step of the
    /// program (steps past the end keep the last value).
    pub load_ratios: Vec<f64>,
    /// Largest damage growth of any point in one increment of a fatigue
    /// step (the laws' `damage_rate` times `delta_cycles`).
    pub max_damage_increment: f64,
    /// Direction of crack growth along which the driver measures the
    /// crack's energy release rate and process-zone length at the start of
    /// each fatigue increment ([`Model::crack_drive`], passed to the laws
    /// as [`crate::element::StepInfo::crack_drive`]); `None`: the laws
    /// estimate both themselves, point by point.
    pub front_direction: Option<[f64; 3]>,
}

/// A quantity given at the end of each step of a program (`ends[s]`),
/// going linearly over step `s` from the previous step's end (0 before the
/// first step), at the fraction `t` (0..=1) of step `step`; steps past the
/// end keep the last value. `None` for an empty program.
fn program_ramp(ends: &[f64], step: usize, t: f64) -> Option<f64> {
    let &last = ends.last()?;
    let end = ends.get(step).copied().unwrap_or(last);
    let start = match step {
        0 => 0.0,
        s => ends.get(s - 1).copied().unwrap_or(last),
    };
    Some(if t >= 1.0 {
        end
    } else {
        start + t * (end - start)
    })
}

/// The use of each dof (`3 node + component`): the components
/// ([`Element::active_components`]) of the elements at each node.
fn used_dofs(mesh: &Mesh, elements: &[Arc<dyn Element>]) -> Vec<bool> {
    let mut used = vec![false; 3 * mesh.nodes.len()];
    for (b, el) in mesh.blocks.iter().zip(elements) {
        let active = el.active_components();
        for &i in &b.connectivity {
            for (c, &on) in active.iter().enumerate() {
                used[3 * i + c] |= on;
            }
        }
    }
    used
}

impl Model {
    /// Assemble a model: validates the mesh, checks that every block has an
    /// element of the right shape, checks every element's geometry, and
    /// builds the dof map from `(dof, value)` constraints.
    pub fn new(
        mesh: Mesh,
        elements: Vec<Arc<dyn Element>>,
        constraints: &[(usize, f64)],
        f_ext: Vec<f64>,
        reaction_sets: Vec<String>,
    ) -> Result<Self, CoreError> {
        mesh.validate()?;
        if elements.len() != mesh.blocks.len() {
            return Err(CoreError::Invalid(format!(
                "{} element objects for {} blocks",
                elements.len(),
                mesh.blocks.len()
            )));
        }
        for (b, el) in mesh.blocks.iter().zip(&elements) {
            if el.shape() != b.shape {
                return Err(CoreError::Invalid(format!(
                    "block `{}` has {} cells but element type `{}` expects {}",
                    b.name,
                    b.shape.name(),
                    el.key(),
                    el.shape().name()
                )));
            }
        }
        if f_ext.len() != 3 * mesh.nodes.len() {
            return Err(CoreError::Invalid(
                "force vector length differs from 3 x nodes".into(),
            ));
        }
        check_geometry(&mesh, &elements)?;
        let dofs =
            DofMap::with_used_dofs(mesh.nodes.len(), constraints, &used_dofs(&mesh, &elements))?;
        Ok(Model {
            mesh,
            elements,
            dofs,
            f_ext,
            reaction_sets,
            equations: Vec::new(),
            temperature: None,
            temperature_steps: Vec::new(),
            fatigue: None,
            kept_assembler: KeptAssembler::default(),
        })
    }

    /// Add linear equations (`*EQUATION`; see [`DofMap::add_equations`]);
    /// messages name the mesh's node labels.
    pub fn add_equations(
        &mut self,
        equations: &[crate::dof::LinearEquation],
    ) -> Result<(), CoreError> {
        self.dofs.add_equations(equations, &self.mesh.node_labels)?;
        self.equations.extend_from_slice(equations);
        Ok(())
    }

    /// Body of each node: nodes connected through elements that are not
    /// interface elements (those with [`Element::interface_stiffness`])
    /// share a body; bodies are numbered 0.. in node order. Nodes of no
    /// element form bodies of their own.
    pub fn node_bodies(&self) -> Vec<u32> {
        let n = self.mesh.nodes.len();
        let mut parent: Vec<usize> = (0..n).collect();
        fn find(p: &mut [usize], mut i: usize) -> usize {
            while p[i] != i {
                p[i] = p[p[i]];
                i = p[i];
            }
            i
        }
        for (b, el) in self.mesh.blocks.iter().zip(&self.elements) {
            if el.interface_stiffness().is_some() {
                continue;
            }
            let k = b.nodes_per_element();
            for cell in b.connectivity.chunks(k.max(1)) {
                let r0 = find(&mut parent, cell[0]);
                for &v in &cell[1..] {
                    let r = find(&mut parent, v);
                    if r != r0 {
                        parent[r] = r0;
                    }
                }
            }
        }
        let mut id = vec![u32::MAX; n];
        let mut next = 0u32;
        (0..n)
            .map(|i| {
                let r = find(&mut parent, i);
                if id[r] == u32::MAX {
                    id[r] = next;
                    next += 1;
                }
                id[r]
            })
            .collect()
    }

    /// Node, component and body of each equation (for AMG).
    pub fn equation_layout(&self) -> crate::solver::EquationLayout {
        self.dofs.equation_layout(&self.node_bodies())
    }

    /// Kind of the tangent matrix: the largest kind over the elements
    /// (SPD < symmetric indefinite < general).
    pub fn matrix_kind(&self) -> crate::solver::MatrixKind {
        self.elements
            .iter()
            .map(|e| e.tangent_kind())
            .max()
            .unwrap_or_default()
    }

    /// Whether any element stores the symmetric part of a tangent that can
    /// be nonsymmetric ([`crate::Element::symmetrises_tangent`]).
    pub fn tangent_symmetrised(&self) -> bool {
        self.matrix_kind() != crate::solver::MatrixKind::General
            && self.elements.iter().any(|e| e.symmetrises_tangent())
    }

    /// The largest scaled skew of the element tangents stored as their
    /// symmetric part since the last call, over the blocks
    /// ([`crate::Element::take_symmetrised_skew`], which it resets); over
    /// several ranks the largest of the ranks' (the same on every rank).
    pub fn take_symmetrised_skew(&self) -> f64 {
        let mut largest = [self
            .elements
            .iter()
            .map(|e| e.take_symmetrised_skew())
            .fold(0.0, f64::max)];
        if let Some(c) = crate::distributed::collective() {
            c.max_in_place(&mut largest);
        }
        largest[0]
    }

    /// Set the nodal temperature changes ([`Model::temperature`]); an
    /// error unless there is one finite value per node.
    pub fn set_temperature(&mut self, delta: Option<Vec<f64>>) -> Result<(), CoreError> {
        if let Some(d) = &delta {
            if d.len() != self.mesh.nodes.len() {
                return Err(CoreError::Invalid(format!(
                    "{} temperature changes for {} nodes",
                    d.len(),
                    self.mesh.nodes.len()
                )));
            }
            if let Some(i) = d.iter().position(|t| !t.is_finite()) {
                return Err(CoreError::Invalid(format!(
                    "temperature change {} at node {} is not finite",
                    d[i],
                    self.mesh.node_labels.get(i).copied().unwrap_or(i)
                )));
            }
        }
        self.temperature = delta;
        Ok(())
    }

    /// The temperature factor at the fraction `t` (0..=1) of step `step`
    /// of an incremental program ([`Model::temperature_steps`]).
    pub fn temperature_factor(&self, step: usize, t: f64) -> f64 {
        program_ramp(&self.temperature_steps, step, t).unwrap_or(1.0)
    }

    /// The cycle count at the fraction `t` (0..=1) of step `step`
    /// ([`FatigueProgram`]; 0 without one).
    pub fn cycles(&self, step: usize, t: f64) -> f64 {
        self.fatigue
            .as_ref()
            .and_then(|f| program_ramp(&f.cycle_steps, step, t))
            .unwrap_or(0.0)
    }

    /// The load ratio of step `step` of the fatigue program (0 without
    /// one).
    pub fn load_ratio(&self, step: usize) -> f64 {
        self.fatigue.as_ref().map_or(0.0, |f| {
            let r = &f.load_ratios;
            r.get(step).or(r.last()).copied().unwrap_or(0.0)
        })
    }

    /// Sparsity pattern and colouring for this model, with its temperature
    /// field ([`Model::temperature`]). In a run over several ranks (a
    /// [`crate::distributed::Collective`] installed) the assembler of this
    /// rank's elements ([`Assembler::for_rank`], the partition of
    /// [`crate::distributed::partition_elements`]): every rank must then
    /// call each of its assemblies.
    pub fn assembler(&self) -> Assembler {
        if let Some(mut asm) = self.take_kept_assembler() {
            asm.set_temperature(self.temperature.clone());
            return asm;
        }
        let mut asm = match crate::distributed::collective() {
            Some(c) => Assembler::for_rank(
                &self.mesh,
                &self.dofs,
                crate::distributed::partition_elements(&self.mesh, c.size()),
                c.rank(),
            ),
            None => Assembler::new(&self.mesh, &self.dofs),
        };
        asm.set_temperature(self.temperature.clone());
        asm
    }

    /// Keep `asm` (built by [`Model::assembler`] for a look at its
    /// pattern) for the next [`Model::assembler`] call, so that the pattern
    /// and colouring are built once: the automatic solver choice analyses
    /// the pattern before the run assembles into it. The next call takes
    /// it if the dof map and the connectivity are still those it was built
    /// from, else builds a new one.
    pub fn keep_assembler(&self, asm: Assembler) {
        let fingerprint = self.pattern_fingerprint();
        if let Ok(mut k) = self.kept_assembler.0.lock() {
            *k = Some((fingerprint, asm));
        }
    }

    /// Whether an assembler is kept for the next [`Model::assembler`] call.
    pub fn has_kept_assembler(&self) -> bool {
        self.kept_assembler
            .0
            .lock()
            .map(|k| k.is_some())
            .unwrap_or(false)
    }

    /// The kept assembler, if any and still valid (taken: one use).
    fn take_kept_assembler(&self) -> Option<Assembler> {
        let (fingerprint, asm) = self.kept_assembler.0.lock().ok()?.take()?;
        (fingerprint == self.pattern_fingerprint()).then_some(asm)
    }

    /// A hash of what the pattern and colouring depend on: the equation of
    /// every dof, the dependents of linear equations and every block's
    /// connectivity, and the ranks the run is spread over.
    fn pattern_fingerprint(&self) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        self.dofs.eq.hash(&mut h);
        self.dofs.dependents.dofs.hash(&mut h);
        for b in &self.mesh.blocks {
            b.shape.num_nodes().hash(&mut h);
            b.connectivity.hash(&mut h);
        }
        crate::distributed::collective()
            .map(|c| (c.size(), c.rank()))
            .hash(&mut h);
        h.finish()
    }

    /// The assembler of every element in this process, even in a run over
    /// several ranks: for work one rank does alone (a print table of the
    /// converged state, an exported matrix).
    pub fn whole_assembler(&self) -> Assembler {
        let mut asm = Assembler::new(&self.mesh, &self.dofs);
        asm.set_temperature(self.temperature.clone());
        asm
    }

    /// State storage with every element's initial state.
    pub fn initial_state(&self) -> StateStore {
        let layout: Vec<(usize, usize)> = self
            .mesh
            .blocks
            .iter()
            .zip(&self.elements)
            .map(|(b, e)| (b.len(), e.state_len()))
            .collect();
        let mut s = StateStore::new(&layout);
        for (bi, b) in self.mesh.blocks.iter().enumerate() {
            for e in 0..b.len() {
                let r = s.range(bi, e);
                self.elements[bi].init_state(&mut s.committed[r.clone()]);
            }
        }
        s.restore();
        s
    }

    /// Total reaction `[Fx, Fy, Fz]` on a node set from the residual
    /// `r = f_int - f_ext` (full length).
    pub fn set_total(&self, set: &str, r: &[f64]) -> Result<[f64; 3], CoreError> {
        let nodes = self.mesh.node_set(set)?;
        let mut t = [0.0; 3];
        for &n in nodes {
            for c in 0..3 {
                t[c] += r[3 * n + c];
            }
        }
        Ok(t)
    }

    /// Energy dissipated so far by the laws, from the committed `state`:
    /// the integral over every element's integration points of the per-area
    /// outputs `dissipated_energy` and `viscous_energy` (see
    /// [`crate::law::output`]) times the point's `area`. Zero for a model
    /// whose laws dissipate nothing. `u` is the full displacement vector.
    pub fn dissipated_energy(&self, u: &[f64], state: &StateStore) -> Result<f64, CoreError> {
        let mut total = 0.0;
        self.for_each_interface_element(
            u,
            state,
            |b| Ok(self.prefetch_committed_outputs(b, state)),
            |b, ctx| {
                total += self.elements[b].dissipated_energy(ctx)?;
                Ok(())
            },
        )?;
        Ok(total)
    }

    /// Before a pass over interface block `b` that reads its laws' outputs
    /// of the committed `state` only: a batched law (a law written in
    /// Python) is asked once for the whole block's outputs, none per point.
    /// No law responses: `Some` of an empty list
    /// ([`Self::for_each_interface_element`]).
    fn prefetch_committed_outputs(
        &self,
        b: usize,
        state: &StateStore,
    ) -> Option<Vec<crate::LawResponse>> {
        if let Some(law) = self.elements[b].batch_law() {
            law.prefetch_outputs(state.block_committed(b, self.mesh.blocks[b].len()));
        }
        Some(Vec::new())
    }

    /// The largest value of the scalar law output `name` over every
    /// interface integration point, from the committed `state` (0 where no
    /// law reports it), e.g. the fatigue laws' `damage_rate`: the laws'
    /// outputs only ([`crate::Element::max_law_output`]), not the points'
    /// whole output.
    pub fn max_law_output(
        &self,
        u: &[f64],
        state: &StateStore,
        name: &str,
    ) -> Result<f64, CoreError> {
        let mut max = 0.0f64;
        self.for_each_interface_element(
            u,
            state,
            |b| Ok(self.prefetch_committed_outputs(b, state)),
            |b, ctx| {
                max = max.max(self.elements[b].max_law_output(ctx, name)?);
                Ok(())
            },
        )?;
        Ok(max)
    }

    /// For interface block `b` with a batched law (a law written in
    /// Python): its responses at `u` from one call for the whole block, and
    /// the outputs of its committed states prefetched
    /// ([`crate::InterfaceLaw::prefetch_outputs`]), so that a pass over its
    /// points asks the law nothing per point. Empty for the other blocks.
    fn batched_block_responses(
        &self,
        b: usize,
        u: &[f64],
        state: &StateStore,
    ) -> Result<Vec<crate::LawResponse>, CoreError> {
        let el = &self.elements[b];
        let Some(law) = el.batch_law() else {
            return Ok(Vec::new());
        };
        let committed = state.block_committed(b, self.mesh.blocks[b].len());
        law.prefetch_outputs(committed);
        let mut trial = committed.to_vec();
        crate::assembly::block_law_responses(
            &self.mesh,
            el.as_ref(),
            b,
            u,
            committed,
            &mut trial,
            crate::element::StepInfo::default(),
        )
    }

    /// True when some interface law of the model has a contact switch
    /// ([`crate::InterfaceLaw::has_contact_switch`]).
    pub fn has_contact_switch(&self) -> bool {
        self.elements.iter().any(|e| e.has_contact_switch())
    }

    /// The contact status (closed or not) of every integration point of
    /// the interfaces whose law has a contact switch, at the full
    /// displacement `u` and the committed `state`, into `out` (cleared
    /// first; block by block, element by element, point by point, so that
    /// two calls on the same model compare point by point). Empty for a
    /// model without such laws.
    pub fn contact_statuses(
        &self,
        u: &[f64],
        state: &StateStore,
        out: &mut Vec<bool>,
    ) -> Result<(), CoreError> {
        out.clear();
        self.for_each_interface_element(
            u,
            state,
            |b| Ok(self.elements[b].has_contact_switch().then(Vec::new)),
            |b, ctx| {
                let start = out.len();
                out.resize(start + self.elements[b].num_points(), false);
                self.elements[b].contact_closed_into(ctx, &mut out[start..])
            },
        )
    }

    /// Calls `f` with the outputs of every interface integration point at
    /// the displacement `u` and the committed `state`.
    pub(crate) fn for_each_interface_point(
        &self,
        u: &[f64],
        state: &StateStore,
        mut f: impl FnMut(&crate::element::PointOutput),
    ) -> Result<(), CoreError> {
        self.for_each_interface_element(
            u,
            state,
            |b| self.batched_block_responses(b, u, state).map(Some),
            |b, ctx| {
                self.elements[b].point_outputs(ctx)?.iter().for_each(&mut f);
                Ok(())
            },
        )
    }

    /// Calls `f(b, ctx)` for every element of each interface block `b`,
    /// its nodes gathered at `u` with its committed `state`. `prepare(b)`
    /// comes first for each block: `None` skips it, and a non-empty list
    /// holds the block's law responses (a batched law's,
    /// [`Self::batched_block_responses`]) that each element's context
    /// carries. An element's error is named by block and element.
    fn for_each_interface_element(
        &self,
        u: &[f64],
        state: &StateStore,
        mut prepare: impl FnMut(usize) -> Result<Option<Vec<crate::LawResponse>>, CoreError>,
        mut f: impl FnMut(
            usize,
            &crate::element::ElementContext<'_>,
        ) -> Result<(), crate::element::ElementError>,
    ) -> Result<(), CoreError> {
        let mut coords = Vec::new();
        let mut disp = Vec::new();
        for (b, block) in self.mesh.blocks.iter().enumerate() {
            if !block.shape.is_interface() {
                continue;
            }
            let Some(responses) = prepare(b)? else {
                continue;
            };
            let np = self.elements[b].num_points();
            for e in 0..block.len() {
                crate::assembly::gather_nodes(
                    &self.mesh,
                    block.element(e),
                    u,
                    &mut coords,
                    &mut disp,
                );
                let ctx = crate::element::ElementContext {
                    coords: &coords,
                    disp: &disp,
                    state_committed: &state.committed[state.range(b, e)],
                    step: crate::element::StepInfo::default(),
                    law_responses: (!responses.is_empty())
                        .then(|| &responses[e * np..(e + 1) * np]),
                    temperature: None,
                };
                f(b, &ctx).map_err(|source| CoreError::Element {
                    block: block.name.clone(),
                    element: e,
                    source,
                })?;
            }
        }
        Ok(())
    }
}

impl crate::step::StepInfo {
    /// This step at pseudo-time `t` (0 to 1) of step `step` of `model`'s
    /// load program: the temperature factor, the cycle count and the load
    /// ratio from the model's programs ([`Model::temperature_factor`],
    /// [`Model::cycles`], [`Model::load_ratio`]); `delta_cycles` and the
    /// rest unchanged. `StepInfo::at(inc, lambda, dlambda).in_program(model,
    /// step, t)` is the step a driver hands to the elements.
    pub fn in_program(self, model: &Model, step: usize, t: f64) -> Self {
        crate::step::StepInfo {
            temperature_factor: model.temperature_factor(step, t),
            cycles: model.cycles(step, t),
            load_ratio: model.load_ratio(step),
            ..self
        }
    }
}
