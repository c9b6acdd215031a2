//! `navkf._navkf`: the native module of the `navkf` Python package (python/navkf/ wraps it
//! with Python names, argument checks and type stubs).
//!
//! A thin layer: every function here converts Python values (numpy arrays, dicts, strings)
//! into the library crates' types, calls the same code the `navkf` command runs, and converts
//! the answer back. No physics, filtering or statistics lives here; the Rust crates know
//! nothing of Python. Long calls release the GIL and run on navkf's own threads
//! ([`background`]), so a progress callback runs and Ctrl-C stops them as it stops the
//! command line.

use pyo3::prelude::*;

mod background;
pub mod columns;
mod dataset;
mod diagnose;
mod errors;
mod filter;
mod instruction_set;
mod simulate;
mod study;

#[pymodule]
fn _navkf(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("NavkfError", m.py().get_type::<errors::NavkfError>())?;
    m.add_class::<dataset::Dataset>()?;
    m.add_class::<filter::Filter>()?;
    m.add_function(wrap_pyfunction!(simulate::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(study::study, m)?)?;
    m.add_function(wrap_pyfunction!(study::plan, m)?)?;
    m.add_function(wrap_pyfunction!(diagnose::diagnose, m)?)?;
    m.add_function(wrap_pyfunction!(instruction_set::instruction_set, m)?)?;
    m.add_function(wrap_pyfunction!(instruction_set::ignored_simd_setting, m)?)?;
    m.add_function(wrap_pyfunction!(columns::families, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
