//! Typed errors of the core crate.

use thiserror::Error;

/// Errors raised while building or checking a model.
#[derive(Debug, Error)]
pub enum CoreError {
    /// A named node, element or face set does not exist.
    #[error("unknown {kind} set `{name}`; defined {kind} sets: {valid}")]
    UnknownSet {
        /// Kind of set: `"node"`, `"element"` or `"face"`.
        kind: &'static str,
        /// The name asked for.
        name: String,
        /// Comma-separated names of the sets of that kind the mesh defines.
        valid: String,
    },
    /// A registry lookup found no entry with that key.
    #[error("unknown {kind} `{key}`; valid {kind} keys: {valid}")]
    UnknownKey {
        /// Kind of plugin ([`crate::registry::Entry::KIND`]: `"element"`,
        /// `"material"`, `"law"`, `"criterion"`, `"ply criterion"`, `"solver"`).
        kind: &'static str,
        /// The key asked for.
        key: String,
        /// Comma-separated keys registered for that kind.
        valid: String,
    },
    /// A plugin's parameter table is invalid.
    #[error("invalid parameters for {kind} `{key}`: {message}")]
    InvalidParameters {
        /// Kind of plugin (`"element"`, `"material"`, `"law"`, ...).
        kind: &'static str,
        /// Registry key of the plugin whose table was rejected.
        key: String,
        /// What is wrong: the deserializer's message (unknown or missing
        /// key, wrong type) or the plugin's own check (a value out of range).
        message: String,
    },
    /// Connectivity refers to a node that does not exist.
    #[error("element {element} of block `{block}` refers to node {node}, but the mesh has {num_nodes} nodes")]
    BadConnectivity {
        /// Name of the element block.
        block: String,
        /// Index of the element within the block (0-based).
        element: usize,
        /// The out-of-range node index (0-based).
        node: usize,
        /// Number of nodes in the mesh.
        num_nodes: usize,
    },
    /// An element's geometry is invalid (inverted, degenerate).
    #[error("element {element} of block `{block}`: {source}")]
    Element {
        /// Name of the element block.
        block: String,
        /// Index of the element within the block (0-based).
        element: usize,
        /// What the element kernel reported.
        #[source]
        source: crate::element::ElementError,
    },
    /// Two boundary conditions prescribe different values on one dof.
    #[error("conflicting boundary conditions on node {node} component {component}: {a} and {b}")]
    ConflictingBc {
        /// Node index (0-based).
        node: usize,
        /// Displacement component (0 = x, 1 = y, 2 = z).
        component: usize,
        /// Value prescribed first.
        a: f64,
        /// The different value prescribed later.
        b: f64,
    },
    /// A part of the model is held by no support (its rigid-body modes
    /// are free; [`crate::connectivity`]): the blocks, elements and modes.
    #[error("{0}")]
    Unsupported(String),
    /// Any other inconsistency in a model.
    #[error("{0}")]
    Invalid(String),
}
