//! The degree-of-freedom map: three displacement dofs per node (dof id
//! `3 node + component`), Dirichlet conditions applied by *elimination*:
//! constrained dofs get no equation; their prescribed values enter the
//! right-hand side through the internal force of the elements.
//!
//! Free dofs are numbered in node order; the solver reorders them itself.

use crate::error::CoreError;

/// Marker of a constrained dof in [`DofMap::eq`].
pub const CONSTRAINED: usize = usize::MAX;

/// Map from dofs to equations.
#[derive(Debug, Clone, PartialEq)]
pub struct DofMap {
    /// Number of nodes.
    pub num_nodes: usize,
    /// Equation of each dof, or [`CONSTRAINED`].
    pub eq: Vec<usize>,
    /// Prescribed value of each dof (meaningful for constrained dofs).
    pub prescribed: Vec<f64>,
    /// Number of free dofs (equations).
    pub num_free: usize,
    /// Dofs constrained only because their node belongs to no element.
    pub orphan: Vec<bool>,
}

impl DofMap {
    /// Build the map from `(dof, value)` constraints. Nodes used by no
    /// element (`used[node] == false`) are fixed at zero silently.
    /// Two different values on one dof are an error.
    pub fn new(
        num_nodes: usize,
        constraints: &[(usize, f64)],
        used: &[bool],
    ) -> Result<Self, CoreError> {
        let ndof = 3 * num_nodes;
        let mut fixed: Vec<Option<f64>> = vec![None; ndof];
        for &(d, v) in constraints {
            if d >= ndof {
                return Err(CoreError::Invalid(format!(
                    "constraint on dof {d}, but the model has {ndof} dofs"
                )));
            }
            match fixed[d] {
                Some(old) if (old - v).abs() > 1e-14 * old.abs().max(v.abs()) => {
                    return Err(CoreError::ConflictingBc {
                        node: d / 3,
                        component: d % 3,
                        a: old,
                        b: v,
                    })
                }
                _ => fixed[d] = Some(v),
            }
        }
        let mut eq = vec![CONSTRAINED; ndof];
        let mut prescribed = vec![0.0; ndof];
        let mut orphan = vec![false; ndof];
        let mut n = 0;
        for d in 0..ndof {
            if !used.get(d / 3).copied().unwrap_or(true) {
                orphan[d] = true;
                continue;
            }
            match fixed[d] {
                Some(v) => prescribed[d] = v,
                None => {
                    eq[d] = n;
                    n += 1;
                }
            }
        }
        Ok(DofMap {
            num_nodes,
            eq,
            prescribed,
            num_free: n,
            orphan,
        })
    }

    /// Total number of dofs (free and constrained).
    pub fn num_dofs(&self) -> usize {
        self.eq.len()
    }

    /// Full displacement vector with prescribed values scaled by `factor`
    /// and free values taken from `free` (or zero when `None`).
    pub fn expand(&self, free: Option<&[f64]>, factor: f64) -> Vec<f64> {
        (0..self.eq.len())
            .map(|d| match self.eq[d] {
                CONSTRAINED => factor * self.prescribed[d],
                e => free.map_or(0.0, |f| f[e]),
            })
            .collect()
    }

    /// Gather the free part of a full-length vector.
    pub fn gather(&self, full: &[f64]) -> Vec<f64> {
        let mut v = vec![0.0; self.num_free];
        for (d, &e) in self.eq.iter().enumerate() {
            if e != CONSTRAINED {
                v[e] = full[d];
            }
        }
        v
    }

    /// Node, component and body (from `node_body`, one per node) of each
    /// equation.
    pub fn equation_layout(&self, node_body: &[u32]) -> crate::solver::EquationLayout {
        let mut l = crate::solver::EquationLayout {
            node: vec![0; self.num_free],
            component: vec![0; self.num_free],
            body: vec![0; self.num_free],
        };
        for (d, &e) in self.eq.iter().enumerate() {
            if e != CONSTRAINED {
                l.node[e] = d / 3;
                l.component[e] = (d % 3) as u8;
                l.body[e] = node_body.get(d / 3).copied().unwrap_or(0);
            }
        }
        l
    }

    /// Coordinates of the node of each equation (for geometric orderings).
    pub fn equation_coords(&self, nodes: &[[f64; 3]]) -> Vec<[f64; 3]> {
        let mut c = vec![[0.0; 3]; self.num_free];
        for (d, &e) in self.eq.iter().enumerate() {
            if e != CONSTRAINED {
                c[e] = nodes[d / 3];
            }
        }
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elimination_numbers_free_dofs_and_rejects_conflicts() {
        let used = [true, true, false];
        let m = DofMap::new(3, &[(0, 0.0), (4, 0.5)], &used).unwrap();
        assert_eq!(m.num_free, 4); // 6 dofs of used nodes minus 2 constrained
        assert_eq!(m.eq[0], CONSTRAINED);
        assert_eq!(m.eq[1], 0);
        assert!(m.orphan[6] && m.eq[6] == CONSTRAINED);
        let u = m.expand(Some(&[1.0, 2.0, 3.0, 4.0]), 2.0);
        assert_eq!(&u[..6], &[0.0, 1.0, 2.0, 3.0, 1.0, 4.0]);
        assert!(matches!(
            DofMap::new(3, &[(0, 0.0), (0, 1.0)], &used),
            Err(CoreError::ConflictingBc { node: 0, .. })
        ));
    }
}
