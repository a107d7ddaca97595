//! The one error type of the core crate.
//!
//! Every fallible operation returns [`Result<T>`]. Variants name *what* was wrong and *where*
//! (the element index, the file, the entity) so that the Python layer can raise a typed
//! exception with a message an artist can act on. The Python binding maps each variant to one
//! exception class exactly once (see `tailor-py/src/errors.rs`); nothing here panics on bad
//! input.

use thiserror::Error;

/// Errors raised by Tailor's core.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum TailorError {
    /// The mesh has no vertices or no triangles.
    #[error("empty mesh: {what}")]
    EmptyMesh { what: String },

    /// An index (triangle corner, seam vertex, pin) points past the end of an array.
    #[error("{context}: index {index} is out of range (only {len} {items})")]
    IndexOutOfRange { context: String, index: i64, len: usize, items: &'static str },

    /// A coordinate is NaN or infinite.
    #[error("{context}: {what} {index} has a non-finite coordinate ({value})")]
    NonFinite { context: String, what: &'static str, index: usize, value: f32 },

    /// A triangle whose rest (2D pattern) shape has zero or negative area, or repeats a vertex.
    #[error("triangle {triangle} is degenerate: {reason}")]
    DegenerateTriangle { triangle: usize, reason: String },

    /// An edge shared by more than two triangles.
    #[error("non-manifold mesh: edge ({a}, {b}) is shared by {count} triangles (at most 2 allowed)")]
    NonManifold { a: u32, b: u32, count: usize },

    /// A mesh taken for a character's body is not one of a standing humanoid where a part was
    /// looked for (arrangement round the body: legs, arms, neck).
    #[error("not a standing humanoid: {part}: {reason}")]
    NotABody { part: String, reason: String },

    /// A particle mass (or mass scale) is zero, negative or not finite.
    #[error("particle {particle} has invalid mass {mass}: masses must be positive and finite")]
    InvalidMass { particle: usize, mass: f32 },

    /// Array shapes disagree (for example a seam pairing different counts).
    #[error("{context}: {reason}")]
    ShapeMismatch { context: String, reason: String },

    /// A seam is invalid: a path off the contour, a vertex used twice, bad orientation.
    #[error("seam {seam}: {reason}")]
    InvalidSeam { seam: String, reason: String },

    /// A solver or scene setting is out of its valid range.
    #[error("invalid setting {name} = {value}: {reason}")]
    InvalidSetting { name: &'static str, value: String, reason: String },

    /// A pattern or mesh file could not be read or understood.
    #[error("{file}: {entity}: {reason}")]
    Parse { file: String, entity: String, reason: String },

    /// The file uses a feature Tailor does not support.
    #[error("{file}: {entity}: unsupported: {reason}")]
    Unsupported { file: String, entity: String, reason: String },

    /// Reading or writing a file failed at the operating-system level.
    #[error("{path}: {reason}")]
    Io { path: String, reason: String },

    /// The simulation produced non-finite values (it blew up); the state was not advanced.
    #[error("simulation diverged: {reason}")]
    Diverged { reason: String },

    /// The operation was cancelled by the caller.
    #[error("cancelled")]
    Cancelled,

    /// An object is in use by a call in another thread (a `Simulation` stepping with the GIL
    /// released); the caller may retry once that call has returned.
    #[error("busy: {what}")]
    Busy { what: String },

    /// A bug in Tailor: a panic caught at the Python boundary (`tailor-py`'s `guard`) instead
    /// of crossing it. Never returned by the core itself; it lives here so that the one
    /// mapping to Python covers it too.
    #[error("internal error (a bug in Tailor, please report it): {reason}")]
    Internal { reason: String },
}

/// Result alias used throughout the core crate.
pub type Result<T, E = TailorError> = std::result::Result<T, E>;

impl TailorError {
    /// Shorthand for [`TailorError::IndexOutOfRange`].
    pub fn index(context: impl Into<String>, index: i64, len: usize, items: &'static str) -> Self {
        TailorError::IndexOutOfRange { context: context.into(), index, len, items }
    }

    /// Shorthand for [`TailorError::ShapeMismatch`].
    pub fn shape(context: impl Into<String>, reason: impl Into<String>) -> Self {
        TailorError::ShapeMismatch { context: context.into(), reason: reason.into() }
    }

    /// Shorthand for [`TailorError::InvalidSetting`].
    pub fn setting(name: &'static str, value: impl ToString, reason: impl Into<String>) -> Self {
        TailorError::InvalidSetting { name, value: value.to_string(), reason: reason.into() }
    }

    /// Shorthand for [`TailorError::NotABody`].
    pub fn not_a_body(part: impl Into<String>, reason: impl Into<String>) -> Self {
        TailorError::NotABody { part: part.into(), reason: reason.into() }
    }

    /// Shorthand for [`TailorError::Parse`].
    pub fn parse(file: impl Into<String>, entity: impl Into<String>, reason: impl Into<String>) -> Self {
        TailorError::Parse { file: file.into(), entity: entity.into(), reason: reason.into() }
    }

    /// Shorthand for [`TailorError::Io`] from a `std::io::Error`.
    pub fn io(path: impl Into<String>, err: std::io::Error) -> Self {
        TailorError::Io { path: path.into(), reason: err.to_string() }
    }
}
