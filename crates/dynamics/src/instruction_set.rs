//! The hot kernels compiled twice, the copy chosen when the process starts: what lets one
//! binary (a wheel, a CLI built without `target-cpu=native`) run on any x86-64 and still use
//! 256-bit vectors and fused multiply-adds where the CPU has them.
//!
//! A build for plain x86-64 may only use SSE2: two `f64` per vector and no FMA instruction,
//! so [`f64::mul_add`] becomes a call into libm. On the UKF's step that costs about 40 %
//! (`benches/compare_builds.sh`, `docs/speed.md`). [`crate::dispatch!`] runs a kernel in a function compiled with
//! AVX2 and FMA enabled when the CPU reports both, and in the plain one otherwise. The
//! kernel's body is `#[inline(always)]` into both, so everything it inlines is compiled
//! twice; what it calls without inlining runs the plain copy.
//!
//! **Both copies give the same bits.** They are the same source with the same operations:
//! Rust never fuses `a * b + c` on its own, a fused multiply-add written as such is exact
//! whether an instruction or libm computes it, and the vector width changes no rounding (every
//! lane does its own arithmetic). A portable binary therefore gives the same results whichever
//! copy runs. (What it calls in libm, `sin_cos` of a reference latitude among them, is the
//! system's: glibc picks its own FMA or plain variant by CPU, which may differ in a rare last
//! bit.) `NAVKF_SIMD=baseline` forces the plain copies, to check that (a test does) or to
//! compare speeds.
//!
//! A build that already targets AVX2 and FMA (`target-cpu=native` on such a CPU) compiles
//! one copy and checks nothing.
//!
//! ```
//! use navkf_dynamics::instruction_set::instruction_set;
//! let sum = navkf_dynamics::dispatch!((1..=4).map(|k| k as f64).sum::<f64>());
//! assert_eq!(sum, 10.0);
//! println!("kernels run as {}", instruction_set());
//! ```

use std::fmt;

/// Which copy of the hot kernels this process runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InstructionSet {
    /// The binary's own target (SSE2 only on plain x86-64).
    Baseline,
    /// The copies compiled with AVX2 and FMA, chosen at run time.
    Avx2Fma,
    /// The binary itself targets AVX2 and FMA: there is one copy.
    CompiledIn,
}

impl fmt::Display for InstructionSet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            InstructionSet::Baseline => "the build's baseline target, without AVX2 and FMA",
            InstructionSet::Avx2Fma => "AVX2 + FMA, chosen at run time",
            InstructionSet::CompiledIn => "the build's own target (AVX2 + FMA compiled in)",
        })
    }
}

/// The environment variable that forces [`InstructionSet::Baseline`] when set to `baseline`.
pub const FORCE_VARIABLE: &str = "NAVKF_SIMD";

/// Values of [`FORCE_VARIABLE`] that mean something: `baseline` forces the plain copies; an
/// empty value (the variable set to nothing) leaves the choice to the CPU.
const FORCE_VALUES: [&str; 2] = ["baseline", ""];

/// A warning when [`FORCE_VARIABLE`] is set to a value it ignores (`NAVKF_SIMD=plain` would
/// otherwise run the AVX2 copies without a word); `None` when it is unset or understood.
pub fn ignored_setting() -> Option<String> {
    let value = std::env::var_os(FORCE_VARIABLE)?;
    let text = value.to_string_lossy();
    (!FORCE_VALUES.contains(&text.as_ref())).then(|| {
        format!(
            "{FORCE_VARIABLE}={text:?} is ignored: expected \"baseline\" (the plain copies of \
             the kernels) or nothing; running: {}",
            instruction_set()
        )
    })
}

/// Whether this build has the second copies at all.
const TWO_COPIES: bool = cfg!(all(
    target_arch = "x86_64",
    not(all(target_feature = "avx2", target_feature = "fma"))
));

/// The copy this process runs (decided once, on first use).
pub fn instruction_set() -> InstructionSet {
    if !TWO_COPIES {
        return if cfg!(target_arch = "x86_64") {
            InstructionSet::CompiledIn
        } else {
            InstructionSet::Baseline
        };
    }
    if avx2_fma() {
        InstructionSet::Avx2Fma
    } else {
        InstructionSet::Baseline
    }
}

#[cfg(all(
    target_arch = "x86_64",
    not(all(target_feature = "avx2", target_feature = "fma"))
))]
mod copies {
    use std::sync::atomic::{AtomicU8, Ordering};

    /// 0: not yet decided; 1: baseline; 2: AVX2 + FMA.
    static CHOICE: AtomicU8 = AtomicU8::new(0);

    /// Whether the AVX2 + FMA copies run (one relaxed load once decided).
    #[inline(always)]
    pub(super) fn avx2_fma() -> bool {
        match CHOICE.load(Ordering::Relaxed) {
            0 => decide(),
            c => c == 2,
        }
    }

    /// See [`super::force_baseline`].
    pub(super) fn force_baseline(on: bool) {
        CHOICE.store(if on { 1 } else { 0 }, Ordering::Relaxed);
    }

    #[cold]
    fn decide() -> bool {
        let forced = std::env::var(super::FORCE_VARIABLE).is_ok_and(|v| v == "baseline");
        let fast = !forced
            && std::arch::is_x86_feature_detected!("avx2")
            && std::arch::is_x86_feature_detected!("fma");
        CHOICE.store(if fast { 2 } else { 1 }, Ordering::Relaxed);
        fast
    }

    /// `kernel` compiled with AVX2 and FMA.
    ///
    /// # Safety
    /// The CPU must have AVX2 and FMA.
    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn run_avx2_fma<R>(kernel: impl FnOnce() -> R) -> R {
        kernel()
    }
}

#[cfg(all(
    target_arch = "x86_64",
    not(all(target_feature = "avx2", target_feature = "fma"))
))]
use copies::avx2_fma;

#[cfg(not(all(
    target_arch = "x86_64",
    not(all(target_feature = "avx2", target_feature = "fma"))
)))]
fn avx2_fma() -> bool {
    false
}

/// Makes every later kernel of this process run the baseline copy (`on`), or the copy the
/// CPU and [`FORCE_VARIABLE`] choose again (`!on`). Both give the same bits, so a switch in the
/// middle of a run changes its speed only: what the tests comparing the copies rely on.
pub fn force_baseline(on: bool) {
    #[cfg(all(
        target_arch = "x86_64",
        not(all(target_feature = "avx2", target_feature = "fma"))
    ))]
    copies::force_baseline(on);
    let _ = on;
}

/// Evaluates an expression in the copy [`instruction_set`] names: [`dispatch`] with the
/// closure marked `#[inline(always)]`, without which the closure stays one function compiled
/// for the baseline, called from both copies (measured: the UKF's propagation ran no faster).
/// Functions the expression calls must be `#[inline(always)]` too to be compiled twice.
///
/// ```
/// fn norm_squared(v: &[f64]) -> f64 {
///     navkf_dynamics::dispatch!(v.iter().map(|x| x * x).sum::<f64>())
/// }
/// assert_eq!(norm_squared(&[3.0, 4.0]), 25.0);
/// ```
#[macro_export]
macro_rules! dispatch {
    ($kernel:expr) => {
        $crate::instruction_set::dispatch(
            #[inline(always)]
            || $kernel,
        )
    };
}

/// Runs `kernel` in the copy [`instruction_set`] names. Use [`crate::dispatch!`], which
/// marks the closure `#[inline(always)]`.
#[inline(always)]
pub fn dispatch<R>(kernel: impl FnOnce() -> R) -> R {
    #[cfg(all(
        target_arch = "x86_64",
        not(all(target_feature = "avx2", target_feature = "fma"))
    ))]
    if copies::avx2_fma() {
        // SAFETY: `avx2_fma` is true only when the CPU reported AVX2 and FMA.
        return unsafe { copies::run_avx2_fma(kernel) };
    }
    kernel()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_copies_round_alike() {
        // A fused multiply-add and a plain one: whichever copy runs, the same bits as the
        // scalar definitions.
        let (a, b, c) = (0.1f64, 10.0f64, -1.0f64);
        let (fused, plain) = crate::dispatch!((a.mul_add(b, c), a * b + c));
        assert_eq!(fused.to_bits(), 0.1f64.mul_add(10.0, -1.0).to_bits());
        assert_eq!(
            plain.to_bits(),
            (std::hint::black_box(0.1) * 10.0 - 1.0f64).to_bits()
        );
        assert_ne!(
            fused, plain,
            "the test needs a case where fusing changes the result"
        );
        assert!(TWO_COPIES || instruction_set() != InstructionSet::Avx2Fma);
    }
}
