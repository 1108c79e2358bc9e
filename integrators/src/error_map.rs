//! [`ErrorMap`]: how the local-error and Newton tests of every method see a state — as the
//! quantities a user reads (cell stretches) rather than as raw unknowns (positions).
//!
//! By default each component `i` of an error vector `e` is measured against
//! `rtol·|y_i| + atol_i`. For a line of cells that makes the tolerance depend on where the
//! origin is, and near the far end of a long line `rtol·|x|` is larger than a whole cell. A
//! problem may instead declare, per component, one of three [`Row`]s:
//!
//! * [`Row::Own`] — the default test, `e_i / (rtol·|y_i| + atol_i)` (internal variables such as
//!   a growth factor keep it);
//! * [`Row::Difference`] — the component is the far end of a cell whose near end is component
//!   `p`: the tested quantity is `(e_i − e_p) / (rtol·|y_i − y_p| + atol_i)`, which is the
//!   stretch error `(e_i − e_p)/L₀` against `rtol·|λ| + atol/L₀`; with the per-component
//!   tolerance `atol_i = a·L₀` of a position (as celltissue's arrays give) it is exactly
//!   `δλ / (rtol·|λ| + a)`, the contract of `docs/model.md §8.1`;
//! * [`Row::Anchor`] — a component with no free neighbour (the first free boundary of a line):
//!   `e_i / (rtol·ℓ + atol_i)` with `ℓ` the size of its cell, i.e. its position to `rtol`
//!   cell lengths (a stretch of order one), independent of where it is.
//!
//! Differences and anchors make the tests translation invariant: adding a constant to every
//! position changes no weight and no tested quantity. Everything is O(n) with no allocation per
//! step: the map is built once per problem dimension (at the start and after every resize)
//! and read as one `i32` per component.
//!
//! ```
//! use integrators::error_map::{ErrorMap, Row};
//! use integrators::ErrorNorm;
//! // three positions of a line whose left end is fixed: x₁ (anchor, cell length 1), x₂, x₃
//! let map = ErrorMap::from_rows(vec![
//!     Row::Anchor { size: 1.0 },
//!     Row::Difference { partner: 0 },
//!     Row::Difference { partner: 1 },
//! ])
//! .unwrap();
//! // a rigid shift of x₂ and x₃ by 0.5 is no error of cells 3; cell 2 sees it
//! let w = [1.0; 3];
//! assert_eq!(map.norm(&[0.0, 0.5, 0.5], &w, ErrorNorm::Max), 0.5);
//! // weights: rtol·|x_i − x_p| + atol_i, or rtol·ℓ + atol_i for the anchor
//! let y = [1.0, 3.0, 4.0];
//! let mut wt = [0.0; 3];
//! let mut map = map;
//! let eatol = map.effective_atol(&[0.1; 3], 0.5);
//! map.weights(&y, &eatol, 0.5, 0, &mut wt);
//! assert_eq!(wt, [1.0 / 0.6, 1.0 / 1.1, 1.0 / 0.6]);
//! ```

use crate::options::ErrorNorm;

/// How one component enters the local-error and Newton tests (see the [module](self) docs).
///
/// ```
/// use integrators::{ErrorMap, Row};
/// // three boundaries of a line of cells: x₀ anchored (cell size 1), x₁ and x₂ through their cells
/// let map = ErrorMap::from_rows(vec![
///     Row::Anchor { size: 1.0 },
///     Row::Difference { partner: 0 },
///     Row::Difference { partner: 1 },
/// ]).unwrap();
/// assert_eq!(map.len(), 3);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Row {
    /// Measured on its own against `rtol·|y_i| + atol_i` (the default).
    Own,
    /// Measured as the difference with component `partner` (the other end of its cell).
    Difference {
        /// Index of the other end of the cell (≠ the row's own index).
        partner: usize,
    },
    /// Measured on its own against `rtol·size + atol_i`, independent of `y_i`.
    Anchor {
        /// The size of the row's cell (> 0, finite), in the units of the component.
        size: f64,
    },
}

/// Marker of an own row in [`ErrorMap::back`].
const OWN: i32 = 0;
/// Marker of an anchor row in [`ErrorMap::back`].
const ANCHOR: i32 = i32::MIN;
/// Rows per segment of the norm and weight passes (see `ErrorMap::segments`).
const SEG: usize = 256;

/// What the rows of one segment of the norm and weight passes are (`ErrorMap::segments`).
#[derive(Clone, Copy)]
enum Segment {
    /// Every row a difference row with its partner this many rows back.
    Difference(usize),
    /// Every row an own row or a difference row with its partner this many rows back.
    OwnOrDifference(usize),
    /// Anything else: each row looked up.
    Mixed,
}

/// A prescribed position `t ↦ X(t)` (a wall, a moving end) that an end row's cell reaches to
/// ([`ErrorMap::with_end_at`]).
///
/// ```
/// use integrators::error_map::Position;
/// let wall: Position = std::sync::Arc::new(|_t| 0.0);
/// assert_eq!(wall(3.0), 0.0);
/// ```
pub type Position = std::sync::Arc<dyn Fn(f64) -> f64 + Send + Sync>;

/// A [`Position`] that does not move (a wall, a base, a ring's pinned seam).
///
/// ```
/// use integrators::error_map::fixed;
/// assert_eq!(fixed(2.5)(10.0), 2.5);
/// ```
pub fn fixed(x: f64) -> Position {
    std::sync::Arc::new(move |_| x)
}

/// One end row of an [`ErrorMap`]: the row whose own error is the stretch error of a cell
/// with no other unknown end, that cell's reference size, and where its other end is.
#[derive(Clone)]
struct End {
    row: usize,
    size: f64,
    at: Option<Position>,
    /// A seam ([`ErrorMap::with_seam`]): the cell's other end is this component moved by
    /// `offset`, and the tested quantity is the difference of the two errors.
    seam: Option<(usize, f64)>,
}

impl std::fmt::Debug for End {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("End")
            .field("row", &self.row)
            .field("size", &self.size)
            .field("at", &self.at.as_ref().map(|_| "Position"))
            .field("seam", &self.seam)
            .finish()
    }
}

impl PartialEq for End {
    /// Positions compare by identity (a closure has no value to compare).
    fn eq(&self, other: &Self) -> bool {
        self.row == other.row
            && self.size == other.size
            && self.seam == other.seam
            && match (&self.at, &other.at) {
                (None, None) => true,
                (Some(a), Some(b)) => std::sync::Arc::ptr_eq(a, b),
                _ => false,
            }
    }
}

/// Per-component description of the quantities the error tests measure (see the
/// [module](self) docs). Built by a [`crate::Problem`] through
/// [`crate::Problem::error_map`]; an empty map (the default) is the identity.
///
/// ```
/// use integrators::{ErrorMap, Row};
/// // three boundaries of a line: the first measured in cells of size 1, the others by the
/// // stretch of the cell to their left
/// let map = ErrorMap::from_rows(vec![Row::Anchor { size: 1.0 }, Row::Difference { partner: 0 },
///                                    Row::Difference { partner: 1 }]).unwrap();
/// assert!(ErrorMap::from_rows(vec![Row::Difference { partner: 5 }]).is_err()); // no such row
/// let _ = map;
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ErrorMap {
    /// Per row: [`OWN`], [`ANCHOR`], or `i − partner` (non-zero) of a difference row.
    back: Vec<i32>,
    /// Anchor rows and their sizes.
    anchors: Vec<(usize, f64)>,
    /// The largest backward partner offset `i − partner` (0 if none).
    max_back: usize,
    /// Extra quantities: rows whose own error is also tested on its own (the last cell before
    /// a prescribed end, the first after a wall), against a fixed size or the distance to a
    /// prescribed position.
    ends: Vec<End>,
    /// `(row, weight)` of the `ends`: `1/(rtol·size + atol_row)`, set by
    /// [`effective_atol`](Self::effective_atol), and for an end at a prescribed position
    /// `1/(rtol·|y_row − at(t)| + atol_row)`, set by [`refresh_ends`](Self::refresh_ends).
    end_w: Vec<(usize, f64)>,
    /// `atol_row` of each of the `ends`, set by [`effective_atol`](Self::effective_atol) for
    /// [`refresh_ends`](Self::refresh_ends).
    end_atol: Vec<f64>,
}

/// Why rows do not make an [`ErrorMap`].
///
/// ```
/// use integrators::{ErrorMap, ErrorMapError, Row};
/// let e = ErrorMap::from_rows(vec![Row::Difference { partner: 0 }]).unwrap_err();
/// assert_eq!(e, ErrorMapError::Partner { row: 0, partner: 0, n: 1 }); // a row cannot partner itself
/// ```
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ErrorMapError {
    /// A difference row names itself or a component outside the problem.
    #[error("error map row {row}: partner {partner} must be another component in 0..{n}")]
    Partner {
        /// The row.
        row: usize,
        /// Its partner.
        partner: usize,
        /// The number of components.
        n: usize,
    },
    /// An anchor size is not positive and finite.
    #[error("error map row {row}: anchor size {size} must be positive and finite")]
    Size {
        /// The row.
        row: usize,
        /// Its size.
        size: f64,
    },
    /// A listed row ([`ErrorMap::from_listed_rows`]) out of increasing order or not below `n`.
    #[error("error map row {row}: listed rows must increase and lie in 0..{n}")]
    Listed {
        /// The row.
        row: usize,
        /// Number of components.
        n: usize,
    },
    /// The map has more components than an `i32` offset can address.
    #[error("error map of {0} rows is larger than 2³¹ − 1")]
    TooLarge(usize),
    /// The map's length differs from the problem's dimension.
    #[error("error map has {len} rows but dim() = {n}")]
    Length {
        /// Rows of the map.
        len: usize,
        /// Problem dimension.
        n: usize,
    },
}

impl ErrorMap {
    /// A map from one [`Row`] per component.
    ///
    /// ```
    /// use integrators::{ErrorMap, Row};
    /// // boundaries x₁, x₂ of a line whose wall x₀ = 0 is fixed: x₁ anchored in cells of size 1,
    /// // x₂ through its cell x₂ − x₁
    /// let map = ErrorMap::from_rows(vec![Row::Anchor { size: 1.0 }, Row::Difference { partner: 0 }]).unwrap();
    /// assert_eq!((map.row(0), map.row(1)), (Row::Anchor { size: 1.0 }, Row::Difference { partner: 0 }));
    /// ```
    pub fn from_rows(rows: Vec<Row>) -> Result<Self, ErrorMapError> {
        Self::from_listed_rows(rows.len(), rows.into_iter().enumerate())
    }

    /// A map of `n` components from the rows that are not [`Row::Own`], as `(index, row)` in
    /// increasing index order: a problem whose own rows are most of them (a line's growth
    /// stretches) builds it without a row per component.
    ///
    /// ```
    /// use integrators::{ErrorMap, ErrorMapError, Row};
    /// // (g₁, x₁, g₂, x₂): the growth stretches own rows, x₁ anchored, x₂ through x₂ − x₁
    /// let map = ErrorMap::from_listed_rows(
    ///     4,
    ///     [(1, Row::Anchor { size: 1.0 }), (3, Row::Difference { partner: 1 })],
    /// )?;
    /// assert_eq!((map.row(0), map.row(3)), (Row::Own, Row::Difference { partner: 1 }));
    /// // listed out of order, or beyond n
    /// let late = ErrorMap::from_listed_rows(4, [(3, Row::Own), (1, Row::Own)]);
    /// assert_eq!(late.unwrap_err(), ErrorMapError::Listed { row: 1, n: 4 });
    /// # Ok::<(), ErrorMapError>(())
    /// ```
    pub fn from_listed_rows(
        n: usize,
        rows: impl IntoIterator<Item = (usize, Row)>,
    ) -> Result<Self, ErrorMapError> {
        if n > i32::MAX as usize {
            return Err(ErrorMapError::TooLarge(n));
        }
        let mut back = vec![OWN; n];
        let mut anchors = Vec::new();
        let mut max_back = 0;
        let mut next = 0;
        for (i, r) in rows {
            if i < next || i >= n {
                return Err(ErrorMapError::Listed { row: i, n });
            }
            next = i + 1;
            back[i] = match r {
                Row::Own => OWN,
                Row::Difference { partner } => {
                    if partner == i || partner >= n {
                        return Err(ErrorMapError::Partner { row: i, partner, n });
                    }
                    max_back = max_back.max(i.saturating_sub(partner));
                    // both < 2³¹, so the difference fits and is non-zero
                    (i as i64 - partner as i64) as i32
                }
                Row::Anchor { size } => {
                    if !(size > 0.0 && size.is_finite()) {
                        return Err(ErrorMapError::Size { row: i, size });
                    }
                    anchors.push((i, size));
                    ANCHOR
                }
            };
        }
        Ok(Self {
            back,
            anchors,
            max_back,
            ends: Vec::new(),
            end_w: Vec::new(),
            end_atol: Vec::new(),
        })
    }

    /// Also tests the error of row `row` on its own against `rtol·size + atol_row`, besides
    /// its row's quantity: the far end of a cell whose other end is prescribed (no unknown), so
    /// that the cell's stretch error (the row's own error over `size`) is controlled too. The
    /// norm then has one more term (an RMS norm still divides by the number of rows).
    ///
    /// ```
    /// use integrators::{ErrorMap, Row};
    /// // boundaries x₁, x₂ of a line whose wall x₀ = 0 is fixed: x₁ anchored in cells of size 1,
    /// // x₂ through its cell x₂ − x₁
    /// let map = ErrorMap::from_rows(vec![Row::Anchor { size: 1.0 }, Row::Difference { partner: 0 }]).unwrap();
    /// // x₂'s far cell ends at a prescribed end: test x₂'s own error against that cell's size too
    /// let map = map.with_end(1, 1.0).unwrap();
    /// assert_eq!(map.len(), 2);
    /// assert!(ErrorMap::from_rows(vec![Row::Own]).unwrap().with_end(5, 1.0).is_err()); // no row 5
    /// ```
    pub fn with_end(mut self, row: usize, size: f64) -> Result<Self, ErrorMapError> {
        if row >= self.back.len() {
            return Err(ErrorMapError::Partner {
                row,
                partner: row,
                n: self.back.len(),
            });
        }
        if !(size > 0.0 && size.is_finite()) {
            return Err(ErrorMapError::Size { row, size });
        }
        self.ends.push(End {
            row,
            size,
            at: None,
            seam: None,
        });
        Ok(self)
    }

    /// Also tests the cell between component `partner` and component `row` moved by `offset`
    /// (a ring's seam cell, from its last free boundary `partner` to the image `x₀ + P` of its
    /// first, `row`): the quantity `e_row − e_partner`, its length error, against
    /// `rtol·|y_row + offset − y_partner| + atol_row`, as every other cell is — a cell that no
    /// [`Row::Difference`] can express, since `row` has its own row already. The weight is set
    /// at each step from the state it starts at ([`refresh_ends`](Self::refresh_ends)); `size`
    /// (the cell's reference length) serves until the first refresh.
    ///
    /// ```
    /// use integrators::{ErrorMap, ErrorNorm, Row};
    /// // a ring of three cells of length 1 (period 3): x₀ anchored, x₁, x₂ through their cells,
    /// // and the seam cell from x₂ to x₀ + 3
    /// let map = ErrorMap::from_rows(vec![
    ///     Row::Anchor { size: 1.0 },
    ///     Row::Difference { partner: 0 },
    ///     Row::Difference { partner: 1 },
    /// ])?;
    /// let mut map = map.with_seam(0, 2, 1.0, 3.0)?;
    /// let eatol = map.effective_atol(&[1e-8; 3], 1e-6);
    /// // the seam cell crushed to 0.1: x₂ = 2.9
    /// let y = [0.0, 1.45, 2.9];
    /// map.refresh_ends(0.0, &y, 1e-6);
    /// let mut w = [0.0; 3];
    /// map.weights(&y, &eatol, 1e-6, 0, &mut w);
    /// // x₂ off by 1e-7, every other boundary exact: the seam cell's error dominates
    /// let got = map.norm(&[0.0, 0.0, 1e-7], &w, ErrorNorm::Max);
    /// assert!((got - 1e-7 / (1e-6 * 0.1 + 1e-8)).abs() < 1e-9 * got);
    /// # Ok::<(), integrators::ErrorMapError>(())
    /// ```
    pub fn with_seam(
        self,
        row: usize,
        partner: usize,
        size: f64,
        offset: f64,
    ) -> Result<Self, ErrorMapError> {
        let n = self.back.len();
        if partner == row || partner >= n || !offset.is_finite() {
            return Err(ErrorMapError::Partner { row, partner, n });
        }
        let mut map = self.with_end(row, size)?;
        if let Some(end) = map.ends.last_mut() {
            end.seam = Some((partner, offset));
        }
        Ok(map)
    }

    /// As [`with_end`](Self::with_end), for a cell whose other end is at the prescribed
    /// position `at(t)` (a wall, a moving end): the row's own error is tested against
    /// `rtol·|y_row − at(t)| + atol_row`, i.e. that cell's stretch error against
    /// `rtol·|λ| + atol/L₀` (the contract of every other cell), not against
    /// `rtol·size + atol_row` as if its stretch were one. A cell crushed to λ = 0.05 at a
    /// prescribed end is then held to its own stretch, twenty times tighter. The weight is set
    /// at each step from the state it starts at ([`refresh_ends`](Self::refresh_ends), which
    /// the solver calls); `size` (the cell's reference length) serves until the first refresh.
    ///
    /// ```
    /// use integrators::{ErrorMap, ErrorNorm, Row};
    /// use std::sync::Arc;
    /// // boundaries x₁, x₂; the end x₃ = l(t) = 3 − t is prescribed
    /// let map = ErrorMap::from_rows(vec![Row::Anchor { size: 1.0 }, Row::Difference { partner: 0 }])?;
    /// let mut map = map.with_end_at(1, 1.0, Arc::new(|t| 3.0 - t))?;
    /// let eatol = map.effective_atol(&[1e-8, 1e-8], 1e-6);
    /// // at t = 0.9 the last cell is crushed to x₃ − x₂ = 0.1: an error of 1e-7 in x₂ is a
    /// // stretch error of 1e-6 against rtol·0.1 + atol
    /// let y = [1.0, 2.0];
    /// map.refresh_ends(0.9, &y, 1e-6);
    /// let mut w = [0.0; 2];
    /// map.weights(&y, &eatol, 1e-6, 0, &mut w);
    /// let got = map.norm(&[1e-7, 1e-7], &w, ErrorNorm::Max);
    /// assert!((got - 1e-7 / (1e-6 * 0.1 + 1e-8)).abs() < 1e-9);
    /// # Ok::<(), integrators::ErrorMapError>(())
    /// ```
    pub fn with_end_at(self, row: usize, size: f64, at: Position) -> Result<Self, ErrorMapError> {
        let mut map = self.with_end(row, size)?;
        if let Some(end) = map.ends.last_mut() {
            end.at = Some(at);
        }
        Ok(map)
    }

    /// The same map for the problem with every position moved by `shift`: each prescribed
    /// position of [`with_end_at`](Self::with_end_at) moves with them, so that the tests stay
    /// translation invariant (a wrapper that shifts a problem's positions shifts its map so).
    ///
    /// ```
    /// use integrators::{ErrorMap, ErrorNorm, Row};
    /// use std::sync::Arc;
    /// let map = ErrorMap::from_rows(vec![Row::Anchor { size: 1.0 }])?.with_end_at(0, 1.0, Arc::new(|_| 2.0))?;
    /// let (mut a, mut b) = (map.clone(), map.translated(1e3));
    /// let (ea, eb) = (a.effective_atol(&[1e-8], 1e-6), b.effective_atol(&[1e-8], 1e-6));
    /// a.refresh_ends(0.0, &[1.5], 1e-6);
    /// b.refresh_ends(0.0, &[1.5 + 1e3], 1e-6);
    /// let (mut wa, mut wb) = ([0.0], [0.0]);
    /// a.weights(&[1.5], &ea, 1e-6, 0, &mut wa);
    /// b.weights(&[1.5 + 1e3], &eb, 1e-6, 0, &mut wb);
    /// let (na, nb) = (a.norm(&[1e-7], &wa, ErrorNorm::Max), b.norm(&[1e-7], &wb, ErrorNorm::Max));
    /// assert!((na - nb).abs() < 1e-9 * na); // the end cell (length 0.5) weighs the same
    /// # Ok::<(), integrators::ErrorMapError>(())
    /// ```
    pub fn translated(mut self, shift: f64) -> Self {
        for end in &mut self.ends {
            if let Some(at) = end.at.take() {
                end.at = Some(std::sync::Arc::new(move |t| at(t) + shift));
            }
        }
        self
    }

    /// Whether some end row is measured against a prescribed position
    /// ([`with_end_at`](Self::with_end_at)) or is a seam ([`with_seam`](Self::with_seam)), so
    /// that [`refresh_ends`](Self::refresh_ends) has work to do.
    ///
    /// ```
    /// use integrators::{ErrorMap, Row};
    /// let map = ErrorMap::from_rows(vec![Row::Anchor { size: 1.0 }])?;
    /// assert!(!map.with_end(0, 1.0)?.has_positions());
    /// let map = ErrorMap::from_rows(vec![Row::Anchor { size: 1.0 }])?;
    /// assert!(map.with_end_at(0, 1.0, std::sync::Arc::new(|_| 0.0))?.has_positions());
    /// # Ok::<(), integrators::ErrorMapError>(())
    /// ```
    pub fn has_positions(&self) -> bool {
        self.ends.iter().any(|e| e.at.is_some() || e.seam.is_some())
    }

    /// Sets the weights of the end rows measured against a prescribed position
    /// ([`with_end_at`](Self::with_end_at)) from state `y` at time `t`:
    /// `1/(rtol·|y_row − at(t)| + atol_row)`, with the `atol` last given to
    /// [`effective_atol`](Self::effective_atol) (which must have been called). O(number of
    /// end rows). A non-finite distance keeps the last weight.
    ///
    /// ```
    /// use integrators::{ErrorMap, ErrorNorm, Row};
    /// use std::sync::Arc;
    /// // one boundary x₁ between a wall at 0 and a fixed end at 2: two cells of size 1
    /// let map = ErrorMap::from_rows(vec![Row::Own])?
    ///     .with_end_at(0, 1.0, Arc::new(|_| 0.0))?
    ///     .with_end_at(0, 1.0, Arc::new(|_| 2.0))?;
    /// let mut map = map;
    /// let eatol = map.effective_atol(&[0.0], 1e-6);
    /// // x₁ = 1.9: the right cell is crushed to 0.1, and its term is the largest
    /// map.refresh_ends(0.0, &[1.9], 1e-6);
    /// let mut w = [0.0];
    /// map.weights(&[1.9], &eatol, 1e-6, 0, &mut w);
    /// let got = map.norm(&[1e-8], &w, ErrorNorm::Max);
    /// assert!((got - 1e-8 / (1e-6 * 0.1)).abs() < 1e-6);
    /// # Ok::<(), integrators::ErrorMapError>(())
    /// ```
    pub fn refresh_ends(&mut self, t: f64, y: &[f64], rtol: f64) {
        let ends = self.ends.iter().zip(&self.end_atol);
        for ((end, &a), w) in ends.zip(self.end_w.iter_mut()) {
            let gap = match (&end.at, end.seam) {
                (_, Some((p, offset))) => Some((y[end.row] + offset - y[p]).abs()),
                (Some(at), None) => Some((y[end.row] - at(t)).abs()),
                (None, None) => None,
            };
            if let Some(gap) = gap {
                let wk = 1.0 / (rtol * gap + a);
                if wk.is_finite() {
                    w.1 = wk;
                }
            }
        }
    }

    /// Number of rows (0 for the identity map).
    ///
    /// ```
    /// use integrators::{ErrorMap, Row};
    /// // boundaries x₁, x₂ of a line whose wall x₀ = 0 is fixed: x₁ anchored in cells of size 1,
    /// // x₂ through its cell x₂ − x₁
    /// let map = ErrorMap::from_rows(vec![Row::Anchor { size: 1.0 }, Row::Difference { partner: 0 }]).unwrap();
    /// assert_eq!(map.len(), 2);
    /// ```
    pub fn len(&self) -> usize {
        self.back.len()
    }

    /// Whether this is the identity map (every row [`Row::Own`], the default test).
    ///
    /// ```
    /// use integrators::{ErrorMap, Row};
    /// // boundaries x₁, x₂ of a line whose wall x₀ = 0 is fixed: x₁ anchored in cells of size 1,
    /// // x₂ through its cell x₂ − x₁
    /// let map = ErrorMap::from_rows(vec![Row::Anchor { size: 1.0 }, Row::Difference { partner: 0 }]).unwrap();
    /// assert!(!map.is_empty());
    /// assert!(ErrorMap::default().is_empty()); // the identity map
    /// ```
    pub fn is_empty(&self) -> bool {
        self.back.is_empty()
    }

    /// The row of component `i`.
    ///
    /// ```
    /// use integrators::{ErrorMap, Row};
    /// // boundaries x₁, x₂ of a line whose wall x₀ = 0 is fixed: x₁ anchored in cells of size 1,
    /// // x₂ through its cell x₂ − x₁
    /// let map = ErrorMap::from_rows(vec![Row::Anchor { size: 1.0 }, Row::Difference { partner: 0 }]).unwrap();
    /// assert_eq!(map.row(1), Row::Difference { partner: 0 });
    /// ```
    pub fn row(&self, i: usize) -> Row {
        match self.back[i] {
            OWN => Row::Own,
            ANCHOR => {
                let k = self
                    .anchors
                    .binary_search_by_key(&i, |&(j, _)| j)
                    .expect("anchor rows are listed");
                Row::Anchor {
                    size: self.anchors[k].1,
                }
            }
            b => Row::Difference {
                partner: (i as i64 - b as i64) as usize,
            },
        }
    }

    /// Checks the map against the problem dimension.
    pub(crate) fn check_len(&self, n: usize) -> Result<(), ErrorMapError> {
        if self.back.len() != n {
            return Err(ErrorMapError::Length {
                len: self.back.len(),
                n,
            });
        }
        Ok(())
    }

    /// The tolerances the weights add to `rtol·|…|`: `atol_i` for own and difference rows,
    /// `rtol·size + atol_i` for anchors (so that an anchor's weight is `1/eatol_i`).
    ///
    /// ```
    /// use integrators::{ErrorMap, Row};
    /// // boundaries x₁, x₂ of a line whose wall x₀ = 0 is fixed: x₁ anchored in cells of size 1,
    /// // x₂ through its cell x₂ − x₁
    /// let map = ErrorMap::from_rows(vec![Row::Anchor { size: 1.0 }, Row::Difference { partner: 0 }]).unwrap();
    /// let mut map = map;
    /// // an anchor adds rtol·size to its tolerance
    /// assert_eq!(map.effective_atol(&[1e-8, 1e-8], 1e-6), [1e-6 + 1e-8, 1e-8]);
    /// ```
    pub fn effective_atol(&mut self, atol: &[f64], rtol: f64) -> Vec<f64> {
        self.end_w = self
            .ends
            .iter()
            .map(|e| (e.row, 1.0 / (rtol * e.size + atol[e.row])))
            .collect();
        self.end_atol = self.ends.iter().map(|e| atol[e.row]).collect();
        let mut e = atol.to_vec();
        for &(i, size) in &self.anchors {
            e[i] = rtol * size + atol[i];
        }
        e
    }

    /// The partner of difference row `i`, `None` for own and anchor rows.
    #[inline(always)]
    fn partner(&self, i: usize) -> Option<usize> {
        let b = self.back[i];
        if b == OWN || b == ANCHOR {
            None
        } else {
            Some((i as i64 - b as i64) as usize)
        }
    }

    /// The weight of component `i` at state `y` (whole vector), with the tolerances of
    /// [`effective_atol`](Self::effective_atol).
    #[inline(always)]
    pub(crate) fn weight(&self, i: usize, y: &[f64], eatol: f64, rtol: f64) -> f64 {
        let b = self.back[i];
        if b == OWN {
            1.0 / (rtol * y[i].abs() + eatol)
        } else if b == ANCHOR {
            1.0 / eatol
        } else {
            let p = (i as i64 - b as i64) as usize;
            1.0 / (rtol * (y[i] - y[p]).abs() + eatol)
        }
    }

    /// Weights of components `lo..lo + w.len()` at state `y` (whole vector), with `eatol`
    /// (whole vector) from [`effective_atol`](Self::effective_atol).
    ///
    /// ```
    /// use integrators::{ErrorMap, Row};
    /// // boundaries x₁, x₂ of a line whose wall x₀ = 0 is fixed: x₁ anchored in cells of size 1,
    /// // x₂ through its cell x₂ − x₁
    /// let map = ErrorMap::from_rows(vec![Row::Anchor { size: 1.0 }, Row::Difference { partner: 0 }]).unwrap();
    /// let mut map = map;
    /// let eatol = map.effective_atol(&[1e-8, 1e-8], 1e-6);
    /// let mut w = [0.0; 2];
    /// map.weights(&[1.0, 2.5], &eatol, 1e-6, 0, &mut w);
    /// // x₂ is weighted by its cell's length 1.5, not by |x₂| = 2.5
    /// assert!((1.0 / w[1] - (1e-6 * 1.5 + 1e-8)).abs() < 1e-20);
    /// ```
    pub fn weights(&self, y: &[f64], eatol: &[f64], rtol: f64, lo: usize, w: &mut [f64]) {
        let hi = lo + w.len();
        self.segments(lo, hi, |a, b, kind| {
            let out = &mut w[a - lo..b - lo];
            match kind {
                Segment::Difference(d) => {
                    for (((wk, &yi), &yp), &ea) in out
                        .iter_mut()
                        .zip(&y[a..b])
                        .zip(&y[a - d..])
                        .zip(&eatol[a..b])
                    {
                        *wk = 1.0 / (rtol * (yi - yp).abs() + ea);
                    }
                }
                Segment::OwnOrDifference(d) => {
                    for ((((wk, &yi), &yp), &ea), &m) in out
                        .iter_mut()
                        .zip(&y[a..b])
                        .zip(&y[a - d..])
                        .zip(&eatol[a..b])
                        .zip(&self.back[a..b])
                    {
                        let q = if m == OWN { yi } else { yi - yp };
                        *wk = 1.0 / (rtol * q.abs() + ea);
                    }
                }
                Segment::Mixed => {
                    for (k, wk) in out.iter_mut().enumerate() {
                        *wk = self.weight(a + k, y, eatol[a + k], rtol);
                    }
                }
            }
        });
    }

    /// How close the tolerances come to the round-off of the tested quantities at state `y`
    /// (whole vector; `eatol` from [`effective_atol`](Self::effective_atol)): the largest,
    /// over the rows, of `ε·(|y_i| + |y_p|)·w_i` for a difference row (the resolution of a
    /// difference of two stored positions against its weight `w_i`), `ε·|y_i|·w_i` for the
    /// others, with the row where it is largest. Near 1 a row's error test measures rounding
    /// noise and no step size passes it reliably; the solver stops before that
    /// ([`crate::ErrorKind::TooMuchAccuracy`]). The identity map is measured as own rows.
    ///
    /// ```
    /// use integrators::{ErrorMap, Row};
    /// // a cell of length 1e-3 between boundaries at 1e4: rtol 1e-12 asks for its stretch to
    /// // 1e-15, below what two positions of size 1e4 resolve (ε·2e4 ≈ 4.4e-12)
    /// let mut map = ErrorMap::from_rows(vec![Row::Own, Row::Difference { partner: 0 }]).unwrap();
    /// let eatol = map.effective_atol(&[0.0, 0.0], 1e-12);
    /// let (ratio, row) = map.roundoff_ratio(&[1e4, 1e4 + 1e-3], &eatol, 1e-12);
    /// assert_eq!(row, 1);
    /// assert!(ratio > 1e3);
    /// // at rtol 1e-6 the same cell is resolved with room to spare
    /// let (ratio, _) = map.roundoff_ratio(&[1e4, 1e4 + 1e-3], &eatol, 1e-6);
    /// assert!(ratio < 1e-2);
    /// ```
    pub fn roundoff_ratio(&self, y: &[f64], eatol: &[f64], rtol: f64) -> (f64, usize) {
        // size / tolerance of a row (ε applied at the end)
        let row = |i: usize| {
            let (yi, ea) = (y[i], eatol[i]);
            match self.back[i] {
                OWN => yi.abs() / (rtol * yi.abs() + ea),
                ANCHOR => yi.abs() / ea,
                _ => {
                    let yp = y[self.partner(i).expect("a difference row")];
                    (yi.abs() + yp.abs()) / (rtol * (yi - yp).abs() + ea)
                }
            }
        };
        // per segment, the largest ratio of its difference rows without a per-row lookup (the
        // check runs every few steps over the whole state); the row itself only where a
        // segment holds the largest so far
        let mut worst = (0.0, 0);
        self.segments(0, y.len(), |a, b, kind| {
            let m = match kind {
                Segment::Difference(d) => y[a..b]
                    .iter()
                    .zip(&y[a - d..])
                    .zip(&eatol[a..b])
                    .map(|((&yi, &yp), &ea)| (yi.abs() + yp.abs()) / (rtol * (yi - yp).abs() + ea))
                    .fold(0.0, f64::max),
                _ => (a..b).map(row).fold(0.0, f64::max),
            };
            if m > worst.0 {
                worst = (m, (a..b).find(|&i| row(i) == m).unwrap_or(a));
            }
        });
        let mut worst = (f64::EPSILON * worst.0, worst.1);
        for (end, &(i, we)) in self.ends.iter().zip(&self.end_w) {
            let partner = end.seam.map_or(0.0, |(p, _)| y[p].abs());
            let r = f64::EPSILON * (y[i].abs() + partner) * we;
            if r > worst.0 {
                worst = (r, i);
            }
        }
        worst
    }

    /// The rows' markers, read one per component by a kernel that holds the error vector in
    /// a buffer; [`offset`](Self::offset) turns one into its partner offset.
    #[inline(always)]
    pub(crate) fn markers(&self) -> &[i32] {
        &self.back
    }

    /// The partner offset `i − partner` of a row marker ([`markers`](Self::markers)), 0 for
    /// own and anchor rows.
    #[inline(always)]
    pub(crate) fn offset(marker: i32) -> i64 {
        if marker == OWN || marker == ANCHOR {
            0
        } else {
            marker as i64
        }
    }

    /// The largest backward partner offset `i − partner` (0 when no partner precedes its row).
    #[inline(always)]
    pub(crate) fn max_back(&self) -> usize {
        self.max_back
    }

    /// The tested quantity of component `i` of error vector `v` (whole vector), unweighted:
    /// `v_i − v_p` for a difference row, `v_i` otherwise.
    #[inline(always)]
    pub(crate) fn quantity(&self, i: usize, v: &[f64]) -> f64 {
        match self.partner(i) {
            Some(p) => v[i] - v[p],
            None => v[i],
        }
    }

    /// The norm of the weighted quantities `q_i·w_i` of error vector `v` (whole vectors):
    /// for the identity map exactly [`ErrorNorm::of`].
    ///
    /// ```
    /// use integrators::{ErrorMap, Row};
    /// // boundaries x₁, x₂ of a line whose wall x₀ = 0 is fixed: x₁ anchored in cells of size 1,
    /// // x₂ through its cell x₂ − x₁
    /// let map = ErrorMap::from_rows(vec![Row::Anchor { size: 1.0 }, Row::Difference { partner: 0 }]).unwrap();
    /// use integrators::ErrorNorm;
    /// // equal errors at both ends of a cell leave its length unchanged: x₂'s row sees 0
    /// let v = [1e-3, 1e-3];
    /// assert_eq!(map.norm(&v, &[1.0, 1.0], ErrorNorm::Max), 1e-3);
    /// assert_eq!(map.norm(&[0.0, 1e-3], &[1.0, 1.0], ErrorNorm::Max), 1e-3);
    /// ```
    pub fn norm(&self, v: &[f64], w: &[f64], norm: ErrorNorm) -> f64 {
        if self.is_empty() {
            return norm.of(v, w);
        }
        assert!(
            v.len() == self.len() && w.len() == self.len(),
            "norm: length mismatch"
        );
        self.norm_range(v, w, norm, 0, v.len())
            .finish(norm, v.len())
    }

    /// Partial norm over rows `lo..hi` (see [`NormSum`]), end rows included.
    pub(crate) fn norm_range(
        &self,
        v: &[f64],
        w: &[f64],
        norm: ErrorNorm,
        lo: usize,
        hi: usize,
    ) -> NormSum {
        let mut s = NormSum::default();
        let mut q = [0.0; SEG];
        self.segments(lo, hi, |a, b, kind| {
            let q = &mut q[..b - a];
            match kind {
                Segment::Difference(d) => {
                    for (((qi, &vi), &vp), &wi) in
                        q.iter_mut().zip(&v[a..b]).zip(&v[a - d..]).zip(&w[a..b])
                    {
                        *qi = (vi - vp) * wi;
                    }
                }
                Segment::OwnOrDifference(d) => {
                    for ((((qi, &vi), &vp), &wi), &m) in q
                        .iter_mut()
                        .zip(&v[a..b])
                        .zip(&v[a - d..])
                        .zip(&w[a..b])
                        .zip(&self.back[a..b])
                    {
                        *qi = (if m == OWN { vi } else { vi - vp }) * wi;
                    }
                }
                Segment::Mixed => {
                    for (k, qi) in q.iter_mut().enumerate() {
                        *qi = self.quantity(a + k, v) * w[a + k];
                    }
                }
            }
            s.push_slice(norm, q);
        });
        self.for_each_end(lo, hi, w, |i, p, we| {
            s.push(norm, (v[i] - p.map_or(0.0, |p| v[p])) * we)
        });
        s
    }

    /// Calls `f(a, b, kind)` for consecutive segments `a..b` of at most [`SEG`] rows covering
    /// `lo..hi`, with the segment's [`Segment`] kind: when every row is a difference row whose
    /// partner is `d` rows back (a line's boundaries), or is that or an own row (a growing
    /// line's boundaries interleaved with the cells' growth stretches), the caller's loop over
    /// the segment has no per-row lookup or branch and vectorises.
    #[inline(always)]
    fn segments(&self, lo: usize, hi: usize, mut f: impl FnMut(usize, usize, Segment)) {
        let mut a = lo;
        while a < hi {
            let b = (a + SEG).min(hi);
            let back = &self.back[a..b];
            // the segment's first difference marker (at most the first two rows are looked
            // at: past them the segment is mixed anyway)
            let first = if back[0] == OWN && b - a > 1 {
                back[1]
            } else {
                back[0]
            };
            let d = Self::offset(first);
            // (folds, not `all`: without the early exit the comparisons run in vector lanes)
            let kind = if d <= 0 || (d as usize) > a {
                Segment::Mixed
            } else if back.iter().fold(true, |same, &m| same & (m == first)) {
                Segment::Difference(d as usize)
            } else if back
                .iter()
                .fold(true, |same, &m| same & ((m == first) | (m == OWN)))
            {
                Segment::OwnOrDifference(d as usize)
            } else {
                Segment::Mixed
            };
            f(a, b, kind);
            a = b;
        }
    }

    /// Calls `f(row, seam partner, weight)` for the end rows (see [`with_end`](Self::with_end))
    /// in `lo..hi`, skipping those where `w` is zero (a suppressed algebraic component); the
    /// caller adds `(error(row) − error(partner))·weight` to its norm (`error(row)·weight`
    /// without a partner).
    #[inline]
    pub(crate) fn for_each_end(
        &self,
        lo: usize,
        hi: usize,
        w: &[f64],
        mut f: impl FnMut(usize, Option<usize>, f64),
    ) {
        for (end, &(i, we)) in self.ends.iter().zip(&self.end_w) {
            if (lo..hi).contains(&i) && w[i] != 0.0 {
                f(i, end.seam.map(|(p, _)| p), we);
            }
        }
    }

    /// The component with the largest weighted quantity (the first NaN if any), for failure
    /// reports.
    ///
    /// ```
    /// use integrators::{ErrorMap, Row};
    /// // boundaries x₁, x₂ of a line whose wall x₀ = 0 is fixed: x₁ anchored in cells of size 1,
    /// // x₂ through its cell x₂ − x₁
    /// let map = ErrorMap::from_rows(vec![Row::Anchor { size: 1.0 }, Row::Difference { partner: 0 }]).unwrap();
    /// // the second cell's length error is the largest
    /// assert_eq!(map.worst(&[1e-4, 5e-3], &[1.0, 1.0]), Some(1));
    /// ```
    pub fn worst(&self, v: &[f64], w: &[f64]) -> Option<usize> {
        let mut best: Option<(usize, f64)> = None;
        for i in 0..v.len() {
            let q = if self.is_empty() {
                v[i]
            } else {
                self.quantity(i, v)
            };
            let x = (q * w[i]).abs();
            let x = if x.is_nan() { f64::INFINITY } else { x };
            if best.is_none_or(|(_, m)| x > m) {
                best = Some((i, x));
            }
        }
        best.map(|(i, _)| i)
    }
}

/// The largest `|x|` of `xs` (0 if empty) and whether any `x` is NaN: exact and independent
/// of the order the entries are visited in, so four running lanes let the loop vectorise.
#[inline(always)]
pub(crate) fn max_abs(xs: &[f64]) -> (f64, bool) {
    let mut m = [0.0f64; 4];
    let mut nan = [false; 4];
    let chunks = xs.chunks_exact(4);
    let rest = chunks.remainder();
    for c in chunks {
        for l in 0..4 {
            let a = c[l].abs();
            nan[l] |= a.is_nan();
            m[l] = if a > m[l] { a } else { m[l] };
        }
    }
    for (l, &x) in rest.iter().enumerate() {
        let a = x.abs();
        nan[l] |= a.is_nan();
        m[l] = if a > m[l] { a } else { m[l] };
    }
    let max = m
        .iter()
        .fold(0.0f64, |acc, &a| if a > acc { a } else { acc });
    (max, nan.iter().any(|&b| b))
}

/// A partial weighted norm: sum of squares (RMS, summed in the order pushed) or running
/// maximum with a NaN flag (max: the flag beside the maximum instead of a NaN-sticky fold takes
/// the NaN test off the dependency chain), mergeable across the halves of a two-thread split.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct NormSum {
    sum: f64,
    max: f64,
    nan: bool,
}

impl NormSum {
    #[inline(always)]
    pub(crate) fn push(&mut self, norm: ErrorNorm, x: f64) {
        match norm {
            ErrorNorm::Rms => self.sum += x * x,
            ErrorNorm::Max => {
                let a = x.abs();
                self.nan |= a.is_nan();
                self.max = if a > self.max { a } else { self.max };
            }
        }
    }

    /// [`push`](Self::push) of every entry of `xs`, in order (the maximum in vector lanes:
    /// exact in any order).
    #[inline(always)]
    pub(crate) fn push_slice(&mut self, norm: ErrorNorm, xs: &[f64]) {
        match norm {
            ErrorNorm::Rms => {
                for &x in xs {
                    self.sum += x * x;
                }
            }
            ErrorNorm::Max => {
                let (m, nan) = max_abs(xs);
                self.nan |= nan;
                self.max = if m > self.max { m } else { self.max };
            }
        }
    }

    pub(crate) fn merge(&mut self, o: &NormSum) {
        self.sum += o.sum;
        self.nan |= o.nan;
        self.max = self.max.max(o.max);
    }

    pub(crate) fn finish(&self, norm: ErrorNorm, n: usize) -> f64 {
        if n == 0 {
            return 0.0;
        }
        match norm {
            ErrorNorm::Rms => (self.sum / n as f64).sqrt(),
            ErrorNorm::Max if self.nan => f64::NAN,
            ErrorNorm::Max => self.max,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line_map(n: usize) -> ErrorMap {
        let mut rows = vec![Row::Anchor { size: 2.0 }];
        rows.extend((1..n).map(|i| Row::Difference { partner: i - 1 }));
        ErrorMap::from_rows(rows).unwrap()
    }

    #[test]
    fn listed_rows_are_the_rows_with_own_rows_left_out() {
        // a growing line's layout (g₁, x₁, g₂, x₂, g₃, x₃): x₁ anchored, x₂, x₃ differenced
        let dense = vec![
            Row::Own,
            Row::Anchor { size: 1.5 },
            Row::Own,
            Row::Difference { partner: 1 },
            Row::Own,
            Row::Difference { partner: 3 },
        ];
        let listed = dense
            .iter()
            .enumerate()
            .filter(|(_, r)| **r != Row::Own)
            .map(|(i, r)| (i, *r));
        let m = ErrorMap::from_listed_rows(6, listed).unwrap();
        assert_eq!(m, ErrorMap::from_rows(dense).unwrap());
        // validated as the dense rows are, and in order within 0..n
        let bad = |rows: &[(usize, Row)]| ErrorMap::from_listed_rows(4, rows.iter().copied());
        assert_eq!(
            bad(&[(1, Row::Difference { partner: 4 })]),
            Err(ErrorMapError::Partner {
                row: 1,
                partner: 4,
                n: 4
            })
        );
        assert_eq!(
            bad(&[(2, Row::Anchor { size: 0.0 })]),
            Err(ErrorMapError::Size { row: 2, size: 0.0 })
        );
        assert_eq!(
            bad(&[(4, Row::Own)]),
            Err(ErrorMapError::Listed { row: 4, n: 4 })
        );
        assert_eq!(
            bad(&[(2, Row::Own), (2, Row::Own)]),
            Err(ErrorMapError::Listed { row: 2, n: 4 })
        );
    }

    #[test]
    fn rows_round_trip_and_are_validated() {
        let rows = vec![
            Row::Own,
            Row::Difference { partner: 2 },
            Row::Difference { partner: 1 },
            Row::Anchor { size: 0.5 },
        ];
        let m = ErrorMap::from_rows(rows.clone()).unwrap();
        assert_eq!((0..4).map(|i| m.row(i)).collect::<Vec<_>>(), rows);
        assert_eq!(
            ErrorMap::from_rows(vec![Row::Difference { partner: 0 }]),
            Err(ErrorMapError::Partner {
                row: 0,
                partner: 0,
                n: 1
            })
        );
        assert!(matches!(
            ErrorMap::from_rows(vec![Row::Own, Row::Difference { partner: 7 }]),
            Err(ErrorMapError::Partner { row: 1, .. })
        ));
        assert!(matches!(
            ErrorMap::from_rows(vec![Row::Anchor { size: f64::NAN }]),
            Err(ErrorMapError::Size { row: 0, .. })
        ));
        assert!(m.check_len(3).is_err() && m.check_len(4).is_ok());
    }

    #[test]
    fn weights_and_norms_are_translation_invariant() {
        let n = 50;
        let mut m = line_map(n);
        let y: Vec<f64> = (0..n)
            .map(|i| 2.0 * i as f64 * (1.0 + 0.01 * i as f64))
            .collect();
        let e: Vec<f64> = (0..n).map(|i| 1e-7 * (i as f64).sin()).collect();
        let ea = m.effective_atol(&vec![1e-8; n], 1e-6);
        let (mut w1, mut w2) = (vec![0.0; n], vec![0.0; n]);
        m.weights(&y, &ea, 1e-6, 0, &mut w1);
        let shifted: Vec<f64> = y.iter().map(|x| x + 1e6).collect();
        m.weights(&shifted, &ea, 1e-6, 0, &mut w2);
        for (a, b) in w1.iter().zip(&w2) {
            // |(x_i + s) − (x_p + s)| differs from |x_i − x_p| by rounding of s only
            assert!((a - b).abs() <= 1e-9 * a, "{a} vs {b}");
        }
        // a rigid shift of the error changes only the anchor's term
        let mut w0 = w1.clone();
        w0[0] = 0.0;
        let e2: Vec<f64> = e.iter().map(|x| x + 1e-3).collect();
        for norm in [ErrorNorm::Max, ErrorNorm::Rms] {
            let a = m.norm(&e, &w0, norm);
            assert!(a > 0.0 && (m.norm(&e2, &w0, norm) - a).abs() <= 1e-8 * a);
        }
    }

    #[test]
    fn an_end_at_a_prescribed_position_is_weighed_by_its_distance_and_moves_with_a_shift() {
        // x₁ (anchor, wall at 0), x₂; the end x₃ = 3 − t is prescribed
        let wall = fixed(0.0);
        let end: Position = std::sync::Arc::new(|t| 3.0 - t);
        let map = ErrorMap::from_rows(vec![
            Row::Anchor { size: 1.0 },
            Row::Difference { partner: 0 },
        ])
        .unwrap()
        .with_end_at(0, 1.0, wall)
        .unwrap()
        .with_end_at(1, 1.0, end)
        .unwrap();
        let (rtol, atol) = (1e-6, [1e-8; 2]);
        let norm_at = |mut m: ErrorMap, t: f64, y: &[f64], e: &[f64]| {
            let ea = m.effective_atol(&atol, rtol);
            m.refresh_ends(t, y, rtol);
            let mut w = [0.0; 2];
            m.weights(y, &ea, rtol, 0, &mut w);
            m.norm(e, &w, ErrorNorm::Max)
        };
        // at t = 0.9 the end cell is x₃ − x₂ = 0.1 long: e₂ = 1e-7 is a stretch error of 1e-6
        // against rtol·0.1 + atol, ten times what the fixed-size test read
        let (y, e) = ([1.0, 2.0], [0.0, 1e-7]);
        let got = norm_at(map.clone(), 0.9, &y, &e);
        assert!(
            (got - 1e-7 / (rtol * 0.1 + 1e-8)).abs() < 1e-9 * got,
            "{got}"
        );
        let fixed = ErrorMap::from_rows(vec![
            Row::Anchor { size: 1.0 },
            Row::Difference { partner: 0 },
        ])
        .unwrap()
        .with_end(1, 1.0)
        .unwrap();
        assert!(got > 8.0 * norm_at(fixed, 0.9, &y, &e));
        // the wall cell: x₁ = 0.05 from the wall
        let got = norm_at(map.clone(), 0.9, &[0.05, 2.0], &[1e-8, 1e-8]);
        assert!(
            (got - 1e-8 / (rtol * 0.05 + 1e-8)).abs() < 1e-9 * got,
            "{got}"
        );
        // shifted positions with the translated map: the same norm to rounding
        let s = 1e6;
        let shifted = norm_at(map.clone().translated(s), 0.9, &[1.0 + s, 2.0 + s], &e);
        let plain = norm_at(map.clone(), 0.9, &y, &e);
        assert!(
            (shifted - plain).abs() < 1e-6 * plain,
            "{shifted} vs {plain}"
        );
        // a non-finite position keeps the last weight
        let nan: Position = std::sync::Arc::new(|_| f64::NAN);
        let mut m = ErrorMap::from_rows(vec![Row::Own])
            .unwrap()
            .with_end_at(0, 2.0, nan)
            .unwrap();
        let _ = m.effective_atol(&[1e-8], rtol);
        m.refresh_ends(0.0, &[1.0], rtol);
        let mut n = 0;
        m.for_each_end(0, 1, &[1.0], |_, _, we| {
            n += 1;
            assert_eq!(we, 1.0 / (rtol * 2.0 + 1e-8));
        });
        assert_eq!(n, 1);
    }

    #[test]
    fn quantities_are_stretch_errors() {
        // cell lengths 2, stretch 1.5: rtol·|Δx| + atol·L₀ = 1e-6·3 + 1e-8·2
        let mut m = line_map(3);
        let y = [0.0, 3.0, 6.0];
        let ea = m.effective_atol(&[2e-8; 3], 1e-6);
        let mut w = [0.0; 3];
        m.weights(&y, &ea, 1e-6, 0, &mut w);
        let e = [0.0, 0.0, 2.0 * 1.5e-6]; // cell 2's stretch off by 1.5e-6 = rtol·λ
        let got = m.norm(&e, &w, ErrorNorm::Max);
        let want = 1.5e-6 / (1e-6 * 1.5 + 1e-8);
        assert!((got - want).abs() < 1e-12, "{got} vs {want}");
        assert_eq!(m.worst(&e, &w), Some(2));
        // identity map = ErrorNorm::of
        let id = ErrorMap::default();
        assert_eq!(id.norm(&e, &w, ErrorNorm::Rms), ErrorNorm::Rms.of(&e, &w));
    }

    #[test]
    fn interleaved_segments_are_the_per_row_weights_and_norms_bitwise() {
        // a growing line's rows: g₁ own, x₁ anchored, then (gⱼ own, xⱼ − xⱼ₋₁) pairs, the last
        // boundary an end row: whole and from every kind of start, the weights and the norms
        // are the rows' own formulas (`weight`, `quantity`) bit for bit, on segments of the
        // own-or-difference kind and mixed ones
        let cells = 2 * SEG + 37;
        let n = 2 * cells;
        let mut rows = vec![(1, Row::Anchor { size: 1.0 })];
        rows.extend((2..cells).map(|c| (2 * c - 1, Row::Difference { partner: 2 * c - 3 })));
        let m = ErrorMap::from_listed_rows(n - 1, rows)
            .unwrap()
            .with_end(n - 3, 0.5)
            .unwrap();
        let n = n - 1;
        let y: Vec<f64> = (0..n)
            .map(|i| {
                if i % 2 == 0 {
                    1.0 + 0.3 * (i as f64).sin()
                } else {
                    i as f64 * 0.6
                }
            })
            .collect();
        let ea: Vec<f64> = (0..n)
            .map(|i| 1e-8 * (1.0 + 0.1 * (i % 7) as f64))
            .collect();
        let v: Vec<f64> = (0..n).map(|i| 1e-6 * ((i as f64) * 0.77).cos()).collect();
        let bits = |x: &[f64]| x.iter().map(|a| a.to_bits()).collect::<Vec<_>>();
        for lo in [0, 1, 2, 3, SEG - 1, SEG, SEG + 1, n - 5] {
            let mut w = vec![0.0; n - lo];
            m.weights(&y, &ea, 1e-6, lo, &mut w);
            let want: Vec<f64> = (lo..n).map(|i| m.weight(i, &y, ea[i], 1e-6)).collect();
            assert_eq!(bits(&w), bits(&want), "lo = {lo}");
            let mut wfull = vec![0.0; n];
            m.weights(&y, &ea, 1e-6, 0, &mut wfull);
            for norm in [ErrorNorm::Max, ErrorNorm::Rms] {
                let got = m.norm_range(&v, &wfull, norm, lo, n);
                let mut want = NormSum::default();
                for (i, &wi) in wfull.iter().enumerate().skip(lo) {
                    want.push(norm, m.quantity(i, &v) * wi);
                }
                m.for_each_end(lo, n, &wfull, |i, p, we| {
                    want.push(norm, (v[i] - p.map_or(0.0, |p| v[p])) * we)
                });
                assert_eq!(
                    got.finish(norm, n).to_bits(),
                    want.finish(norm, n).to_bits(),
                    "lo = {lo} {norm:?}"
                );
            }
        }
    }
}
