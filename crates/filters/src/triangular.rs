//! Square-root kernels for the square-root UKF: triangularisation of a tall matrix
//! (Householder QR, keeping only `R`) and rank-one updates and downdates of a Cholesky factor.
//!
//! Both work in place on column-major slices and allocate nothing.

/// Triangularises the column-major `m x n` matrix `a` (`m >= n`): on return its top `n` rows
/// hold the upper-triangular `R` of `A = Q R` with a non-negative diagonal (rows below and
/// the strict lower triangle are zeroed). `R^T R = A^T A`, so `R^T` is a Cholesky factor of
/// `A^T A` computed without forming it.
///
/// ```
/// use navkf_filters::triangular::householder_r;
/// // A = [3 0; 4 5] (column-major): A^T A = [25 20; 20 25] = R^T R with R = [5 4; 0 3].
/// let mut a = [3.0, 4.0, 0.0, 5.0];
/// householder_r(&mut a, 2, 2);
/// let r = [a[0], a[2], a[3]];
/// for (got, want) in r.iter().zip([5.0, 4.0, 3.0]) {
///     assert!((got - want).abs() < 1e-12);
/// }
/// ```
pub fn householder_r(a: &mut [f64], m: usize, n: usize) {
    debug_assert!(m >= n && a.len() >= m * n);
    for j in 0..n {
        let (head, tail) = a.split_at_mut((j + 1) * m);
        let v = &mut head[j * m + j..(j + 1) * m];
        let x0 = v[0];
        let tail_sq = dot(&v[1..], &v[1..]);
        let norm = (x0 * x0 + tail_sq).sqrt();
        if tail_sq == 0.0 {
            // Already triangular in this column.
            continue;
        }
        // Reflect onto -sign(x0) |x| e1 (no cancellation in v0 = x0 - alpha).
        let alpha = if x0 > 0.0 { -norm } else { norm };
        let v0 = x0 - alpha;
        let vtv = v0 * v0 + tail_sq;
        let beta = 2.0 / vtv;
        v[0] = v0;
        for c in tail.chunks_exact_mut(m).take(n - j - 1) {
            let col = &mut c[j..m];
            let f = beta * dot(col, v);
            for (ci, vi) in col.iter_mut().zip(v.iter()) {
                *ci -= f * vi;
            }
        }
        v[0] = alpha;
        v[1..].fill(0.0);
    }
    // Non-negative diagonal: negate the rows whose pivot is negative.
    for j in 0..n {
        if a[j + j * m] < 0.0 {
            for c in j..n {
                a[j + c * m] = -a[j + c * m];
            }
        }
    }
}

/// Dot product with four independent accumulators (a plain fold is one serial chain of
/// adds, which the compiler may not reorder).
#[inline(always)]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        for l in 0..4 {
            acc[l] = crate::linalg::fmadd(x[l], y[l], acc[l]);
        }
    }
    let tail: f64 = ra.iter().zip(rb).map(|(x, y)| x * y).sum();
    (acc[0] + acc[2]) + (acc[1] + acc[3]) + tail
}

/// Rank-one update (`sign = 1`) or downdate (`sign = -1`) of a lower Cholesky factor:
/// `L L^T + sign x x^T = L' L'^T`, `L` column-major `n x n`, `x` overwritten. A downdate that
/// would leave the matrix not positive definite fails with the pivot and its value (`L` is
/// then partly updated and must not be used).
///
/// ```
/// use navkf_filters::triangular::rank_one_update;
/// // [16] + [3][3] = [25]: L = 4 becomes 5; a downdate takes it back; taking 5^2 from 4^2
/// // would leave a negative variance.
/// let mut l = [4.0];
/// rank_one_update(&mut l, 1, &mut [3.0], 1.0).unwrap();
/// assert!((l[0] - 5.0).abs() < 1e-15);
/// rank_one_update(&mut l, 1, &mut [3.0], -1.0).unwrap();
/// assert!((l[0] - 4.0).abs() < 1e-15);
/// assert!(rank_one_update(&mut l, 1, &mut [5.0], -1.0).is_err());
/// ```
pub fn rank_one_update(
    l: &mut [f64],
    n: usize,
    x: &mut [f64],
    sign: f64,
) -> Result<(), (usize, f64)> {
    for k in 0..n {
        let lkk = l[k + k * n];
        let xk = x[k];
        let r2 = lkk * lkk + sign * xk * xk;
        if !(r2 > 0.0) || !r2.is_finite() || !(lkk > 0.0) {
            return Err((k, r2));
        }
        let r = r2.sqrt();
        let c = r / lkk;
        let s = xk / lkk;
        l[k + k * n] = r;
        let col = &mut l[k * n + k + 1..(k + 1) * n];
        let inv_c = 1.0 / c;
        for (li, xi) in col.iter_mut().zip(&mut x[k + 1..n]) {
            *li = (*li + sign * s * *xi) * inv_c;
            *xi = c * *xi - s * *li;
        }
    }
    Ok(())
}

/// `P = S S^T` for a lower-triangular `S` (column-major `n x n`), written in full. `rows`
/// (at least `n * n`) receives the rows of `S` contiguously, so each entry is one dot
/// product over contiguous memory.
pub fn outer_of_lower(s: &[f64], n: usize, p: &mut [f64], rows: &mut [f64]) {
    for j in 0..n {
        for i in 0..n {
            rows[j + i * n] = s[i + j * n];
        }
    }
    for j in 0..n {
        let rj = &rows[j * n..j * n + j + 1];
        for i in j..n {
            // (S S^T)[i, j] = sum_{c <= j} S[i, c] S[j, c].
            let v = dot(&rows[i * n..i * n + j + 1], rj);
            p[i + j * n] = v;
            p[j + i * n] = v;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::cholesky_in_place;

    /// A deterministic, well-conditioned tall matrix.
    fn tall(m: usize, n: usize) -> Vec<f64> {
        (0..m * n)
            .map(|k| {
                ((k * 7919 % 1000) as f64 / 500.0 - 1.0) + if k % (m + 1) == 0 { 2.0 } else { 0.0 }
            })
            .collect()
    }

    /// `A^T A` of a column-major `m x n` matrix.
    fn gram(a: &[f64], m: usize, n: usize) -> Vec<f64> {
        let mut g = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                g[i + j * n] = (0..m).map(|r| a[r + i * m] * a[r + j * m]).sum();
            }
        }
        g
    }

    #[test]
    fn householder_r_is_the_cholesky_factor_of_the_gram_matrix() {
        for (m, n) in [(45, 20), (24, 24), (44, 4), (3, 1)] {
            let a = tall(m, n);
            let mut l = gram(&a, m, n);
            cholesky_in_place(&mut l, n).unwrap();
            let mut r = a.clone();
            householder_r(&mut r, m, n);
            for j in 0..n {
                for i in 0..m {
                    // R[i, j] = L[j, i] above the diagonal, zero below.
                    let want = if i < n && i <= j { l[j + i * n] } else { 0.0 };
                    let scale = l[j + j * n].abs().max(1.0);
                    assert!(
                        (r[i + j * m] - want).abs() <= 1e-12 * scale,
                        "{m}x{n}: R[{i},{j}] = {} against {want}",
                        r[i + j * m]
                    );
                }
            }
        }
    }

    #[test]
    fn rank_one_update_and_downdate_match_a_fresh_factorisation() {
        let n = 6;
        let a = tall(10, n);
        let p = gram(&a, 10, n);
        let x: Vec<f64> = (0..n).map(|i| 0.3 * (i as f64 + 1.0).sin()).collect();
        for sign in [1.0, -1.0] {
            let mut l = p.clone();
            cholesky_in_place(&mut l, n).unwrap();
            let mut xv = x.clone();
            rank_one_update(&mut l, n, &mut xv, sign).unwrap();
            let mut want = p.clone();
            for i in 0..n {
                for j in 0..n {
                    want[i + j * n] += sign * x[i] * x[j];
                }
            }
            cholesky_in_place(&mut want, n).unwrap();
            for j in 0..n {
                for i in j..n {
                    assert!(
                        (l[i + j * n] - want[i + j * n]).abs() < 1e-12,
                        "sign {sign}"
                    );
                }
            }
        }
    }

    #[test]
    fn outer_of_lower_rebuilds_the_matrix() {
        let n = 5;
        let a = tall(8, n);
        let p = gram(&a, 8, n);
        let mut l = p.clone();
        cholesky_in_place(&mut l, n).unwrap();
        let mut back = vec![0.0; n * n];
        outer_of_lower(&l, n, &mut back, &mut vec![0.0; n * n]);
        for (b, q) in back.iter().zip(&p) {
            assert!((b - q).abs() < 1e-12 * q.abs().max(1.0));
        }
    }
}
