//! `navkf.instruction_set()`: which compiled copy of the hot kernels this process runs
//! (`navkf_dynamics::instruction_set`), for a user comparing step costs between machines.

use navkf_dynamics::instruction_set::{instruction_set as chosen, InstructionSet};
use pyo3::prelude::*;

/// Which copy of the hot kernels runs: "avx2-fma" (chosen at run time), "baseline" (a CPU
/// without AVX2 and FMA, or NAVKF_SIMD=baseline) or "native" (a build for its own CPU). The
/// first two give the same results to the bit.
#[pyfunction]
pub fn instruction_set() -> &'static str {
    match chosen() {
        InstructionSet::Avx2Fma => "avx2-fma",
        InstructionSet::Baseline => "baseline",
        InstructionSet::CompiledIn => "native",
    }
}

/// The warning for a `NAVKF_SIMD` value the kernels ignore, or `None`
/// (`navkf_dynamics::instruction_set::ignored_setting`); the package warns with it on import,
/// as the command line does on start.
#[pyfunction]
pub fn ignored_simd_setting() -> Option<String> {
    navkf_dynamics::instruction_set::ignored_setting()
}
