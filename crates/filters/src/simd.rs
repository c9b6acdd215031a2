//! Four `f64` lanes as one value, for the few hand kernels where LLVM's vectoriser picks the
//! wrong loop to vectorise (`triangular.rs` says where, and `benches/linalg.rs` measures it).
//!
//! In a build that targets AVX and FMA (`-C target-cpu=native` on such a CPU) each operation
//! is one 256-bit intrinsic. In the default, portable build it is four lanes of plain
//! arithmetic, which the AVX2 copies of the kernels ([`navkf_dynamics::instruction_set`])
//! compile to 256-bit instructions, with the same rounding: [`F64x4::mul_add`] is fused
//! exactly when [`crate::linalg::fmadd`] is. A kernel written on this type therefore gives the
//! same bits as the scalar loop it replaces, lane by lane.

#[cfg(all(target_arch = "x86_64", target_feature = "avx", target_feature = "fma"))]
mod imp {
    use std::arch::x86_64::*;

    /// See the module documentation.
    #[derive(Clone, Copy)]
    pub struct F64x4(__m256d);

    impl F64x4 {
        #[inline(always)]
        pub fn splat(v: f64) -> Self {
            // SAFETY: AVX and FMA are on for the whole build (this module's cfg).
            F64x4(unsafe { _mm256_set1_pd(v) })
        }
        #[inline(always)]
        pub fn load(a: &[f64; 4]) -> Self {
            // SAFETY: `a` is four readable f64; the load has no alignment requirement.
            F64x4(unsafe { _mm256_loadu_pd(a.as_ptr()) })
        }
        #[inline(always)]
        pub fn store(self, a: &mut [f64; 4]) {
            // SAFETY: `a` is four writable f64; the store has no alignment requirement.
            unsafe { _mm256_storeu_pd(a.as_mut_ptr(), self.0) }
        }
        /// `self * b + c`, one rounding.
        #[inline(always)]
        pub fn mul_add(self, b: Self, c: Self) -> Self {
            // SAFETY: AVX and FMA are on for the whole build (this module's cfg).
            F64x4(unsafe { _mm256_fmadd_pd(self.0, b.0, c.0) })
        }
        #[inline(always)]
        pub fn mul(self, b: Self) -> Self {
            // SAFETY: AVX and FMA are on for the whole build (this module's cfg).
            F64x4(unsafe { _mm256_mul_pd(self.0, b.0) })
        }
        #[inline(always)]
        pub fn add(self, b: Self) -> Self {
            // SAFETY: AVX and FMA are on for the whole build (this module's cfg).
            F64x4(unsafe { _mm256_add_pd(self.0, b.0) })
        }
        #[inline(always)]
        pub fn sub(self, b: Self) -> Self {
            // SAFETY: AVX and FMA are on for the whole build (this module's cfg).
            F64x4(unsafe { _mm256_sub_pd(self.0, b.0) })
        }
    }
}

#[cfg(not(all(target_arch = "x86_64", target_feature = "avx", target_feature = "fma")))]
mod imp {
    use crate::linalg::fmadd;

    /// See the module documentation.
    #[derive(Clone, Copy)]
    pub struct F64x4([f64; 4]);

    impl F64x4 {
        #[inline(always)]
        pub fn splat(v: f64) -> Self {
            F64x4([v; 4])
        }
        #[inline(always)]
        pub fn load(a: &[f64; 4]) -> Self {
            F64x4(*a)
        }
        #[inline(always)]
        pub fn store(self, a: &mut [f64; 4]) {
            *a = self.0;
        }
        /// `self * b + c`, fused when [`fmadd`] is.
        #[inline(always)]
        pub fn mul_add(self, b: Self, c: Self) -> Self {
            F64x4(std::array::from_fn(|l| fmadd(self.0[l], b.0[l], c.0[l])))
        }
        #[inline(always)]
        pub fn mul(self, b: Self) -> Self {
            F64x4(std::array::from_fn(|l| self.0[l] * b.0[l]))
        }
        #[inline(always)]
        pub fn add(self, b: Self) -> Self {
            F64x4(std::array::from_fn(|l| self.0[l] + b.0[l]))
        }
        #[inline(always)]
        pub fn sub(self, b: Self) -> Self {
            F64x4(std::array::from_fn(|l| self.0[l] - b.0[l]))
        }
    }
}

pub(crate) use imp::F64x4;

impl F64x4 {
    /// The four lanes, in order.
    #[inline(always)]
    pub fn to_array(self) -> [f64; 4] {
        let mut a = [0.0; 4];
        self.store(&mut a);
        a
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::fmadd;

    #[test]
    fn lanes_round_as_the_scalar_operations() {
        let a = [1.0 / 3.0, -2.5e-17, 7.0e300, -0.0];
        let b = [3.0, 1.0e17, 1.0e10, 5.0];
        let c = [-1.0, 0.1, -f64::MAX, 0.0];
        let (va, vb, vc) = (F64x4::load(&a), F64x4::load(&b), F64x4::load(&c));
        let lanes = |f: fn(f64, f64, f64) -> f64| -> [f64; 4] {
            std::array::from_fn(|l| f(a[l], b[l], c[l]))
        };
        let bits = |x: [f64; 4]| x.map(f64::to_bits);
        assert_eq!(bits(va.mul_add(vb, vc).to_array()), bits(lanes(fmadd)));
        assert_eq!(bits(va.mul(vb).to_array()), bits(lanes(|x, y, _| x * y)));
        assert_eq!(bits(va.add(vc).to_array()), bits(lanes(|x, _, z| x + z)));
        assert_eq!(bits(va.sub(vc).to_array()), bits(lanes(|x, _, z| x - z)));
        assert_eq!(bits(F64x4::splat(-0.0).to_array()), bits([-0.0; 4]));
    }
}
