//! The energy balances of path following's dissipation constraint
//! ([`crate::arc_length`], whose module doc states the equations) and the
//! element terms they need.
//!
//! # Global balance (small kinematics)
//!
//! With linear solids and laws with secant unloading the stored energy of
//! the whole model is `½ u . f_int` (Clapeyron), and `D = W_ext - ½ u .
//! f_int` gives `ΔD` from the work measures `a = f_ext,f . u_f`, `p = ubar_c
//! . f_int,c` and `t = f_th . u` ([`Base`], [`work_measures`]), linearised
//! with the coupling terms `q`, `g`, `h` of the elements with a prescribed
//! displacement ([`Coupling`]).
//!
//! # Interface balance (any kinematics)
//!
//! Under large deformation the solids' stored energy is not `½ u . f_int`
//! (a Saint Venant-Kirchhoff or neo-Hookean body stiffens or softens as it
//! turns), so the global balance reads elastic unloading of a turning arm
//! as dissipation. Clapeyron still holds at each interface point, whatever
//! the bulk kinematics, for a law with secant unloading (`t = S(state)
//! delta` in the point's own frame: bilinear, exponential, their contact
//! branch, the viscous regularisation): the point stores `½ t . delta` and
//! dissipates, from a state `0` to a state `1` along a straight path in
//! `(delta, t)`,
//!
//! ```text
//! ΔD_p = ∫ (t . ddelta - d(½ t . delta)) = ½ ∫ (t . ddelta - delta . dt)
//!      = ½ (t_0 . Δdelta - Δt . delta_0)      (exact on the straight path)
//! ```
//!
//! (Verhoosel, Remmers & Gutiérrez 2009, IJNME 77: the dissipated
//! energy of a cohesive interface). The interface elements' internal force
//! `f_I` (interfaces only, not the solids) is `f_I = Σ_q w_q B_q^T t_q`
//! with `B_q` the jump operator; under small kinematics `delta_q = B_q u`,
//! so `f_I . u = Σ_q w_q t_q . delta_q` and summing the points gives
//!
//! ```text
//! ΔD_I = ½ (f_I,0 . Δu - Δf_I . u_0) = ½ (f_I,0 . u - f_I . u_0)
//! ```
//!
//! exactly. Under finite kinematics (the interface element's current
//! mid-surface frame `theta` and area factor `j`, `F_q = j theta t`) a
//! zero-thickness element still has `f_I . u = Σ_q w_q j_q t_q . delta_q`
//! exactly (the gap `g = Σ N_a (u_top - u_bot)` is the whole of `u` the
//! forces see, and `delta = theta^T g`), and rigid motions add nothing:
//! the balance is the points' Clapeyron on the current area. The frame's
//! turning (`dtheta`, of the order of the arms' rotation increment) and
//! the area change (the bending strain of the faces) make it approximate
//! there, but it stays a monotone measure of the energy the interfaces
//! let go, which is all the path parameter needs. Its linearisation, with
//! `du = T du_f + dlambda ubar` (the prescribed dofs follow the load
//! factor) and `df_I = K_I du`:
//!
//! ```text
//! dΔD_I = w . du,      w = ½ (f_I,0 - K_I^T u_0)        (full length)
//!       = (T^T w) . du_f + (w . ubar) dlambda
//! ```
//!
//! needs only `f_I` and `K_I^T u_0`, which the assembly sums in the same
//! pass as the residual ([`junta_core::assembly::InterfaceShare`]; the
//! engine's `InterfaceShareBuffers`, probe `u_0`): no second assembly per
//! iteration, and no coupling terms `g`, `h`. The solids, their kinematics
//! and their material (elastic or not), and a temperature held over the
//! step (interfaces carry no thermal strain) do not enter.
//!
//! Why not sum the laws' own dissipated energies
//! ([`junta_core::Model::dissipated_energy`]) and linearise those: the
//! laws report `D(state)` but not its derivative in the jump, so the
//! constraint's linearisation would need a derivative no law gives (or a
//! finite difference per iteration); and each law's `D` is a function of
//! its damage variable alone, flat on the elastic branch and at a point's
//! unloading, where the constraint would degenerate. The interface balance
//! is of the same kind as the global one (exact for secant laws), so the
//! driver around it is the same.

use super::engine::InterfaceShareBuffers;
use super::vocabulary::energy_balance_holds;
use junta_core::dof::CONSTRAINED;
use junta_core::element::{ElementContext, StepInfo};
use junta_core::state::StateStore;
use junta_core::{CoreError, Model};

/// The energy balance the dissipation constraint is written on (module
/// doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Balance {
    /// The whole model's, `D = W_ext - ½ u . f_int`: every element under
    /// small kinematics ([`energy_balance_holds`]).
    Global,
    /// The interfaces' alone, `ΔD_I = ½ (f_I,0 . u - f_I . u_0)`: under
    /// large deformation.
    Interface,
}

impl Balance {
    /// The balance that holds for `model`: the global one where every
    /// element has small kinematics (its results are those of the driver
    /// before the interface balance existed), else the interfaces'.
    pub(super) fn of(model: &Model) -> Self {
        if energy_balance_holds(model) {
            Balance::Global
        } else {
            Balance::Interface
        }
    }
}

/// `ΔD_I = ½ (f_I,0 . u - f_I . u_0)` (module doc): `base_force` is
/// `f_I,0`, `share` the interface share of the last assembly (at `u`),
/// whose probe is `u_0`.
pub(super) fn interface_dissipation(
    base_force: &[f64],
    u: &[f64],
    share: &InterfaceShareBuffers,
) -> f64 {
    let mut d = 0.0;
    for i in 0..u.len() {
        d += base_force[i] * u[i] - share.force[i] * share.probe[i];
    }
    0.5 * d
}

/// The linearisation of [`interface_dissipation`]: `w = ½ (f_I,0 - K_I^T
/// u_0)` reduced to the equations (`T^T w`) into `w_eq`, using `full` (by
/// dof) as scratch; returns `w . ubar` (the derivative in the load factor).
pub(super) fn interface_gradient(
    model: &Model,
    base_force: &[f64],
    share: &InterfaceShareBuffers,
    ubar: &[f64],
    full: &mut [f64],
    w_eq: &mut [f64],
) -> f64 {
    let mut c_l = 0.0;
    for i in 0..full.len() {
        full[i] = 0.5 * (base_force[i] - share.tangent_probe[i]);
        c_l += full[i] * ubar[i];
    }
    model.dofs.reduce_into(full, w_eq);
    c_l
}

/// Element matrices needed for `q`, `g`, `h` (see the module doc).
pub(super) struct Coupling {
    /// The thermal force `f_th` of the step's temperature change (module
    /// doc), if the model has one.
    pub(super) thermal: Option<ThermalForce>,
    /// Elements `(block, element)` with a prescribed non-zero displacement
    /// whose matrix changes with `u` (recomputed at every call).
    elements: Vec<(usize, usize)>,
    /// The same for the linear elements (small strain, no state), whose
    /// constant matrices give a constant part of `q`, `g` and `h`.
    linear_elements: Vec<(usize, usize)>,
    /// That constant part, once computed: `(q, g, h)`, `q` without `f_ext`.
    linear_part: Option<(Vec<f64>, Vec<f64>, f64)>,
    /// `ubar` (full length; zero on free dofs).
    pub(super) ubar: Vec<f64>,
    /// `|ubar_c|^2`.
    pub(super) c: f64,
    /// Scratch.
    trial: Vec<f64>,
    kbuf: Vec<f64>,
    fbuf: Vec<f64>,
    coords: Vec<[f64; 3]>,
    disp: Vec<f64>,
    /// The element's nodal temperature changes (scaled by the step's
    /// temperature factor): the stress, hence the geometric stiffness of
    /// an nlgeom solid, depends on them.
    temps: Vec<f64>,
    dofs: Vec<usize>,
}

impl Coupling {
    /// `f0`: the internal force at zero displacement at the step's
    /// temperature ([`internal_force_at_zero`]), if the
    /// model has a temperature field.
    pub(super) fn new(model: &Model, f0: Option<Vec<f64>>) -> Self {
        // the prescribed values, and the dependents of linear equations
        // that follow them (`u = T u_f + lambda ubar`)
        let mut ubar: Vec<f64> = model
            .dofs
            .prescribed
            .iter()
            .enumerate()
            .map(|(d, &v)| {
                if model.dofs.eq[d] == CONSTRAINED && !model.dofs.dependents.contains(d) {
                    v
                } else {
                    0.0
                }
            })
            .collect();
        model.dofs.fill_dependents(&mut ubar);
        let (mut elements, mut linear_elements) = (Vec::new(), Vec::new());
        for (b, block) in model.mesh.blocks.iter().enumerate() {
            let el = &model.elements[b];
            let linear = el.is_linear() && el.state_len() == 0;
            for e in 0..block.len() {
                if block
                    .element(e)
                    .iter()
                    .any(|&n| (0..3).any(|c| ubar[3 * n + c] != 0.0))
                {
                    if linear {
                        linear_elements.push((b, e));
                    } else {
                        elements.push((b, e));
                    }
                }
            }
        }
        let thermal = f0.map(|f| ThermalForce::new(model, &ubar, f));
        Coupling {
            thermal,
            elements,
            linear_elements,
            linear_part: None,
            c: ubar.iter().map(|v| v * v).sum(),
            ubar,
            trial: Vec::new(),
            kbuf: Vec::new(),
            fbuf: Vec::new(),
            coords: Vec::new(),
            disp: Vec::new(),
            temps: Vec::new(),
            dofs: Vec::new(),
        }
    }

    /// `q` (free, by equation), `g` (free, by equation) and `h` at `u`.
    /// With linear equations (`*EQUATION`), `ubar` holds the dependents
    /// too and the element rows / columns go to the equations behind each
    /// dof ([`junta_core::dof::DofMap::targets`]): `q = T^T (f_ext - K
    /// ubar)`, `g = T^T K^T ubar`, `h = ubar^T K ubar`.
    pub(super) fn compute(
        &mut self,
        model: &Model,
        u: &[f64],
        state: &StateStore,
        step: StepInfo,
        q: &mut [f64],
        g: &mut [f64],
    ) -> Result<f64, CoreError> {
        if self.linear_part.is_none() {
            let (mut ql, mut gl) = (vec![0.0; q.len()], vec![0.0; g.len()]);
            let mut hl = 0.0;
            for (b, e) in std::mem::take(&mut self.linear_elements) {
                hl += self.add_element(model, u, state, step, (b, e), &mut ql, &mut gl)?;
            }
            self.linear_part = Some((ql, gl, hl));
        }
        model.dofs.reduce_into(&model.f_ext, q);
        let mut h = {
            let (ql, gl, hl) = self.linear_part.as_ref().expect("computed above");
            for (qi, v) in q.iter_mut().zip(ql) {
                *qi += v;
            }
            g.copy_from_slice(gl);
            *hl
        };
        for i in 0..self.elements.len() {
            let be = self.elements[i];
            h += self.add_element(model, u, state, step, be, q, g)?;
        }
        Ok(h)
    }

    /// Element `(b, e)`'s part of `q` (`-K ubar`) and `g` (`K^T ubar`),
    /// added; returns its part of `h` (`ubar^T K ubar`).
    #[allow(clippy::too_many_arguments)]
    fn add_element(
        &mut self,
        model: &Model,
        u: &[f64],
        state: &StateStore,
        step: StepInfo,
        (b, e): (usize, usize),
        q: &mut [f64],
        g: &mut [f64],
    ) -> Result<f64, CoreError> {
        let mut h = 0.0;
        let block = &model.mesh.blocks[b];
        let el = &model.elements[b];
        let conn = block.element(e);
        let nd = 3 * conn.len();
        self.coords.clear();
        self.disp.clear();
        self.dofs.clear();
        self.temps.clear();
        if let Some(t) = &model.temperature {
            let theta = step.temperature_factor;
            self.temps.extend(conn.iter().map(|&n| theta * t[n]));
        }
        for &n in conn {
            self.coords.push(model.mesh.nodes[n]);
            for c in 0..3 {
                self.disp.push(u[3 * n + c]);
                self.dofs.push(3 * n + c);
            }
        }
        let r = state.range(b, e);
        self.trial.clear();
        self.trial.extend_from_slice(&state.committed[r.clone()]);
        self.kbuf.resize(nd * nd, 0.0);
        self.fbuf.resize(nd, 0.0);
        let ctx = ElementContext {
            coords: &self.coords,
            disp: &self.disp,
            state_committed: &state.committed[r],
            step,
            law_responses: None,
            temperature: (model.temperature.is_some() && !el.shape().is_interface())
                .then_some(self.temps.as_slice()),
        };
        el.compute(&ctx, &mut self.trial, &mut self.fbuf, Some(&mut self.kbuf))
            .map_err(|source| CoreError::Element {
                block: block.name.clone(),
                element: e,
                source,
            })?;
        for i in 0..nd {
            let di = self.dofs[i];
            let ui = self.ubar[di];
            for j in 0..nd {
                let dj = self.dofs[j];
                let kij = self.kbuf[i * nd + j];
                let uj = self.ubar[dj];
                // row i's equations: -K ubar into q
                if uj != 0.0 {
                    for (ei, ci) in model.dofs.targets(di) {
                        q[ei] -= ci * kij * uj;
                    }
                }
                // column j's equations: K^T ubar into g
                if ui != 0.0 {
                    for (ej, cj) in model.dofs.targets(dj) {
                        g[ej] += cj * ui * kij;
                    }
                }
                h += ui * kij * uj;
            }
        }
        Ok(h)
    }
}

/// The thermal force of a step whose temperature is held: `f_th` by dof,
/// its reduction to the equations and `f_th . ubar_c`.
pub(super) struct ThermalForce {
    by_dof: Vec<f64>,
    pub(super) by_equation: Vec<f64>,
    pub(super) prescribed: f64,
}

impl ThermalForce {
    /// From the internal force at zero displacement `f0 = -f_th`.
    fn new(model: &Model, ubar: &[f64], f0: Vec<f64>) -> Self {
        let by_dof: Vec<f64> = f0.iter().map(|v| -v).collect();
        let by_equation = model.dofs.reduce(&by_dof);
        let prescribed = by_dof.iter().zip(ubar).map(|(f, u)| f * u).sum();
        ThermalForce {
            by_dof,
            by_equation,
            prescribed,
        }
    }
}

/// `f_th . u` over all dofs (0 without a thermal force).
fn thermal_measure(coupling: &Coupling, u: &[f64]) -> f64 {
    coupling
        .thermal
        .as_ref()
        .map_or(0.0, |t| t.by_dof.iter().zip(u).map(|(f, v)| f * v).sum())
}

/// Energy measures of a state: `a = f_ext,f . u_f`, `p = ubar_c . f_int,c`
/// (with linear equations: `a` over the free and dependent dofs, `p` over
/// the prescribed dofs and the dependents that follow them), and `t = f_th
/// . u` ([`thermal_measure`]).
pub(super) fn work_measures(
    model: &Model,
    coupling: &Coupling,
    u: &[f64],
    f_int: &[f64],
) -> (f64, f64, f64) {
    let (mut a, mut p) = (0.0, 0.0);
    for (d, &eq) in model.dofs.eq.iter().enumerate() {
        if eq != CONSTRAINED || model.dofs.dependents.contains(d) {
            a += model.f_ext[d] * u[d];
        }
        p += coupling.ubar[d] * f_int[d];
    }
    (a, p, thermal_measure(coupling, u))
}

/// Converged state at the start of an increment.
#[derive(Debug, Clone, Copy)]
pub(super) struct Base {
    pub(super) lambda: f64,
    pub(super) a: f64,
    pub(super) p: f64,
    /// `f_th . u` ([`thermal_measure`]).
    pub(super) t: f64,
}

impl Base {
    /// `ΔD = ½ (lambda_0 Δa - Δlambda a_0 + p_0 Δlambda - lambda_0 Δp +
    /// Δt)`: the energy dissipated from this state to one with the measures
    /// `a`, `p`, `t` at the load factor `lambda` (module doc of [`crate::arc_length`]).
    pub(super) fn dissipation(&self, a: f64, p: f64, t: f64, lambda: f64) -> f64 {
        0.5 * (self.lambda * (a - self.a) - (lambda - self.lambda) * self.a
            + self.p * (lambda - self.lambda)
            - self.lambda * (p - self.p)
            + (t - self.t))
    }
}
