//! [`CellGrid`]: the proliferating continuum on a grid in the **cell-number** coordinate — every
//! segment holds a whole number of cells (`c` at the start) that does not change when they
//! divide together, so a division splits a segment in two instead of doubling its density
//! (see the [module docs](super), "A grid in the cell-number coordinate").
//!
//! It is a [`Dividing`] line (the discrete model's division events, O(N + k) splits, history
//! carried across each resize) run on a continuum [`Line`] whose segments are `c` cells wide,
//! with the drags lumped from the `c` boundaries each segment stands for: `K c` at an interior
//! face, `K (c + 1)/2` at a free end (the tip boundary's own drag plus half of its segment's
//! others). With `c = 1` it is the discrete model exactly.
//!
//! With [`CellGrid::coarsen`] set, segments that have all but stopped growing (growth rate
//! below a fraction of the unstressed one, as behind a proliferating rim) are merged in
//! neighbouring pairs ([`Dividing::merge`]), up to a largest segment, so the number of
//! segments follows the growing cells rather than all cells. A merged segment keeps its
//! members' growth stretches (as constant offsets from its own `g`: they share its stress, so
//! they grow alike) and divides each member when the rule says so, inside the segment: the
//! segment's reference length and cell count grow, nothing is resized. Cells with a Maxwell
//! branch merge with one viscous stretch per segment, their `a_v` weighted by grown length
//! ([`Line::merge_cells`]).

use crate::array::CellArray;
use crate::energy::StrainEnergy;
use crate::events::{Dividing, DivisionLog, DivisionRule, EventError, SplitMix64};
use crate::line::run::LineModel;
use crate::line::Line;
use crate::scalar::Scalar;
use crate::substrate::FreeEndDrag;
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
    /// Cells in each segment now (`c`, or more after merges).
    pub multiplicity: Vec<usize>,
    /// The members of each merged segment (`None` for a segment of `c` cells that share one
    /// phase), in order along the line.
    pub members: Vec<Option<Vec<Member>>>,
    /// Merging of segments that no longer grow (default none).
    pub coarsen: Option<Coarsening>,
    /// Whether a segment's cells divide one by one: set when the rule draws a threshold for
    /// each cell (`random_area`) and segments hold more than one cell. Each segment then
    /// starts as a list of single-cell [`Member`]s with their own thresholds, and a growing
    /// segment that has doubled its cells splits in two (see the [module docs](super)).
    pub asynchronous: bool,
    /// No division once the line has this many cells (default none; one event may pass it
    /// by the cells of the segments it splits).
    pub max_cells: Option<usize>,
}

/// A merged segment splits once the stress change across it exceeds this many merge
/// tolerances ([`Coarsening::stress_within`]). The halves then differ by about twice the
/// tolerance, so they do not merge again until the line has evened out. Measured against the
/// discrete line (N₀ = 100, K = 1e-5 to t = 18 at a tolerance of 1e-2, and K = 1e-8 to t = 14
/// at 1e-3): 2 took 1.5–1.6× the steps of 4, for errors in `N` up to 7× smaller (K = 1e-8)
/// and in `l` up to 1.9× (K = 1e-5); 8 took 0.7–0.8× the steps at up to 2.2× the errors
/// (docs/model.md §8.4).
const SPLIT_SPAN: f64 = 4.0;

/// One of the segments a merged segment was made of: its cells keep their own growth stretch
/// (they grow at the merged segment's rate, so the offset from its `g` is constant) and divide
/// by the rule when that reaches it.
///
/// ```
/// use celltissue::proliferation::Member;
/// let m = Member { l0: 1.0, offset: 0.3, cells: 1, birth: 0.0, threshold: f64::NAN };
/// assert_eq!(m.l0 * (1.2 + m.offset), 1.5); // its grown length when the segment's g is 1.2
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Member {
    /// Reference length.
    pub l0: f64,
    /// Its growth stretch minus the merged segment's.
    pub offset: f64,
    /// Cells it stands for.
    pub cells: usize,
    /// Birth time (for age rules).
    pub birth: f64,
    /// Threshold drawn at birth (`NaN` for deterministic rules; daughters inherit it).
    pub threshold: f64,
}

/// When [`CellGrid`] merges two neighbouring segments: both grow at less than
/// `growth_below × G(0)`, or (with `stress_within`) their stresses differ by at most that
/// fraction of the growth law's stress scale `G(0)/G′(0)`, and together they hold at most
/// `max_cells` cells; merges wait until `batch` pairs qualify (each merging event restarts the
/// integrator without its history).
///
/// The first criterion finds cells that have stopped growing (behind a proliferating rim); the
/// second finds neighbours that grow alike because they bear nearly the same stress (a line
/// under weak drag, where every cell grows): their members then share one stress, at a cost
/// of about `stress_within` of the stress scale when they merge and at most four times that
/// before the segment splits again.
///
/// ```
/// use celltissue::proliferation::Coarsening;
/// let c = Coarsening::default();
/// // θ = 1e-3 holds N exactly on the K = 1e-2 rim to t = 1000 (docs/model.md §8.4)
/// assert_eq!((c.growth_below, c.stress_within, c.max_cells, c.batch), (1e-3, None, 64, 8));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coarsening {
    /// Growth rate below which a segment may merge, as a fraction of `G(0)` (0: none).
    pub growth_below: f64,
    /// Largest stress difference at which two neighbouring segments may merge, as a fraction
    /// of the growth law's stress scale `G(0)/G′(0)` (none: only slow growth merges).
    pub stress_within: Option<f64>,
    /// Largest number of cells in a merged segment.
    pub max_cells: usize,
    /// Pairs that must qualify before an event merges them.
    pub batch: usize,
}

impl Default for Coarsening {
    fn default() -> Self {
        Self {
            growth_below: 1e-3,
            stress_within: None,
            max_cells: 64,
            batch: 8,
        }
    }
}

impl<E: StrainEnergy> CellGrid<E> {
    /// Wraps a growing continuum line of `n` segments built for `n0` initial cells (`n` must
    /// divide `n0`); segments divide by `rule`, all of a segment's cells at once, unless the
    /// rule draws a threshold per cell ([`CellGrid::asynchronous`]). Random thresholds come
    /// from the rule's seed ([`DivisionRule::seed`]).
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
            return Err(Self::uneven(n, n0));
        }
        let c = n0 / n;
        let lengths = (0..n0)
            .map(|k| line.cells.l0[k / c] / c as f64)
            .collect::<Vec<_>>();
        Self::with_cell_lengths(line, &lengths, rule)
    }

    /// As [`CellGrid::new`] for cells of the given reference lengths, `c` consecutive ones per
    /// segment (a line from [`cell_groups`](crate::line::build::cell_groups)): a segment's
    /// cells keep their own lengths where they divide on their own
    /// ([`CellGrid::asynchronous`]).
    ///
    /// ```
    /// use celltissue::proliferation::CellGrid;
    /// use celltissue::events::AreaDoubling;
    /// use celltissue::line::build::{cell_groups, LineParams};
    /// let mut p = LineParams::unit_cells(4);
    /// p.ref_lengths = vec![0.5, 1.5, 1.0, 1.0];
    /// p.right = celltissue::boundary::RightEnd::Free(None);
    /// p.growth = Some(std::sync::Arc::new(celltissue::cell::TanhGrowth::default()));
    /// let line = cell_groups(celltissue::NeoHookean::new(1.0)?, &p, 2)?;
    /// let grid = CellGrid::with_cell_lengths(line, &p.ref_lengths, Box::new(AreaDoubling::default()))?;
    /// assert_eq!((grid.segments(), grid.cells()), (2, 4));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn with_cell_lengths(
        line: Line<E>,
        lengths: &[f64],
        rule: Box<dyn DivisionRule>,
    ) -> Result<Self, EventError> {
        let (n, n0) = (line.n_cells(), lengths.len());
        if n == 0 || !n0.is_multiple_of(n) {
            return Err(Self::uneven(n, n0));
        }
        let c = n0 / n;
        let draws = !rule.draw_threshold(&mut SplitMix64::new(0)).is_nan();
        let seed = rule.seed();
        // a segment stands for its cells, not one cell: no lineage
        let mut dividing = Dividing::new(line, rule, seed)?;
        dividing.lineage = None;
        let mut grid = Self {
            dividing,
            cells_per_segment: c,
            multiplicity: vec![c; n],
            members: vec![None; n],
            coarsen: None,
            asynchronous: draws && c > 1,
            max_cells: None,
        };
        if grid.asynchronous {
            // c single cells per segment, each with its own threshold
            for j in 0..n {
                let list = lengths[j * c..(j + 1) * c]
                    .iter()
                    .map(|&l0| Member {
                        l0,
                        offset: 0.0,
                        cells: 1,
                        birth: 0.0,
                        threshold: grid.dividing.draw_threshold(),
                    })
                    .collect();
                grid.members[j] = Some(list);
            }
        }
        grid.lump_drags();
        Ok(grid)
    }

    fn uneven(n: usize, n0: usize) -> EventError {
        EventError::Unsupported(format!(
            "{n} segments for {n0} cells: the cell-number grid needs a whole number of \
             cells per segment (nodes must divide cells)"
        ))
    }

    /// Number of cells `N`, the sum of the segments' cell counts.
    ///
    /// ```
    /// use celltissue::proliferation::CellGrid;
    /// use celltissue::events::AreaDoubling;
    /// use celltissue::line::{continuum, LineParams};
    /// let mut p = LineParams::unit_cells(12);
    /// p.right = celltissue::boundary::RightEnd::Free(None);
    /// p.growth = Some(std::sync::Arc::new(celltissue::cell::TanhGrowth::default()));
    /// let line = continuum(celltissue::NeoHookean::new(1.0)?, &p, 4)?;
    /// let grid = CellGrid::new(line, 12, Box::new(AreaDoubling::default()))?;
    /// assert_eq!(grid.cells(), 12); // 4 segments of 3 cells
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn cells(&self) -> usize {
        self.multiplicity.iter().sum()
    }

    /// Number of segments.
    ///
    /// ```
    /// use celltissue::proliferation::CellGrid;
    /// use celltissue::events::AreaDoubling;
    /// use celltissue::line::{continuum, LineParams};
    /// let mut p = LineParams::unit_cells(12);
    /// p.right = celltissue::boundary::RightEnd::Free(None);
    /// p.growth = Some(std::sync::Arc::new(celltissue::cell::TanhGrowth::default()));
    /// let line = continuum(celltissue::NeoHookean::new(1.0)?, &p, 4)?;
    /// let grid = CellGrid::new(line, 12, Box::new(AreaDoubling::default()))?;
    /// assert_eq!(grid.segments(), 4);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn segments(&self) -> usize {
        self.dividing.line.n_cells()
    }

    /// The division log, with `cells_after` counted in cells.
    ///
    /// ```
    /// use celltissue::proliferation::CellGrid;
    /// use celltissue::events::AreaDoubling;
    /// use celltissue::line::{continuum, LineParams};
    /// let mut p = LineParams::unit_cells(12);
    /// p.right = celltissue::boundary::RightEnd::Free(None);
    /// p.growth = Some(std::sync::Arc::new(celltissue::cell::TanhGrowth::default()));
    /// let line = continuum(celltissue::NeoHookean::new(1.0)?, &p, 4)?;
    /// let grid = CellGrid::new(line, 12, Box::new(AreaDoubling::default()))?;
    /// assert!(grid.log().records.is_empty()); // nothing divided yet
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
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
            FreeEndDrag::Cells.end_face(m) / m * k[i]
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

    /// Whether segment `i` (0-based) grows at less than [`CellGrid::coarsen`]'s fraction of
    /// the unstressed rate (`false` without coarsening).
    fn grows_slowly(&self, i: usize, t: f64, y: &[f64], yp: &[f64]) -> bool {
        self.stress(i, t, y, yp)
            .is_some_and(|sigma| self.slow_at(sigma))
    }

    /// Segment `i`'s (0-based) stress, where it evaluates.
    fn stress(&self, i: usize, t: f64, y: &[f64], yp: &[f64]) -> Option<f64> {
        self.dividing
            .line
            .eval_cell(i + 1, t, y, yp)
            .ok()
            .map(|c| c.sigma)
    }

    /// Every segment's stress at `(t, y, ẏ)` (`None` where it does not evaluate).
    fn stresses(&self, t: f64, y: &[f64], yp: &[f64]) -> Vec<Option<f64>> {
        (0..self.segments())
            .map(|i| self.stress(i, t, y, yp))
            .collect()
    }

    /// Whether a segment at stress `sigma` grows at less than [`CellGrid::coarsen`]'s fraction
    /// of the unstressed rate.
    fn slow_at(&self, sigma: f64) -> bool {
        let (Some(rule), Some(growth)) = (self.coarsen, self.dividing.line.growth()) else {
            return false;
        };
        // (0: no merging for slow growth, even where a law's rate falls below zero)
        rule.growth_below > 0.0 && growth.rate(sigma).0 < rule.growth_below * growth.rate(0.0).0
    }

    /// The largest stress difference at which neighbours merge ([`Coarsening::stress_within`]
    /// times the growth law's stress scale `G(0)/G′(0)`), if in-phase merging is on.
    pub(crate) fn stress_tolerance(&self) -> Option<f64> {
        let within = self.coarsen?.stress_within?;
        let (g0, slope) = self.dividing.line.growth()?.rate(0.0);
        (slope > 0.0).then(|| within * g0 / slope)
    }

    /// The pairs to merge now (first segment of each, 1-based), under [`CellGrid::coarsen`];
    /// no segment marked in `fresh` (the halves of this event's splits, which share their
    /// parent's stress until the line has moved) takes part.
    fn pairs_to_merge(&self, t: f64, y: &[f64], yp: &[f64], fresh: &[bool]) -> Vec<usize> {
        let Some(rule) = self.coarsen else {
            return Vec::new();
        };
        let n = self.segments();
        let sigma = self.stresses(t, y, yp);
        let tolerance = self.stress_tolerance();
        let qualify = |a: usize, b: usize| match (sigma[a], sigma[b]) {
            (Some(sa), Some(sb)) => {
                (self.slow_at(sa) && self.slow_at(sb))
                    || tolerance.is_some_and(|tol| (sa - sb).abs() <= tol)
            }
            _ => false,
        };
        let mut pairs = Vec::new();
        let mut j = 1;
        while j < n {
            let (a, b) = (self.multiplicity[j - 1], self.multiplicity[j]);
            let split_now =
                fresh.get(j - 1).is_some_and(|&f| f) || fresh.get(j).is_some_and(|&f| f);
            if a + b <= rule.max_cells && !split_now && qualify(j - 1, j) {
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

    /// The segments to split now (0-based, decreasing). With in-phase merging
    /// ([`Coarsening::stress_within`]): merged segments that still grow and whose stress
    /// profile has grown too wide, the change across them (estimated from a neighbour's stress
    /// difference over the cells between their centres) exceeding [`SPLIT_SPAN`] times the
    /// merge tolerance. Otherwise, when cells divide one by one ([`CellGrid::asynchronous`]):
    /// those that hold at least twice the cells they started with and still grow. A segment
    /// merged because it stopped growing stays whole either way.
    fn segments_to_split(&self, t: f64, y: &[f64], yp: &[f64]) -> Vec<usize> {
        let several = |j: usize| self.members[j].as_ref().is_some_and(|m| m.len() >= 2);
        if let Some(tol) = self.stress_tolerance() {
            let n = self.segments();
            let sigma = self.stresses(t, y, yp);
            let width = |j: usize| self.multiplicity[j] as f64;
            // the stress change across segment j, from its difference to neighbour b
            let span = |j: usize, b: usize| match (sigma[j], sigma[b]) {
                (Some(sj), Some(sb)) => (sj - sb).abs() * width(j) / (0.5 * (width(j) + width(b))),
                _ => 0.0,
            };
            return (0..n)
                .rev()
                .filter(|&j| {
                    several(j)
                        && sigma[j].is_some_and(|sj| !self.slow_at(sj))
                        && ((j > 0 && span(j, j - 1) > SPLIT_SPAN * tol)
                            || (j + 1 < n && span(j, j + 1) > SPLIT_SPAN * tol))
                })
                .collect();
        }
        if !self.asynchronous {
            return Vec::new();
        }
        (0..self.segments())
            .rev()
            .filter(|&j| {
                several(j)
                    && self.multiplicity[j] >= 2 * self.cells_per_segment
                    && !self.grows_slowly(j, t, y, yp)
            })
            .collect()
    }

    /// The members of segment `j` (0-based) as they would enter a merge at state `y`: its own
    /// list, or the segment itself as one member.
    fn members_of(&self, j: usize, y: &[f64]) -> Vec<Member> {
        match &self.members[j] {
            Some(m) => m.clone(),
            None => vec![Member {
                l0: self.dividing.line.cells.l0[j],
                offset: 0.0,
                cells: self.multiplicity[j],
                birth: self.dividing.birth[j],
                threshold: self.dividing.threshold[j],
            }],
        }
        .into_iter()
        .map(|mut m| {
            // offsets are kept relative to the segment's own g until the merge shifts them
            m.offset += y[self.dividing.line.layout.gi[j]];
            m
        })
        .collect()
    }

    /// Merges the pairs `(j, j + 1)` for `j` in `pairs` (1-based): the line, `Dividing`'s
    /// per-cell records, the cell counts and the member lists.
    pub(crate) fn merge(&mut self, pairs: &[usize], y: &mut Vec<f64>) -> Result<(), ResidualError> {
        // members with absolute g before the merge
        let joined: Vec<Vec<Member>> = pairs
            .iter()
            .map(|&j| {
                let mut m = self.members_of(j - 1, y);
                m.extend(self.members_of(j, y));
                m
            })
            .collect();
        self.dividing
            .merge(pairs, y)
            .map_err(|e| ResidualError::Fatal(e.to_string()))?;
        let n_old = self.multiplicity.len();
        let (mut m, mut lists) = (Vec::with_capacity(n_old), Vec::with_capacity(n_old));
        let mut f = pairs.iter().zip(joined).peekable();
        let mut i = 0;
        while i < n_old {
            if let Some((_, mut members)) = f.next_if(|(&j, _)| j == i + 1) {
                // absolute growth stretches to offsets from the merged segment's
                let g = y[self.dividing.line.layout.gi[lists.len()]];
                members.iter_mut().for_each(|mb| mb.offset -= g);
                m.push(self.multiplicity[i] + self.multiplicity[i + 1]);
                lists.push(Some(members));
                i += 2;
            } else {
                m.push(self.multiplicity[i]);
                lists.push(self.members[i].take());
                i += 1;
            }
        }
        self.multiplicity = m;
        self.members = lists;
        Ok(())
    }
}

impl<E: StrainEnergy> CellArray for CellGrid<E> {
    integrators::forward_problem!(dividing: dim, pattern, residual<S: Scalar>, jacobian(&self),
        atol, algebraic, set_threads, num_events, restart_derivative, map_history,
        map_jacobian);
    fn events(&mut self, t: f64, y: &[f64], g: &mut [f64]) {
        let capped = self
            .dividing
            .max_cells
            .is_some_and(|m| self.segments() >= m);
        let geometry = self.geometry(t, y);
        // `Dividing`'s values serve the cap and the in-phase segments of a rule that reads
        // growth and age only; every other value is computed once, below
        if capped || (geometry.is_none() && self.members.iter().any(Option::is_none)) {
            self.dividing.events(t, y, g);
        }
        if capped {
            return;
        }
        for (j, out) in g.iter_mut().enumerate() {
            if self.members[j].is_some() {
                // a segment with members fires when the first of them reaches the rule
                *out = self
                    .member_views(j, t, y, geometry.as_ref())
                    .iter()
                    .map(|v| self.dividing.rule.event(v))
                    .fold(f64::NEG_INFINITY, f64::max);
            } else if let Some(geo) = &geometry {
                // a rule that reads the shape sees one cell of a segment, not the segment
                // (and the neighbouring segments' mean cells as its neighbours)
                *out = self
                    .dividing
                    .rule
                    .event(&self.segment_cell_view(j, t, y, geo));
            }
        }
    }
    fn handle_event(
        &mut self,
        t: f64,
        fired: &[usize],
        y: &mut Vec<f64>,
        yp: &[f64],
    ) -> Result<EventAction, ResidualError> {
        let logged = self.dividing.log.records.len();
        let mut added: Vec<usize> = Vec::new();
        let (merged, plain): (Vec<usize>, Vec<usize>) =
            fired.iter().partition(|&&j| self.members[j].is_some());
        // members of merged segments divide inside them: no resize
        let geometry = self.geometry(t, y);
        for &j in &merged {
            self.divide_members(j, t, y, geometry.as_ref(), &mut added);
        }
        let mut action = if added.is_empty() {
            EventAction::Continue
        } else {
            EventAction::Modified
        };
        let member_records = self.dividing.log.records.len();
        if !plain.is_empty() {
            let a = self.dividing.handle_event(t, &plain, y, yp)?;
            if matches!(a, EventAction::Resized) {
                action = a;
                // the split records, in decreasing index order: each parent's cells doubled
                let mut parents: Vec<usize> = self.dividing.log.records[member_records..]
                    .iter()
                    .map(|r| r.parent)
                    .collect();
                added.extend(parents.iter().map(|&p| self.multiplicity[p - 1]));
                parents.reverse();
                let n = self.multiplicity.len() + parents.len();
                let (mut m, mut lists) = (Vec::with_capacity(n), Vec::with_capacity(n));
                let mut f = parents.iter().peekable();
                for (i, &c) in self.multiplicity.iter().enumerate() {
                    m.push(c);
                    lists.push(self.members[i].take());
                    if f.next_if(|&&j| j == i + 1).is_some() {
                        m.push(c);
                        lists.push(None);
                    }
                }
                self.multiplicity = m;
                self.members = lists;
            }
        }
        let mut cells = self.cells() - added.iter().sum::<usize>();
        for (r, a) in self.dividing.log.records[logged..].iter_mut().zip(&added) {
            cells += a;
            r.cells_after = cells;
        }
        if matches!(action, EventAction::Continue) {
            return Ok(action);
        }
        // the new state's ẏ is not known here; stresses are elastic enough to choose splits
        // and merges
        let mut zero = vec![0.0; y.len()];
        let full = self.segments_to_split(t, y, &zero);
        for &j in &full {
            self.split_full(j, t, y).map_err(ResidualError::Fatal)?;
        }
        // each split added two unknowns
        zero.resize(y.len(), 0.0);
        // the halves of each split (`full` is decreasing: the i-th from its end has i splits
        // before it)
        let mut fresh = vec![false; self.segments()];
        for (i, &j) in full.iter().rev().enumerate() {
            fresh[j + i] = true;
            fresh[j + i + 1] = true;
        }
        let pairs = self.pairs_to_merge(t, y, &zero, &fresh);
        if !pairs.is_empty() {
            self.merge(&pairs, y)?;
        }
        if !full.is_empty() || !pairs.is_empty() {
            action = EventAction::Resized;
        }
        if !merged.is_empty() || !pairs.is_empty() || !full.is_empty() {
            // a member's division changed its segment's g: no history carried across
            self.dividing.forget_last_split();
        }
        self.lump_drags();
        // the cap counts cells: once reached, hold `Dividing` at its segment count
        if self.max_cells.is_some_and(|m| self.cells() >= m) {
            self.dividing.max_cells = Some(self.segments());
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

    /// A merged segment's members divide inside it: the cell count and reference length grow,
    /// `Σ L₀g` and every boundary stay, and the snapshot counts the cells per segment.
    #[test]
    fn members_of_a_merged_segment_divide_inside_it() {
        let line = continuum(NeoHookean::new(1.0).unwrap(), &params(1e-2), 20).unwrap();
        let mut grid = CellGrid::new(line, 20, Box::new(AreaDoubling::default())).unwrap();
        let mut y = grid.dividing.line.initial_state();
        let gi = grid.dividing.line.layout.gi.clone();
        // cells 3 and 4 at g = 1.9 and 1.5, merged: one segment of two cells, g = 1.7
        y[gi[2]] = 1.9;
        y[gi[3]] = 1.5;
        grid.merge(&[3], &mut y).unwrap();
        let k = grid.dividing.line.layout.gi[2];
        assert_eq!((grid.segments(), grid.cells(), y[k]), (19, 20, 1.7));
        // the first member reaches 2 when the segment's g is 1.8
        let mut g = vec![0.0; 19];
        y[k] = 1.8;
        grid.events(0.0, &y, &mut g);
        assert!(g[2].abs() < 1e-12, "{}", g[2]);
        let (l, grown) = (grid.dividing.line.boundary(19, 0.0, &y, &y).0, 2.0 * 1.8);
        let action = grid.handle_event(1.0, &[2], &mut y, &[]).unwrap();
        assert!(matches!(action, EventAction::Modified));
        let k = grid.dividing.line.layout.gi[2];
        assert_eq!((grid.segments(), grid.cells()), (19, 21));
        assert_eq!(grid.dividing.line.boundary(19, 1.0, &y, &y).0, l);
        // reference length 1 + 1 + 1 (two daughters of the member that was at g = 2)
        assert_eq!(grid.dividing.line.cells.l0[2], 3.0);
        assert!((3.0 * y[k] - grown).abs() < 1e-12);
        assert_eq!(grid.log().records.last().unwrap().cells_after, 21);
        let snap = grid.observe(1.0, &y, &vec![0.0; y.len()]).unwrap();
        assert_eq!(snap.cell_counts.unwrap()[2], 3.0);
    }

    /// In-phase merging: neighbours within the tolerance merge (unless just split); a merged
    /// segment splits once the stress across it exceeds four tolerances, unless it merged
    /// because it stopped growing.
    #[test]
    fn in_phase_segments_merge_and_split_by_their_stresses() {
        let line = continuum(NeoHookean::new(1.0).unwrap(), &params(1e-2), 20).unwrap();
        let mut grid = CellGrid::new(line, 20, Box::new(AreaDoubling::default())).unwrap();
        grid.coarsen = Some(Coarsening {
            growth_below: 0.0,
            stress_within: Some(1e-2),
            max_cells: 64,
            batch: 1,
        });
        // the tanh law's stress scale is σ₀ = 0.1, so the tolerance is 1e-3
        assert!((grid.stress_tolerance().unwrap() - 1e-3).abs() < 1e-15);
        let mut y = grid.dividing.line.initial_state();
        let zero = vec![0.0; y.len()];
        // at rest every stress is 0: every pair qualifies, none that was just split
        let all: Vec<usize> = (1..20).step_by(2).collect();
        assert_eq!(grid.pairs_to_merge(0.0, &y, &zero, &[]), all);
        let mut fresh = vec![false; 20];
        fresh[3] = true;
        let pairs = grid.pairs_to_merge(0.0, &y, &zero, &fresh);
        assert!(!pairs.contains(&3) && !pairs.contains(&4), "{pairs:?}");
        // cells 3 and 4 merged (segment 2, 0-based); then stretch cell 2 (segment 1) by `e`
        grid.merge(&[3], &mut y).unwrap();
        let stretch = |grid: &CellGrid<NeoHookean>, y: &mut Vec<f64>, e: f64| {
            let xi = grid.dividing.line.layout.xi.clone();
            for b in 2..=19 {
                y[xi[b]] += e;
            }
        };
        let zero = vec![0.0; y.len()];
        let sigma = |grid: &CellGrid<NeoHookean>, y: &[f64], j: usize| {
            grid.stress(j, 0.0, y, &zero).unwrap()
        };
        let mut small = y.clone();
        stretch(&grid, &mut small, 1e-5);
        let d = (sigma(&grid, &small, 1) - sigma(&grid, &small, 2)).abs();
        assert!(d > 0.0 && d < 1e-3, "{d}");
        assert!(grid.segments_to_split(0.0, &small, &zero).is_empty());
        let mut large = y.clone();
        stretch(&grid, &mut large, 0.05);
        // across a merged segment of two cells beside one of one: 4/3 of the difference
        let d = (sigma(&grid, &large, 1) - sigma(&grid, &large, 2)).abs();
        assert!(4.0 / 3.0 * d > 4e-3, "{d}");
        assert_eq!(grid.segments_to_split(0.0, &large, &zero), vec![2]);
        // a segment merged because it stopped growing stays whole: compress it far into the
        // law's flat (σ ≪ −σ₀), where it grows at less than 1e-3 of G(0)
        let mut crushed = y.clone();
        let xi = grid.dividing.line.layout.xi.clone();
        for b in 3..=19 {
            crushed[xi[b]] -= 0.6;
        }
        assert!(sigma(&grid, &crushed, 2) < -1.0);
        assert_eq!(grid.segments_to_split(0.0, &crushed, &zero), vec![2]);
        grid.coarsen = Some(Coarsening {
            growth_below: 1e-3,
            ..grid.coarsen.unwrap()
        });
        assert!(grid.segments_to_split(0.0, &crushed, &zero).is_empty());
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
