//! Typed errors of the core crate.

use thiserror::Error;

/// Errors raised while building or checking a model.
#[derive(Debug, Error)]
pub enum CoreError {
    /// A named node, element or face set does not exist.
    #[error("unknown {kind} set `{name}`; defined {kind} sets: {valid}")]
    UnknownSet {
        kind: &'static str,
        name: String,
        valid: String,
    },
    /// A registry lookup found no entry with that key.
    #[error("unknown {kind} `{key}`; valid {kind} keys: {valid}")]
    UnknownKey {
        kind: &'static str,
        key: String,
        valid: String,
    },
    /// A plugin's parameter table is invalid.
    #[error("invalid parameters for {kind} `{key}`: {message}")]
    InvalidParameters {
        kind: &'static str,
        key: String,
        message: String,
    },
    /// Connectivity refers to a node that does not exist.
    #[error("element {element} of block `{block}` refers to node {node}, but the mesh has {num_nodes} nodes")]
    BadConnectivity {
        block: String,
        element: usize,
        node: usize,
        num_nodes: usize,
    },
    /// An element's geometry is invalid (inverted, degenerate).
    #[error("element {element} of block `{block}`: {source}")]
    Element {
        block: String,
        element: usize,
        #[source]
        source: crate::element::ElementError,
    },
    /// Two boundary conditions prescribe different values on one dof.
    #[error("conflicting boundary conditions on node {node} component {component}: {a} and {b}")]
    ConflictingBc {
        node: usize,
        component: usize,
        a: f64,
        b: f64,
    },
    /// Any other inconsistency in a model.
    #[error("{0}")]
    Invalid(String),
}
