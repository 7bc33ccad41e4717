//! The [`Element`] trait: one element *type with its material or law*
//! (e.g. "H20 of steel", "INTER18 with linear penalty"), called once per
//! element of a block per assembly.

use crate::topology::CellShape;
use thiserror::Error;

/// Errors raised by an element kernel.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ElementError {
    /// det J <= 0 at an integration point: the element is inverted or degenerate.
    #[error("non-positive Jacobian determinant {det:.6e} at integration point {point} (inverted or degenerate element; check the node order)")]
    NegativeJacobian {
        /// Integration point (0-based, in the element's rule order).
        point: usize,
        /// The determinant of `J = dx/dxi` there (non-positive or NaN).
        det: f64,
    },
    /// A zero-area interface (coincident nodes across the face).
    #[error(
        "degenerate interface surface: |V_xi x V_eta| = {area:.3e} at integration point {point}"
    )]
    DegenerateSurface {
        /// Integration point (0-based, in the element's rule order).
        point: usize,
        /// The surface Jacobian `|V_xi x V_eta|` of the mid-surface there
        /// (at most `1e-12 |V_xi| |V_eta|`, or not finite).
        area: f64,
    },
    /// The constitutive law failed.
    #[error("law failed at integration point {point}: {message}")]
    Law {
        /// Integration point (0-based, in the element's rule order).
        point: usize,
        /// The law's (or the kernel's) message.
        message: String,
    },
}

/// Kinematics of an element, chosen per model (scene `[analysis] nlgeom`,
/// deck `*STEP, NLGEOM`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Kinematics {
    /// Small displacements and strains: strains linear in the
    /// displacements, interfaces framed on their reference mid-surface.
    #[default]
    Small,
    /// Large displacements and rotations: total-Lagrangian solids (Green
    /// strain, second Piola-Kirchhoff stress), interfaces framed on their
    /// current mid-surface.
    Finite,
}

pub use crate::step::StepInfo;

/// The out-of-plane width a plane cell or a line interface stands for
/// (forces, reactions and energies of a plane model are those of this
/// width).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PlaneWidth {
    /// Plane strain or plane stress: a slice of constant thickness `t`.
    Thickness(f64),
    /// Axisymmetric about the y axis (x is the radius): the full ring,
    /// width `2 pi r`.
    Axisymmetric,
}

impl PlaneWidth {
    /// The width at a point `x`: `t`, or `2 pi x[0]`.
    pub fn at(self, x: [f64; 3]) -> f64 {
        match self {
            PlaneWidth::Thickness(t) => t,
            PlaneWidth::Axisymmetric => 2.0 * std::f64::consts::PI * x[0],
        }
    }
}

/// Everything an element kernel reads. Buffers are owned by the caller.
#[derive(Debug, Clone, Copy)]
pub struct ElementContext<'a> {
    /// Reference coordinates of the element's nodes (len = `num_nodes`).
    pub coords: &'a [[f64; 3]],
    /// Total nodal displacements, node-major (len = 3 `num_nodes`).
    pub disp: &'a [f64],
    /// Committed integration-point state of this element (len = `state_len`).
    pub state_committed: &'a [f64],
    /// Increment information.
    pub step: StepInfo,
    /// The law's responses at this element's points when its law is
    /// evaluated in batches ([`crate::InterfaceLaw::is_batched`]): the
    /// assembler evaluates the whole block first and the element uses these
    /// instead of calling the law (`None` for every other law).
    pub law_responses: Option<&'a [crate::law::LawResponse]>,
    /// Temperature change of each node from the stress-free temperature
    /// (len = `num_nodes`) when the model carries a temperature field
    /// (already scaled by [`StepInfo::temperature_factor`]), `None`
    /// otherwise. Solids interpolate it to their integration points and
    /// subtract the material's thermal strain; interfaces ignore it (they
    /// see the jump the solids' expansion makes).
    pub temperature: Option<&'a [f64]>,
}

/// Output at one integration point: position and named values.
#[derive(Debug, Clone, PartialEq)]
pub struct PointOutput {
    /// Position in the reference configuration.
    pub position: [f64; 3],
    /// Named values: e.g. `("stress", [sxx, syy, szz, sxy, syz, szx])`.
    pub values: Vec<(&'static str, Vec<f64>)>,
}

impl PointOutput {
    /// The value named `name`, if present.
    pub fn get(&self, name: &str) -> Option<&[f64]> {
        self.values
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, v)| v.as_slice())
    }
}

/// One element type bound to its material or law.
///
/// Kernels use fixed-size arrays inside and write into caller buffers: no
/// allocation per call.
pub trait Element: Send + Sync + std::fmt::Debug {
    /// Registry key of the element type (`"h20"`, `"inter18"`, ...).
    fn key(&self) -> &'static str;
    /// Cell shape (node count and order, faces).
    fn shape(&self) -> CellShape;
    /// Number of nodes.
    fn num_nodes(&self) -> usize {
        self.shape().num_nodes()
    }
    /// Degrees of freedom per node (3 for every element so far).
    fn dofs_per_node(&self) -> usize {
        3
    }
    /// The displacement components `[x, y, z]` the element uses at its
    /// nodes: all three for 3D elements, `[true, true, false]` for plane
    /// ones. A node's component that no element uses gets no equation
    /// ([`crate::Model::new`]), so a plane model solves two per node.
    fn active_components(&self) -> [bool; 3] {
        [true; 3]
    }
    /// The width a plane element stands for (`None` for 3D elements).
    fn plane_width(&self) -> Option<PlaneWidth> {
        None
    }
    /// Number of integration points.
    fn num_points(&self) -> usize;
    /// Number of state values this element keeps (all points together).
    fn state_len(&self) -> usize {
        0
    }
    /// Write the initial state (before any increment) into `state`.
    fn init_state(&self, _state: &mut [f64]) {}
    /// Compute the internal force `f_int` (len = ndof) and, if asked, the
    /// tangent `k` (ndof x ndof, row-major), writing the trial state into
    /// `state_trial` (len = `state_len`).
    fn compute(
        &self,
        ctx: &ElementContext<'_>,
        state_trial: &mut [f64],
        f_int: &mut [f64],
        k: Option<&mut [f64]>,
    ) -> Result<(), ElementError>;
    /// The interface law of an element whose law is evaluated in batches
    /// (see [`crate::InterfaceLaw::is_batched`]); `None` otherwise.
    fn batch_law(&self) -> Option<&dyn crate::InterfaceLaw> {
        None
    }
    /// The local jumps `[s1, s2, n]` at the integration points
    /// (interface elements; `out.len() == num_points()`), for batched laws.
    fn jumps_into(
        &self,
        _ctx: &ElementContext<'_>,
        _out: &mut [[f64; 3]],
    ) -> Result<(), ElementError> {
        Ok(())
    }
    /// Check the reference geometry (positive Jacobian everywhere).
    fn check_geometry(&self, coords: &[[f64; 3]]) -> Result<(), ElementError>;
    /// Integration-point output for post-processing (may allocate).
    fn point_outputs(&self, ctx: &ElementContext<'_>) -> Result<Vec<PointOutput>, ElementError>;
    /// The energy the element's laws have dissipated (their
    /// `dissipated_energy` and `viscous_energy` outputs times each point's
    /// reference area, `area` under small strain), from the committed
    /// state. By default from [`Element::point_outputs`]; an element that
    /// can skip the other outputs overrides it (the drivers ask every
    /// increment).
    fn dissipated_energy(&self, ctx: &ElementContext<'_>) -> Result<f64, ElementError> {
        use crate::law::output::{DISSIPATED_ENERGY, VISCOUS_ENERGY};
        let mut total = 0.0;
        for p in self.point_outputs(ctx)? {
            // under nlgeom the reference area: a failed point keeps its
            // energy when its faces move apart
            let area = p
                .get("reference_area")
                .or_else(|| p.get("area"))
                .map_or(0.0, |a| a[0]);
            for name in [DISSIPATED_ENERGY, VISCOUS_ENERGY] {
                if let Some(d) = p.get(name) {
                    total += d[0] * area;
                }
            }
        }
        Ok(total)
    }
    /// The largest value of the law output `name` (a scalar the element's
    /// laws report, such as `viscous_energy` or `damage_rate`) over the
    /// element's points, from the committed state; 0 where no law reports
    /// it or every value is below 0. By default from
    /// [`Element::point_outputs`]; an element that can skip the other
    /// outputs overrides it (the drivers ask every increment).
    fn max_law_output(&self, ctx: &ElementContext<'_>, name: &str) -> Result<f64, ElementError> {
        let mut max = 0.0f64;
        for p in self.point_outputs(ctx)? {
            if let Some(v) = p.get(name) {
                max = max.max(v[0]);
            }
        }
        Ok(max)
    }
    /// A representative Young's modulus of the element's material (solids),
    /// for diagnostics such as the penalty advisor.
    fn reference_modulus(&self) -> Option<f64> {
        None
    }
    /// The element's solid material, if it has one (post-processing reads
    /// its axes, [`crate::Material::axes_at`]).
    fn material(&self) -> Option<&dyn crate::Material> {
        None
    }
    /// Initial stiffness `[d1, d2, d3]` of the element's traction law
    /// (interfaces), for diagnostics.
    fn interface_stiffness(&self) -> Option<[f64; 3]> {
        None
    }
    /// Requests from the element for small increments (e.g. a point being
    /// released); the driver may honour it. Default: none.
    fn wants_small_increments(&self, _state_committed: &[f64]) -> bool {
        false
    }
    /// True when the internal force is `K u` with a constant `K` (linear
    /// elastic solids, no state), plus, under a temperature change, a
    /// thermal force linear in the nodal temperature changes
    /// ([`ElementContext::temperature`]): an incremental driver may then
    /// compute the element's matrix and its thermal force once and reuse them
    /// ([`crate::assembly::Assembler::assemble_cached`]).
    fn is_linear(&self) -> bool {
        false
    }
    /// Young's modulus of the element's material along the unit direction
    /// `n` (solids), for diagnostics such as the cohesive-zone advice.
    fn directional_modulus(&self, _n: [f64; 3]) -> Option<f64> {
        None
    }
    /// Fracture properties of the element's law (softening interfaces).
    fn fracture_properties(&self) -> Option<crate::law::FractureProperties> {
        None
    }
    /// The fatigue growth law of the element's law, `(G_c, da/dN)` at the
    /// cycle's maximum energy release rate `g_max`, mode ratio and load
    /// ratio ([`crate::InterfaceLaw::fatigue_growth_rate`]).
    fn fatigue_growth_rate(
        &self,
        _g_max: f64,
        _mode_ratio: f64,
        _load_ratio: f64,
    ) -> Option<(f64, f64)> {
        None
    }
    /// The role of the element's law's penalty (interfaces; see
    /// [`crate::law::InterfaceLaw::penalty_role`]). Default: none (solids).
    fn penalty_role(&self) -> Option<crate::law::PenaltyRole> {
        None
    }
    /// Warnings about the element's law or material parameters.
    fn warnings(&self) -> Vec<String> {
        Vec::new()
    }
    /// True for an interface element whose law has a contact switch
    /// ([`crate::law::InterfaceLaw::contact_closed`]). Default: false.
    fn has_contact_switch(&self) -> bool {
        false
    }
    /// For an element with a contact switch ([`Element::has_contact_switch`]):
    /// whether each integration point is closed at `ctx` (committed state),
    /// into `out` (`out.len() == num_points()`). Default: nothing written.
    fn contact_closed_into(
        &self,
        _ctx: &ElementContext<'_>,
        _out: &mut [bool],
    ) -> Result<(), ElementError> {
        Ok(())
    }
    /// Kind of the tangent this element can produce (its law's or
    /// material's); see [`crate::solver::MatrixKind`].
    fn tangent_kind(&self) -> crate::solver::MatrixKind {
        crate::solver::MatrixKind::SymmetricPositiveDefinite
    }
    /// True when the element stores the symmetric part of a tangent that
    /// is not symmetric everywhere (a mixed-mode softening law of a
    /// symmetric kind), and assembles the exact one in full when
    /// [`StepInfo::exact_tangent`] asks. Default: false.
    fn symmetrises_tangent(&self) -> bool {
        false
    }
    /// The largest scaled skew `max |k_ij - k_ji| / sqrt(|k_ii k_jj|)` of
    /// the element tangents this element stored as their symmetric part
    /// since the last call (an interface under finite kinematics), which
    /// the call resets; 0 for an element that stores its tangent as it is.
    /// Default: 0.
    fn take_symmetrised_skew(&self) -> f64 {
        0.0
    }
    /// Whether the element's material expands with temperature (solids;
    /// [`crate::Material::has_thermal_expansion`]). Default: false.
    fn has_thermal_expansion(&self) -> bool {
        false
    }
    /// The element's kinematics. Default: small.
    fn kinematics(&self) -> Kinematics {
        Kinematics::Small
    }
}
