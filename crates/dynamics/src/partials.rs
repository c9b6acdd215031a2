//! The buffer that effects, linear rates and the model write their partial derivatives into,
//! for the EKF's Jacobians (docs/model.md eqs. (19), (21)).

/// Rows of partial derivatives with respect to the full state, row-major, `cols` wide.
///
/// For rate partials the rows are the 7 navigation-state derivatives; for measurement partials
/// they are the 4 measurement channels.
pub struct Partials<'a> {
    data: &'a mut [f64],
    cols: usize,
}

impl<'a> Partials<'a> {
    /// Wraps a row-major buffer of `data.len() / cols` rows.
    pub fn new(data: &'a mut [f64], cols: usize) -> Self {
        debug_assert_eq!(data.len() % cols, 0);
        Partials { data, cols }
    }
    /// Adds `value` to the partial of row `row` with respect to state `col`.
    #[inline]
    pub fn add(&mut self, row: usize, col: usize, value: f64) {
        self.data[row * self.cols + col] += value;
    }
    /// Number of columns: the row stride, at least the state dimension.
    pub fn cols(&self) -> usize {
        self.cols
    }
}
