//! What one increment of the load program is, as elements and laws see
//! it: [`StepInfo`], and the crack's driving force [`CrackDrive`] that a
//! fatigue increment hands to its laws.
//!
//! This module imports nothing from the rest of the crate: elements
//! ([`crate::element`]), laws ([`crate::law`]) and the crack-drive
//! measurement ([`crate::crack_drive`]) all read these types, and none of
//! them has to import another for them. A driver builds the step of an
//! increment with [`StepInfo::at`] and [`crate::Model::program_step`]:
//!
//! ```
//! use junta_core::StepInfo;
//! // increment 3 takes the load factor from 0.4 to 0.5
//! let s = StepInfo::at(3, 0.5, 0.1);
//! assert_eq!((s.increment, s.secant, s.temperature_factor), (3, false, 1.0));
//! ```

/// The crack's driving force measured on the interface at one converged
/// state (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CrackDrive {
    /// J integral of the cohesive tractions along the line with the
    /// largest one [energy/area].
    pub energy_release_rate: f64,
    /// Mode ratio `G_II / G` of that line: the shear components' part of
    /// the integral over the whole (0 when J is 0).
    pub mode_ratio: f64,
    /// Length of that line's process zone along the direction (0: no
    /// point of it is past onset).
    pub process_zone_length: f64,
}

/// Increment information handed down to elements and laws.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepInfo {
    /// Index of the increment being computed: 1 + the number of converged
    /// increments (1-based; the same on every iteration and cut-back retry).
    pub increment: usize,
    /// Load factor at the end of the current increment.
    pub load_factor: f64,
    /// Size of the current load-factor increment.
    pub delta_load_factor: f64,
    /// Ask for a secant tangent instead of the consistent one. The Newton
    /// driver sets it for the rest of an attempt when an iteration with the
    /// consistent tangent fails to reduce the residual (Newton cycling
    /// between the loading and unloading branches of a softening point).
    /// Laws without a secant form ignore it.
    pub secant: bool,
    /// Assemble the law's exact tangent in full, nonsymmetric where it is,
    /// also for a law that declares a symmetric kind (whose tangent is
    /// otherwise stored as its symmetric part). The drivers set it after
    /// switching to the exact tangent when Newton stagnated on the
    /// symmetric part ([`crate::Element::symmetrises_tangent`]).
    pub exact_tangent: bool,
    /// Temperature factor at the end of the current increment: the
    /// temperature change of every node is this factor times the model's
    /// [`crate::Model::temperature`] (the change from the stress-free
    /// temperature at the end of the thermal program). 1 by default (a
    /// linear analysis applies the whole change); the incremental drivers
    /// set it from the program's temperature steps.
    pub temperature_factor: f64,
    /// Cycle count `N` at the end of the current increment of a fatigue
    /// step (a cycle-jump step holds the load at the envelope maximum of a
    /// constant-amplitude cycle and counts cycles as pseudo-time). 0 outside
    /// fatigue steps.
    pub cycles: f64,
    /// Cycles advanced in the current increment, `dN >= 0`. Fatigue laws
    /// grow their damage by their rate per cycle times `dN`; 0 (the
    /// default, and every non-fatigue step) means the law behaves as its
    /// static counterpart.
    pub delta_cycles: f64,
    /// Load ratio `R = min / max` of the constant-amplitude cycle of a
    /// fatigue step (0 by default). Laws use it through the cyclic energy
    /// release rate (`(1 - R^2) G_max`).
    pub load_ratio: f64,
    /// The crack's energy release rate and process-zone length measured
    /// on the interface at the start of a fatigue increment
    /// ([`crate::Model::crack_drive`]), when the fatigue program asks for
    /// it ([`crate::FatigueProgram::front_direction`]); `None` otherwise.
    /// Fatigue laws use it instead of their point-local estimates.
    pub crack_drive: Option<CrackDrive>,
}

impl Default for StepInfo {
    /// Increment 0, load factor 0, no secant or exact tangent, temperature
    /// factor 1 (the whole temperature change of the model, if it has one),
    /// no cycles (`cycles = delta_cycles = load_ratio = 0`).
    fn default() -> Self {
        StepInfo {
            increment: 0,
            load_factor: 0.0,
            delta_load_factor: 0.0,
            secant: false,
            exact_tangent: false,
            temperature_factor: 1.0,
            cycles: 0.0,
            delta_cycles: 0.0,
            load_ratio: 0.0,
            crack_drive: None,
        }
    }
}

impl StepInfo {
    /// Increment `increment` (1-based), ending at `load_factor` after a
    /// change of `delta_load_factor`; everything else as
    /// [`StepInfo::default`] (no secant or exact tangent, temperature
    /// factor 1, no cycles, no crack drive).
    pub fn at(increment: usize, load_factor: f64, delta_load_factor: f64) -> Self {
        StepInfo {
            increment,
            load_factor,
            delta_load_factor,
            ..StepInfo::default()
        }
    }
}
