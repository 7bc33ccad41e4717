//! The [`InterfaceLaw`] trait: traction-separation laws in the local frame
//! `[s1, s2, n]` (two slips, then the opening; positive opening separates).
//! Laws never see geometry.

use crate::step::StepInfo;
use thiserror::Error;

/// Errors raised by a law.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum LawError {
    /// The law cannot evaluate this jump.
    #[error("{0}")]
    Failed(String),
}

/// What a law reads at one integration point.
#[derive(Debug, Clone, Copy)]
pub struct LawContext<'a> {
    /// Displacement jump in the local frame `[delta_1, delta_2, delta_3]`.
    pub jump: [f64; 3],
    /// Committed state of this point (len = `state_len`).
    pub state_committed: &'a [f64],
    /// Increment information.
    pub step: StepInfo,
}

/// What a law returns at one integration point.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LawResponse {
    /// Traction `[tau_13, tau_23, sigma_33]`.
    pub traction: [f64; 3],
    /// Consistent tangent `d traction / d jump` (row-major 3x3).
    pub tangent: [[f64; 3]; 3],
}

/// Names of the per-point outputs shared by laws (the VTU writers, the
/// summary and the curve read values by these names).
pub mod output {
    /// Damage variable in `[0, 1]` (the fraction of the undamaged
    /// stiffness lost; the released fraction for `paper_debond`).
    pub const DAMAGE: &str = "damage";
    /// Fracture energy dissipated per unit area.
    pub const DISSIPATED_ENERGY: &str = "dissipated_energy";
    /// Energy dissipated per unit area by viscous regularisation (on top
    /// of the fracture energy).
    pub const VISCOUS_ENERGY: &str = "viscous_energy";
    /// Mode ratio `B = G_II / (G_I + G_II)` of the last opening evaluation.
    pub const MODE_RATIO: &str = "mode_ratio";
    /// Plastic (irreversible) slip, first and second local slip direction.
    pub const PLASTIC_SLIP_1: &str = "plastic_slip_1";
    /// See [`PLASTIC_SLIP_1`].
    pub const PLASTIC_SLIP_2: &str = "plastic_slip_2";
    /// Plastic opening (dilatancy, tension cut-off).
    pub const PLASTIC_OPENING: &str = "plastic_opening";
    /// Accumulated plastic slip `int |d slip_p|`.
    pub const ACCUMULATED_SLIP: &str = "accumulated_slip";
    /// Contact state of a frictional or plastic point as a number:
    /// [`STICK`] (elastic), [`SLIP`] (plastic / sliding), [`OPEN`].
    pub const SLIP_STATE: &str = "slip_state";
    /// Value of [`SLIP_STATE`]: closed and elastic (sticking).
    pub const STICK: f64 = 0.0;
    /// Value of [`SLIP_STATE`]: on the yield surface (sliding).
    pub const SLIP: f64 = 1.0;
    /// Value of [`SLIP_STATE`]: open (no contact).
    pub const OPEN: f64 = 2.0;
    /// Energy dissipated per unit area by friction or interface plasticity
    /// (`int t . d jump_p`, never negative).
    pub const FRICTIONAL_DISSIPATION: &str = "frictional_dissipation";
    /// Fatigue laws: the part of the energy damage `D` (fraction of the
    /// toughness dissipated) grown by fatigue cycles.
    pub const FATIGUE_DAMAGE: &str = "fatigue_damage";
    /// Fatigue laws: the energy damage `D` of the point, the fraction of
    /// its toughness a monotone path to its damage dissipates (0 to 1).
    pub const ENERGY_DAMAGE: &str = "energy_damage";
    /// Fatigue laws: the energy release rate `G_max` the law's Paris rate
    /// used at the last evaluation (energy/area).
    pub const ENERGY_RELEASE_RATE: &str = "energy_release_rate";
    /// Fatigue laws: the energy-damage rate `dD/dN` per cycle of the last
    /// evaluation (0 outside the process zone or under the threshold).
    pub const DAMAGE_RATE: &str = "damage_rate";
}

/// Where an interface point stands on its way to a crack: the one
/// definition of a failed point and of the process zone that every output
/// and stop criterion reads ([`InterfaceLaw::stage`]).
///
/// - `Failed`: the point has dissipated its fracture energy for its mode
///   mix, or carries no traction (contact aside). For the bilinear-type
///   laws that is the same thing: the equivalent opening has reached the
///   final opening `lam_f` of its mode mix. Each law's doc says how it
///   decides (a law whose traction never reaches zero states the energy
///   fraction it uses).
/// - `ProcessZone`: damage has started and the point has not failed (it
///   still carries traction and has energy left to dissipate).
/// - `Intact`: no damage yet, or a law without fracture.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum PointStage {
    /// No damage (or a law that never fractures).
    Intact,
    /// Damage started, fracture energy not yet dissipated.
    ProcessZone,
    /// Fracture energy dissipated: a crack.
    Failed,
}

impl PointStage {
    /// The point output value: 0 intact, 1 process zone, 2 failed (the
    /// `stage` of a point's results).
    pub fn code(self) -> f64 {
        match self {
            PointStage::Intact => 0.0,
            PointStage::ProcessZone => 1.0,
            PointStage::Failed => 2.0,
        }
    }

    /// The stage of an output value written by [`PointStage::code`]
    /// (nearest code; anything above 1.5 is failed).
    pub fn of_code(code: f64) -> PointStage {
        if code > 1.5 {
            PointStage::Failed
        } else if code > 0.5 {
            PointStage::ProcessZone
        } else {
            PointStage::Intact
        }
    }

    /// The stage a damage variable `d` alone gives, for laws whose
    /// traction is `(1 - d)` times the undamaged one (no energy left once
    /// it is traction-free): failed at `d >= 1 - 1e-12` (1 to round-off,
    /// as the built-in laws take it), process zone for `0 < d` below.
    pub fn of_damage(d: f64) -> PointStage {
        if d >= 1.0 - 1e-12 {
            PointStage::Failed
        } else if d > 0.0 {
            PointStage::ProcessZone
        } else {
            PointStage::Intact
        }
    }
}

/// Fracture properties of a softening law, for diagnostics (mesh advice,
/// consistency warnings).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FractureProperties {
    /// Normal strength N.
    pub strength_normal: f64,
    /// Shear strength S.
    pub strength_shear: f64,
    /// Mode I toughness G_Ic (energy per unit area).
    pub toughness_mode_i: f64,
    /// Mode II toughness G_IIc.
    pub toughness_mode_ii: f64,
    /// Undamaged penalties `[K_1, K_2, K_n]`.
    pub penalty: [f64; 3],
}

/// What a law's penalty stiffness is, for the penalty advisor
/// ([`InterfaceLaw::penalty_role`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PenaltyRole {
    /// The penalty enforces a constraint (bonded faces that must not
    /// separate or slide, contact that must not interpenetrate, sticking
    /// friction): ideally infinite, any finite value is an error. The
    /// paper's error analysis (eqs. 41-55) applies: the advisor balances
    /// the constraint error against round-off and recommends `d_op`.
    Constraint,
    /// The penalty is the initial stiffness of a cohesive (fracture) law,
    /// part of the model: it adds compliance to the bodies it joins and
    /// sets the opening at damage onset. The advisor compares its
    /// compliance with the solids' (Turon et al. 2007's `K >= 50 E_33 / t`)
    /// and warns of ill-conditioning when it is far above that bound; it
    /// never recommends the constraint optimum.
    Cohesive,
}

impl PenaltyRole {
    /// Name for summaries (`"constraint"`, `"cohesive"`).
    pub fn name(self) -> &'static str {
        match self {
            PenaltyRole::Constraint => "constraint",
            PenaltyRole::Cohesive => "cohesive",
        }
    }
}

/// A traction-separation law.
pub trait InterfaceLaw: Send + Sync + std::fmt::Debug {
    /// Registry key (`"linear_penalty"`, ...).
    fn key(&self) -> &'static str;
    /// Number of state values per integration point.
    fn state_len(&self) -> usize {
        0
    }
    /// Initial state of one point.
    fn init_state(&self, _state: &mut [f64]) {}
    /// Initial states of many points, `state_len()` values each. The
    /// default calls [`InterfaceLaw::init_state`] point by point; a law that
    /// is costly per call (one written in Python) sets them all at once.
    fn init_states(&self, states: &mut [f64]) {
        let k = self.state_len();
        if k > 0 {
            for chunk in states.chunks_mut(k) {
                self.init_state(chunk);
            }
        }
    }
    /// Traction and tangent for the given jump; trial state into `state_trial`.
    fn evaluate(
        &self,
        ctx: &LawContext<'_>,
        state_trial: &mut [f64],
    ) -> Result<LawResponse, LawError>;
    /// Initial (undamaged) stiffness `[d1, d2, d3]`, for diagnostics.
    fn initial_stiffness(&self) -> [f64; 3];
    /// True when the committed state asks for small increments.
    fn wants_small_increments(&self, _state_committed: &[f64]) -> bool {
        false
    }
    /// The point's [`PointStage`] from its state: the one definition of a
    /// failed point and of the process zone (failed points, damaged area,
    /// crack length and front, process zone, `stop_when_separated`).
    /// Laws without fracture keep the default, `Intact`.
    fn stage(&self, _state: &[f64]) -> PointStage {
        PointStage::Intact
    }
    /// True when the point has failed: [`InterfaceLaw::stage`] is
    /// `Failed`. Implement `stage`, not this.
    fn is_failed(&self, state: &[f64]) -> bool {
        self.stage(state) == PointStage::Failed
    }
    /// The last failure index stored in the state, if the law keeps one.
    fn failure_index(&self, _state: &[f64]) -> Option<f64> {
        None
    }
    /// Kind of the tangent this law can produce: SPD for laws that never
    /// soften, symmetric indefinite for softening laws, general for
    /// nonsymmetric tangents. The model's matrix kind is the largest over
    /// its elements; the driver picks the linear back end from it.
    fn tangent_kind(&self) -> crate::solver::MatrixKind {
        crate::solver::MatrixKind::SymmetricPositiveDefinite
    }
    /// True when the law's tangent can be nonsymmetric although its
    /// [`InterfaceLaw::tangent_kind`] is symmetric (the element then
    /// stores its symmetric part, and a driver may switch to the exact
    /// tangent: [`crate::step::StepInfo::exact_tangent`]). Default: false.
    fn tangent_is_symmetrised(&self) -> bool {
        false
    }
    /// Names of the scalar per-point outputs this law reports (see
    /// [`output`] for the shared names). Default: none.
    fn output_names(&self) -> &'static [&'static str] {
        &[]
    }
    /// Values of [`InterfaceLaw::output_names`] from a point's state
    /// (`out.len() == output_names().len()`).
    fn outputs(&self, _state: &[f64], _out: &mut [f64]) {}
    /// Fracture properties, for softening laws.
    fn fracture_properties(&self) -> Option<FractureProperties> {
        None
    }
    /// For a fatigue law: the crack growth rate per cycle it is built to
    /// reproduce when the cycle's maximum energy release rate is `g_max`
    /// at mode ratio `mode_ratio` (`G_II / G`) and load ratio `load_ratio`,
    /// as `(G_c, da/dN)` with `G_c` the toughness at that mode (e.g. a
    /// Paris law `da/dN = C ((1 - R^2) G_max / G_c)^m`). Drawn as the law's
    /// line on the chart of a fatigue run. `None` (the default): the law
    /// has no fatigue growth law.
    fn fatigue_growth_rate(
        &self,
        _g_max: f64,
        _mode_ratio: f64,
        _load_ratio: f64,
    ) -> Option<(f64, f64)> {
        None
    }
    /// What the law's penalty is: a constraint penalty, judged by the
    /// paper's error analysis, or a cohesive law's stiffness, judged
    /// against the solids' compliance (see [`PenaltyRole`]). Default:
    /// [`PenaltyRole::Cohesive`] for a law that gives
    /// [`InterfaceLaw::fracture_properties`] (it has a fracture energy),
    /// else [`PenaltyRole::Constraint`]. A law whose stiffness is physical
    /// without a fracture energy (an adhesive layer of known modulus)
    /// should say `Cohesive`.
    fn penalty_role(&self) -> PenaltyRole {
        if self.fracture_properties().is_some() {
            PenaltyRole::Cohesive
        } else {
            PenaltyRole::Constraint
        }
    }
    /// Warnings about the parameters (shown by `junta check` and in run
    /// summaries), e.g. strengths inconsistent with the penalties.
    fn warnings(&self) -> Vec<String> {
        Vec::new()
    }
    /// True for a law with a unilateral contact switch: its normal
    /// response changes branch where the faces touch (e.g. `contact`).
    /// The Newton driver counts the points whose status
    /// ([`InterfaceLaw::contact_closed`]) changes from one iteration to the
    /// next: such *contact iterations* do not count against the iteration
    /// limit (see the `newton` module of the solvers). Default: false.
    fn has_contact_switch(&self) -> bool {
        false
    }
    /// For a law with a contact switch ([`InterfaceLaw::has_contact_switch`]):
    /// whether the point is closed at the local `jump` with the committed
    /// `state`. Default: false (never called for a law without a switch).
    fn contact_closed(&self, _jump: [f64; 3], _state: &[f64]) -> bool {
        false
    }
    /// True for a law evaluated for all the points of an interface block
    /// at once ([`InterfaceLaw::evaluate_batch`]), such as a law written in
    /// Python: the assembler then calls `evaluate_batch` once per block and
    /// assembly instead of `evaluate` once per point. Default: false.
    fn is_batched(&self) -> bool {
        false
    }
    /// A hint before the output pass asks [`InterfaceLaw::stage`],
    /// [`InterfaceLaw::outputs`] and [`InterfaceLaw::failure_index`] of
    /// many points: their committed states, `state_len()` values each (all
    /// the points of an interface block). A batched law that is costly per
    /// call (one written in Python) evaluates those queries for all the
    /// points at once here and answers the per-point calls that follow from
    /// what it kept; the answers must be the same as without the hint. The
    /// default ignores it. Called for batched laws only
    /// ([`InterfaceLaw::is_batched`]).
    fn prefetch_outputs(&self, _committed: &[f64]) {}
    /// Evaluate `jumps.len()` points at once: point `i` has the jump
    /// `jumps[i]` and the committed state `committed[i*k..(i+1)*k]`
    /// (`k = state_len()`); its trial state goes to the same range of
    /// `trial` and its response to `out[i]`. The default calls
    /// [`InterfaceLaw::evaluate`] point by point. An error names the point
    /// (`LawError::Failed("point 12: ...")`).
    fn evaluate_batch(
        &self,
        jumps: &[[f64; 3]],
        committed: &[f64],
        step: StepInfo,
        trial: &mut [f64],
        out: &mut [LawResponse],
    ) -> Result<(), LawError> {
        let k = self.state_len();
        for (i, (jump, r)) in jumps.iter().zip(out.iter_mut()).enumerate() {
            let ctx = LawContext {
                jump: *jump,
                state_committed: &committed[i * k..(i + 1) * k],
                step,
            };
            *r = self.evaluate(&ctx, &mut trial[i * k..(i + 1) * k])?;
        }
        Ok(())
    }
}
