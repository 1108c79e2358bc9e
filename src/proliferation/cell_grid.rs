//! [`CellGrid`]: the proliferating continuum on a grid in the **cell-number** coordinate — every
//! segment holds the same number `c` of cells for the whole run, so a division splits a
//! segment in two instead of doubling its density (see the [module docs](super), "A grid in
//! the cell-number coordinate").
//!
//! It is a [`Dividing`] line (the discrete model's division events, O(N + k) splits, history
//! carried across each resize) run on a continuum [`Line`] whose segments are `c` cells wide,
//! with the drags lumped from the `c` boundaries each segment stands for: `K c` at an interior
//! face, `K (c + 1)/2` at a free end (the tip boundary's own drag plus half of its segment's
//! others). With `c = 1` it is the discrete model exactly.
//!
//! With [`CellGrid::coarsen`] set, segments that have all but stopped growing (growth rate
//! below a fraction of the unstressed one, as behind a proliferating rim) are merged in
//! neighbouring pairs of equal cell count ([`Dividing::merge`]), up to a largest segment, so
//! the number of segments follows the growing cells rather than all cells.

use crate::array::CellArray;
use crate::energy::StrainEnergy;
use crate::events::{Dividing, DivisionLog, DivisionRule, EventError};
use crate::line::run::LineModel;
use crate::line::Line;
use crate::scalar::Scalar;
use integrators::{EventAction, ResidualError};

/// The proliferating continuum on a grid in the cell-number coordinate: segments of `c` whole
/// cells that divide as cells do, with lumped drags (`K c` inside, `K (c + 1)/2` at a free end;
/// `c = 1` is the discrete line), and optionally merged where they stop growing
/// ([`CellGrid::coarsen`]). See the [module docs](super), "A grid in the cell-number
/// coordinate".
///
/// ```
/// use celltissue::proliferation::CellGrid;
/// use celltissue::events::AreaDoubling;
/// use celltissue::line::build::{continuum, LineParams};
/// use celltissue::line::run::{integrate, SolveSettings};
/// use celltissue::boundary::RightEnd;
/// use celltissue::cell::TanhGrowth;
/// use celltissue::{ArrayProblem, NeoHookean};
/// use std::sync::Arc;
/// let mut p = LineParams::unit_cells(20);
/// p.right = RightEnd::Free(None);
/// p.k = 1e-5.into();
/// p.growth = Some(Arc::new(TanhGrowth::default()));
/// // 10 segments of 2 cells each
/// let line = continuum(NeoHookean::new(1.0)?, &p, 10)?;
/// let grid = CellGrid::new(line, 20, Box::new(AreaDoubling::default()))?;
/// let mut prob = ArrayProblem::new(grid);
/// let traj = integrate(&mut prob, &SolveSettings::default(), &[0.0, 3.0]);
/// assert!(traj.error.is_none());
/// // every cell divided once (near t = 2.1), each segment in two
/// assert_eq!((prob.array.cells(), prob.array.segments()), (40, 20));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct CellGrid<E: StrainEnergy> {
    /// The segments, dividing as cells do.
    pub dividing: Dividing<E>,
    /// Cells per segment at the start, `c`.
    pub cells_per_segment: usize,
    /// Cells in each segment now (`c`, or a power-of-two multiple after merges).
    pub multiplicity: Vec<usize>,
    /// Merging of segments that no longer grow (default none).
    pub coarsen: Option<Coarsening>,
    /// No division once the line has this many cells (default none; one event may pass it
    /// by the cells of the segments it splits).
    pub max_cells: Option<usize>,
}

/// When [`CellGrid`] merges two neighbouring segments: both grow at less than
/// `growth_below × G(0)`, both hold the same number of cells, and together at most
/// `max_cells`; merges wait until `batch` pairs qualify (each merging event restarts the
/// integrator without its history).
///
/// ```
/// use celltissue::proliferation::Coarsening;
/// let c = Coarsening::default();
/// assert_eq!((c.growth_below, c.max_cells, c.batch), (1e-2, 16, 8));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coarsening {
    /// Growth rate below which a segment may merge, as a fraction of `G(0)`.
    pub growth_below: f64,
    /// Largest number of cells in a merged segment.
    pub max_cells: usize,
    /// Pairs that must qualify before an event merges them.
    pub batch: usize,
}

impl Default for Coarsening {
    fn default() -> Self {
        Self {
            growth_below: 1e-2,
            max_cells: 16,
            batch: 8,
        }
    }
}

impl<E: StrainEnergy> CellGrid<E> {
    /// Wraps a growing continuum line of `n` segments built for `n0` initial cells (`n` must
    /// divide `n0`); segments divide by `rule`, all of a segment's cells at once.
    ///
    /// ```
    /// use celltissue::proliferation::CellGrid;
    /// use celltissue::events::AreaDoubling;
    /// use celltissue::line::{continuum, LineParams};
    /// let mut p = LineParams::unit_cells(10);
    /// p.right = celltissue::boundary::RightEnd::Free(None);
    /// p.growth = Some(std::sync::Arc::new(celltissue::cell::TanhGrowth::default()));
    /// let line = continuum(celltissue::NeoHookean::new(1.0)?, &p, 4)?;
    /// // 10 cells do not fill 4 segments evenly
    /// assert!(CellGrid::new(line, 10, Box::new(AreaDoubling::default())).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn new(line: Line<E>, n0: usize, rule: Box<dyn DivisionRule>) -> Result<Self, EventError> {
        let n = line.n_cells();
        if n == 0 || !n0.is_multiple_of(n) {
            return Err(EventError::Unsupported(format!(
                "{n} segments for {n0} cells: the cell-number grid needs a whole number of \
                 cells per segment (nodes must divide cells)"
            )));
        }
        let mut grid = Self {
            dividing: Dividing::new(line, rule, 0)?,
            cells_per_segment: n0 / n,
            multiplicity: vec![n0 / n; n],
            coarsen: None,
            max_cells: None,
        };
        grid.lump_drags();
        Ok(grid)
    }

    /// Number of cells `N`, the sum of the segments' cell counts.
    pub fn cells(&self) -> usize {
        self.multiplicity.iter().sum()
    }

    /// Number of segments.
    pub fn segments(&self) -> usize {
        self.dividing.line.n_cells()
    }

    /// The division log, with `cells_after` counted in cells.
    pub fn log(&self) -> &DivisionLog {
        &self.dividing.log
    }

    /// Face drags from the segments' own (`k_cell`, which is `K m` for a segment of `m`
    /// cells): the mean of the two neighbours inside, `(m + 1)/(2m)` of the end segment's at
    /// each end. O(n); called after every split, whose new face `Dividing` gives the mean of
    /// the parent's two faces (one of them may be an end's), and every merge.
    fn lump_drags(&mut self) {
        let line = &mut self.dividing.line;
        let k = &line.cells.k_cell;
        let n = k.len();
        let end = |i: usize| {
            let m = self.multiplicity[i] as f64;
            (m + 1.0) / (2.0 * m) * k[i]
        };
        for (b, face) in line.k_face.iter_mut().enumerate() {
            *face = match b {
                0 => end(0),
                b if b == n => end(n - 1),
                b => 0.5 * (k[b - 1] + k[b]),
            };
        }
        line.refresh_uniform_fields();
    }

    /// The pairs to merge now (first segment of each, 1-based), under [`CellGrid::coarsen`].
    fn pairs_to_merge(&self, t: f64, y: &[f64], yp: &[f64]) -> Vec<usize> {
        let (Some(rule), Some(growth)) = (self.coarsen, self.dividing.line.growth()) else {
            return Vec::new();
        };
        let line = &self.dividing.line;
        let limit = rule.growth_below * growth.rate(0.0).0;
        let slow = |j: usize| {
            line.eval_cell(j, t, y, yp)
                .is_ok_and(|c| growth.rate(c.sigma).0 < limit)
        };
        let n = line.n_cells();
        let mut pairs = Vec::new();
        let mut j = 1;
        while j < n {
            let (a, b) = (self.multiplicity[j - 1], self.multiplicity[j]);
            if a == b && a + b <= rule.max_cells && slow(j) && slow(j + 1) {
                pairs.push(j);
                j += 2;
            } else {
                j += 1;
            }
        }
        if pairs.len() < rule.batch {
            pairs.clear();
        }
        pairs
    }
}

impl<E: StrainEnergy> CellArray for CellGrid<E> {
    integrators::forward_problem!(dividing: dim, pattern, residual<S: Scalar>, jacobian(&self),
        atol, algebraic, set_threads, num_events, events, restart_derivative, map_history,
        map_jacobian);
    fn handle_event(
        &mut self,
        t: f64,
        fired: &[usize],
        y: &mut Vec<f64>,
        yp: &[f64],
    ) -> Result<EventAction, ResidualError> {
        let logged = self.dividing.log.records.len();
        let before = self.cells();
        let action = self.dividing.handle_event(t, fired, y, yp)?;
        if matches!(action, EventAction::Resized) {
            // the records of this event, in decreasing index order: each split parent's cells
            // are doubled
            let mut parents: Vec<usize> = Vec::new();
            let mut cells = before;
            for r in &mut self.dividing.log.records[logged..] {
                cells += self.multiplicity[r.parent - 1];
                r.cells_after = cells;
                parents.push(r.parent);
            }
            parents.reverse();
            let mut m = Vec::with_capacity(self.multiplicity.len() + parents.len());
            let mut f = parents.iter().peekable();
            for (i, &c) in self.multiplicity.iter().enumerate() {
                m.push(c);
                if f.next_if(|&&j| j == i + 1).is_some() {
                    m.push(c);
                }
            }
            self.multiplicity = m;
            // the new state's ẏ is not known here; stresses are elastic enough to choose merges
            let zero = vec![0.0; y.len()];
            let pairs = self.pairs_to_merge(t, y, &zero);
            if !pairs.is_empty() {
                self.dividing
                    .merge(&pairs, y)
                    .map_err(|e| ResidualError::Fatal(e.to_string()))?;
                let mut m = Vec::with_capacity(self.multiplicity.len() - pairs.len());
                let mut f = pairs.iter().peekable();
                let mut i = 0;
                while i < self.multiplicity.len() {
                    if f.next_if(|&&j| j == i + 1).is_some() {
                        m.push(self.multiplicity[i] + self.multiplicity[i + 1]);
                        i += 2;
                    } else {
                        m.push(self.multiplicity[i]);
                        i += 1;
                    }
                }
                self.multiplicity = m;
            }
            self.lump_drags();
            // the cap counts cells: once reached, hold `Dividing` at its segment count
            if self.max_cells.is_some_and(|m| self.cells() >= m) {
                self.dividing.max_cells = Some(self.segments());
            }
        }
        Ok(action)
    }
}

impl<E: StrainEnergy> LineModel for CellGrid<E> {
    crate::line::run::forward_line_model!(dividing: initial_state, initial_derivative_guess,
        unknown_name, breakpoints);
    fn observe(
        &self,
        t: f64,
        y: &[f64],
        yp: &[f64],
    ) -> Result<crate::line::observe::Snapshot, ResidualError> {
        let mut s = self.dividing.observe(t, y, yp)?;
        s.cell_counts = Some(self.multiplicity.iter().map(|&m| m as f64).collect());
        Ok(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::boundary::RightEnd;
    use crate::cell::TanhGrowth;
    use crate::events::AreaDoubling;
    use crate::line::build::{continuum, discrete, LineParams};
    use crate::line::run::{integrate, SolveSettings};
    use crate::{ArrayProblem, NeoHookean};
    use std::sync::Arc;

    fn params(k: f64) -> LineParams {
        let mut p = LineParams::unit_cells(20);
        p.right = RightEnd::Free(None);
        p.k = k.into();
        p.growth = Some(Arc::new(TanhGrowth::default()));
        p
    }

    /// One cell per segment: the lumped end drag `(1 + 1)/2 · K` is the discrete tip's `K`,
    /// so every step, division and length is the discrete model's.
    #[test]
    fn one_cell_per_segment_is_the_discrete_line() {
        let times = [0.0, 5.0, 20.0];
        let s = SolveSettings::default();
        let d = discrete(NeoHookean::new(1.0).unwrap(), &params(1e-2)).unwrap();
        let mut dp =
            ArrayProblem::new(Dividing::new(d, Box::new(AreaDoubling::default()), 0).unwrap());
        let dt = integrate(&mut dp, &s, &times);
        let c = continuum(NeoHookean::new(1.0).unwrap(), &params(1e-2), 20).unwrap();
        let mut cp =
            ArrayProblem::new(CellGrid::new(c, 20, Box::new(AreaDoubling::default())).unwrap());
        let ct = integrate(&mut cp, &s, &times);
        assert!(dt.error.is_none() && ct.error.is_none());
        assert!(dp.array.line.n_cells() > 20);
        assert_eq!(cp.array.cells(), dp.array.line.n_cells());
        assert_eq!(ct.stats.steps, dt.stats.steps);
        for (a, b) in ct.snapshots.iter().zip(&dt.snapshots) {
            assert_eq!(a.length(), b.length());
        }
    }

    /// A merge keeps every other boundary, `l` and `Σ L₀g`, and the drag summed over faces.
    #[test]
    fn a_merge_keeps_the_length_the_grown_length_and_the_drag() {
        let line = discrete(NeoHookean::new(1.0).unwrap(), &params(0.5)).unwrap();
        let mut d = Dividing::new(line, Box::new(AreaDoubling::default()), 0).unwrap();
        let mut y = d.line.initial_state();
        for (j, k) in d.line.layout.gi.clone().into_iter().enumerate() {
            y[k] = 1.0 + 0.05 * j as f64;
        }
        let grown = |d: &Dividing<NeoHookean>, y: &[f64]| -> f64 {
            (0..d.line.n_cells())
                .map(|j| d.line.cells.l0[j] * y[d.line.layout.gi[j]])
                .sum()
        };
        let (l, sum, drag) = (
            d.line.boundary(20, 0.0, &y, &y).0,
            grown(&d, &y),
            d.line.k_face.iter().sum::<f64>(),
        );
        d.merge(&[3, 7, 19], &mut y).unwrap();
        assert_eq!(d.line.n_cells(), 17);
        assert_eq!(d.line.boundary(17, 0.0, &y, &y).0, l);
        assert!((grown(&d, &y) - sum).abs() < 1e-13 * sum);
        assert!((d.line.k_face.iter().sum::<f64>() - drag).abs() < 1e-13);
        // boundary 3 (between the merged cells 3 and 4) is gone: the merged segment ends at 4
        assert_eq!(d.line.boundary(3, 0.0, &y, &y).0, 4.0);
        assert_eq!(d.line.cells.l0[2], 2.0);
    }
}
