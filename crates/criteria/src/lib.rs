//! # junta-criteria
//!
//! Failure (damage-initiation) criteria behind [`junta_core::FailureCriterion`],
//! one file each, registered with `inventory`. The quadratic stress
//! criterion of the paper (eq. 40) and the maximum-stress criterion arrive
//! with the progressive-debonding work; the crate exists now so that the
//! workspace layout and the plugin linkage are in place.
