//! The arithmetic of the EKF's tangent propagation, in chunks of SIMD width: the fused RK4
//! stage product `dK_s = F_s (Phi + c dK_{s-1})` on the dynamic rows of the transition
//! matrix (docs/model.md eq. (19)), and the rows-times-covariance product of the prediction
//! (docs/model.md eq. (20)).
//!
//! Kept apart from the filter because everything here is about the machine (lanes, cache
//! lines, what the compiler keeps in registers), each choice measured; `ekf.rs` holds the
//! algorithm. Both kernels are compiled for the sizes the platform model has and fall back
//! to a plain loop for any other model.

use crate::linalg::fmadd;
use navkf_dynamics::dispatch;

/// Lanes of a chunk: rows of the tangent are stored padded to a multiple of this, as
/// `[f64; LANES]` chunks, so that every row operation is whole SIMD vectors (one AVX-512
/// register, or one AVX2 register where there is no AVX-512; four lanes measured slower on
/// an AVX-512 machine although n = 20 then needs no padding).
#[cfg(target_feature = "avx512f")]
pub(crate) const LANES: usize = 8;
#[cfg(not(target_feature = "avx512f"))]
pub(crate) const LANES: usize = 4;
pub(crate) type Chunk = [f64; LANES];

/// A buffer of chunks that starts on a cache line (64 bytes), so that no vector load or store
/// straddles two lines: a `Vec` of doubles is only guaranteed 8-byte alignment (the allocator
/// gave 16 here), and with 8-lane chunks every access then touched two lines. The heap block
/// never moves, so neither does the alignment.
pub(crate) struct ChunkBuf {
    buf: Vec<f64>,
    start: usize,
    len: usize,
}

impl ChunkBuf {
    /// `len` zeroed chunks.
    pub(crate) fn new(len: usize) -> Self {
        const LINE: usize = 64;
        let per_line = LINE / std::mem::size_of::<f64>();
        let buf = vec![0.0; len * LANES + per_line - 1];
        let misaligned = (buf.as_ptr() as usize % LINE) / std::mem::size_of::<f64>();
        ChunkBuf {
            start: (per_line - misaligned) % per_line,
            buf,
            len,
        }
    }
}

impl std::ops::Deref for ChunkBuf {
    type Target = [Chunk];
    #[inline]
    fn deref(&self) -> &[Chunk] {
        self.buf[self.start..self.start + self.len * LANES]
            .as_chunks()
            .0
    }
}

impl std::ops::DerefMut for ChunkBuf {
    #[inline]
    fn deref_mut(&mut self) -> &mut [Chunk] {
        self.buf[self.start..self.start + self.len * LANES]
            .as_chunks_mut()
            .0
    }
}

/// `acc += a * src`, lane by lane.
#[inline(always)]
pub(crate) fn axpy(acc: &mut Chunk, a: f64, src: &Chunk) {
    for (o, s) in acc.iter_mut().zip(src) {
        *o = fmadd(a, *s, *o);
    }
}

/// Dynamic dimension of the platform model and of a strapdown model whose biases are
/// constants (their seven navigation states), for which the stage kernel is compiled with
/// every size known.
const PLATFORM_D: usize = navkf_dynamics::state::NAV_DIM;

/// Dynamic dimensions of a strapdown model whose biases wander (docs/model.md eq. (69)): its
/// 13 base states and the departures of one triad, or of both. The diagnosis weighs such
/// models in every round and fits its noise levels on them once one is named, so the kernel is
/// compiled for them too (`ErrorLayout::dynamic_dim`).
const ONE_TRIAD_D: usize = navkf_dynamics::strapdown::state::BASE_DIM + 3;
const TWO_TRIADS_D: usize = navkf_dynamics::strapdown::state::BASE_DIM + 6;

/// How many chunks of a row's stage rate [`Stage::run_any`] holds in its stack buffer at once
/// (64 states with 4 lanes); a wider row goes through it in pieces of this many.
const ROW_CHUNKS: usize = 16;

/// One RK4 stage of the tangent, fused: for every dynamic row `r`,
/// `t = [0 F_b][r] + sum_m F_a[r, m] y_in[m]` (the stage's tangent rate, never stored),
/// then `acc[r] = (first ? base[r] : acc[r]) + w t` and, for the next stage,
/// `y_out[r] = base[r] + c t`. `jac` holds the model Jacobian's `d` padded rows `[F_a F_b]`.
///
/// With the sizes known at compile time (`d` = 7, 16 or 19, up to 8 chunks per row) each
/// row's rate `t` lives in registers. An exactly zero `F_a[r, m]` is skipped by one branch:
/// the platform model's block has at most 27 nonzeros of 49, the other 22 zero whatever the
/// state, so the branches are mostly the same from stage to stage and predicted. Skipping an
/// exact zero leaves every sum as the dense product would make it while `y_in` is finite (a
/// non-finite tangent is caught at the end of the step either way).
/// (Measured slower, on an AVX-512 Zen 5: the dense product; two partial sums per row; all
/// rows of one chunk at a time; `y_in` copied to locals first; outputs formed in registers
/// rather than copied then added to; an index list of the nonzeros rebuilt at every stage.)
pub(crate) struct Stage<'a> {
    pub d: usize,
    pub jac: &'a [Chunk],
    pub y_in: &'a [Chunk],
    pub base: &'a [Chunk],
    pub w: f64,
    pub first: bool,
}

impl Stage<'_> {
    pub(crate) fn run(&self, nc: usize, acc: &mut [Chunk], y_out: Option<(&mut [Chunk], f64)>) {
        dispatch!(self.run_sized(nc, acc, y_out))
    }

    /// [`Stage::run`], inlined into [`navkf_dynamics::dispatch!`]'s copies (see
    /// [`navkf_dynamics::instruction_set`]).
    #[inline(always)]
    fn run_sized(&self, nc: usize, acc: &mut [Chunk], y_out: Option<(&mut [Chunk], f64)>) {
        macro_rules! fixed {
            ($($d:ident: $($n:literal)*;)*) => {
                match (self.d, nc) {
                    $($(($d, $n) => self.run_n::<$d, $n>(acc, y_out),)*)*
                    _ => self.run_any(nc, acc, y_out),
                }
            };
        }
        // Rows of up to 32 states: the base model with every effect a diagnosis weighs.
        fixed!(
            PLATFORM_D: 1 2 3 4 5 6 7 8;
            ONE_TRIAD_D: 4 5 6 7 8;
            TWO_TRIADS_D: 5 6 7 8;
        )
    }

    /// With the sizes known, the row's rate `t` lives in registers.
    #[inline(always)]
    fn run_n<const D: usize, const NC: usize>(
        &self,
        acc: &mut [Chunk],
        mut y_out: Option<(&mut [Chunk], f64)>,
    ) {
        let y_in = &self.y_in[..D * NC];
        for r in 0..D {
            let row: &[Chunk; NC] = self.jac[r * NC..(r + 1) * NC].try_into().unwrap();
            let mut t = *row;
            // [0 F_b]: the dynamic block's columns start at zero (a constant mask).
            for (ch, tc) in t.iter_mut().enumerate() {
                for (l, v) in tc.iter_mut().enumerate() {
                    if ch * LANES + l < D {
                        *v = 0.0;
                    }
                }
            }
            for m in 0..D {
                let a = row[m / LANES][m % LANES];
                if a != 0.0 {
                    for (o, s) in t.iter_mut().zip(&y_in[m * NC..(m + 1) * NC]) {
                        axpy(o, a, s);
                    }
                }
            }
            let rows = r * NC..(r + 1) * NC;
            let base = &self.base[rows.clone()];
            let acc = &mut acc[rows.clone()];
            if self.first {
                acc.copy_from_slice(base);
            }
            for (o, s) in acc.iter_mut().zip(&t) {
                axpy(o, self.w, s);
            }
            if let Some((y, c)) = y_out.as_mut() {
                let y = &mut y[rows];
                y.copy_from_slice(base);
                for (o, s) in y.iter_mut().zip(&t) {
                    axpy(o, *c, s);
                }
            }
        }
    }

    /// Any other size: as [`Stage::run_n`], but with the row's rate in a stack buffer of
    /// [`ROW_CHUNKS`] chunks (a wider row in pieces of that many): each `F_a[r, m]` is read
    /// once per piece and its exact zeros skipped, so every element gets the same sums in the
    /// same order as there.
    #[inline(always)]
    fn run_any(&self, nc: usize, acc: &mut [Chunk], mut y_out: Option<(&mut [Chunk], f64)>) {
        let d = self.d;
        let mut buf = [[0.0; LANES]; ROW_CHUNKS];
        for r in 0..d {
            let row = &self.jac[r * nc..(r + 1) * nc];
            let masked = |ch: usize| {
                let mut t = row[ch];
                for (l, v) in t.iter_mut().enumerate() {
                    if ch * LANES + l < d {
                        *v = 0.0;
                    }
                }
                t
            };
            let mut finish = |ch: usize, t: &Chunk| {
                let i = r * nc + ch;
                let b = &self.base[i];
                if self.first {
                    acc[i] = *b;
                }
                axpy(&mut acc[i], self.w, t);
                if let Some((y, c)) = y_out.as_mut() {
                    y[i] = *b;
                    axpy(&mut y[i], *c, t);
                }
            };
            // A row of up to ROW_CHUNKS chunks at once; a wider one in pieces of that many
            // (each element's sum is over m in order either way).
            for start in (0..nc).step_by(ROW_CHUNKS) {
                let chunks = start..nc.min(start + ROW_CHUNKS);
                let t = &mut buf[..chunks.len()];
                for (tc, ch) in t.iter_mut().zip(chunks.clone()) {
                    *tc = masked(ch);
                }
                for m in 0..d {
                    let a = row[m / LANES][m % LANES];
                    if a != 0.0 {
                        let src = &self.y_in[m * nc + chunks.start..m * nc + chunks.end];
                        for (o, s) in t.iter_mut().zip(src) {
                            axpy(o, a, s);
                        }
                    }
                }
                for (tc, ch) in t.iter().zip(chunks) {
                    finish(ch, tc);
                }
            }
        }
    }
}

/// `out = rows P` for `rows` (padded rows of `nc` chunks, `n` real columns) and `P` given by
/// its `n` padded rows `p_pad` (symmetric, so row `m` is column `m`).
pub(crate) fn rows_times_matrix(
    nc: usize,
    rows: &[Chunk],
    n: usize,
    p_pad: &[Chunk],
    out: &mut [Chunk],
) {
    dispatch!(rows_times_matrix_sized(nc, rows, n, p_pad, out))
}

/// [`rows_times_matrix`], inlined into [`navkf_dynamics::dispatch!`]'s copies.
#[inline(always)]
fn rows_times_matrix_sized(
    nc: usize,
    rows: &[Chunk],
    n: usize,
    p_pad: &[Chunk],
    out: &mut [Chunk],
) {
    macro_rules! fixed {
        ($($k:literal)*) => {
            match nc {
                $($k => rows_times_matrix_n::<$k>(rows, n, p_pad, out),)*
                _ => {
                    for (o, row) in out.chunks_exact_mut(nc).zip(rows.chunks_exact(nc)) {
                        o.fill([0.0; LANES]);
                        for (m, &a) in row.as_flattened()[..n].iter().enumerate() {
                            for (oc, pc) in o.iter_mut().zip(&p_pad[m * nc..(m + 1) * nc]) {
                                axpy(oc, a, pc);
                            }
                        }
                    }
                }
            }
        };
    }
    fixed!(1 2 3 4 5 6 7 8)
}

/// [`rows_times_matrix`] with the row width known: the output row accumulates in registers,
/// and the rows' exact zeros (the identity's, the padding) are skipped.
#[inline(always)]
fn rows_times_matrix_n<const NC: usize>(
    rows: &[Chunk],
    n: usize,
    p_pad: &[Chunk],
    out: &mut [Chunk],
) {
    for (o, row) in out.chunks_exact_mut(NC).zip(rows.chunks_exact(NC)) {
        let mut t = [[0.0; LANES]; NC];
        for (m, &a) in row.as_flattened()[..n].iter().enumerate() {
            if a != 0.0 {
                for (tc, pc) in t.iter_mut().zip(&p_pad[m * NC..(m + 1) * NC]) {
                    axpy(tc, a, pc);
                }
            }
        }
        o.copy_from_slice(&t);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The compiled-size path (7 dynamic states, or a wandering strapdown model's 16 or 19,
    /// up to 8 chunks per row) and the any-size fallback compute the same stage, bit for bit:
    /// the same sums in the same order.
    #[test]
    fn fixed_and_any_size_stages_agree() {
        fixed_and_any_size_stages_agree_at::<PLATFORM_D, 3>();
        fixed_and_any_size_stages_agree_at::<ONE_TRIAD_D, 5>();
        fixed_and_any_size_stages_agree_at::<TWO_TRIADS_D, 8>();
    }

    fn fixed_and_any_size_stages_agree_at<const D: usize, const NC: usize>() {
        let d = D;
        let filled = |seed: f64, len: usize| -> Vec<Chunk> {
            (0..len)
                .map(|i| std::array::from_fn(|l| (seed * (i * LANES + l + 1) as f64).sin()))
                .collect()
        };
        let mut jac = filled(0.7, d * NC);
        // Exact zeros in the dynamic block, which the compiled-size path skips.
        for r in 0..d {
            for m in (r % 3..d).step_by(3) {
                jac[r * NC + m / LANES][m % LANES] = 0.0;
            }
        }
        let (y_in, base) = (filled(1.3, d * NC), filled(2.9, d * NC));
        for first in [true, false] {
            let stage = Stage {
                d,
                jac: &jac,
                y_in: &y_in,
                base: &base,
                w: 0.25,
                first,
            };
            let start = filled(4.1, d * NC);
            let (mut acc_n, mut acc_any) = (start.clone(), start);
            let (mut y_n, mut y_any) = (vec![[0.0; LANES]; d * NC], vec![[0.0; LANES]; d * NC]);
            stage.run_n::<D, NC>(&mut acc_n, Some((&mut y_n, 0.5)));
            stage.run_any(NC, &mut acc_any, Some((&mut y_any, 0.5)));
            for (a, b) in acc_n
                .as_flattened()
                .iter()
                .zip(acc_any.as_flattened())
                .chain(y_n.as_flattened().iter().zip(y_any.as_flattened()))
            {
                assert_eq!(a.to_bits(), b.to_bits(), "{a} vs {b}");
            }
            // And both against the product written out: t = [0 F_b] + F_a y_in.
            let (jf, yf, bf) = (jac.as_flattened(), y_in.as_flattened(), base.as_flattened());
            let np = NC * LANES;
            for r in 0..d {
                for c in 0..np {
                    let mut t = if c < d { 0.0 } else { jf[r * np + c] };
                    for m in 0..d {
                        t += jf[r * np + m] * yf[m * np + c];
                    }
                    let want = bf[r * np + c] + 0.5 * t;
                    let got = y_n.as_flattened()[r * np + c];
                    assert!(
                        (got - want).abs() <= 1e-13,
                        "row {r} col {c}: {got} vs {want}"
                    );
                }
            }
        }
    }

    /// The any-size path against the product written out, for a wandering strapdown model's
    /// 16 dynamic rows (six of them all zero) and for rows wider than its stack buffer.
    #[test]
    fn any_size_stage_is_the_written_out_product() {
        for (d, nc) in [(16, 5), (10, ROW_CHUNKS + 1)] {
            let np = nc * LANES;
            let filled = |seed: f64, len: usize| -> Vec<Chunk> {
                (0..len)
                    .map(|i| std::array::from_fn(|l| (seed * (i * LANES + l + 1) as f64).sin()))
                    .collect()
            };
            let mut jac = filled(0.7, d * nc);
            for r in 7..d.min(13) {
                jac[r * nc..(r + 1) * nc].fill([0.0; LANES]);
            }
            let (y_in, base) = (filled(1.3, d * nc), filled(2.9, d * nc));
            let stage = Stage {
                d,
                jac: &jac,
                y_in: &y_in,
                base: &base,
                w: 0.25,
                first: true,
            };
            let mut acc = filled(4.1, d * nc);
            let mut y = vec![[0.0; LANES]; d * nc];
            stage.run_any(nc, &mut acc, Some((&mut y, 0.5)));
            let (jf, yf, bf) = (jac.as_flattened(), y_in.as_flattened(), base.as_flattened());
            for r in 0..d {
                for c in 0..np {
                    let mut t = if c < d { 0.0 } else { jf[r * np + c] };
                    for m in 0..d {
                        t += jf[r * np + m] * yf[m * np + c];
                    }
                    let i = r * np + c;
                    for (got, want) in [
                        (acc.as_flattened()[i], bf[i] + 0.25 * t),
                        (y.as_flattened()[i], bf[i] + 0.5 * t),
                    ] {
                        assert!(
                            (got - want).abs() <= 1e-13,
                            "d {d}, row {r} col {c}: {got} vs {want}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn chunk_buffers_start_on_a_cache_line() {
        for len in [1, 3, 7, 21, 60] {
            let mut b = ChunkBuf::new(len);
            assert_eq!(b.len(), len);
            assert_eq!(b.as_ptr() as usize % 64, 0);
            assert!(b.as_flattened().iter().all(|&v| v == 0.0));
            b[len - 1][LANES - 1] = 1.0;
            assert_eq!(b.as_flattened()[len * LANES - 1], 1.0);
        }
    }
}
