//! Matrix views: a slice with its shape and layout in the type, so that a kernel's signature
//! says how it reads a buffer instead of a doc comment ("column-major n x k").
//!
//! The filters keep their buffers as flat `Vec<f64>`, sized once (no allocation in a step);
//! a view borrows one for the length of a call. Views cost nothing: a column is the same
//! slice the index arithmetic would give, with the same bounds check.
//!
//! Two layouts occur:
//! - column-major, for covariances, factors, gains and the sigma points (point `i` is
//!   column `i` of an `n x count` matrix);
//! - row-major, for the measurement Jacobian `H` (one row per channel, as
//!   [`navkf_dynamics::SystemModel::measurement_jacobian`] writes it) and the UKF's
//!   deviations (one row per state, padded, so that the row dot products are contiguous).
//!
//! ```
//! use navkf_filters::view::ColMajor;
//! // [1 3; 2 4], column-major.
//! let data = [1.0, 2.0, 3.0, 4.0];
//! let a = ColMajor::new(&data, 2, 2);
//! assert_eq!(a.col(1), &[3.0, 4.0]);
//! assert_eq!(a.at(0, 1), 3.0);
//! ```

/// A column-major `rows x cols` matrix: column `j` is `data[j * rows..(j + 1) * rows]`.
#[derive(Debug, Clone, Copy)]
pub struct ColMajor<'a> {
    data: &'a [f64],
    rows: usize,
    cols: usize,
}

impl<'a> ColMajor<'a> {
    /// Views the first `rows * cols` values of `data`.
    ///
    /// # Panics
    /// If `data` is shorter (a programming error: buffers are sized at construction).
    #[inline(always)]
    pub fn new(data: &'a [f64], rows: usize, cols: usize) -> Self {
        ColMajor {
            data: &data[..rows * cols],
            rows,
            cols,
        }
    }
    /// Number of rows.
    #[inline(always)]
    pub fn rows(&self) -> usize {
        self.rows
    }
    /// Number of columns.
    #[inline(always)]
    pub fn cols(&self) -> usize {
        self.cols
    }
    /// Column `j`.
    #[inline(always)]
    pub fn col(&self, j: usize) -> &'a [f64] {
        &self.data[j * self.rows..(j + 1) * self.rows]
    }
    /// Entry `(i, j)`.
    #[inline(always)]
    pub fn at(&self, i: usize, j: usize) -> f64 {
        self.data[i + j * self.rows]
    }
    /// The values, column after column.
    #[inline(always)]
    pub fn as_slice(&self) -> &'a [f64] {
        self.data
    }
}

/// A mutable column-major `rows x cols` matrix.
#[derive(Debug)]
pub struct ColMajorMut<'a> {
    data: &'a mut [f64],
    rows: usize,
    cols: usize,
}

impl<'a> ColMajorMut<'a> {
    /// Views the first `rows * cols` values of `data`.
    ///
    /// # Panics
    /// If `data` is shorter.
    #[inline(always)]
    pub fn new(data: &'a mut [f64], rows: usize, cols: usize) -> Self {
        ColMajorMut {
            data: &mut data[..rows * cols],
            rows,
            cols,
        }
    }
    /// Number of rows.
    #[inline(always)]
    pub fn rows(&self) -> usize {
        self.rows
    }
    /// Number of columns.
    #[inline(always)]
    pub fn cols(&self) -> usize {
        self.cols
    }
    /// Column `j`, mutable.
    #[inline(always)]
    pub fn col_mut(&mut self, j: usize) -> &mut [f64] {
        &mut self.data[j * self.rows..(j + 1) * self.rows]
    }
    /// Columns `..j` (read) and column `j` (write), for solves that combine finished columns
    /// into the next.
    #[inline(always)]
    pub fn split_at_col(&mut self, j: usize) -> (ColMajor<'_>, &mut [f64]) {
        let (done, rest) = self.data.split_at_mut(j * self.rows);
        (
            ColMajor {
                data: done,
                rows: self.rows,
                cols: j,
            },
            &mut rest[..self.rows],
        )
    }
    /// Column `j` (write) and columns `j + 1..` (read, re-indexed from 0).
    #[inline(always)]
    pub fn split_after_col(&mut self, j: usize) -> (&mut [f64], ColMajor<'_>) {
        let rows = self.rows;
        let cols = self.cols;
        let (head, done) = self.data.split_at_mut((j + 1) * rows);
        (
            &mut head[j * rows..],
            ColMajor {
                data: done,
                rows,
                cols: cols - j - 1,
            },
        )
    }
    /// The values, column after column.
    #[inline(always)]
    pub fn as_mut_slice(&mut self) -> &mut [f64] {
        self.data
    }
}

/// A row-major `rows x cols` matrix: row `i` is `data[i * cols..(i + 1) * cols]`.
#[derive(Debug, Clone, Copy)]
pub struct RowMajor<'a> {
    data: &'a [f64],
    rows: usize,
    cols: usize,
}

impl<'a> RowMajor<'a> {
    /// Views the first `rows * cols` values of `data`.
    ///
    /// # Panics
    /// If `data` is shorter.
    #[inline(always)]
    pub fn new(data: &'a [f64], rows: usize, cols: usize) -> Self {
        RowMajor {
            data: &data[..rows * cols],
            rows,
            cols,
        }
    }
    /// Number of rows.
    #[inline(always)]
    pub fn rows(&self) -> usize {
        self.rows
    }
    /// Number of columns.
    #[inline(always)]
    pub fn cols(&self) -> usize {
        self.cols
    }
    /// Row `i`.
    #[inline(always)]
    pub fn row(&self, i: usize) -> &'a [f64] {
        &self.data[i * self.cols..(i + 1) * self.cols]
    }
}
