//! The one place where core errors become Python exceptions.
//!
//! Hierarchy (all importable from `tailor`):
//!
//! ```text
//! TailorError(Exception)
//! ├── InvalidMeshError(TailorError, ValueError)   empty, out-of-range, degenerate, non-manifold, NaN, not a body
//! ├── InvalidParameterError(TailorError, ValueError)  masses, settings, shape mismatches
//! ├── SeamError(TailorError, ValueError)
//! ├── PatternError(TailorError, ValueError)        a file could not be read or is unsupported
//! ├── TailorIOError(TailorError, OSError)
//! ├── SimulationError(TailorError, RuntimeError)   the solve diverged, or the simulation is busy in another thread
//! ├── CancelledError(TailorError)
//! └── InternalError(TailorError, RuntimeError)    a panic caught at the boundary (a bug)
//! ```
//!
//! Every `#[pyfunction]` and `#[pymethods]` body runs inside [`guard`], so a panic in the core
//! (or here) reaches Python as `InternalError`, an `Exception`, instead of pyo3's
//! `PanicException`, a `BaseException` that `except Exception` does not catch.

use pyo3::exceptions::{PyException, PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::{create_exception, PyErr};
use tailor_core::TailorError as CoreError;

create_exception!(tailor, TailorError, PyException, "Base class of every error Tailor raises.");

/// Declares a subclass of `TailorError` that also derives from a builtin exception
/// (so `except ValueError` still catches a bad mesh). pyo3's `create_exception!` takes one base
/// only, hence `type(name, bases, dict)`, created once per interpreter.
macro_rules! sub_exception {
    ($name:ident, $pyname:literal, $mixin:ty, $doc:literal) => {
        pub struct $name;
        impl $name {
            pub fn type_object(py: Python<'_>) -> PyResult<Bound<'_, pyo3::types::PyType>> {
                static CELL: pyo3::sync::PyOnceLock<Py<pyo3::types::PyType>> = pyo3::sync::PyOnceLock::new();
                let ty = CELL.get_or_try_init(py, || -> PyResult<_> {
                    let dict = pyo3::types::PyDict::new(py);
                    dict.set_item("__doc__", $doc)?;
                    dict.set_item("__module__", "tailor")?;
                    let bases = (py.get_type::<TailorError>(), py.get_type::<$mixin>());
                    let t = py.import("builtins")?.getattr("type")?.call1(($pyname, bases, dict))?;
                    Ok(t.cast_into::<pyo3::types::PyType>()?.unbind())
                })?;
                Ok(ty.bind(py).clone())
            }
        }
    };
}

sub_exception!(InvalidMeshError, "InvalidMeshError", PyValueError, "The cloth mesh is invalid: empty, an index out of range, a degenerate or non-manifold triangle, or a non-finite coordinate.");
sub_exception!(
    InvalidParameterError,
    "InvalidParameterError",
    PyValueError,
    "A parameter is invalid: a mass, a setting, or arrays of mismatched shapes."
);
sub_exception!(SeamError, "SeamError", PyValueError, "A seam is invalid.");
sub_exception!(
    PatternError,
    "PatternError",
    PyValueError,
    "A pattern or mesh file could not be read, or uses an unsupported feature."
);
sub_exception!(TailorIOError, "TailorIOError", PyOSError, "Reading or writing a file failed.");
sub_exception!(
    SimulationError,
    "SimulationError",
    PyRuntimeError,
    "The simulation diverged (non-finite values; the state was not advanced), or it is in use by a call in another thread."
);
sub_exception!(CancelledError, "CancelledError", PyException, "The operation was cancelled.");
sub_exception!(
    InternalError,
    "InternalError",
    PyRuntimeError,
    "A bug in Tailor (a Rust panic caught at the boundary); the object it happened in may be unusable."
);

/// Runs the body of a Python entry point, turning a panic into `InternalError`. The default
/// panic hook still prints the message and location on stderr, which is what a bug report needs.
pub fn guard<T>(f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(payload) => Err(to_py(CoreError::Internal { reason: panic_reason(&payload) })),
    }
}

/// A caught panic's message.
pub fn panic_reason(payload: &Box<dyn std::any::Any + Send>) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic without a message".into())
}

/// Converts a core error into the matching Python exception.
pub fn to_py(err: CoreError) -> PyErr {
    Python::attach(|py| {
        let msg = err.to_string();
        let ty = match &err {
            CoreError::EmptyMesh { .. }
            | CoreError::IndexOutOfRange { .. }
            | CoreError::NonFinite { .. }
            | CoreError::DegenerateTriangle { .. }
            | CoreError::NonManifold { .. }
            | CoreError::NotABody { .. } => InvalidMeshError::type_object(py),
            CoreError::InvalidMass { .. } | CoreError::ShapeMismatch { .. } | CoreError::InvalidSetting { .. } => {
                InvalidParameterError::type_object(py)
            }
            CoreError::InvalidSeam { .. } => SeamError::type_object(py),
            CoreError::Parse { .. } | CoreError::Unsupported { .. } => PatternError::type_object(py),
            CoreError::Io { .. } => TailorIOError::type_object(py),
            CoreError::Diverged { .. } | CoreError::Busy { .. } => SimulationError::type_object(py),
            CoreError::Cancelled => CancelledError::type_object(py),
            CoreError::Internal { .. } => InternalError::type_object(py),
        };
        match ty {
            Ok(ty) => PyErr::from_type(ty, msg),
            Err(e) => e,
        }
    })
}

/// Registers the exception classes on the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("TailorError", py.get_type::<TailorError>())?;
    m.add("InvalidMeshError", InvalidMeshError::type_object(py)?)?;
    m.add("InvalidParameterError", InvalidParameterError::type_object(py)?)?;
    m.add("SeamError", SeamError::type_object(py)?)?;
    m.add("PatternError", PatternError::type_object(py)?)?;
    m.add("TailorIOError", TailorIOError::type_object(py)?)?;
    m.add("SimulationError", SimulationError::type_object(py)?)?;
    m.add("CancelledError", CancelledError::type_object(py)?)?;
    m.add("InternalError", InternalError::type_object(py)?)?;
    Ok(())
}
