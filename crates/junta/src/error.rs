//! The run API's error type.
//!
//! Every error a user can cause names the file, the key or line, and what
//! would be valid (`Error::Input`); the errors of the lower crates keep
//! their own type inside. [`Error::Context`] adds what was being done when
//! an error happened ("solving dcb.toml") in front of it: `{:#}` through
//! `anyhow`, or [`Error::chain`], prints `context: cause: cause`.
//!
//! Inside the crate, `bail!` and `err!` make an [`Error::Input`] from a
//! format string, and [`Context`] adds context to a `Result` or an `Option`
//! (the shape `anyhow` users know).

use std::fmt::Display;

/// An error of the run API. The lower crates' errors are boxed so that a
/// `Result<T, Error>` stays two words larger than `T`.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The input (scene, deck, mesh, override, output directory) is not
    /// valid: the message names the file and the key or line.
    #[error("{0}")]
    Input(String),
    /// The incremental driver failed (a numerical failure with its numbers).
    #[error(transparent)]
    Nonlinear(Box<junta_solvers::newton::NonlinearError>),
    /// A linear analysis failed.
    #[error(transparent)]
    Analysis(Box<junta_solvers::linear_static::AnalysisError>),
    /// The model could not be built or evaluated.
    #[error(transparent)]
    Core(Box<junta_core::CoreError>),
    /// A linear solver failed.
    #[error(transparent)]
    Solver(Box<junta_core::solver::SolverError>),
    /// An element kernel failed.
    #[error(transparent)]
    Element(Box<junta_core::element::ElementError>),
    /// A deck could not be read.
    #[error(transparent)]
    Deck(Box<crate::input::inp::InpError>),
    /// A Gmsh mesh could not be read.
    #[error(transparent)]
    Gmsh(Box<crate::input::gmsh::GmshError>),
    /// A file could not be read or written.
    #[error(transparent)]
    Io(Box<std::io::Error>),
    /// JSON could not be read or written.
    #[error(transparent)]
    Json(Box<serde_json::Error>),
    /// TOML could not be parsed.
    #[error(transparent)]
    Toml(Box<toml::de::Error>),
    /// A chart could not be drawn.
    #[error("{0}")]
    Chart(String),
    /// What was being done when `source` happened.
    #[error("{context}")]
    Context {
        /// What was being done ("solving dcb.toml").
        context: String,
        /// The error that happened.
        #[source]
        source: Box<Error>,
    },
}

/// `From` for a lower crate's error, boxed (keeps `Result<T, Error>` small).
macro_rules! boxed_from {
    ($variant:ident, $t:ty) => {
        impl From<$t> for Error {
            fn from(e: $t) -> Self {
                Error::$variant(Box::new(e))
            }
        }
    };
}

boxed_from!(Nonlinear, junta_solvers::newton::NonlinearError);
boxed_from!(Analysis, junta_solvers::linear_static::AnalysisError);
boxed_from!(Core, junta_core::CoreError);
boxed_from!(Solver, junta_core::solver::SolverError);
boxed_from!(Element, junta_core::element::ElementError);
boxed_from!(Deck, crate::input::inp::InpError);
boxed_from!(Gmsh, crate::input::gmsh::GmshError);
boxed_from!(Toml, toml::de::Error);
boxed_from!(Json, serde_json::Error);
boxed_from!(Io, std::io::Error);

impl From<toml::ser::Error> for Error {
    fn from(e: toml::ser::Error) -> Self {
        Error::Input(e.to_string())
    }
}

impl From<std::fmt::Error> for Error {
    fn from(e: std::fmt::Error) -> Self {
        Error::Input(e.to_string())
    }
}

/// Shorthand for `Result<T, junta::Error>`.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// This error with `context` in front of it.
    pub fn context(self, context: impl Display) -> Error {
        Error::Context {
            context: context.to_string(),
            source: Box::new(self),
        }
    }

    /// The whole message: this error and its causes joined by `: ` (what
    /// the command line prints after `error: `).
    pub fn chain(&self) -> String {
        let mut s = self.to_string();
        let mut cause = std::error::Error::source(self);
        while let Some(c) = cause {
            s.push_str(": ");
            s.push_str(&c.to_string());
            cause = c.source();
        }
        s
    }

    /// True when the cause is the user's input (file, key or line).
    pub fn is_input(&self) -> bool {
        match self {
            Error::Context { source, .. } => source.is_input(),
            Error::Input(_) | Error::Deck(_) | Error::Gmsh(_) | Error::Toml(_) => true,
            _ => false,
        }
    }
}

/// Add context to a `Result` or an `Option`, as `anyhow::Context` does.
pub trait Context<T> {
    /// Wrap the error with `context`.
    fn context<C: Display>(self, context: C) -> Result<T>;
    /// Wrap the error with the context `f` makes (only on error).
    fn with_context<C: Display, F: FnOnce() -> C>(self, f: F) -> Result<T>;
}

impl<T, E: Into<Error>> Context<T> for std::result::Result<T, E> {
    fn context<C: Display>(self, context: C) -> Result<T> {
        self.map_err(|e| e.into().context(context))
    }
    fn with_context<C: Display, F: FnOnce() -> C>(self, f: F) -> Result<T> {
        self.map_err(|e| e.into().context(f()))
    }
}

impl<T> Context<T> for Option<T> {
    fn context<C: Display>(self, context: C) -> Result<T> {
        self.ok_or_else(|| Error::Input(context.to_string()))
    }
    fn with_context<C: Display, F: FnOnce() -> C>(self, f: F) -> Result<T> {
        self.ok_or_else(|| Error::Input(f().to_string()))
    }
}

/// An [`Error::Input`] from a format string.
macro_rules! err {
    ($($t:tt)*) => { $crate::error::Error::Input(format!($($t)*)) };
}

/// Return an [`Error::Input`] from a format string.
macro_rules! bail {
    ($($t:tt)*) => { return Err($crate::error::err!($($t)*)) };
}

pub(crate) use {bail, err};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chain_joins_context_and_causes_as_the_cli_prints_them() {
        let e: Result<()> = Err(err!("bad key `x`"));
        let e = e
            .context("reading a.toml")
            .unwrap_err()
            .context("solving a.toml");
        assert_eq!(e.chain(), "solving a.toml: reading a.toml: bad key `x`");
        assert!(e.is_input());
        let io = std::io::Error::new(std::io::ErrorKind::NotFound, "gone");
        assert!(!Error::from(io).context("x").is_input());
    }
}
