//! Square-root kernels for the square-root UKF: triangularisation of a tall matrix
//! (Householder QR, keeping only `R`) and rank-one updates and downdates of a Cholesky factor:
//! the `qr` and `cholupdate` of docs/model.md eqs. (34)-(36).
//!
//! Both work in place on column-major slices and allocate nothing.
//!
//! The QR and `S S^T` are hand kernels on `F64x4` (`simd.rs`) because they beat faer's at the
//! square-root UKF's sizes (`cargo bench --manifest-path benches/criterion/Cargo.toml
//! --bench linalg -- square_root`; docs/speed.md). Grouping columns or rows changes no
//! result: every entry keeps the arithmetic of the scalar `dot`, which the tests check bit
//! for bit.

use crate::simd::F64x4;

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
    navkf_dynamics::dispatch!(householder_r_inline(a, m, n))
}

/// [`householder_r`], inlined into both copies of [`navkf_dynamics::dispatch!`].
#[inline(always)]
fn householder_r_inline(a: &mut [f64], m: usize, n: usize) {
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
        // The reflection leaves the rows past `v`'s last non-zero entry as they are; skip
        // them (a sparse H leaves most of the update's pre-array below its first rows zero).
        // Cut at a whole chunk of four, so every product lands in the partial sum it would
        // have over the whole column: only zero products are dropped, and the skipped rows
        // would lose `f * 0`. Neither changes a value (at most the sign of a zero).
        let nonzero = v.iter().rposition(|&x| x != 0.0).map_or(0, |r| r + 1);
        let reach = nonzero.next_multiple_of(4).min(v.len());
        let v = &v[..reach];
        let width = n - j - 1;
        let grouped = width / REFLECT_GROUP * REFLECT_GROUP * m;
        let (grouped, rest) = tail[..width * m].split_at_mut(grouped);
        for block in grouped.chunks_exact_mut(REFLECT_GROUP * m) {
            reflect_columns::<REFLECT_GROUP>(block, m, j, v, beta);
        }
        for block in rest.chunks_exact_mut(m) {
            reflect_columns::<1>(block, m, j, v, beta);
        }
        let v = &mut head[j * m + j..(j + 1) * m];
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

/// Columns reflected per pass over the Householder vector in [`householder_r`].
const REFLECT_GROUP: usize = 4;

/// Applies the reflector `I - beta v v^T` to the `K` consecutive columns of `block`
/// (column-major, `m` rows; rows `j..j + v.len()` change): `c -= (beta v.c) v`.
///
/// Each column's arithmetic is that of [`dot`] and of the scalar `c_i -= f v_i`, so `K` does
/// not change the results. Written on [`F64x4`] because LLVM vectorises the `K` dot
/// products across the columns (a transpose of four columns per step); with `K` columns
/// sharing each load of `v`, `householder_r` at the square-root UKF's sizes is measured in
/// `benches/linalg.rs` (`square_root` group, against faer's QR and the scalar loop).
#[inline(always)]
fn reflect_columns<const K: usize>(block: &mut [f64], m: usize, j: usize, v: &[f64], beta: f64) {
    let rows = j..j + v.len();
    let mut columns = block.chunks_exact_mut(m);
    let cols: [&mut [f64]; K] = std::array::from_fn(|_| &mut columns.next().unwrap()[rows.clone()]);
    let (v_body, v_tail) = v.as_chunks::<4>();
    let body = v_body.len();
    let mut acc = [F64x4::splat(0.0); K];
    for (c, y) in v_body.iter().enumerate() {
        let y = F64x4::load(y);
        for k in 0..K {
            let x = F64x4::load(cols[k][4 * c..4 * c + 4].try_into().unwrap());
            acc[k] = x.mul_add(y, acc[k]);
        }
    }
    let f: [F64x4; K] = std::array::from_fn(|k| {
        let tail: f64 = cols[k][4 * body..]
            .iter()
            .zip(v_tail)
            .map(|(x, y)| x * y)
            .sum();
        let a = acc[k].to_array();
        F64x4::splat(beta * ((a[0] + a[2]) + (a[1] + a[3]) + tail))
    });
    for (c, y) in v_body.iter().enumerate() {
        let y = F64x4::load(y);
        for k in 0..K {
            let x: &mut [f64; 4] = (&mut cols[k][4 * c..4 * c + 4]).try_into().unwrap();
            F64x4::load(x).sub(f[k].mul(y)).store(x);
        }
    }
    for k in 0..K {
        let fk = f[k].to_array()[0];
        for (ci, vi) in cols[k][4 * body..].iter_mut().zip(v_tail) {
            *ci -= fk * vi;
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

/// `P = S S^T` for a lower-triangular `S` (column-major `n x n`), written in full.
///
/// Entry `(i, j)`, `i >= j`, is the dot product of rows `i` and `j` of `S` over columns
/// `0..=j`, summed in four interleaved partial sums and a tail. Four rows `i` are formed at
/// once on four-lane vectors, from contiguous pieces of the columns of `S` (measured in
/// `benches/linalg.rs`, `square_root` group); rows left over take the same order in scalars.
///
/// ```
/// use navkf_filters::triangular::outer_of_lower;
/// // S = [2 0; 1 3] (column-major): S S^T = [4 2; 2 10].
/// let mut p = [0.0; 4];
/// outer_of_lower(&[2.0, 1.0, 0.0, 3.0], 2, &mut p);
/// assert_eq!(p, [4.0, 2.0, 2.0, 10.0]);
/// ```
pub fn outer_of_lower(s: &[f64], n: usize, p: &mut [f64]) {
    navkf_dynamics::dispatch!(outer_of_lower_inline(s, n, p))
}

/// [`outer_of_lower`], inlined into both copies of [`navkf_dynamics::dispatch!`].
#[inline(always)]
fn outer_of_lower_inline(s: &[f64], n: usize, p: &mut [f64]) {
    assert!(s.len() >= n * n && p.len() >= n * n);
    for j in 0..n {
        let len = j + 1;
        let body = len / 4;
        let mut i = j;
        while i + 4 <= n {
            let column = |c: usize| F64x4::load(s[i + c * n..i + c * n + 4].try_into().unwrap());
            let mut acc = [F64x4::splat(0.0); 4];
            for b in 0..body {
                for (l, a) in acc.iter_mut().enumerate() {
                    let c = 4 * b + l;
                    *a = column(c).mul_add(F64x4::splat(s[j + c * n]), *a);
                }
            }
            // `Iterator::sum` folds from -0.0; so does this tail, lane by lane.
            let mut tail = F64x4::splat(-0.0);
            for c in 4 * body..len {
                tail = tail.add(column(c).mul(F64x4::splat(s[j + c * n])));
            }
            let v = acc[0].add(acc[2]).add(acc[1].add(acc[3])).add(tail);
            v.store((&mut p[i + j * n..i + j * n + 4]).try_into().unwrap());
            for (l, vl) in v.to_array().into_iter().enumerate() {
                p[j + (i + l) * n] = vl;
            }
            i += 4;
        }
        for i in i..n {
            let v = lower_row_dot(s, n, i, j);
            p[i + j * n] = v;
            p[j + i * n] = v;
        }
    }
}

/// `sum_{c <= j} S[i, c] S[j, c]` in [`dot`]'s order, on the column-major `S`.
#[inline(always)]
fn lower_row_dot(s: &[f64], n: usize, i: usize, j: usize) -> f64 {
    let len = j + 1;
    let body = len / 4;
    let mut acc = [0.0; 4];
    for b in 0..body {
        for (l, a) in acc.iter_mut().enumerate() {
            let c = 4 * b + l;
            *a = crate::linalg::fmadd(s[i + c * n], s[j + c * n], *a);
        }
    }
    let tail: f64 = (4 * body..len).map(|c| s[i + c * n] * s[j + c * n]).sum();
    (acc[0] + acc[2]) + (acc[1] + acc[3]) + tail
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

    /// [`householder_r`] one column at a time with plain loops: the arithmetic the grouped
    /// kernel must keep.
    fn householder_r_one_column_at_a_time(a: &mut [f64], m: usize, n: usize) {
        for j in 0..n {
            let (head, tail) = a.split_at_mut((j + 1) * m);
            let v = &mut head[j * m + j..(j + 1) * m];
            let (x0, tail_sq) = (v[0], dot(&v[1..], &v[1..]));
            if tail_sq == 0.0 {
                continue;
            }
            let norm = (x0 * x0 + tail_sq).sqrt();
            let alpha = if x0 > 0.0 { -norm } else { norm };
            let v0 = x0 - alpha;
            let beta = 2.0 / (v0 * v0 + tail_sq);
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
        for j in 0..n {
            if a[j + j * m] < 0.0 {
                for c in j..n {
                    a[j + c * m] = -a[j + c * m];
                }
            }
        }
    }

    #[test]
    fn householder_r_groups_columns_without_changing_a_bit() {
        for (m, n, sparse) in [
            (45, 20, false),
            (55, 25, false),
            (13, 13, false),
            (30, 9, false),
            (7, 2, false),
            (29, 29, true),
            (24, 24, true),
            (33, 10, true),
        ] {
            let mut a = tall(m, n);
            if sparse {
                // The update's pre-array: the first columns non-zero only in their first
                // rows, the rest upper triangular below them (rows past the reflectors'
                // reach are skipped).
                for c in 0..n {
                    let last = if c < 4 { 11 } else { c + 1 };
                    a[c * m + last.min(m)..(c + 1) * m].fill(0.0);
                }
            }
            let (mut grouped, mut single) = (a.clone(), a);
            householder_r(&mut grouped, m, n);
            householder_r_one_column_at_a_time(&mut single, m, n);
            let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&grouped), bits(&single), "{m}x{n}, sparse {sparse}");
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
    fn outer_of_lower_gives_the_scalar_dot_bits_in_every_entry() {
        // The four-row blocks and the rows left over must agree bit for bit with one dot
        // order, whatever n mod 4 (signed zeros included).
        for n in 1..=11 {
            let mut s = tall(n, n);
            for j in 0..n {
                for i in 0..j {
                    s[i + j * n] = 0.0;
                }
            }
            s[n - 1] = -0.0;
            let mut p = vec![f64::NAN; n * n];
            outer_of_lower(&s, n, &mut p);
            for j in 0..n {
                for i in j..n {
                    let want = lower_row_dot(&s, n, i, j).to_bits();
                    assert_eq!(p[i + j * n].to_bits(), want, "n {n}: P[{i},{j}]");
                    assert_eq!(p[j + i * n].to_bits(), want, "n {n}: P[{j},{i}]");
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
        outer_of_lower(&l, n, &mut back);
        for (b, q) in back.iter().zip(&p) {
            assert!((b - q).abs() < 1e-12 * q.abs().max(1.0));
        }
    }
}
