//! The dense kernels of a filter step at this problem's sizes: the hand-written ones in
//! `navkf_filters::linalg` against nalgebra and faer (sequential, preallocated, so no
//! allocation is timed where the library allows it).
//!
//! `cargo bench --manifest-path benches/criterion/Cargo.toml --bench linalg`

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::matmul::triangular::BlockStructure;
use faer::{Accum, Mat, Par};
use nalgebra::{DMatrix, SMatrix};
use navkf_filters::linalg::{cholesky_in_place, row_dots, weighted_outer_sum, DOT_BLOCK};
use navkf_filters::triangular::{householder_r, outer_of_lower};
use navkf_filters::view::RowMajor;
use std::hint::black_box;

/// A deterministic well-conditioned SPD matrix (column-major n x n).
fn spd(n: usize) -> Vec<f64> {
    let mut a = vec![0.0; n * n];
    for j in 0..n {
        for i in 0..n {
            let v = ((i * 7 + j * 13) % 11) as f64 * 0.01 + if i == j { n as f64 } else { 0.0 };
            a[i + j * n] += v;
            a[j + i * n] += v;
        }
    }
    a
}

/// Deviations: n states x m points, column-major (point-major: column k is point k).
fn deviations(n: usize, m: usize) -> Vec<f64> {
    (0..n * m)
        .map(|i| ((i * 37 % 101) as f64 - 50.0) * 1e-3)
        .collect()
}

fn cholesky(c: &mut Criterion) {
    let mut g = c.benchmark_group("cholesky");
    for n in [20usize, 29] {
        let a = spd(n);
        let mut l = a.clone();
        g.bench_function(BenchmarkId::new("hand", n), |b| {
            b.iter(|| {
                l.copy_from_slice(black_box(&a));
                cholesky_in_place(&mut l, n).unwrap();
                black_box(l[n * n - 1]);
            })
        });
        let am = DMatrix::from_column_slice(n, n, &a);
        g.bench_function(BenchmarkId::new("nalgebra_dynamic", n), |b| {
            b.iter(|| black_box(black_box(am.clone()).cholesky().unwrap().l_dirty()[n * n - 1]))
        });
        let fa = Mat::<f64>::from_fn(n, n, |i, j| a[i + j * n]);
        let mut fl = fa.clone();
        let req = faer::linalg::cholesky::llt::factor::cholesky_in_place_scratch::<f64>(
            n,
            Par::Seq,
            Default::default(),
        );
        let mut buf = MemBuffer::new(req);
        g.bench_function(BenchmarkId::new("faer", n), |b| {
            b.iter(|| {
                fl.copy_from(black_box(&fa));
                faer::linalg::cholesky::llt::factor::cholesky_in_place(
                    fl.as_mut(),
                    Default::default(),
                    Par::Seq,
                    MemStack::new(&mut buf),
                    Default::default(),
                )
                .unwrap();
                black_box(fl[(n - 1, n - 1)]);
            })
        });
    }
    let a = spd(20);
    let sm = SMatrix::<f64, 20, 20>::from_column_slice(&a);
    g.bench_function(BenchmarkId::new("nalgebra_static", 20), |b| {
        b.iter(|| black_box(black_box(sm).cholesky().unwrap().l_dirty()[399]))
    });
    g.finish();
}

/// `P = D D^T` (the covariance of the sigma points up to the weights) for n = 20 states and
/// m = 41 or 59 points.
fn rank_k(c: &mut Criterion) {
    let n = 20;
    let mut g = c.benchmark_group("rank_k_update_n20");
    for m in [41usize, 59] {
        let d = deviations(n, m);
        let w = vec![1.0; m];
        let mut p = vec![0.0; n * n];
        g.bench_function(BenchmarkId::new("hand_rank1_point_major", m), |b| {
            b.iter(|| {
                p.fill(0.0);
                weighted_outer_sum(&mut p, n, black_box(&d), &w);
                black_box(p[7]);
            })
        });
        // State-major, zero-padded copy: the layout the UKF builds its deviations in.
        let len = m.div_ceil(8) * 8;
        let rows = n.div_ceil(DOT_BLOCK) * DOT_BLOCK;
        let mut dt = vec![0.0; rows * len];
        for k in 0..m {
            for s in 0..n {
                dt[s * len + k] = d[k * n + s];
            }
        }
        g.bench_function(BenchmarkId::new("hand_row_dots_state_major", m), |b| {
            b.iter(|| {
                let dt = black_box(&dt);
                for a0 in (0..rows).step_by(DOT_BLOCK) {
                    for b0 in (a0..rows).step_by(DOT_BLOCK) {
                        let dv = RowMajor::new(dt, rows, len);
                        let blk = row_dots(dv, a0, dv, b0);
                        for (i, bi) in blk.iter().enumerate().take(n - a0.min(n)) {
                            for (j, v) in bi.iter().enumerate().take(n - b0.min(n)) {
                                p[(a0 + i) + (b0 + j) * n] = *v;
                                p[(b0 + j) + (a0 + i) * n] = *v;
                            }
                        }
                    }
                }
                black_box(p[7]);
            })
        });
        // nalgebra: gemm_tr on the point-major matrix viewed as m x n (P = Dt^T Dt).
        let dm = DMatrix::from_column_slice(n, m, &d).transpose();
        let mut pm = DMatrix::<f64>::zeros(n, n);
        g.bench_function(BenchmarkId::new("nalgebra_gemm_tr", m), |b| {
            b.iter(|| {
                pm.gemm_tr(1.0, black_box(&dm), &dm, 0.0);
                black_box(pm[7]);
            })
        });
        let fd = Mat::<f64>::from_fn(n, m, |i, k| d[k * n + i]);
        let mut fp = Mat::<f64>::zeros(n, n);
        g.bench_function(BenchmarkId::new("faer_lower_triangular", m), |b| {
            b.iter(|| {
                faer::linalg::matmul::triangular::matmul(
                    fp.as_mut(),
                    BlockStructure::TriangularLower,
                    Accum::Replace,
                    black_box(&fd),
                    BlockStructure::Rectangular,
                    fd.transpose(),
                    BlockStructure::Rectangular,
                    1.0,
                    Par::Seq,
                );
                black_box(fp[(7, 0)]);
            })
        });
        g.bench_function(BenchmarkId::new("faer_full", m), |b| {
            b.iter(|| {
                faer::linalg::matmul::matmul(
                    fp.as_mut(),
                    Accum::Replace,
                    black_box(&fd),
                    fd.transpose(),
                    1.0,
                    Par::Seq,
                );
                black_box(fp[(7, 0)]);
            })
        });
    }
    g.finish();
}

/// A 20 x 20 product `C = A B`.
fn product(c: &mut Criterion) {
    let n = 20;
    let a = spd(n);
    let bm: Vec<f64> = deviations(n, n);
    let mut g = c.benchmark_group("product_20x20");
    // Hand: A row-major (A is symmetric here, so its column-major storage reads as rows) and
    // B^T row-major (B column-major), padded; C = row dots.
    let len = 24;
    let mut ar = vec![0.0; n * len];
    let mut br = vec![0.0; n * len];
    for i in 0..n {
        for k in 0..n {
            ar[i * len + k] = a[i + k * n];
            br[i * len + k] = bm[k + i * n];
        }
    }
    let mut cm = vec![0.0; n * n];
    g.bench_function("hand_row_dots", |b| {
        b.iter(|| {
            let (ar, br) = (black_box(&ar), black_box(&br));
            for a0 in (0..n).step_by(4) {
                for b0 in (0..n).step_by(4) {
                    let blk = row_dots(
                        RowMajor::new(ar, ar.len() / len, len),
                        a0,
                        RowMajor::new(br, br.len() / len, len),
                        b0,
                    );
                    for (i, bi) in blk.iter().enumerate() {
                        for (j, v) in bi.iter().enumerate() {
                            cm[(a0 + i) + (b0 + j) * n] = *v;
                        }
                    }
                }
            }
            black_box(cm[7]);
        })
    });
    let sa = SMatrix::<f64, 20, 20>::from_column_slice(&a);
    let sb = SMatrix::<f64, 20, 20>::from_column_slice(&bm);
    g.bench_function("nalgebra_static", |b| {
        b.iter(|| black_box(black_box(&sa) * black_box(&sb))[7])
    });
    let da = DMatrix::from_column_slice(n, n, &a);
    let db = DMatrix::from_column_slice(n, n, &bm);
    let mut dc = DMatrix::<f64>::zeros(n, n);
    g.bench_function("nalgebra_dynamic_gemm", |b| {
        b.iter(|| {
            dc.gemm(1.0, black_box(&da), &db, 0.0);
            black_box(dc[7]);
        })
    });
    let fa = Mat::<f64>::from_fn(n, n, |i, j| a[i + j * n]);
    let fb = Mat::<f64>::from_fn(n, n, |i, j| bm[i + j * n]);
    let mut fc = Mat::<f64>::zeros(n, n);
    g.bench_function("faer", |b| {
        b.iter(|| {
            faer::linalg::matmul::matmul(
                fc.as_mut(),
                Accum::Replace,
                black_box(&fa),
                &fb,
                1.0,
                Par::Seq,
            );
            black_box(fc[(7, 0)]);
        })
    });
    g.finish();
}

/// The square-root UKF's kernels at its sizes: the triangularisation of the prediction's tall
/// matrix `[sqrt(Wi) (X_i - x^-) ; sqrt(Q)]` ((2n + 5) x n: n = 20 for the base model, 25
/// with two rate effects), and `P = S S^T` from the lower factor.
fn square_root(c: &mut Criterion) {
    let mut g = c.benchmark_group("square_root");
    for n in [20usize, 25] {
        let m = 2 * n + 5;
        let mut a = deviations(n, m);
        for ch in 0..5 {
            a[(2 * n + ch) + ch * m] += 0.5;
        }
        let mut t = a.clone();
        g.bench_function(BenchmarkId::new("householder_r_hand", n), |b| {
            b.iter(|| {
                t.copy_from_slice(black_box(&a));
                householder_r(&mut t, m, n);
                black_box(t[n * m - 1]);
            })
        });
        let fa = Mat::<f64>::from_fn(m, n, |i, j| a[i + j * m]);
        let mut ft = fa.clone();
        let bs = faer::linalg::qr::no_pivoting::factor::recommended_block_size::<f64>(m, n);
        let mut coeff = Mat::<f64>::zeros(bs, n);
        let req = faer::linalg::qr::no_pivoting::factor::qr_in_place_scratch::<f64>(
            m,
            n,
            bs,
            Par::Seq,
            Default::default(),
        );
        let mut buf = MemBuffer::new(req);
        g.bench_function(BenchmarkId::new("qr_faer", n), |b| {
            b.iter(|| {
                ft.copy_from(black_box(&fa));
                faer::linalg::qr::no_pivoting::factor::qr_in_place(
                    ft.as_mut(),
                    coeff.as_mut(),
                    Par::Seq,
                    MemStack::new(&mut buf),
                    Default::default(),
                );
                black_box(ft[(n - 1, n - 1)]);
            })
        });
        let mut s = spd(n);
        cholesky_in_place(&mut s, n).unwrap();
        let mut p = vec![0.0; n * n];
        g.bench_function(BenchmarkId::new("outer_of_lower_hand", n), |b| {
            b.iter(|| {
                outer_of_lower(black_box(&s), n, &mut p);
                black_box(p[7]);
            })
        });
        let fs = Mat::<f64>::from_fn(n, n, |i, j| s[i + j * n]);
        let mut fp = Mat::<f64>::zeros(n, n);
        g.bench_function(BenchmarkId::new("outer_of_lower_faer", n), |b| {
            b.iter(|| {
                faer::linalg::matmul::triangular::matmul(
                    fp.as_mut(),
                    BlockStructure::TriangularLower,
                    Accum::Replace,
                    black_box(&fs),
                    BlockStructure::TriangularLower,
                    fs.transpose(),
                    BlockStructure::TriangularUpper,
                    1.0,
                    Par::Seq,
                );
                black_box(fp[(7, 0)]);
            })
        });
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(30).measurement_time(std::time::Duration::from_secs(1)).warm_up_time(std::time::Duration::from_millis(300));
    targets = cholesky, rank_k, product, square_root
}
criterion_main!(benches);
