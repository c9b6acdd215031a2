//! Small dense kernels on column-major slices, written for the sizes of this problem
//! (n = 20 to 40, measurement size up to 4) and for not allocating.
//!
//! They are not the fastest code for these sizes on every CPU: on the AMD Zen 4 of
//! docs/speed.md, nalgebra's Cholesky (0.73 us at n = 20, a copy included) and faer's
//! product for the UKF covariance (0.85 us for 41 points) beat [`cholesky_in_place`]
//! (1.02 us) and [`row_dots`] (1.45 us) (`cargo bench --manifest-path
//! benches/criterion/Cargo.toml --bench linalg`).
//! They are kept because they allocate nothing and work on the filters' flat buffers; moving
//! to a library call that does neither is an open lead (docs/speed.md).

use crate::view::RowMajor;

/// `a * b + c`, fused (one rounding) when the target has FMA, else multiply then add. Which
/// one is fixed at compile time, so a given binary is deterministic.
#[inline(always)]
pub fn fmadd(a: f64, b: f64, c: f64) -> f64 {
    #[cfg(target_feature = "fma")]
    {
        a.mul_add(b, c)
    }
    #[cfg(not(target_feature = "fma"))]
    {
        a * b + c
    }
}

/// In-place Cholesky `A = L L^T` of a symmetric positive-definite `n x n` matrix stored
/// column-major. On success the lower triangle holds `L` and the strict upper triangle is
/// zeroed. On failure returns the failing pivot's index and value; `a` is then garbage.
pub fn cholesky_in_place(a: &mut [f64], n: usize) -> Result<(), (usize, f64)> {
    navkf_dynamics::dispatch!(cholesky_in_place_inline(a, n))
}

/// [`cholesky_in_place`], inlined into both copies of [`navkf_dynamics::dispatch!`].
#[inline(always)]
fn cholesky_in_place_inline(a: &mut [f64], n: usize) -> Result<(), (usize, f64)> {
    debug_assert!(a.len() >= n * n);
    for j in 0..n {
        // a[j.., j] -= sum_{k<j} L[j..,k] L[j,k]
        for k in 0..j {
            let ljk = a[j + k * n];
            if ljk != 0.0 {
                let (left, right) = a.split_at_mut(j * n);
                let colk = &left[k * n + j..k * n + n];
                let colj = &mut right[j..n];
                for (cj, ck) in colj.iter_mut().zip(colk) {
                    *cj -= ck * ljk;
                }
            }
        }
        let d = a[j + j * n];
        if !(d > 0.0) || !d.is_finite() {
            return Err((j, d));
        }
        let s = d.sqrt();
        let inv = 1.0 / s;
        a[j + j * n] = s;
        for i in j + 1..n {
            a[i + j * n] *= inv;
        }
        for i in 0..j {
            a[i + j * n] = 0.0;
        }
    }
    Ok(())
}

/// Solves `L y = b` in place (`L` lower triangular, column-major `n x n`).
pub fn forward_substitute(l: &[f64], n: usize, b: &mut [f64]) {
    for j in 0..n {
        let y = b[j] / l[j + j * n];
        b[j] = y;
        for i in j + 1..n {
            b[i] -= l[i + j * n] * y;
        }
    }
}

/// Makes a column-major square matrix exactly symmetric: `A = (A + A^T) / 2`.
pub fn symmetrize(a: &mut [f64], n: usize) {
    symmetrize_leading(a, n, n);
}

/// [`symmetrize`] on the leading `d x d` block of an `n x n` column-major matrix only, for a
/// caller whose arithmetic leaves the rest symmetric already.
pub fn symmetrize_leading(a: &mut [f64], n: usize, d: usize) {
    for j in 0..d {
        for i in j + 1..d {
            let m = 0.5 * (a[i + j * n] + a[j + i * n]);
            a[i + j * n] = m;
            a[j + i * n] = m;
        }
    }
}

/// Whether every value is finite.
pub fn all_finite(a: &[f64]) -> bool {
    navkf_dynamics::dispatch!(all_finite_inline(a))
}

/// [`all_finite`], inlined into both copies of [`navkf_dynamics::dispatch!`].
#[inline(always)]
fn all_finite_inline(a: &[f64]) -> bool {
    // A value is infinite or NaN exactly when its exponent bits are all set. No early exit:
    // the OR over the whole slice vectorises.
    const EXP: u64 = 0x7ff0_0000_0000_0000;
    !a.iter()
        .fold(false, |bad, v| bad | (v.to_bits() & EXP == EXP))
}

/// `C += alpha * sum_k w_k d_k d_k^T` over the columns `d_k` of the column-major `n x m`
/// matrix `d` (a weighted rank-m update of the symmetric `n x n` matrix `C`, lower triangle
/// computed, then mirrored).
pub fn weighted_outer_sum(c: &mut [f64], n: usize, d: &[f64], w: &[f64]) {
    for (k, &wk) in w.iter().enumerate() {
        let col = &d[k * n..(k + 1) * n];
        for j in 0..n {
            let f = wk * col[j];
            let cj = &mut c[j * n + j..j * n + n];
            for (ci, di) in cj.iter_mut().zip(&col[j..n]) {
                *ci += f * di;
            }
        }
    }
    for j in 0..n {
        for i in j + 1..n {
            c[j + i * n] = c[i + j * n];
        }
    }
}

/// Rows per block of [`row_dots`]; matrices given to it have their row count padded to a
/// multiple of this with zero rows.
pub const DOT_BLOCK: usize = 4;
const DOT_LANES: usize = 8;

/// Dot products of rows `a0..a0 + 4` of `x` with rows `b0..b0 + 4` of `y`, rows as long in
/// both (a multiple of 8): `out[i][j] = x[a0 + i] . y[b0 + j]`. Sixteen independent SIMD
/// accumulators. Faster than nalgebra's `gemm_tr` for the UKF covariance, slower than faer's
/// product (see the module documentation).
#[inline(always)]
pub fn row_dots(x: RowMajor, a0: usize, y: RowMajor, b0: usize) -> [[f64; 4]; 4] {
    let len = x.cols();
    debug_assert_eq!(len % DOT_LANES, 0);
    debug_assert_eq!(len, y.cols());
    type Chunk = [f64; DOT_LANES];
    let chunk = |m: &RowMajor, row: usize, c: usize| -> Chunk {
        m.row(row)[c * DOT_LANES..(c + 1) * DOT_LANES]
            .try_into()
            .unwrap()
    };
    let mut acc = [[[0.0; DOT_LANES]; 4]; 4];
    for c in 0..len / DOT_LANES {
        let xs: [Chunk; 4] = std::array::from_fn(|i| chunk(&x, a0 + i, c));
        let ys: [Chunk; 4] = std::array::from_fn(|j| chunk(&y, b0 + j, c));
        for (acc_i, xi) in acc.iter_mut().zip(&xs) {
            for (acc_ij, yj) in acc_i.iter_mut().zip(&ys) {
                for ((a, xv), yv) in acc_ij.iter_mut().zip(xi).zip(yj) {
                    *a = fmadd(*xv, *yv, *a);
                }
            }
        }
    }
    let mut out = [[0.0; 4]; 4];
    for i in 0..4 {
        for j in 0..4 {
            let a = &acc[i][j];
            out[i][j] = ((a[0] + a[4]) + (a[1] + a[5])) + ((a[2] + a[6]) + (a[3] + a[7]));
        }
    }
    out
}
