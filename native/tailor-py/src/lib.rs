//! `tailor._tailor`: the thin Python layer over `tailor-core`.
//!
//! Arrays cross as numpy float32/uint32; every solve releases the GIL; every core error becomes
//! one typed Python exception (see [`errors`]). Nothing here holds physics or geometry logic.

mod errors;

use pyo3::prelude::*;

#[pymodule]
fn _tailor(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    errors::register(m)?;
    Ok(())
}
