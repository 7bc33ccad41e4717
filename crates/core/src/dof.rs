//! The degree-of-freedom map: three displacement dofs per node (dof id
//! `3 node + component`), Dirichlet conditions applied by *elimination*:
//! constrained dofs get no equation; their prescribed values enter the
//! right-hand side through the internal force of the elements.
//!
//! Free dofs are numbered in node order; the solver reorders them itself.
//!
//! # Linear constraints (`*EQUATION`)
//!
//! A homogeneous linear equation `sum_k a_k u_{d_k} = 0` makes its first
//! dof *dependent*: `u_{d_0} = sum_{k>0} (-a_k / a_0) u_{d_k}`. Dependents
//! are eliminated like Dirichlet dofs (no equation of their own). After
//! chains are substituted (a dependent among another equation's terms is
//! replaced by its own terms), every dependent is a combination of free and
//! Dirichlet dofs, `u_d = sum_m c_dm u_m`, i.e. `u = T u_free + u_c` with
//! `T` the identity on free dofs and the rows `c_d` on dependents. The
//! assembled system is then `T^T K T du = T^T r`: the assembler adds each
//! element-matrix entry `K_ab` as `c_a c_b K_ab` at the equations of the
//! free dofs behind `a` and `b` ([`DofMap::targets`]), and
//! [`DofMap::reduce`] applies `T^T` to a force vector. The reduced matrix is
//! symmetric positive definite whenever `K` is on the constrained space, so
//! every back end solves it unchanged.

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
    /// Dependent dofs of linear equations (empty without equations).
    pub dependents: Dependents,
}

/// Dependent dofs of linear constraints, each a combination of free and
/// Dirichlet dofs (chains already substituted; see the module doc).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Dependents {
    /// Slot of each dof in `ptr` (`u32::MAX`: not dependent); empty when
    /// the model has no equations.
    slot: Vec<u32>,
    /// Dependent dofs, in the order of their slots.
    pub dofs: Vec<usize>,
    /// Terms of slot `s`: `terms[ptr[s]..ptr[s + 1]]`.
    ptr: Vec<usize>,
    /// `(dof, coefficient)`: the dof is free or Dirichlet-constrained.
    terms: Vec<(usize, f64)>,
}

impl Dependents {
    /// Terms `(dof, c)` of `u_d = sum c u_dof` when `d` is dependent.
    #[inline]
    pub fn terms(&self, d: usize) -> Option<&[(usize, f64)]> {
        match self.slot.get(d) {
            Some(&s) if s != u32::MAX => {
                let s = s as usize;
                Some(&self.terms[self.ptr[s]..self.ptr[s + 1]])
            }
            _ => None,
        }
    }

    /// Whether `d` is a dependent dof.
    #[inline]
    pub fn contains(&self, d: usize) -> bool {
        matches!(self.slot.get(d), Some(&s) if s != u32::MAX)
    }

    /// Every dependent dof with its terms.
    pub fn iter(&self) -> impl Iterator<Item = (usize, &[(usize, f64)])> + '_ {
        self.dofs
            .iter()
            .enumerate()
            .map(|(s, &d)| (d, &self.terms[self.ptr[s]..self.ptr[s + 1]]))
    }

    /// Whether there are no dependent dofs.
    pub fn is_empty(&self) -> bool {
        self.dofs.is_empty()
    }
}

/// One homogeneous linear equation `sum a_k u_{dof_k} = 0`; the first
/// term's dof becomes dependent.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearEquation {
    /// `(dof, a)` terms, the dependent first.
    pub terms: Vec<(usize, f64)>,
    /// Where the equation comes from (e.g. `model.inp:12`), for messages.
    pub origin: String,
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
        let used_dofs: Vec<bool> = (0..3 * num_nodes)
            .map(|d| used.get(d / 3).copied().unwrap_or(true))
            .collect();
        Self::with_used_dofs(num_nodes, constraints, &used_dofs)
    }

    /// As [`DofMap::new`], with the use of each dof (`used_dofs[3 node +
    /// component]`): a dof that no element uses (a node of no element, or
    /// the `z` component of a node of plane elements only) is fixed at
    /// zero silently.
    pub fn with_used_dofs(
        num_nodes: usize,
        constraints: &[(usize, f64)],
        used_dofs: &[bool],
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
            if !used_dofs.get(d).copied().unwrap_or(true) {
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
            dependents: Dependents::default(),
        })
    }

    /// Add linear equations: each first dof becomes dependent (see the
    /// module doc) and the free dofs are renumbered. Errors (each naming
    /// the equation's origin): a dof out of range, a zero or non-finite
    /// coefficient, a dependent that is also Dirichlet-constrained or
    /// dependent in two equations, a dof twice in one equation, and a cycle
    /// of equations whose dependents define each other.
    pub fn add_equations(
        &mut self,
        equations: &[LinearEquation],
        node_labels: &[usize],
    ) -> Result<(), CoreError> {
        // the user's node label of node `n` (1-based index without labels)
        let lab = |n: usize| node_labels.get(n).copied().unwrap_or(n + 1);
        if equations.is_empty() {
            return Ok(());
        }
        let ndof = self.eq.len();
        let bad = |e: &LinearEquation, why: String| {
            CoreError::Invalid(format!("linear equation at {}: {why}", e.origin))
        };
        // raw definition of each dependent: (dof, -a_k / a_0)
        let mut def: Definitions = std::collections::HashMap::with_capacity(equations.len());
        for (i, e) in equations.iter().enumerate() {
            if e.terms.len() < 2 {
                return Err(bad(e, "it needs at least two terms".into()));
            }
            for (k, &(d, a)) in e.terms.iter().enumerate() {
                if d >= ndof {
                    return Err(bad(e, format!("dof {d}, but the model has {ndof} dofs")));
                }
                if !a.is_finite() || (k == 0 && a == 0.0) {
                    return Err(bad(
                        e,
                        format!(
                            "coefficient {a} of node {} dof {} (must be finite, and non-zero on the first, dependent term)",
                            lab(d / 3),
                            d % 3 + 1
                        ),
                    ));
                }
                if e.terms[..k].iter().any(|t| t.0 == d) {
                    return Err(bad(
                        e,
                        format!("node {} dof {} appears twice", lab(d / 3), d % 3 + 1),
                    ));
                }
            }
            let (d0, a0) = e.terms[0];
            if self.eq[d0] == CONSTRAINED && !self.orphan[d0] {
                return Err(bad(
                    e,
                    format!(
                        "its dependent (first) term, node {} dof {}, also has a boundary condition; put another dof first",
                        lab(d0 / 3),
                        d0 % 3 + 1
                    ),
                ));
            }
            let rhs = e.terms[1..].iter().map(|&(d, a)| (d, -a / a0)).collect();
            if let Some((j, _)) = def.insert(d0, (i, rhs)) {
                return Err(bad(
                    e,
                    format!(
                        "node {} dof {} is already the dependent of the equation at {}",
                        lab(d0 / 3),
                        d0 % 3 + 1,
                        equations[j].origin
                    ),
                ));
            }
        }
        // substitute chains (depth-first, cycles are errors)
        let mut resolved: std::collections::HashMap<usize, Vec<(usize, f64)>> =
            std::collections::HashMap::with_capacity(def.len());
        let mut order: Vec<usize> = def.keys().copied().collect();
        order.sort_unstable();
        for &root in &order {
            resolve(root, &def, &mut resolved, &mut Vec::new(), equations, &lab)?;
        }
        // renumber
        let mut slot = vec![u32::MAX; ndof];
        let mut dependents = Dependents {
            slot: Vec::new(),
            dofs: Vec::with_capacity(order.len()),
            ptr: vec![0],
            terms: Vec::new(),
        };
        for (s, &d) in order.iter().enumerate() {
            slot[d] = s as u32;
            dependents.dofs.push(d);
            dependents.terms.extend_from_slice(&resolved[&d]);
            dependents.ptr.push(dependents.terms.len());
            self.eq[d] = CONSTRAINED;
            self.prescribed[d] = 0.0;
            self.orphan[d] = false;
        }
        dependents.slot = slot;
        let mut n = 0;
        for d in 0..ndof {
            if self.eq[d] != CONSTRAINED {
                self.eq[d] = n;
                n += 1;
            }
        }
        self.num_free = n;
        self.dependents = dependents;
        Ok(())
    }

    /// Whether the map has linear equations (dependent dofs).
    pub fn has_equations(&self) -> bool {
        !self.dependents.is_empty()
    }

    /// `(equation, coefficient)` pairs that dof `d` contributes to: its own
    /// equation with 1 when free, the free dofs of its terms when dependent,
    /// nothing when Dirichlet-constrained.
    #[inline]
    pub fn targets(&self, d: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let own = self.eq[d];
        let single = (own != CONSTRAINED).then_some((own, 1.0));
        let terms = self.dependents.terms(d).unwrap_or(&[]);
        single.into_iter().chain(terms.iter().filter_map(|&(m, c)| {
            let e = self.eq[m];
            (e != CONSTRAINED).then_some((e, c))
        }))
    }

    /// Set every dependent dof of a full vector from its terms.
    pub fn fill_dependents(&self, u: &mut [f64]) {
        for (d, terms) in self.dependents.iter() {
            u[d] = terms.iter().map(|&(m, c)| c * u[m]).sum();
        }
    }

    /// Total number of dofs (free and constrained).
    pub fn num_dofs(&self) -> usize {
        self.eq.len()
    }

    /// Full displacement vector with prescribed values scaled by `factor`,
    /// free values taken from `free` (or zero when `None`) and dependent
    /// values from their equations.
    pub fn expand(&self, free: Option<&[f64]>, factor: f64) -> Vec<f64> {
        let mut u: Vec<f64> = (0..self.eq.len())
            .map(|d| match self.eq[d] {
                CONSTRAINED => factor * self.prescribed[d],
                e => free.map_or(0.0, |f| f[e]),
            })
            .collect();
        self.fill_dependents(&mut u);
        u
    }

    /// The reduced (free-equation) form `T^T v` of a full-length force-like
    /// vector: its free entries, plus each dependent entry distributed onto
    /// the free dofs of its equation.
    pub fn reduce(&self, full: &[f64]) -> Vec<f64> {
        let mut v = vec![0.0; self.num_free];
        self.reduce_into(full, &mut v);
        v
    }

    /// [`DofMap::reduce`] into `out` (length [`DofMap::num_free`]), without
    /// allocating: `out[e]` is `full` at the dof of equation `e` plus the
    /// dependents' shares.
    pub fn reduce_into(&self, full: &[f64], out: &mut [f64]) {
        for (d, &e) in self.eq.iter().enumerate() {
            if e != CONSTRAINED {
                out[e] = full[d];
            }
        }
        for (d, terms) in self.dependents.iter() {
            for &(m, c) in terms {
                if self.eq[m] != CONSTRAINED {
                    out[self.eq[m]] += c * full[d];
                }
            }
        }
    }

    /// The reactions of the reduced system, `T^T r` in full-dof form: for
    /// the residual `r = f_int - lambda f_ext` (full length), `out[m] =
    /// r_m + sum_d c_dm r_d` on every dof that is not dependent (the sum
    /// over the dependents `d` whose terms hold `m`, `u_d = sum_m c_dm
    /// u_m`), and 0 on the dependents, whose constraint forces are thereby
    /// moved onto their independent dofs. Equal to `r` without equations.
    ///
    /// Why this is the force conjugate to a prescribed dof. Collect the
    /// independent dofs (free `f` and prescribed `p`) in `w`; the
    /// equations give `u = T w`. The elements' virtual work is `f_int .
    /// du = (T^T f_int) . dw`, and equilibrium of the reduced system is
    /// `(T^T r)_f = 0`. Hence the power of the internal forces is
    ///
    /// ```text
    /// f_int . u' = lambda (T^T f_ext) . w' + (T^T r) . w'
    ///            = lambda f_ext . u'       + sum_p R_p w_p',   R = T^T r,
    /// ```
    ///
    /// so `R_p = r_p + sum_d c_dp r_d` (the Lagrange multipliers of the
    /// equations, i.e. the dependents' constraint forces `r_d`, carried to
    /// `p` with the equation coefficients) is the external force that works
    /// on the prescribed motion `w_p`. `r_p` alone, the elements' share at
    /// the node (what CalculiX prints as `RF`), misses the dependents'
    /// part: for a face tied to a master node by `u_d - u_p = 0` the
    /// master's generalized reaction is the total force on the face.
    /// On a free dof `out` is the reduced residual (zero at convergence).
    pub fn generalized_reactions_into(&self, residual: &[f64], out: &mut [f64]) {
        out.copy_from_slice(residual);
        for (d, terms) in self.dependents.iter() {
            out[d] = 0.0;
            for &(m, c) in terms {
                out[m] += c * residual[d];
            }
        }
    }

    /// [`DofMap::generalized_reactions_into`] into a new vector.
    pub fn generalized_reactions(&self, residual: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; residual.len()];
        self.generalized_reactions_into(residual, &mut out);
        out
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

/// Raw definition of each dependent: dof -> (equation index, `(dof,
/// -a_k / a_0)` terms).
type Definitions = std::collections::HashMap<usize, (usize, Vec<(usize, f64)>)>;

/// Terms of dependent `d` over free and Dirichlet dofs only, substituting
/// dependents among its terms recursively (`path`: the chain being
/// resolved, for cycle detection).
fn resolve(
    d: usize,
    def: &Definitions,
    resolved: &mut std::collections::HashMap<usize, Vec<(usize, f64)>>,
    path: &mut Vec<usize>,
    equations: &[LinearEquation],
    lab: &dyn Fn(usize) -> usize,
) -> Result<(), CoreError> {
    if resolved.contains_key(&d) {
        return Ok(());
    }
    let (i, raw) = &def[&d];
    if path.contains(&d) {
        return Err(CoreError::Invalid(format!(
            "linear equation at {}: its dependent, node {} dof {}, is defined through itself by a cycle of equations",
            equations[*i].origin,
            lab(d / 3),
            d % 3 + 1
        )));
    }
    path.push(d);
    let mut out: Vec<(usize, f64)> = Vec::with_capacity(raw.len());
    for &(m, c) in raw {
        if def.contains_key(&m) {
            resolve(m, def, resolved, path, equations, lab)?;
            out.extend(resolved[&m].iter().map(|&(mm, cc)| (mm, c * cc)));
        } else {
            out.push((m, c));
        }
    }
    path.pop();
    out.sort_unstable_by_key(|t| t.0);
    let mut merged: Vec<(usize, f64)> = Vec::with_capacity(out.len());
    for (m, c) in out {
        match merged.last_mut() {
            Some(last) if last.0 == m => last.1 += c,
            _ => merged.push((m, c)),
        }
    }
    if merged.iter().any(|t| t.0 == d) {
        return Err(CoreError::Invalid(format!(
            "linear equation at {}: its dependent, node {} dof {}, appears among its own terms after substituting the other equations",
            equations[*i].origin,
            lab(d / 3),
            d % 3 + 1
        )));
    }
    resolved.insert(d, merged);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `T^T r` moves a dependent's constraint force onto its terms with
    /// their coefficients: `u_3 = -2 u_0 + 2 u_7` (from the test above)
    /// puts `-2 r_3` on the prescribed dof 0 and `2 r_3` on dof 7; the work
    /// `R . w'` then equals `r . u'` for any motion `u = T w`.
    #[test]
    fn generalized_reactions_carry_dependent_forces_to_their_terms() {
        let used = [true; 3];
        let mut m = DofMap::new(3, &[(0, 0.5)], &used).unwrap();
        let eqs = [
            LinearEquation {
                terms: vec![(3, 1.0), (6, -2.0)],
                origin: "a".into(),
            },
            LinearEquation {
                terms: vec![(6, 2.0), (7, -2.0), (0, 2.0)],
                origin: "b".into(),
            },
        ];
        m.add_equations(&eqs, &[]).unwrap();
        let r: Vec<f64> = (0..9).map(|i| 1.0 + i as f64).collect();
        let g = m.generalized_reactions(&r);
        // dependents 3 (= -2 u0 + 2 u7) and 6 (= u7 - u0)
        assert_eq!(g[3], 0.0);
        assert_eq!(g[6], 0.0);
        assert_eq!(g[0], r[0] - 2.0 * r[3] - r[6]);
        assert_eq!(g[7], r[7] + 2.0 * r[3] + r[6]);
        assert_eq!(g[1], r[1]);
        let free = [0.3, -1.0, 2.0, 0.7, 1.5, -0.2];
        let u = m.expand(Some(&free), 1.0);
        let ru: f64 = r.iter().zip(&u).map(|(a, b)| a * b).sum();
        let gu: f64 = g.iter().zip(&u).map(|(a, b)| a * b).sum();
        assert!((ru - gu).abs() < 1e-12 * ru.abs(), "{ru} vs {gu}");
        // without equations it is the residual itself
        let plain = DofMap::new(3, &[(0, 0.5)], &used).unwrap();
        assert_eq!(plain.generalized_reactions(&r), r);
    }

    #[test]
    fn equations_make_dependents_and_chains_are_substituted() {
        let used = [true; 3];
        // node 0 fixed in x; u_{1,x} = 2 u_{2,x}; u_{2,x} = u_{2,y} - u_{0,x}
        let mut m = DofMap::new(3, &[(0, 0.5)], &used).unwrap();
        let eqs = [
            LinearEquation {
                terms: vec![(3, 1.0), (6, -2.0)],
                origin: "a".into(),
            },
            LinearEquation {
                terms: vec![(6, 2.0), (7, -2.0), (0, 2.0)],
                origin: "b".into(),
            },
        ];
        m.add_equations(&eqs, &[]).unwrap();
        assert_eq!(m.num_free, 9 - 3);
        assert_eq!(m.eq[3], CONSTRAINED);
        assert_eq!(m.dependents.terms(3).unwrap(), &[(0, -2.0), (7, 2.0)]);
        // u: free dofs 1,2,4,5,7,8 numbered 0..6
        let free = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        let u = m.expand(Some(&free), 1.0);
        assert_eq!(u[6], 5.0 - 0.5);
        assert_eq!(u[3], 2.0 * (5.0 - 0.5));
        // T^T of a unit force on dof 3 lands on dof 7 (equation 4) with 2
        let mut f = vec![0.0; 9];
        f[3] = 1.0;
        let r = m.reduce(&f);
        assert_eq!(r, vec![0.0, 0.0, 0.0, 0.0, 2.0, 0.0]);
        // a cycle and a dependent with a boundary condition are errors
        let mut c = DofMap::new(3, &[(0, 0.0)], &used).unwrap();
        let cyc = [
            LinearEquation {
                terms: vec![(3, 1.0), (6, -1.0)],
                origin: "x".into(),
            },
            LinearEquation {
                terms: vec![(6, 1.0), (3, -1.0)],
                origin: "y".into(),
            },
        ];
        assert!(c
            .add_equations(&cyc, &[])
            .unwrap_err()
            .to_string()
            .contains("cycle"));
        let fixed = [LinearEquation {
            terms: vec![(0, 1.0), (3, -1.0)],
            origin: "z".into(),
        }];
        assert!(c
            .add_equations(&fixed, &[])
            .unwrap_err()
            .to_string()
            .contains("boundary condition"));
    }

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
