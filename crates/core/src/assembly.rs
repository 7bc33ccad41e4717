//! Assembly into a fixed sparsity pattern.
//!
//! The pattern (upper triangle of the free-dof matrix, [`SymmetricCsc`]) is
//! built once from the connectivity; values are then filled in parallel
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
}

/// Scratch buffers of one assembly task.
struct Scratch {
    coords: Vec<[f64; 3]>,
    disp: Vec<f64>,
    dofs: Vec<usize>,
    f: Vec<f64>,
    k: Vec<f64>,
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
        }
    }
}

impl Assembler {
    /// Build the pattern and the colouring.
    pub fn new(mesh: &Mesh, dofs: &DofMap) -> Self {
        let nn = mesh.nodes.len();
        // node adjacency
        let mut adj: Vec<Vec<u32>> = vec![Vec::new(); nn];
        for b in &mesh.blocks {
            for e in 0..b.len() {
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
        };
        drop(adj);
        Assembler {
            pattern,
            colors: color_elements(mesh),
        }
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
        mut k: Option<&mut SymmetricCsc>,
        f_int: &mut [f64],
    ) -> Result<(), CoreError> {
        f_int.iter_mut().for_each(|v| *v = 0.0);
        if let Some(k) = k.as_deref_mut() {
            k.values.iter_mut().for_each(|v| *v = 0.0);
        }
        let max_nodes = mesh
            .blocks
            .iter()
            .map(|b| b.nodes_per_element())
            .max()
            .unwrap_or(0);
        let want_k = k.is_some();
        let (kp, kv) = match k {
            Some(k) => {
                let SymmetricCsc {
                    col_ptr,
                    row_idx,
                    values,
                    ..
                } = k;
                (
                    Some((col_ptr.as_slice(), row_idx.as_slice())),
                    SharedMut(values.as_mut_ptr()),
                )
            }
            None => (None, SharedMut(std::ptr::null_mut())),
        };
        let fv = SharedMut(f_int.as_mut_ptr());
        let committed = &state.committed;
        let trial = SharedMut(state.trial.as_mut_ptr());
        let st = &*state;
        let ranges: Vec<Vec<std::ops::Range<usize>>> = (0..mesh.blocks.len())
            .map(|b| (0..mesh.blocks[b].len()).map(|e| st.range(b, e)).collect())
            .collect();
        for color in &self.colors {
            color.par_iter().try_for_each_init(
                || Scratch::new(max_nodes),
                |s, er| -> Result<(), CoreError> {
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
                    let ctx = ElementContext {
                        coords: &s.coords[..n],
                        disp: &s.disp[..nd],
                        state_committed: &committed[r.clone()],
                        step,
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
                    if let Some((cp, ri)) = kp {
                        for b in 0..nd {
                            let j = dofs.eq[s.dofs[b]];
                            if j == CONSTRAINED {
                                continue;
                            }
                            let rows = &ri[cp[j]..cp[j + 1]];
                            for a in 0..nd {
                                let i = dofs.eq[s.dofs[a]];
                                if i == CONSTRAINED || i > j {
                                    continue;
                                }
                                let p =
                                    cp[j] + rows.binary_search(&i).expect("pattern covers element");
                                // SAFETY: entry (i, j) belongs to nodes of this element only
                                // among the elements of this colour.
                                unsafe { kv.add(p, s.k[a * nd + b]) };
                            }
                        }
                    }
                    Ok(())
                },
            )?;
        }
        Ok(())
    }
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

/// Check every element's reference geometry; the first bad one is an error.
pub fn check_geometry(mesh: &Mesh, elements: &[Arc<dyn Element>]) -> Result<(), CoreError> {
    for (bi, b) in mesh.blocks.iter().enumerate() {
        let mut coords = vec![[0.0; 3]; b.nodes_per_element()];
        for e in 0..b.len() {
            for (a, &n) in b.element(e).iter().enumerate() {
                coords[a] = mesh.nodes[n];
            }
            elements[bi]
                .check_geometry(&coords)
                .map_err(|source| CoreError::Element {
                    block: b.name.clone(),
                    element: e,
                    source,
                })?;
        }
    }
    Ok(())
}
