//! Assembly into a fixed sparsity pattern.
//!
//! The pattern (upper triangle of the free-dof matrix, [`SymmetricCsc`]) is
//! built once from the connectivity (structurally symmetric: the lower
//! triangle of a nonsymmetric tangent lives in [`SymmetricCsc::lower`] on
//! the same pattern; a symmetric matrix receives the symmetric part
//! `(K_e + K_e^T) / 2` of each element matrix); values are then filled in parallel
//! with rayon. Elements are greedily coloured so that no two elements of a
//! colour share a node: within a colour, every element writes to its own
//! matrix entries and force entries, so the scatter needs no lock. Scratch
//! buffers are allocated once per rayon task, never per element.

use crate::dof::{DofMap, CONSTRAINED};
use crate::element::{Element, ElementContext, StepInfo};
use crate::error::CoreError;
use crate::mesh::{ElementRef, Mesh};
use crate::sparse::SymmetricCsc;
use crate::state::StateStore;
use rayon::prelude::*;
use std::sync::Arc;

/// Pointer wrapper to scatter from parallel tasks into disjoint entries.
#[derive(Clone, Copy)]
struct SharedMut(*mut f64);
unsafe impl Send for SharedMut {}
unsafe impl Sync for SharedMut {}
impl SharedMut {
    /// # Safety
    /// No other task may touch index `i` concurrently.
    #[inline]
    unsafe fn add(self, i: usize, v: f64) {
        *self.0.add(i) += v;
    }
    /// # Safety
    /// The range must be disjoint from every other task's.
    #[inline]
    unsafe fn slice<'a>(self, r: std::ops::Range<usize>) -> &'a mut [f64] {
        std::slice::from_raw_parts_mut(self.0.add(r.start), r.len())
    }
}

/// Sparsity pattern, element colouring and the state layout of a model.
#[derive(Debug, Clone)]
pub struct Assembler {
    /// Matrix with the pattern of the free-dof system (values zero).
    pub pattern: SymmetricCsc,
    /// Elements grouped by colour.
    pub colors: Vec<Vec<ElementRef>>,
    /// Stiffness of the linear elements, built by the first
    /// [`Assembler::assemble_cached`].
    linear: Option<LinearCache>,
    /// Temperature change of every node at temperature factor 1
    /// ([`Assembler::set_temperature`]); the elements get it times
    /// [`StepInfo::temperature_factor`].
    temperature: Option<Vec<f64>>,
    /// In a run over several ranks ([`crate::distributed`]): the rank of
    /// every element and this process's rank. The pattern and the colours
    /// then hold this rank's elements only, and every assembly ends with
    /// the ranks' exchange ([`Assembler::share_across_ranks`]).
    ranks: Option<Arc<RankPartition>>,
}

/// The partition of an assembler over several ranks.
#[derive(Debug, Clone)]
struct RankPartition {
    /// Rank of each element, `parts[block][element]`.
    parts: Vec<Vec<u32>>,
    /// This process's rank.
    rank: u32,
}

/// The constant part of an incremental analysis: the elements whose
/// internal force is `K_e u_e` with a constant `K_e`
/// ([`Element::is_linear`], e.g. linear elastic solids) with a symmetric
/// `K_e`. Their matrices are kept (element-major, each as its packed upper
/// triangle, row by row: `nd (nd + 1) / 2` values) and their sum in the
/// pattern, so that a Newton iteration recomputes only the nonlinear
/// elements (the interfaces) and adds the kept part: a copy of the matrix
/// values and one small symmetric matrix-vector product per linear element.
#[derive(Debug, Clone)]
struct LinearCache {
    /// Sum of the linear elements' matrices, in the pattern.
    values: Vec<f64>,
    /// Linear elements by colour.
    linear_colors: Vec<Vec<LinearElement>>,
    /// Nonlinear elements by colour.
    nonlinear_colors: Vec<Vec<ElementRef>>,
    /// Where the entries of each nonlinear element's matrix go in the
    /// pattern (`ScatterMap`), when they fit in [`SCATTER_MAP_ENTRIES`].
    nonlinear_map: Option<ScatterMap>,
    /// Element matrices over their kept dofs (packed upper triangles).
    mats: Vec<f64>,
    /// Global component index (`3 node + c`) of each kept dof.
    kept_dofs: Vec<usize>,
    /// Internal force of each linear element at zero displacement and
    /// temperature factor 1 (minus its thermal force, one value per kept
    /// dof), when the assembler has a temperature field: a linear
    /// element's force is `K_e u_e + theta f_e`.
    thermal: Vec<f64>,
}

/// A linear element of [`LinearCache`]: its dofs that its matrix or
/// thermal force touch (a plane element's `z` components are left out),
/// at `dofs` in `kept_dofs` and `thermal`, and its packed matrix over them
/// at `mat` in `mats`.
#[derive(Debug, Clone, Copy)]
struct LinearElement {
    dofs: usize,
    len: usize,
    mat: usize,
}

/// Largest number of element-matrix entries whose pattern positions
/// [`LinearCache`] keeps (4 bytes each): the nonlinear elements of an
/// interface model fit many times over; a model of nonlinear solids that
/// does not falls back to searching the pattern.
const SCATTER_MAP_ENTRIES: usize = 1 << 25;

/// Pattern position of every entry `(a, b)` of the element matrices of a
/// list of elements (row-major, `u32::MAX` for an entry that is not stored:
/// a constrained dof or the lower triangle), so that an assembly adds each
/// entry without a search.
#[derive(Debug, Clone)]
struct ScatterMap {
    /// Offset of each element's block in `pos`, by colour then element.
    offsets: Vec<Vec<usize>>,
    pos: Vec<u32>,
}

/// Not stored (`ScatterMap::pos`).
const NO_ENTRY: u32 = u32::MAX;

/// Scratch buffers of one assembly task.
struct Scratch {
    coords: Vec<[f64; 3]>,
    disp: Vec<f64>,
    dofs: Vec<usize>,
    f: Vec<f64>,
    k: Vec<f64>,
    /// Nodal temperature changes of the element.
    temp: Vec<f64>,
}

impl Scratch {
    fn new(max_nodes: usize) -> Self {
        let n = 3 * max_nodes;
        Scratch {
            coords: vec![[0.0; 3]; max_nodes],
            disp: vec![0.0; n],
            dofs: vec![0; n],
            f: vec![0.0; n],
            k: vec![0.0; n * n],
            temp: vec![0.0; max_nodes],
        }
    }
}

/// The interface elements' share of an assembly
/// ([`Assembler::assemble_cached_sharing`]): their internal force `f_I` and
/// `K_I^T x` for a probe vector `x`, with `K_I` their tangent, both full
/// length (by dof, constrained dofs included), summed over the elements
/// whose block is an interface ([`crate::topology::CellShape::is_interface`])
/// during the same pass that assembles the whole model. Path following
/// under large deformation builds its dissipation constraint on them (the
/// energy balance of the interfaces alone, crate `junta_solvers`, module
/// `arc_length`). Interface elements kept in the linear part of a cached
/// assembly (a linear law without state) are left out: for a constant
/// symmetric `K_e` the balance `½ (f_0 . u - f . u_0)` they would add is
/// zero.
pub struct InterfaceShare<'a> {
    /// `x`: the probe vector (full length).
    pub probe: &'a [f64],
    /// `f_I` (full length), overwritten.
    pub force: &'a mut [f64],
    /// `K_I^T x` (full length), overwritten; zero when no tangent is
    /// assembled.
    pub tangent_probe: &'a mut [f64],
}

/// Raw pointers of an [`InterfaceShare`] for the parallel scatter.
#[derive(Clone, Copy)]
struct ShareOut<'a> {
    probe: &'a [f64],
    force: SharedMut,
    tangent_probe: SharedMut,
}

impl Assembler {
    /// Build the pattern and the colouring.
    pub fn new(mesh: &Mesh, dofs: &DofMap) -> Self {
        Self::of_elements(mesh, dofs, None)
    }

    /// The assembler of rank `rank`'s elements in a run over several ranks
    /// (`parts[block][element]` is each element's rank,
    /// [`crate::distributed::partition_elements`]): its pattern holds the
    /// entries of those elements only (the full number of equations, most
    /// columns empty), and every assembly computes those elements, then
    /// sums the internal forces over the ranks and shares their trial
    /// states, through the installed [`crate::distributed::collective`].
    /// The tangent it fills is this rank's part of the sum.
    pub fn for_rank(mesh: &Mesh, dofs: &DofMap, parts: Vec<Vec<u32>>, rank: usize) -> Self {
        Self::of_elements(
            mesh,
            dofs,
            Some(Arc::new(RankPartition {
                parts,
                rank: rank as u32,
            })),
        )
    }

    /// The pattern and colouring of every element, or of one rank's.
    fn of_elements(mesh: &Mesh, dofs: &DofMap, ranks: Option<Arc<RankPartition>>) -> Self {
        let nn = mesh.nodes.len();
        let mine = |b: usize, e: usize| ranks.as_ref().is_none_or(|r| r.parts[b][e] == r.rank);
        // node adjacency
        let mut adj: Vec<Vec<u32>> = vec![Vec::new(); nn];
        for (bi, b) in mesh.blocks.iter().enumerate() {
            for e in (0..b.len()).filter(|&e| mine(bi, e)) {
                let c = b.element(e);
                for &i in c {
                    adj[i].extend(c.iter().map(|&j| j as u32));
                }
            }
        }
        adj.par_iter_mut().for_each(|a| {
            a.sort_unstable();
            a.dedup();
        });
        if dofs.has_equations() {
            adj = adjacency_through_equations(adj, dofs);
        }
        // columns of the upper triangle: eq(i) <= eq(j); equations are in node order
        let mut col_ptr = vec![0usize; dofs.num_free + 1];
        for (node, nbrs) in adj.iter().enumerate() {
            for c in 0..3 {
                let j = dofs.eq[3 * node + c];
                if j == CONSTRAINED {
                    continue;
                }
                let mut count = 0;
                for &a in nbrs {
                    for c2 in 0..3 {
                        let i = dofs.eq[3 * a as usize + c2];
                        if i != CONSTRAINED && i <= j {
                            count += 1;
                        }
                    }
                }
                col_ptr[j + 1] = count;
            }
        }
        for j in 0..dofs.num_free {
            col_ptr[j + 1] += col_ptr[j];
        }
        let mut row_idx = vec![0usize; col_ptr[dofs.num_free]];
        for (node, nbrs) in adj.iter().enumerate() {
            for c in 0..3 {
                let j = dofs.eq[3 * node + c];
                if j == CONSTRAINED {
                    continue;
                }
                let mut p = col_ptr[j];
                for &a in nbrs {
                    for c2 in 0..3 {
                        let i = dofs.eq[3 * a as usize + c2];
                        if i != CONSTRAINED && i <= j {
                            row_idx[p] = i;
                            p += 1;
                        }
                    }
                }
                // sorted because adjacency is sorted and equations follow node order
                debug_assert!(row_idx[col_ptr[j]..p].windows(2).all(|w| w[0] < w[1]));
            }
        }
        let nnz = row_idx.len();
        let pattern = SymmetricCsc {
            n: dofs.num_free,
            col_ptr,
            row_idx,
            values: vec![0.0; nnz],
            lower: Vec::new(),
        };
        drop(adj);
        let mut colors = color_elements(mesh);
        if ranks.is_some() {
            for color in &mut colors {
                color.retain(|er| mine(er.block, er.element));
            }
            colors.retain(|c| !c.is_empty());
        }
        if dofs.has_equations() {
            // An element with a dependent dof writes to the equations of
            // its dependents' free dofs, which other elements of its colour
            // may share: each such element gets a colour of its own.
            let touches = |er: &ElementRef| {
                mesh.blocks[er.block]
                    .element(er.element)
                    .iter()
                    .any(|&n| (0..3).any(|c| dofs.dependents.contains(3 * n + c)))
            };
            let mut alone = Vec::new();
            for color in &mut colors {
                color.retain(|er| {
                    let t = touches(er);
                    if t {
                        alone.push(vec![*er]);
                    }
                    !t
                });
            }
            colors.retain(|c| !c.is_empty());
            colors.extend(alone);
        }
        Assembler {
            pattern,
            colors,
            linear: None,
            temperature: None,
            ranks,
        }
    }

    /// Whether this assembler computes one rank's elements of a run over
    /// several ranks ([`Assembler::for_rank`]).
    pub fn is_distributed(&self) -> bool {
        self.ranks.is_some()
    }

    /// End an assembly over several ranks: agree on an element failure met
    /// by any rank (every rank returns the same `CoreError::Element`, the
    /// lowest failing rank's, so that every rank cuts back alike), sum the
    /// internal forces, and give every rank the trial state of every
    /// element (each element's owner sends it; the others' slices are
    /// zeroed first, so the sum copies it exactly). A no-op in a
    /// single-process run.
    fn share_across_ranks(
        &self,
        outcome: Result<(), CoreError>,
        state: &mut StateStore,
        f_int: &mut [f64],
    ) -> Result<(), CoreError> {
        let (Some(ranks), Some(c)) = (&self.ranks, crate::distributed::collective()) else {
            return outcome;
        };
        let local = outcome.as_ref().err().map(|e| match e {
            CoreError::Element {
                block,
                element,
                source,
            } => {
                format!("{block}\u{1f}{element}\u{1f}{source}")
            }
            other => format!("\u{1f}\u{1f}{other}"),
        });
        if let Some((rank, message)) = crate::distributed::first_message(c, local) {
            return Err(outcome
                .err()
                .unwrap_or_else(|| remote_error(rank, &message)));
        }
        c.sum_in_place(f_int);
        for (b, parts) in ranks.parts.iter().enumerate() {
            for (e, &r) in parts.iter().enumerate() {
                if r != ranks.rank {
                    let range = state.range(b, e);
                    state.trial[range].iter_mut().for_each(|v| *v = 0.0);
                }
            }
        }
        c.sum_in_place(&mut state.trial);
        Ok(())
    }

    /// Set the temperature change of every node at temperature factor 1
    /// (from the stress-free temperature; `None`: no thermal load). Every
    /// assembly hands each element its nodes' changes times
    /// [`StepInfo::temperature_factor`] ([`ElementContext::temperature`]);
    /// interface elements get none. Drops the kept linear part of
    /// [`Assembler::assemble_cached`].
    pub fn set_temperature(&mut self, temperature: Option<Vec<f64>>) {
        self.temperature = temperature;
        self.linear = None;
    }

    /// The nodal temperature field ([`Assembler::set_temperature`]).
    pub fn temperature(&self) -> Option<&[f64]> {
        self.temperature.as_deref()
    }

    /// [`Assembler::assemble`] for repeated assemblies of one model (an
    /// incremental analysis): the first call computes and keeps the
    /// matrices of the linear elements ([`Element::is_linear`] with no
    /// state; see `LinearCache`), later calls recompute only the other
    /// elements. Same results as `assemble` to round-off; memory: one
    /// packed upper triangle per linear element (14.6 kB for an H20).
    #[allow(clippy::too_many_arguments)]
    pub fn assemble_cached(
        &mut self,
        mesh: &Mesh,
        elements: &[Arc<dyn Element>],
        dofs: &DofMap,
        u: &[f64],
        state: &mut StateStore,
        step: StepInfo,
        k: Option<&mut SymmetricCsc>,
        f_int: &mut [f64],
    ) -> Result<(), CoreError> {
        self.assemble_cached_sharing(mesh, elements, dofs, u, state, step, k, f_int, None)
    }

    /// [`Assembler::assemble_cached`] that also fills the interface
    /// elements' share ([`InterfaceShare`]) in the same pass, when given.
    #[allow(clippy::too_many_arguments)]
    pub fn assemble_cached_sharing(
        &mut self,
        mesh: &Mesh,
        elements: &[Arc<dyn Element>],
        dofs: &DofMap,
        u: &[f64],
        state: &mut StateStore,
        step: StepInfo,
        k: Option<&mut SymmetricCsc>,
        f_int: &mut [f64],
        mut share: Option<InterfaceShare<'_>>,
    ) -> Result<(), CoreError> {
        if let Some(sh) = share.as_mut() {
            sh.force.iter_mut().for_each(|v| *v = 0.0);
            sh.tangent_probe.iter_mut().for_each(|v| *v = 0.0);
        }
        let out = share.as_mut().map(|sh| ShareOut {
            probe: sh.probe,
            force: SharedMut(sh.force.as_mut_ptr()),
            tangent_probe: SharedMut(sh.tangent_probe.as_mut_ptr()),
        });
        let mut outcome = Ok(());
        if self.linear.is_none() {
            match self.build_linear_cache(mesh, elements, dofs) {
                Ok(cache) => self.linear = Some(cache),
                Err(e) => outcome = Err(e),
            }
        }
        if outcome.is_ok() {
            outcome =
                self.assemble_kept_and_others(mesh, elements, dofs, u, state, step, k, f_int, out);
        }
        let outcome = self.share_across_ranks(outcome, state, f_int);
        if let (Ok(()), Some(sh), Some(_), Some(c)) = (
            &outcome,
            share.as_mut(),
            &self.ranks,
            crate::distributed::collective(),
        ) {
            c.sum_in_place(sh.force);
            c.sum_in_place(sh.tangent_probe);
        }
        outcome
    }

    /// [`Assembler::assemble_cached`] on this process's elements.
    #[allow(clippy::too_many_arguments)]
    fn assemble_kept_and_others(
        &self,
        mesh: &Mesh,
        elements: &[Arc<dyn Element>],
        dofs: &DofMap,
        u: &[f64],
        state: &mut StateStore,
        step: StepInfo,
        k: Option<&mut SymmetricCsc>,
        f_int: &mut [f64],
        share: Option<ShareOut<'_>>,
    ) -> Result<(), CoreError> {
        let cache = self.linear.as_ref().expect("built by assemble_cached");
        self.assemble_colors(
            &cache.nonlinear_colors,
            cache.nonlinear_map.as_ref(),
            Some(&cache.values),
            mesh,
            elements,
            dofs,
            u,
            state,
            step,
            k,
            f_int,
            share,
        )?;
        let fv = SharedMut(f_int.as_mut_ptr());
        let theta = step.temperature_factor;
        let thermal = !cache.thermal.is_empty() && theta != 0.0;
        for color in &cache.linear_colors {
            color.par_iter().for_each_init(
                || (Vec::<f64>::new(), Vec::<f64>::new()),
                |(ue, fe), el| {
                    let (nd, dofs) = (el.len, &cache.kept_dofs[el.dofs..el.dofs + el.len]);
                    ue.clear();
                    ue.extend(dofs.iter().map(|&d| u[d]));
                    fe.clear();
                    fe.resize(nd, 0.0);
                    // packed upper triangle, row by row: the diagonal entry
                    // and the rest of the row, used for row a and column a
                    let mut p = el.mat;
                    for a in 0..nd {
                        let row = &cache.mats[p..p + nd - a];
                        p += nd - a;
                        let ua = ue[a];
                        let mut acc = row[0] * ua;
                        for ((k, ub), fb) in row[1..].iter().zip(&ue[a + 1..]).zip(&mut fe[a + 1..])
                        {
                            acc += k * ub;
                            *fb += k * ua;
                        }
                        fe[a] += acc;
                    }
                    if thermal {
                        for (f, t) in fe.iter_mut().zip(&cache.thermal[el.dofs..el.dofs + nd]) {
                            *f += theta * t;
                        }
                    }
                    for (&d, &f) in dofs.iter().zip(fe.iter()) {
                        // SAFETY: elements of one colour share no node.
                        unsafe { fv.add(d, f) };
                    }
                },
            );
        }
        Ok(())
    }

    fn build_linear_cache(
        &self,
        mesh: &Mesh,
        elements: &[Arc<dyn Element>],
        dofs: &DofMap,
    ) -> Result<LinearCache, CoreError> {
        let is_lin = |er: &ElementRef| {
            let el = &elements[er.block];
            el.is_linear() && el.state_len() == 0
        };
        let max_nodes = mesh
            .blocks
            .iter()
            .map(|b| b.nodes_per_element())
            .max()
            .unwrap_or(0);
        let mut s = Scratch::new(max_nodes);
        let mut linear_colors = Vec::new();
        let mut nonlinear_colors = Vec::new();
        let mut mats = Vec::new();
        let mut kept_dofs = Vec::new();
        let mut thermal = Vec::new();
        let mut values = vec![0.0; self.pattern.values.len()];
        for color in &self.colors {
            let mut lin = Vec::new();
            let mut non = Vec::new();
            for er in color {
                if !is_lin(er) {
                    non.push(*er);
                    continue;
                }
                let block = &mesh.blocks[er.block];
                let conn = block.element(er.element);
                let n = conn.len();
                let nd = 3 * n;
                for (a, &node) in conn.iter().enumerate() {
                    s.coords[a] = mesh.nodes[node];
                    for c in 0..3 {
                        s.dofs[3 * a + c] = 3 * node + c;
                    }
                }
                s.disp[..nd].iter_mut().for_each(|v| *v = 0.0);
                let temperature = gather_temperature(
                    self.temperature.as_deref(),
                    1.0,
                    el_is_solid(mesh, er),
                    conn,
                    &mut s.temp,
                );
                let ctx = ElementContext {
                    coords: &s.coords[..n],
                    disp: &s.disp[..nd],
                    state_committed: &[],
                    step: StepInfo::default(),
                    law_responses: None,
                    temperature,
                };
                let ke = &mut s.k[..nd * nd];
                elements[er.block]
                    .compute(&ctx, &mut [], &mut s.f[..nd], Some(&mut *ke))
                    .map_err(|source| CoreError::Element {
                        block: block.name.clone(),
                        element: er.element,
                        source,
                    })?;
                // a linear element with a nonsymmetric matrix is assembled
                // with the others, each time
                let scale = ke.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                let symmetric = (0..nd).all(|a| {
                    (a + 1..nd).all(|b| (ke[a * nd + b] - ke[b * nd + a]).abs() <= 1e-12 * scale)
                });
                if !symmetric {
                    non.push(*er);
                    continue;
                }
                let with_thermal = self.temperature.is_some();
                let kept: Vec<usize> = (0..nd)
                    .filter(|&a| {
                        ke[a * nd..(a + 1) * nd].iter().any(|v| *v != 0.0)
                            || (with_thermal && s.f[a] != 0.0)
                    })
                    .collect();
                lin.push(LinearElement {
                    dofs: kept_dofs.len(),
                    len: kept.len(),
                    mat: mats.len(),
                });
                kept_dofs.extend(kept.iter().map(|&a| s.dofs[a]));
                if with_thermal {
                    // f_int(u = 0) at temperature factor 1: minus the thermal force
                    thermal.extend(kept.iter().map(|&a| s.f[a]));
                }
                for (i, &a) in kept.iter().enumerate() {
                    mats.extend(kept[i..].iter().map(|&b| ke[a * nd + b]));
                }
                let (cp, ri) = (&self.pattern.col_ptr, &self.pattern.row_idx);
                scatter_upper(cp, ri, dofs, &s.dofs[..nd], ke, |p, v, _| values[p] += v);
            }
            if !lin.is_empty() {
                linear_colors.push(lin);
            }
            if !non.is_empty() {
                nonlinear_colors.push(non);
            }
        }
        let nonlinear_map = self.scatter_map(mesh, dofs, &nonlinear_colors);
        Ok(LinearCache {
            values,
            linear_colors,
            nonlinear_colors,
            nonlinear_map,
            mats,
            kept_dofs,
            thermal,
        })
    }

    /// The [`ScatterMap`] of the elements of `colors`, or `None` past
    /// [`SCATTER_MAP_ENTRIES`] entries (or a pattern too large for `u32`).
    fn scatter_map(
        &self,
        mesh: &Mesh,
        dofs: &DofMap,
        colors: &[Vec<ElementRef>],
    ) -> Option<ScatterMap> {
        let size = |er: &ElementRef| {
            let nd = 3 * mesh.blocks[er.block].nodes_per_element();
            nd * nd
        };
        let total: usize = colors.iter().flatten().map(size).sum();
        if total > SCATTER_MAP_ENTRIES
            || self.pattern.row_idx.len() >= NO_ENTRY as usize
            || dofs.has_equations()
        {
            return None;
        }
        let mut offsets = Vec::with_capacity(colors.len());
        let mut pos = vec![NO_ENTRY; total];
        let mut off = 0;
        let mut edofs = Vec::new();
        let (cp, ri) = (&self.pattern.col_ptr, &self.pattern.row_idx);
        for color in colors {
            let mut offs = Vec::with_capacity(color.len());
            for er in color {
                let conn = mesh.blocks[er.block].element(er.element);
                let nd = 3 * conn.len();
                edofs.clear();
                edofs.extend(
                    conn.iter()
                        .flat_map(|&node| (0..3).map(move |c| 3 * node + c)),
                );
                let block = &mut pos[off..off + nd * nd];
                upper_positions(cp, ri, dofs, &edofs, |a, b, p| block[a * nd + b] = p as u32);
                offs.push(off);
                off += nd * nd;
            }
            offsets.push(offs);
        }
        Some(ScatterMap { offsets, pos })
    }

    /// Assemble the internal force `f_int` (full length, all dofs, so that
    /// reactions can be read on constrained dofs) and, if `k` is given, the
    /// tangent into `k` (which must have this assembler's pattern). Trial
    /// state is written into `state.trial`.
    #[allow(clippy::too_many_arguments)]
    pub fn assemble(
        &self,
        mesh: &Mesh,
        elements: &[Arc<dyn Element>],
        dofs: &DofMap,
        u: &[f64],
        state: &mut StateStore,
        step: StepInfo,
        k: Option<&mut SymmetricCsc>,
        f_int: &mut [f64],
    ) -> Result<(), CoreError> {
        let outcome = self.assemble_colors(
            &self.colors,
            None,
            None,
            mesh,
            elements,
            dofs,
            u,
            state,
            step,
            k,
            f_int,
            None,
        );
        self.share_across_ranks(outcome, state, f_int)
    }

    /// Zero `f_int`, set `k` to `base` (both triangles: `base` is
    /// symmetric) or zero, then assemble the elements of `colors` (with
    /// `map`, its pattern positions, built for `colors`); the interface
    /// elements' share into `share` (zeroed by the caller), when given.
    #[allow(clippy::too_many_arguments)]
    fn assemble_colors(
        &self,
        colors: &[Vec<ElementRef>],
        map: Option<&ScatterMap>,
        base: Option<&[f64]>,
        mesh: &Mesh,
        elements: &[Arc<dyn Element>],
        dofs: &DofMap,
        u: &[f64],
        state: &mut StateStore,
        step: StepInfo,
        mut k: Option<&mut SymmetricCsc>,
        f_int: &mut [f64],
        share: Option<ShareOut<'_>>,
    ) -> Result<(), CoreError> {
        reset_to_base(k.as_deref_mut(), base, f_int);
        let max_nodes = mesh
            .blocks
            .iter()
            .map(|b| b.nodes_per_element())
            .max()
            .unwrap_or(0);
        let want_k = k.is_some();
        let (kp, kv, kl) = match k {
            Some(k) => {
                let SymmetricCsc {
                    col_ptr,
                    row_idx,
                    values,
                    lower,
                    ..
                } = k;
                let kl = if lower.is_empty() {
                    None
                } else {
                    Some(SharedMut(lower.as_mut_ptr()))
                };
                (
                    Some((col_ptr.as_slice(), row_idx.as_slice())),
                    SharedMut(values.as_mut_ptr()),
                    kl,
                )
            }
            None => (None, SharedMut(std::ptr::null_mut()), None),
        };
        let batches = batch_law_responses(mesh, elements, u, state, step)?;
        let fv = SharedMut(f_int.as_mut_ptr());
        let committed = &state.committed;
        let trial = SharedMut(state.trial.as_mut_ptr());
        let st = &*state;
        let ranges: Vec<Vec<std::ops::Range<usize>>> = (0..mesh.blocks.len())
            .map(|b| (0..mesh.blocks[b].len()).map(|e| st.range(b, e)).collect())
            .collect();
        for (ci, color) in colors.iter().enumerate() {
            color.par_iter().enumerate().try_for_each_init(
                || Scratch::new(max_nodes),
                |s, (ei, er)| -> Result<(), CoreError> {
                    let block = &mesh.blocks[er.block];
                    let el = &elements[er.block];
                    let conn = block.element(er.element);
                    let n = conn.len();
                    let nd = 3 * n;
                    for (a, &node) in conn.iter().enumerate() {
                        s.coords[a] = mesh.nodes[node];
                        for c in 0..3 {
                            s.dofs[3 * a + c] = 3 * node + c;
                            s.disp[3 * a + c] = u[3 * node + c];
                        }
                    }
                    let r = ranges[er.block][er.element].clone();
                    let temperature = gather_temperature(
                        self.temperature.as_deref(),
                        step.temperature_factor,
                        el_is_solid(mesh, er),
                        conn,
                        &mut s.temp,
                    );
                    let ctx = ElementContext {
                        coords: &s.coords[..n],
                        disp: &s.disp[..nd],
                        state_committed: &committed[r.clone()],
                        step,
                        law_responses: {
                            let np = el.num_points();
                            batches[er.block].get(er.element * np..(er.element + 1) * np)
                        },
                        temperature,
                    };
                    // SAFETY: each element owns its state range.
                    let trial_slice = unsafe { trial.slice(r) };
                    let kbuf = if want_k {
                        Some(&mut s.k[..nd * nd])
                    } else {
                        None
                    };
                    el.compute(&ctx, trial_slice, &mut s.f[..nd], kbuf)
                        .map_err(|source| CoreError::Element {
                            block: block.name.clone(),
                            element: er.element,
                            source,
                        })?;
                    for a in 0..nd {
                        // SAFETY: elements of one colour share no node.
                        unsafe { fv.add(s.dofs[a], s.f[a]) };
                    }
                    if let Some(sh) = share.filter(|_| block.shape.is_interface()) {
                        add_interface_share(
                            sh,
                            &s.dofs[..nd],
                            &s.f[..nd],
                            want_k.then_some(&s.k[..nd * nd]),
                        );
                    }
                    // SAFETY: entry (i, j) belongs to nodes of this element
                    // only among the elements of this colour.
                    let store = |p: usize, upper: f64, lower: f64| match kl {
                        // nonsymmetric storage: both triangles
                        Some(kl) => unsafe {
                            kv.add(p, upper);
                            kl.add(p, lower);
                        },
                        // symmetric storage: the symmetric part
                        None => unsafe { kv.add(p, 0.5 * (upper + lower)) },
                    };
                    let ke = &s.k[..nd * nd];
                    if let (Some(_), Some(map)) = (kp, map) {
                        // positions kept: no search
                        let off = map.offsets[ci][ei];
                        let pos = &map.pos[off..off + nd * nd];
                        // row by row: no division per entry
                        for (a, (row, ke_row)) in
                            pos.chunks_exact(nd).zip(ke.chunks_exact(nd)).enumerate()
                        {
                            for (b, (&p, &kab)) in row.iter().zip(ke_row).enumerate() {
                                if p != NO_ENTRY {
                                    store(p as usize, kab, ke[b * nd + a]);
                                }
                            }
                        }
                    } else if let Some((cp, ri)) = kp {
                        scatter_upper(cp, ri, dofs, &s.dofs[..nd], ke, store);
                    }
                    Ok(())
                },
            )?;
        }
        Ok(())
    }
}

/// Zero `f_int`; set both triangles of `k` to `base` (symmetric) when it
/// fits, else zero.
fn reset_to_base(k: Option<&mut SymmetricCsc>, base: Option<&[f64]>, f_int: &mut [f64]) {
    f_int.iter_mut().for_each(|v| *v = 0.0);
    if let Some(k) = k {
        for part in [&mut k.values, &mut k.lower] {
            match base {
                Some(b) if part.len() == b.len() => part
                    .par_iter_mut()
                    .zip(b.par_iter())
                    .for_each(|(a, b)| *a = *b),
                _ => part.par_iter_mut().for_each(|v| *v = 0.0),
            }
        }
    }
}

/// The coordinates and displacements of the nodes `conn`, node by node,
/// into `coords` and `disp` (cleared first).
pub(crate) fn gather_nodes(
    mesh: &Mesh,
    conn: &[usize],
    u: &[f64],
    coords: &mut Vec<[f64; 3]>,
    disp: &mut Vec<f64>,
) {
    coords.clear();
    disp.clear();
    for &node in conn {
        coords.push(mesh.nodes[node]);
        disp.extend_from_slice(&u[3 * node..3 * node + 3]);
    }
}

/// Add an interface element's force `fe` and, with its tangent `ke`
/// (row-major, `ke[a nd + b] = d f_a / d u_b`), `ke^T x` to the share.
#[inline]
fn add_interface_share(sh: ShareOut<'_>, edofs: &[usize], fe: &[f64], ke: Option<&[f64]>) {
    let nd = edofs.len();
    for (a, &d) in edofs.iter().enumerate() {
        // SAFETY: elements of one colour share no node.
        unsafe { sh.force.add(d, fe[a]) };
    }
    if let Some(ke) = ke {
        for (b, &db) in edofs.iter().enumerate() {
            let v: f64 = (0..nd).map(|a| ke[a * nd + b] * sh.probe[edofs[a]]).sum();
            // SAFETY: as above.
            unsafe { sh.tangent_probe.add(db, v) };
        }
    }
}

/// The element failure another rank met, as `CoreError::Element` (its
/// message from [`Assembler::share_across_ranks`]: block, element and
/// kernel message separated by U+001F).
fn remote_error(rank: usize, message: &str) -> CoreError {
    let mut fields = message.splitn(3, '\u{1f}');
    let block = fields.next().unwrap_or_default().to_string();
    let element = fields.next().and_then(|e| e.parse().ok()).unwrap_or(0);
    let text = fields.next().unwrap_or_default();
    CoreError::Element {
        block,
        element,
        source: crate::element::ElementError::Law {
            point: 0,
            message: format!("met on rank {rank}: {text}"),
        },
    }
}

/// Whether element `er` is a solid (it gets the nodal temperatures;
/// interface elements carry no thermal strain).
#[inline]
fn el_is_solid(mesh: &Mesh, er: &ElementRef) -> bool {
    mesh.blocks[er.block].shape.is_solid()
}

/// The temperature changes of the nodes `conn` (`theta` times `field`) in
/// `buf`, for a solid element of a model with a temperature field and a
/// non-zero factor; `None` otherwise.
#[inline]
fn gather_temperature<'a>(
    field: Option<&[f64]>,
    theta: f64,
    solid: bool,
    conn: &[usize],
    buf: &'a mut [f64],
) -> Option<&'a [f64]> {
    let field = field?;
    if !solid || theta == 0.0 {
        return None;
    }
    for (t, &node) in buf.iter_mut().zip(conn) {
        *t = theta * field[node];
    }
    Some(&buf[..conn.len()])
}

/// Add the upper-triangle entries of an element matrix `ke` (`nd x nd`,
/// row-major, dofs `edofs`) of free dofs to the pattern `(cp, ri)`:
/// `add(position, K[i][j], K[j][i])` for the global entry `(i, j)`,
/// `i <= j` (the caller stores both for a nonsymmetric matrix, or their
/// mean, the symmetric part, for a symmetric one).
#[inline]
fn scatter_upper(
    cp: &[usize],
    ri: &[usize],
    dofs: &DofMap,
    edofs: &[usize],
    ke: &[f64],
    mut add: impl FnMut(usize, f64, f64),
) {
    let nd = edofs.len();
    if dofs.has_equations() && edofs.iter().any(|&d| dofs.dependents.contains(d)) {
        // K^ = T^T K T: entry (a, b) reaches every (i, j) behind a and b
        for b in 0..nd {
            for (j, cj) in dofs.targets(edofs[b]) {
                let rows = &ri[cp[j]..cp[j + 1]];
                for a in 0..nd {
                    for (i, ci) in dofs.targets(edofs[a]) {
                        if i > j {
                            continue;
                        }
                        let p = cp[j] + rows.binary_search(&i).expect("pattern covers element");
                        let c = ci * cj;
                        add(p, c * ke[a * nd + b], c * ke[b * nd + a]);
                    }
                }
            }
        }
        return;
    }
    upper_positions(cp, ri, dofs, edofs, |a, b, p| {
        add(p, ke[a * nd + b], ke[b * nd + a])
    });
}

/// Node adjacency of the reduced system of a model with linear equations:
/// nodes `p` and `q` are adjacent when an element joins nodes `x` and `y`
/// with `p` among `x` and the nodes of `x`'s dependents' terms, and `q`
/// likewise for `y`.
fn adjacency_through_equations(adj: Vec<Vec<u32>>, dofs: &DofMap) -> Vec<Vec<u32>> {
    let nn = adj.len();
    // nodes behind each node: itself and the nodes of its dependents' terms
    let behind = |x: usize| -> Vec<u32> {
        let mut v = vec![x as u32];
        for c in 0..3 {
            if let Some(t) = dofs.dependents.terms(3 * x + c) {
                v.extend(t.iter().map(|&(m, _)| (m / 3) as u32));
            }
        }
        v.sort_unstable();
        v.dedup();
        v
    };
    let mut out: Vec<Vec<u32>> = adj
        .par_iter()
        .map(|nbrs| {
            let mut v: Vec<u32> = nbrs.iter().flat_map(|&y| behind(y as usize)).collect();
            v.sort_unstable();
            v.dedup();
            v
        })
        .collect();
    for x in 0..nn {
        let bx = behind(x);
        if bx.len() == 1 {
            continue;
        }
        let row = out[x].clone();
        for &p in &bx {
            if p as usize != x {
                out[p as usize].extend_from_slice(&row);
            }
        }
    }
    out.par_iter_mut().for_each(|a| {
        a.sort_unstable();
        a.dedup();
    });
    out
}

/// For every pair `(a, b)` of element dofs `edofs` whose global entry `(i,
/// j)` is a stored upper-triangle entry of free dofs (`i <= j`),
/// `at(a, b, position)` with its position in the pattern `(cp, ri)`.
#[inline]
fn upper_positions(
    cp: &[usize],
    ri: &[usize],
    dofs: &DofMap,
    edofs: &[usize],
    mut at: impl FnMut(usize, usize, usize),
) {
    let nd = edofs.len();
    for b in 0..nd {
        let j = dofs.eq[edofs[b]];
        if j == CONSTRAINED {
            continue;
        }
        let rows = &ri[cp[j]..cp[j + 1]];
        for a in 0..nd {
            let i = dofs.eq[edofs[a]];
            if i == CONSTRAINED || i > j {
                continue;
            }
            let p = cp[j] + rows.binary_search(&i).expect("pattern covers element");
            at(a, b, p);
        }
    }
}

/// Evaluate the laws that work in batches
/// ([`crate::InterfaceLaw::is_batched`], e.g. a law written in Python): for
/// every interface block with such a law, the jumps of all its points, one
/// `evaluate_batch` call, the trial states into `state.trial`. Returns the
/// responses per block, element-major (empty for the other blocks). Costs
/// nothing when no law is batched.
pub fn batch_law_responses(
    mesh: &Mesh,
    elements: &[Arc<dyn Element>],
    u: &[f64],
    state: &mut StateStore,
    step: StepInfo,
) -> Result<Vec<Vec<crate::LawResponse>>, CoreError> {
    let mut out = vec![Vec::new(); elements.len()];
    for (b, el) in elements.iter().enumerate() {
        if el.batch_law().is_none() {
            continue;
        }
        let span = state.block_offsets[b]
            ..state.block_offsets[b] + mesh.blocks[b].len() * state.per_element[b];
        out[b] = block_law_responses(
            mesh,
            el.as_ref(),
            b,
            u,
            &state.committed[span.clone()],
            &mut state.trial[span],
            step,
        )?;
    }
    Ok(out)
}

/// The batched law of block `b` (element `el`) evaluated once for all the
/// block's points: `committed` and `trial` are the block's spans of the
/// state (element-major, `el.state_len()` values per element). Returns
/// the responses, element-major. An empty vector when the block's law is
/// not batched.
pub fn block_law_responses(
    mesh: &Mesh,
    el: &dyn Element,
    b: usize,
    u: &[f64],
    committed: &[f64],
    trial: &mut [f64],
    step: StepInfo,
) -> Result<Vec<crate::LawResponse>, CoreError> {
    let Some(law) = el.batch_law() else {
        return Ok(Vec::new());
    };
    let block = &mesh.blocks[b];
    let np = el.num_points();
    let per_element = el.state_len();
    let n = block.len();
    let mut jumps = vec![[0.0; 3]; n * np];
    let mut coords = Vec::new();
    let mut disp = Vec::new();
    for e in 0..n {
        gather_nodes(mesh, block.element(e), u, &mut coords, &mut disp);
        let ctx = ElementContext {
            coords: &coords,
            disp: &disp,
            state_committed: &committed[e * per_element..(e + 1) * per_element],
            step,
            law_responses: None,
            temperature: None,
        };
        el.jumps_into(&ctx, &mut jumps[e * np..(e + 1) * np])
            .map_err(|source| CoreError::Element {
                block: block.name.clone(),
                element: e,
                source,
            })?;
    }
    let mut responses = vec![crate::LawResponse::default(); n * np];
    law.evaluate_batch(&jumps, committed, step, trial, &mut responses)
        .map_err(|e| {
            CoreError::Invalid(format!(
                "interface block `{}`: law `{}`: {e}",
                block.name,
                law.key()
            ))
        })?;
    Ok(responses)
}

/// Greedy colouring: no two elements of a colour share a node.
pub fn color_elements(mesh: &Mesh) -> Vec<Vec<ElementRef>> {
    let nn = mesh.nodes.len();
    // colours used at each node, as a bit mask (spill to a Vec past 64 colours)
    let mut node_mask: Vec<u128> = vec![0; nn];
    let mut colors: Vec<Vec<ElementRef>> = Vec::new();
    for (bi, b) in mesh.blocks.iter().enumerate() {
        for e in 0..b.len() {
            let conn = b.element(e);
            let used = conn.iter().fold(0u128, |m, &i| m | node_mask[i]);
            let c = (!used).trailing_zeros() as usize;
            assert!(
                c < 128,
                "more than 128 colours needed (extremely irregular mesh)"
            );
            if c == colors.len() {
                colors.push(Vec::new());
            }
            colors[c].push(ElementRef {
                block: bi,
                element: e,
            });
            for &i in conn {
                node_mask[i] |= 1u128 << c;
            }
        }
    }
    colors
}

/// Check every element's reference geometry, the elements in parallel;
/// the first bad one (by block, then element number) is an error.
pub fn check_geometry(mesh: &Mesh, elements: &[Arc<dyn Element>]) -> Result<(), CoreError> {
    for (bi, b) in mesh.blocks.iter().enumerate() {
        let bad = (0..b.len())
            .into_par_iter()
            .map_init(
                || vec![[0.0; 3]; b.nodes_per_element()],
                |coords, e| {
                    for (a, &n) in b.element(e).iter().enumerate() {
                        coords[a] = mesh.nodes[n];
                    }
                    elements[bi].check_geometry(coords).err().map(|s| (e, s))
                },
            )
            .find_first(Option::is_some)
            .flatten();
        if let Some((element, source)) = bad {
            return Err(CoreError::Element {
                block: b.name.clone(),
                element,
                source,
            });
        }
    }
    Ok(())
}
