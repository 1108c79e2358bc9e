//! Where a Jacobian sweep adds its entries ([`EntrySink`]): a whole [`Matrix`], or one of the
//! two column windows of a [`BandMatrix`] ([`BandMatrix::split_columns_mut`]), so that two
//! threads can fill disjoint columns of one band matrix at once (a line's own Jacobian on two
//! threads).

use super::{BandMatrix, Matrix};

/// A matrix, or part of one, that a Jacobian sweep adds entries into.
///
/// ```
/// use integrators::linalg::{EntrySink, Matrix};
/// use integrators::Pattern;
/// fn diagonal(sink: &mut impl EntrySink, rows: std::ops::Range<usize>) {
///     for i in rows {
///         sink.add(i, i, 2.0);
///     }
/// }
/// let mut m = Matrix::zeros(4, &Pattern::Banded { lower: 1, upper: 1 });
/// diagonal(&mut m, 0..4);
/// assert_eq!(m.get(3, 3), 2.0);
/// ```
pub trait EntrySink {
    /// Adds `v` to entry `(i, j)`; an entry outside the sink is a programmer error (panics in
    /// debug builds, ignored in release), as for [`Matrix::add`].
    fn add(&mut self, i: usize, j: usize, v: f64);
}

impl EntrySink for Matrix {
    #[inline(always)]
    fn add(&mut self, i: usize, j: usize, v: f64) {
        Matrix::add(self, i, j, v);
    }
}

/// Columns `first..end` of a [`BandMatrix`], borrowed mutably from
/// [`BandMatrix::split_columns_mut`].
#[derive(Debug)]
pub struct BandColumns<'a> {
    n: usize,
    lower: usize,
    upper: usize,
    ld: usize,
    first: usize,
    end: usize,
    data: &'a mut [f64],
}

impl BandColumns<'_> {
    /// The first column and one past the last.
    pub fn columns(&self) -> (usize, usize) {
        (self.first, self.end)
    }
}

impl EntrySink for BandColumns<'_> {
    #[inline(always)]
    fn add(&mut self, i: usize, j: usize, v: f64) {
        let inside = i < self.n
            && (self.first..self.end).contains(&j)
            && i <= j + self.lower
            && j <= i + self.upper;
        if inside {
            // BandMatrix::index, counted from the window's first column
            self.data[(j - self.first) * self.ld + self.lower + self.upper + i - j] += v;
        } else {
            debug_assert!(
                false,
                "entry ({i}, {j}) is outside columns {}..{} of the band",
                self.first, self.end
            );
        }
    }
}

impl BandMatrix {
    /// The columns `0..c` and `c..n` as two windows that can be filled at once (`c` is
    /// clamped to `n`). The band's storage is by column, so the windows are the two halves of
    /// it; an entry lands where [`Matrix::add`] would put it.
    ///
    /// ```
    /// use integrators::linalg::{BandMatrix, EntrySink};
    /// let mut b = BandMatrix::zeros(6, 1, 1);
    /// let (mut left, mut right) = b.split_columns_mut(3);
    /// std::thread::scope(|s| {
    ///     s.spawn(|| left.add(1, 2, 5.0)); // row 1, column 2: the left window
    ///     s.spawn(|| right.add(2, 3, 7.0)); // row 2, column 3: the right one
    /// });
    /// assert_eq!(b.data[b.index(1, 2).unwrap()], 5.0);
    /// assert_eq!(b.data[b.index(2, 3).unwrap()], 7.0);
    /// ```
    pub fn split_columns_mut(&mut self, c: usize) -> (BandColumns<'_>, BandColumns<'_>) {
        let (n, lower, upper, ld) = (self.n, self.lower, self.upper, self.ld());
        let c = c.min(n);
        let (a, b) = self.data.split_at_mut(c * ld);
        let window = |first, end, data| BandColumns {
            n,
            lower,
            upper,
            ld,
            first,
            end,
            data,
        };
        (window(0, c, a), window(c, n, b))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Pattern;

    #[test]
    fn windows_put_every_entry_where_the_matrix_does() {
        for (lower, upper) in [(1, 1), (2, 1), (1, 3)] {
            let n = 11;
            let p = Pattern::Banded { lower, upper };
            let mut whole = Matrix::zeros(n, &p);
            let mut split = Matrix::zeros(n, &p);
            let Matrix::Banded(b) = &mut split else {
                unreachable!()
            };
            let (mut left, mut right) = b.split_columns_mut(5);
            for i in 0..n {
                for j in i.saturating_sub(lower)..(i + upper + 1).min(n) {
                    let v = (i * 31 + j * 7) as f64;
                    whole.add(i, j, v);
                    if j < 5 {
                        left.add(i, j, v);
                    } else {
                        right.add(i, j, v);
                    }
                }
            }
            assert_eq!((left.columns(), right.columns()), ((0, 5), (5, n)));
            for i in 0..n {
                for j in 0..n {
                    assert_eq!(whole.get(i, j), split.get(i, j), "({i}, {j})");
                }
            }
        }
    }
}
