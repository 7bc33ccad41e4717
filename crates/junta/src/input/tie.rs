//! `[[tie]]`: node-to-node linear equations between two node sets of a
//! scene, for periodic cells and generalized plane strain slices.
//!
//! Each node `p` of the dependent set (`sets[0]`) is paired with the node
//! `q` of the independent set (`sets[1]`) at `x_q + offset` within
//! `within` of `x_p`. For every listed component `k`:
//!
//! * without `relative_to`: `u_k(p) = u_k(q)`;
//! * with `relative_to = "S"` (a set of one node `r` of the dependent set,
//!   paired with `r'`): `u_k(p) - u_k(q) = u_k(r) - u_k(r')`: every pair
//!   moves apart as the reference pair does. Prescribing `u_x(r) - u_x(r')
//!   = eps L` with boundaries on `r` and `r'` gives a slice of length `L`
//!   the mean stretch `eps`, its sections free to warp (Pipes & Pagano's
//!   displacement field `u = eps x + U(y, z)`, `v = V(y, z)`, `w = W(y,
//!   z)` when `v` and `w` are tied without `relative_to`).
//!
//! Coincident nodes (the two copies of an interface's faces) are told
//! apart by the element blocks that use them: `q` must be used by the
//! same blocks as `p`. A dependent dof that already has a boundary
//! condition is left out (its partner must then carry the same one).
//! `offset` defaults to the difference of the sets' centroids; `within`
//! to `1e-6` times the mesh's diagonal.

use crate::error::{bail, err, Result};
use crate::input::scene::{component, SceneFile};
use junta_core::dof::LinearEquation;
use junta_core::mesh::Mesh;
use serde::Deserialize;
use std::collections::{HashMap, HashSet};
use toml::Spanned;

/// One `[[tie]]` table.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TieSpec {
    /// `[dependent, independent]` node sets.
    pub sets: Spanned<[String; 2]>,
    /// Tied components (`x`, `y`, `z`); all three by default.
    #[serde(default)]
    pub components: Vec<String>,
    /// `x_dependent - x_independent` of a pair; the centroids' difference
    /// by default.
    pub offset: Option<[f64; 3]>,
    /// Distance within which a pair's nodes must match.
    pub within: Option<f64>,
    /// A set of one dependent node whose pair every pair follows.
    pub relative_to: Option<Spanned<String>>,
}

/// The linear equations of every `[[tie]]` of the scene; `constrained`
/// holds the dofs that have boundary conditions.
pub fn equations(
    sf: &SceneFile,
    mesh: &Mesh,
    constrained: &HashSet<usize>,
    notes: &mut Vec<String>,
) -> Result<Vec<LinearEquation>> {
    let mut all = Vec::new();
    for (i, t) in sf.scene.tie.iter().enumerate() {
        let at = sf.at(t.sets.span());
        let key = format!("{at}: key `tie[{i}]");
        let pairs = pair_nodes(mesh, t, &key)?;
        let comps = components(t, &key)?;
        let reference = match &t.relative_to {
            Some(s) => Some(reference_pair(mesh, s.get_ref(), &pairs, &key)?),
            None => None,
        };
        let mut skipped = 0usize;
        for &(p, q) in &pairs {
            if reference.is_some_and(|(r, _)| r == p) {
                continue;
            }
            for &k in &comps {
                let (dp, dq) = (3 * p + k, 3 * q + k);
                if constrained.contains(&dp) {
                    skipped += 1;
                    continue;
                }
                let mut terms = vec![(dp, 1.0), (dq, -1.0)];
                if let Some((r, r2)) = reference {
                    terms.extend([(3 * r + k, -1.0), (3 * r2 + k, 1.0)]);
                }
                all.push(LinearEquation {
                    terms,
                    origin: format!("{at} (tie[{i}], node {})", label(mesh, p)),
                });
            }
        }
        if skipped > 0 {
            notes.push(format!(
                "{key}`: {skipped} tied dofs of `{}` have boundary conditions and are left to them",
                t.sets.get_ref()[0]
            ));
        }
    }
    Ok(all)
}

fn label(mesh: &Mesh, n: usize) -> usize {
    mesh.node_labels.get(n).copied().unwrap_or(n + 1)
}

fn components(t: &TieSpec, key: &str) -> Result<Vec<usize>> {
    if t.components.is_empty() {
        return Ok(vec![0, 1, 2]);
    }
    t.components
        .iter()
        .map(|c| {
            component(c).ok_or_else(|| err!("{key}.components`: `{c}` is not valid; use x, y or z"))
        })
        .collect()
}

/// The reference pair `(r, r')` of `relative_to`.
fn reference_pair(
    mesh: &Mesh,
    set: &str,
    pairs: &[(usize, usize)],
    key: &str,
) -> Result<(usize, usize)> {
    let nodes = mesh
        .node_set(set)
        .map_err(|e| err!("{key}.relative_to`: {e}"))?;
    let [r] = nodes else {
        bail!(
            "{key}.relative_to`: set `{set}` has {} nodes; it must hold one node of the dependent set",
            nodes.len()
        );
    };
    pairs
        .iter()
        .copied()
        .find(|&(p, _)| p == *r)
        .ok_or_else(|| {
            err!(
                "{key}.relative_to`: node {} of set `{set}` is not in the dependent set",
                label(mesh, *r)
            )
        })
}

/// Each dependent node with its independent partner.
fn pair_nodes(mesh: &Mesh, t: &TieSpec, key: &str) -> Result<Vec<(usize, usize)>> {
    let [dep_name, ind_name] = t.sets.get_ref();
    let set = |name: &str| mesh.node_set(name).map_err(|e| err!("{key}.sets`: {e}"));
    let (dep, ind) = (set(dep_name)?, set(ind_name)?);
    if let Some(&n) = dep.iter().find(|n| ind.binary_search(n).is_ok()) {
        bail!(
            "{key}.sets`: node {} is in both `{dep_name}` and `{ind_name}`; a node cannot be tied to its own set",
            label(mesh, n)
        );
    }
    let offset = t.offset.unwrap_or_else(|| {
        let (a, b) = (centroid(mesh, dep), centroid(mesh, ind));
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    });
    let within = t.within.unwrap_or(1e-6 * diagonal(mesh));
    if !(within > 0.0 && within.is_finite()) {
        bail!("{key}.within`: {within} is not valid; give a distance > 0");
    }
    let users = block_users(mesh, dep, ind);
    let grid = Grid::new(mesh, ind, offset, within);
    let mut pairs = Vec::with_capacity(dep.len());
    for &p in dep {
        let q = grid
            .near(mesh, mesh.nodes[p], within)
            .find(|q| users[q] == users[&p])
            .ok_or_else(|| {
                let x = mesh.nodes[p];
                err!(
                    "{key}.sets`: node {} of `{dep_name}` at ({}, {}, {}) has no node of `{ind_name}` at its position minus offset ({}, {}, {}) within {within}; check `offset` and `within`",
                    label(mesh, p), x[0], x[1], x[2], offset[0], offset[1], offset[2]
                )
            })?;
        pairs.push((p, q));
    }
    Ok(pairs)
}

fn centroid(mesh: &Mesh, nodes: &[usize]) -> [f64; 3] {
    let mut c = [0.0; 3];
    for &n in nodes {
        for k in 0..3 {
            c[k] += mesh.nodes[n][k];
        }
    }
    c.map(|v| v / nodes.len().max(1) as f64)
}

fn diagonal(mesh: &Mesh) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for x in &mesh.nodes {
        for k in 0..3 {
            lo[k] = lo[k].min(x[k]);
            hi[k] = hi[k].max(x[k]);
        }
    }
    (0..3)
        .map(|k| (hi[k] - lo[k]).powi(2))
        .sum::<f64>()
        .sqrt()
        .max(f64::MIN_POSITIVE)
}

/// The sorted element blocks using each node of `a` and `b`.
fn block_users(mesh: &Mesh, a: &[usize], b: &[usize]) -> HashMap<usize, Vec<usize>> {
    let mut users: HashMap<usize, Vec<usize>> =
        a.iter().chain(b).map(|&n| (n, Vec::new())).collect();
    for (bi, block) in mesh.blocks.iter().enumerate() {
        for n in &block.connectivity {
            if let Some(u) = users.get_mut(n) {
                if u.last() != Some(&bi) {
                    u.push(bi);
                }
            }
        }
    }
    users
}

/// The independent nodes, moved by `offset`, bucketed in cubes of side
/// `h >= within`.
struct Grid {
    h: f64,
    offset: [f64; 3],
    cells: HashMap<[i64; 3], Vec<usize>>,
}

impl Grid {
    fn new(mesh: &Mesh, nodes: &[usize], offset: [f64; 3], within: f64) -> Self {
        let h = 2.0 * within;
        let mut cells: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
        for &n in nodes {
            let x = mesh.nodes[n];
            let moved = [x[0] + offset[0], x[1] + offset[1], x[2] + offset[2]];
            cells.entry(cell(moved, h)).or_default().push(n);
        }
        Grid { h, offset, cells }
    }

    /// Independent nodes whose moved position is within `within` of `x`.
    fn near<'a>(
        &'a self,
        mesh: &'a Mesh,
        x: [f64; 3],
        within: f64,
    ) -> impl Iterator<Item = usize> + 'a {
        let c = cell(x, self.h);
        let off = self.offset;
        (0..27i64).flat_map(move |i| {
            let key = [c[0] + i % 3 - 1, c[1] + (i / 3) % 3 - 1, c[2] + i / 9 - 1];
            self.cells
                .get(&key)
                .into_iter()
                .flatten()
                .copied()
                .filter(move |&n| {
                    let y = mesh.nodes[n];
                    (0..3)
                        .map(|k| (y[k] + off[k] - x[k]).powi(2))
                        .sum::<f64>()
                        .sqrt()
                        <= within
                })
        })
    }
}

fn cell(x: [f64; 3], h: f64) -> [i64; 3] {
    x.map(|v| (v / h).floor() as i64)
}
