//! [`Dividing`]: a growing [`Line`] whose cells divide by a [`DivisionRule`] — one event
//! function per cell, located by the integrator on its dense output; at an event all fired
//! cells are split in one O(N + k) pass ([`Line::split_cells`]), the log is written (in
//! decreasing index order), and [`EventAction::Resized`] tells the driver to rebuild its banded
//! workspace for the new size. With [`Dividing::carry_history`] (default) the resize is mapped
//! (`map_history`: the interpolated `ẏ` carried onto the new layout) and BDF goes on from it
//! with a step-doubled first step; otherwise the driver restarts with a consistent `ẏ`
//! (docs/model.md §2.8–2.9).
//!
//! Per-cell rule state (birth time, random threshold) and the material width `ΔX` of each cell
//! (in initial reference coordinates, halved at each division, so daughters are reported at
//! their material centres `X ∓ ΔX/4`) follow their cells through every insertion.

use super::division::{CellView, DivisionRule, SplitMix64};
use super::lineage::Lineage;
use super::log::DivisionLog;
use super::reindex::{expand_in_place, Ahead};
use super::EventError;
use crate::array::CellArray;
use crate::energy::StrainEnergy;
use crate::line::array::{NONE, PAR_MIN_CELLS};
use crate::line::run::LineModel;
use crate::line::Line;
use crate::observe::DivisionRecord;
use crate::scalar::Scalar;
use integrators::linalg::Matrix;
use integrators::{EventAction, ResidualError};

/// Cells whose division-rule views are built and evaluated per call of
/// [`DivisionRule::event_batch`] (the views live on the stack: 128 of 96 bytes).
const EVENT_CHUNK: usize = 128;

/// Largest change of the division invariants (docs/model.md §5.5) seen over all events, measured
/// just before and just after each split (enable with [`Dividing::check_invariants`]). A
/// division brought forward ([`Dividing::batch_within`]) changes `Σ L₀g` by design, and the
/// boundaries beyond it (on a free end) or its daughters' stretch (otherwise).
///
/// ```
/// use celltissue::boundary::RightEnd;
/// use celltissue::cell::TanhGrowth;
/// use celltissue::events::{AreaDoubling, Dividing, InvariantReport};
/// use celltissue::line::build::{discrete, LineParams};
/// use celltissue::line::run::integrate;
/// use celltissue::{ArrayProblem, NeoHookean, SolveSettings};
/// let mut p = LineParams::unit_cells(10);
/// p.right = RightEnd::Free(None);
/// p.k = 1e-5.into();
/// p.growth = Some(std::sync::Arc::new(TanhGrowth::default()));
/// let line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
/// let mut div = Dividing::new(line, Box::new(AreaDoubling::default()), 0).unwrap();
/// div.check_invariants = Some(InvariantReport::default());
/// let mut prob = ArrayProblem::new(div);
/// assert!(integrate(&mut prob, &SolveSettings::default(), &[0.0, 2.5]).error.is_none());
/// let r = prob.array.check_invariants.unwrap();
/// // every split keeps the boundaries, the length and Σ L₀g, and the daughters' state
/// assert!(r.events > 0 && r.boundary_shift == 0.0 && r.length_change == 0.0);
/// assert!(r.sum_l0g_rel < 1e-14 && r.alpha_jump < 1e-12);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct InvariantReport {
    /// Events checked.
    pub events: usize,
    /// `max |x_b(after) − x_b(before)|` over existing boundaries.
    pub boundary_shift: f64,
    /// `|l(after) − l(before)|`.
    pub length_change: f64,
    /// `|Σ L₀g(after) − Σ L₀g(before)| / Σ L₀g`.
    pub sum_l0g_rel: f64,
    /// `max |α(daughter) − α(parent)|` and over unchanged cells.
    pub alpha_jump: f64,
    /// Same for the elastic stress `σ_el`.
    pub sigma_el_jump: f64,
    /// Same for the elastic pressure `p_el`.
    pub p_el_jump: f64,
}

/// What the last event did to the layout: enough to map a vector of the old layout onto the
/// new one in one O(N + k) pass ([`Dividing`]'s `map_history`).
#[derive(Clone, Debug, Default)]
struct SplitMap {
    /// Cells before the event.
    n_old: usize,
    /// Unknowns per cell: `g` and `x`, and with a Maxwell branch `a_v` between them.
    stride: usize,
    /// Divided cells (old 1-based indices, increasing).
    cells: Vec<usize>,
    /// Each divided cell's `g` at division.
    g_parent: Vec<f64>,
    /// Its daughters' `g` after the split (1 unless split ahead of its time, [`Ahead`]).
    g_daughter: Vec<f64>,
    /// How far the boundaries beyond it moved ([`crate::events::Split::tail_shift`]).
    tail_shift: Vec<f64>,
    /// The old index of every unknown of the new layout (`usize::MAX` for a divided cell's
    /// first `g`, new boundary and second `g`; a daughter's `a_v` is its parent's), or empty if
    /// the layout is not the growing line's `[x₀,] (g₁, [a₁,] x₁, …, g_N, [a_N,] [x_N])`.
    sources: Vec<usize>,
    /// The cells whose Newton-matrix rows are evaluated afresh after the event (new 1-based
    /// indices, merged runs `lo..=hi`): the daughters and three cells on each side.
    runs: Vec<(usize, usize)>,
    /// Per unknown of the new layout, whether its row is in [`SplitMap::runs`].
    fresh: Vec<bool>,
}

impl SplitMap {
    /// Fills [`SplitMap::runs`] and [`SplitMap::fresh`] for the new `layout` of `n` cells: the
    /// daughters of the k-th split (new cells `j + k` and `j + k + 1`) and three cells on each
    /// side.
    fn fill_fresh(&mut self, layout: &crate::line::Layout, n: usize) {
        self.runs.clear();
        for (k, &j) in self.cells.iter().enumerate() {
            let (lo, hi) = ((j + k).saturating_sub(3).max(1), (j + k + 4).min(n));
            match self.runs.last_mut() {
                Some(r) if lo <= r.1 + 1 => r.1 = r.1.max(hi),
                _ => self.runs.push((lo, hi)),
            }
        }
        self.fresh.clear();
        self.fresh.resize(layout.dim, false);
        for &(lo, hi) in &self.runs {
            for c in lo..=hi {
                for k in [layout.gi[c - 1], layout.vi[c - 1], layout.xi[c]] {
                    if k != NONE {
                        self.fresh[k] = true;
                    }
                }
            }
        }
    }

    /// Writes [`SplitMap::sources`] into `src` for a layout with `seam` (a ring's `x₀`, 0 or
    /// 1) and a free or fixed right end, `dim` unknowns after the split.
    fn fill_sources(&self, src: &mut Vec<usize>, seam: usize, free: bool, dim: usize) {
        const NEW: usize = usize::MAX;
        src.clear();
        src.reserve(dim);
        src.extend((0..seam).map(|_| 0));
        let mut divided = self.cells.iter().peekable();
        let stride = self.stride;
        for j in 1..=self.n_old {
            let gk = seam + stride * (j - 1);
            match (divided.next_if(|&&c| c == j).is_some(), stride) {
                (true, 2) => src.extend_from_slice(&[NEW; 3]),
                // each daughter keeps its parent's viscous stretch a_v (at gk + 1)
                (true, _) => src.extend_from_slice(&[NEW, gk + 1, NEW, NEW, gk + 1]),
                (false, _) => src.extend(gk..gk + stride - 1),
            }
            if j < self.n_old || free {
                src.push(gk + stride - 1);
            }
        }
        if src.len() != dim {
            src.clear();
        }
    }
}

/// A growing line with cell division (see the module docs).
///
/// ```no_run
/// use celltissue::events::{AreaDoubling, Dividing};
/// use celltissue::line::build::{discrete, LineParams};
/// use celltissue::line::run::{integrate, SolveSettings};
/// use celltissue::boundary::RightEnd;
/// use celltissue::cell::TanhGrowth;
/// use celltissue::{ArrayProblem, NeoHookean};
/// use std::sync::Arc;
/// let mut p = LineParams::unit_cells(100);
/// p.right = RightEnd::Free(None);
/// p.k = 1e-5.into();
/// p.growth = Some(Arc::new(TanhGrowth::default()));
/// let line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
/// let div = Dividing::new(line, Box::new(AreaDoubling::default()), 0).unwrap();
/// let mut prob = ArrayProblem::new(div);
/// let traj = integrate(&mut prob, &SolveSettings::default(), &[0.0, 3.0]);
/// assert_eq!(prob.array.line.n_cells(), 200);
/// ```
pub struct Dividing<E: StrainEnergy> {
    /// The line (its size changes at every division).
    pub line: Line<E>,
    /// The division rule.
    pub rule: Box<dyn DivisionRule>,
    /// Birth time of each cell.
    pub birth: Vec<f64>,
    /// Threshold of each cell drawn at birth (`NaN` for deterministic rules).
    pub threshold: Vec<f64>,
    /// Material width `ΔX` of each cell in initial reference coordinates.
    pub dx_ref: Vec<f64>,
    /// Each cell's identity and clone (`Some` from [`Dividing::new`]; `None` where the
    /// "cells" are segments of many, as in the cell-number grid, and after a
    /// [`merge`](Dividing::merge)). With it the records name the dividing cell and its
    /// daughters, and the profiles carry each cell's `id`, `ancestor` and `age`.
    pub lineage: Option<Lineage>,
    /// The event log.
    pub log: DivisionLog,
    /// No division once `N` reaches this (default none).
    pub max_cells: Option<usize>,
    /// Initial number of cells.
    pub n0: usize,
    /// Invariant measurements (`Some` to enable; costs O(N) extra per event).
    pub check_invariants: Option<InvariantReport>,
    /// After a division of an inviscid line, restart the integrator from the pre-event
    /// velocities and the smooth velocity of each new boundary (the mean of its neighbours')
    /// instead of the consistent `ẏ` (default `true`; see [`CellArray::restart_derivative`]
    /// on this type). `false` restores the plain consistent restart, for comparison.
    pub smooth_restart: bool,
    /// Carry the integrator's history across each division ([`CellArray::map_history`] on
    /// this type; default `true`). `false` makes every division a restart of the method from
    /// a consistent state, for comparison.
    pub carry_history: bool,
    /// Divisions due within this time after an event are brought forward to it (default 0:
    /// every division at its own located time). A cell is due when its event function,
    /// extrapolated along the event's `ẏ` (and the clock, for age rules), reaches zero within
    /// `batch_within`, at an advance `Δt`. It is split as its own division would have been,
    /// run back over `Δt` ([`Line::split_cells_ahead`]): the daughters start from
    /// `g = 1 − ġΔt` with the reference length of the parent's split at its time, and on a
    /// free end the boundaries beyond move in by the pair's shortfall in grown length, so
    /// stresses stay continuous. Their age runs from the event, so under an age rule a
    /// lineage still comes up to `batch_within` earlier each generation. A change of model,
    /// not of numerics: each such division comes up to `batch_within` early in the cell
    /// count; where divisions are dense (a nearly stress-free line) the length errs at first
    /// order in it, whatever the tolerance, growing with the drag's stress along the line:
    /// about 0.001 of the window relative at 800 cells, 0.056 at 9 000 and 0.071 at 17 350
    /// (K = 1e-8; docs/model.md §2.8). What it buys is fewer events, each a restart of the
    /// integrator's step sequence.
    ///
    /// ```
    /// use celltissue::boundary::RightEnd;
    /// use celltissue::cell::TanhGrowth;
    /// use celltissue::events::{AreaDoubling, Dividing};
    /// use celltissue::line::build::{discrete, LineParams};
    /// use celltissue::line::run::integrate;
    /// use celltissue::{ArrayProblem, NeoHookean, SolveSettings};
    /// let mut p = LineParams::unit_cells(20);
    /// p.right = RightEnd::Free(None);
    /// p.k = 1e-8.into();
    /// p.growth = Some(std::sync::Arc::new(TanhGrowth::default()));
    /// let line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
    /// let mut div = Dividing::new(line, Box::new(AreaDoubling::default()), 0).unwrap();
    /// div.batch_within = 1e-2;
    /// let mut prob = ArrayProblem::new(div);
    /// let traj = integrate(&mut prob, &SolveSettings::default(), &[0.0, 4.0]);
    /// assert!(traj.error.is_none());
    /// // the first generation's 20 divisions, in fewer events
    /// assert_eq!(prob.array.log.len(), 20);
    /// assert!(traj.stats.events < 20, "{} events", traj.stats.events);
    /// ```
    pub batch_within: f64,
    /// The last event's splits, for [`CellArray::map_history`].
    last: Option<SplitMap>,
    /// Boundaries inserted by the last event (indices in the resized line).
    new_boundaries: Vec<usize>,
    /// The integrator's interpolated `ẏ` at the last event, mapped to the resized layout.
    yp_event: Vec<f64>,
    /// Scratch of [`Dividing::due_within`]: the state extrapolated by the window, and the event
    /// functions there (kept across events, so none allocates).
    ahead: Vec<f64>,
    g_ahead: Vec<f64>,
    /// Scratch of [`Dividing::due_within`]: the event values at the event itself.
    g_now: Vec<f64>,
    rng: SplitMix64,
}

impl<E: StrainEnergy> Dividing<E> {
    /// Wraps a growing line or ring; `seed` seeds the rule's random thresholds.
    ///
    /// ```
    /// use celltissue::events::{AreaDoubling, Dividing};
    /// use celltissue::line::{discrete, LineParams};
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(4))?;
    /// // a line that does not grow cannot divide
    /// assert!(Dividing::new(line, Box::new(AreaDoubling::default()), 0).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn new(line: Line<E>, rule: Box<dyn DivisionRule>, seed: u64) -> Result<Self, EventError> {
        if !line.is_growing() {
            return Err(EventError::Unsupported(
                "division without growth: add a growth law".into(),
            ));
        }
        let n = line.n_cells();
        let mut rng = SplitMix64::new(seed);
        let threshold = (0..n).map(|_| rule.draw_threshold(&mut rng)).collect();
        Ok(Self {
            birth: vec![0.0; n],
            threshold,
            dx_ref: line.cells.l0.clone(),
            lineage: Some(Lineage::new(n)),
            log: DivisionLog::default(),
            max_cells: None,
            n0: n,
            check_invariants: None,
            smooth_restart: true,
            carry_history: true,
            batch_within: 0.0,
            last: None,
            new_boundaries: Vec::new(),
            ahead: Vec::new(),
            g_ahead: Vec::new(),
            g_now: Vec::new(),
            yp_event: Vec::new(),
            rng,
            rule,
            line,
        })
    }

    /// Merges each cell `j` of `firsts` with cell `j + 1` ([`Line::merge_cells`]): birth time
    /// the earlier, material width the sum, the first's threshold. The integrator's history is
    /// not carried across this event: the next restart is from a consistent state. A merged
    /// cell is no individual cell: the [`lineage`](Dividing::lineage) is dropped.
    ///
    /// ```
    /// use celltissue::events::{AreaDoubling, Dividing};
    /// use celltissue::line::{discrete, LineParams};
    /// let mut p = LineParams::unit_cells(4);
    /// p.growth = Some(std::sync::Arc::new(celltissue::cell::TanhGrowth::default()));
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &p)?;
    /// let mut d = Dividing::new(line, Box::new(AreaDoubling::default()), 0)?;
    /// let mut y = celltissue::line::run::LineModel::initial_state(&d);
    /// d.merge(&[1, 3], &mut y)?;
    /// assert_eq!((d.line.n_cells(), d.dx_ref.clone()), (2, vec![2.0, 2.0]));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn merge(&mut self, firsts: &[usize], y: &mut Vec<f64>) -> Result<(), EventError> {
        self.line.merge_cells(firsts, y)?;
        let n_old = self.birth.len();
        let (mut birth, mut threshold, mut dx_ref) = (Vec::new(), Vec::new(), Vec::new());
        let mut f = firsts.iter().peekable();
        let mut i = 0;
        while i < n_old {
            if f.next_if(|&&j| j == i + 1).is_some() {
                birth.push(self.birth[i].min(self.birth[i + 1]));
                dx_ref.push(self.dx_ref[i] + self.dx_ref[i + 1]);
                i += 1;
            } else {
                birth.push(self.birth[i]);
                dx_ref.push(self.dx_ref[i]);
            }
            threshold.push(self.threshold[i]);
            i += 1;
        }
        self.birth = birth;
        self.threshold = threshold;
        self.dx_ref = dx_ref;
        self.lineage = None;
        self.last = None;
        self.new_boundaries.clear();
        self.yp_event.clear();
        Ok(())
    }

    /// Drops the last split's map, so the integrator's history is not carried across an
    /// event that also changed the state in a way the map does not know (the next restart is
    /// from a consistent state).
    pub(crate) fn forget_last_split(&mut self) {
        self.last = None;
        self.new_boundaries.clear();
        self.yp_event.clear();
    }

    /// The cells (1-based) whose event function, extrapolated linearly from `(t, y)` along
    /// `yp`, reaches zero within [`Dividing::batch_within`], each with its advance: the time
    /// `Δt ∈ [0, batch_within]` at which its event function, interpolated linearly between
    /// `t` and `t + batch_within`, reaches zero (none when the window is 0 or `yp` is not this
    /// layout's; an error naming the field when it is negative or not finite).
    fn due_within(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
    ) -> Result<Vec<(usize, f64)>, ResidualError> {
        let dt = self.batch_within;
        super::division::check_batch_within(dt).map_err(|e| ResidualError::Fatal(e.to_string()))?;
        if dt == 0.0 || yp.len() != y.len() {
            return Ok(Vec::new());
        }
        let mut ahead = std::mem::take(&mut self.ahead);
        let mut g = std::mem::take(&mut self.g_ahead);
        ahead.clear();
        ahead.extend(y.iter().zip(yp).map(|(a, v)| a + dt * v));
        g.clear();
        g.resize(self.line.n_cells(), 0.0);
        self.events(t + dt, &ahead, &mut g);
        // the event functions at the event, for the advances
        let mut now = std::mem::take(&mut self.g_now);
        now.clear();
        now.resize(g.len(), 0.0);
        if g.iter().any(|&v| v >= 0.0) {
            self.events(t, y, &mut now);
        }
        let due = (0..g.len())
            .filter(|&i| g[i] >= 0.0)
            .map(|i| {
                let (f0, f1) = (now[i], g[i]);
                let advance = if f0 < 0.0 {
                    (dt * -f0 / (f1 - f0)).clamp(0.0, dt)
                } else {
                    0.0
                };
                (i + 1, advance)
            })
            .collect();
        (self.ahead, self.g_ahead, self.g_now) = (ahead, g, now);
        Ok(due)
    }

    /// The growth over each advance of `due` (cells 1-based, with their advance `Δt`), read
    /// from the event's `ẏ`: the parent's `ġΔt`, for the parent and for each daughter (a
    /// daughter grows at its parent's absolute rate `G(σ)`; with viscosity it restarts from
    /// the relative rate, [`Dividing::map_history`], but the parent's absolute rate put the
    /// windowed line's length 1.4–2× nearer the exact-time one's at η = 1, BENCHMARKS.md).
    /// No growth when `yp` is not this layout's (the divisions are then at their time).
    fn growth_ahead(&self, due: &[(usize, f64)], yp: &[f64]) -> Vec<Ahead> {
        let lay = &self.line.layout;
        due.iter()
            .map(|&(j, dt)| {
                let k = lay.gi[j - 1];
                if dt == 0.0 || k == NONE || yp.len() != lay.dim {
                    return Ahead::default();
                }
                let grown = yp[k] * dt;
                Ahead {
                    parent: grown,
                    daughter: grown,
                }
            })
            .collect()
    }

    /// Whether the cap on the number of cells has been reached.
    fn capped(&self) -> bool {
        self.max_cells.is_some_and(|m| self.line.n_cells() >= m)
    }

    /// Length `x_N − x₀` of state `y`.
    fn length(&self, t: f64, y: &[f64]) -> f64 {
        let n = self.line.n_cells();
        self.line.boundary(n, t, y, y).0 - self.line.boundary(0, t, y, y).0
    }

    /// Boundaries, `Σ L₀g` and per-cell `(α, σ_el, p_el)` (elastic: independent of `ẏ`).
    fn elastic(&self, t: f64, y: &[f64]) -> (Vec<f64>, f64, Vec<[f64; 3]>) {
        let line = &self.line;
        let n = line.n_cells();
        let zero = vec![0.0; y.len()];
        let xs = (0..=n).map(|b| line.boundary(b, t, y, &zero).0).collect();
        let mut sum = 0.0;
        let mut cells = Vec::with_capacity(n);
        for j in 1..=n {
            let g = y[line.layout.gi[j - 1]];
            sum += line.cells.l0[j - 1] * g;
            if let Ok(c) = line.eval_cell(j, t, y, &zero) {
                let r = line.energy.line(c.alpha);
                let mu = line.cells.mu[j - 1];
                cells.push([c.alpha, mu * r.sigma, mu * r.pressure]);
            } else {
                cells.push([f64::NAN; 3]);
            }
        }
        (xs, sum, cells)
    }

    /// Splits the cells `asc` (1-based, increasing) in one O(N + k) pass and logs them
    /// (records in decreasing index order, as the cells were split one by one before).
    /// `spare`: the previous event's map, whose vectors are reused.
    fn divide(
        &mut self,
        asc: &[usize],
        ahead: &[Ahead],
        t: f64,
        y: &mut Vec<f64>,
        spare: Option<SplitMap>,
    ) -> Result<(), EventError> {
        let n_old = self.line.n_cells();
        let splits = self.line.split_cells_ahead(asc, ahead, t, y)?;
        // thresholds drawn in decreasing index order, lower daughter first (reproducible)
        let mut draws = vec![(0.0, 0.0); asc.len()];
        for d in draws.iter_mut().rev() {
            let a = self.rule.draw_threshold(&mut self.rng);
            *d = (a, self.rule.draw_threshold(&mut self.rng));
        }
        let k = asc.len();
        // the per-cell records expanded in place, as the line's fields are
        let at: Vec<usize> = asc.iter().map(|&j| j - 1).collect();
        // the parents' ages, read before their daughters' births replace them
        let ages: Vec<f64> = at.iter().map(|&i| t - self.birth[i]).collect();
        let identities = self.lineage.as_mut().map(|l| l.divide(&at));
        // born at the event, also when split ahead (their age runs from when they appear)
        expand_in_place(&mut self.birth, &at, |_, _| [t, t]);
        expand_in_place(&mut self.threshold, &at, |e, _| [draws[e].0, draws[e].1]);
        expand_in_place(&mut self.dx_ref, &at, |e, v| [0.5 * v[at[e]]; 2]);
        for (e, &i) in at.iter().enumerate() {
            // the daughters' material centres X ∓ ΔX/4 (new indices i + e, i + e + 1)
            let c = i + e;
            let (d, x) = (self.dx_ref[c], self.line.cells.x_ref[c]);
            self.line.cells.x_ref[c] = x - 0.5 * d;
            self.line.cells.x_ref[c + 1] = x + 0.5 * d;
        }
        let l = self.length(t, y);
        let x0 = self.line.boundary(0, t, y, y).0;
        for (m, (&j, s)) in asc.iter().zip(&splits).enumerate().rev() {
            self.log.push(DivisionRecord {
                t,
                parent: j,
                x: s.x_new,
                x_over_length: (s.x_new - x0) / l,
                cells_after: n_old + k - m,
                age: Some(ages[m]),
                cell: identities.as_ref().map(|v| v[m].0),
                daughters: identities.as_ref().map(|v| v[m].1),
            });
        }
        // the previous event's map, refilled (its vectors keep their allocations)
        let mut map = spare.unwrap_or_default();
        map.n_old = n_old;
        map.stride = 2 + usize::from(self.line.maxwell.is_some());
        map.cells.clear();
        map.cells.extend_from_slice(asc);
        map.g_parent.clear();
        map.g_parent.extend(splits.iter().map(|s| s.g_parent));
        map.g_daughter.clear();
        map.g_daughter.extend(splits.iter().map(|s| s.g_daughter));
        map.tail_shift.clear();
        map.tail_shift.extend(splits.iter().map(|s| s.tail_shift));
        let seam = usize::from(self.line.layout.xi[0] != NONE);
        let mut src = std::mem::take(&mut map.sources);
        map.fill_sources(
            &mut src,
            seam,
            self.line.right.is_free(),
            self.line.layout.dim,
        );
        map.sources = src;
        // the rows the Jacobian map re-evaluates (read only when the history is carried)
        if self.carry_history {
            map.fill_fresh(&self.line.layout, self.line.n_cells());
        } else {
            map.fresh.clear();
        }
        self.last = Some(map);
        Ok(())
    }

    /// Maps a vector of the layout before the last event onto the current one (see
    /// [`CellArray::map_history`] on this type).
    fn map_split(&self, t: f64, old: &[f64], derivative: bool, new: &mut [f64]) -> bool {
        let Some(m) = &self.last else {
            return false;
        };
        let free = self.line.right.is_free();
        let n_old = m.n_old;
        // the growing layout: a ring's x₀ (without a gauge), then (g₁, [a₁,] x₁, …, g_N,
        // [a_N,] [x_N]), `stride` unknowns per cell
        let seam = usize::from(self.line.layout.xi[0] != NONE);
        let stride = m.stride;
        let dim_old = seam + stride * n_old - usize::from(!free);
        if old.len() != dim_old || new.len() != self.line.layout.dim {
            return false;
        }
        let n_new = self.line.n_cells();
        // the fixed wall (x = 0, ẋ = 0), or the ring's seam x₀ (ẋ₀ in a derivative)
        let x0 = if seam == 1 { old[0] } else { 0.0 };
        let right = |t: f64| {
            if self.line.right.is_periodic() {
                // x_N = x₀ + period, ẋ_N = ẋ₀
                return if derivative {
                    x0
                } else {
                    x0 + self.line.period
                };
            }
            let (x, v) = self.line.boundary::<f64>(n_new, t, &[], &[]);
            if derivative {
                v
            } else {
                x
            }
        };
        if m.sources.len() != new.len() {
            return false;
        }
        // every unknown the split left in place keeps its value
        for (v, &k) in new.iter_mut().zip(&m.sources) {
            if k != usize::MAX {
                *v = old[k];
            }
        }
        // the k-th divided cell j (in increasing order) had its g at old index
        // seam + stride·(j − 1), and the k earlier splits inserted `stride` unknowns each
        // before it (a daughter's a_v came with the sources)
        for (k, ((&j, &gs), &g1)) in m
            .cells
            .iter()
            .zip(&m.g_parent)
            .zip(&m.g_daughter)
            .enumerate()
        {
            let gk = seam + stride * (j - 1);
            let has_x = j < n_old || free;
            let g = old[gk];
            let xl = if j == 1 { x0 } else { old[gk - 1] };
            let xr = if has_x {
                old[gk + stride - 1]
            } else {
                right(t)
            };
            // a daughter starts from g = 1 with its parent's stress: inviscid, that is the
            // parent's rate ġ = G(σ); viscous, the parent's relative rate ġ/g (the
            // Kelvin–Voigt stress reads α̇/α = ℓ̇/ℓ − ġ/g, so the parent's absolute rate would
            // drop the daughters' stress by ηġ/2 at once)
            let viscous = self.line.cells.eta[j - 1 + k] != 0.0;
            let gd = match (derivative, viscous) {
                (true, false) => g,
                (true, true) => g / gs,
                (false, _) => g - gs + g1,
            };
            let w = gk + stride * k;
            new[w] = gd;
            new[w + stride - 1] = 0.5 * (xl + xr);
            new[w + stride] = gd;
        }
        // a value's boundaries beyond a split ahead move with the state's (the new boundary,
        // between the daughters, by half its split's shift)
        if !derivative && m.tail_shift.iter().any(|&d| d != 0.0) {
            let mut cum = 0.0;
            let mut next = m.cells.iter().zip(&m.tail_shift).enumerate().peekable();
            for b in 1..=n_new {
                let mut add = cum;
                if let Some(&(k, (&j, &d))) = next.peek() {
                    if b == j + k {
                        add = cum + 0.5 * d;
                        cum += d;
                        next.next();
                    }
                }
                let kx = self.line.layout.xi[b];
                if kx != NONE {
                    new[kx] += add;
                }
            }
        }
        true
    }

    /// Event values of a rule that reads the cells' geometry and mechanics: one O(N) sweep
    /// evaluating each cell once (its elastic state; the viscous stress with `ẏ = 0`, since
    /// the event functions see only `y`).
    fn mechanical_events(&self, t: f64, y: &[f64], g: &mut [f64]) {
        let line = &self.line;
        let zero = vec![0.0; y.len()];
        let xs = self.boundaries(t, y, &zero);
        for (i, out) in g.iter_mut().enumerate() {
            *out = self.rule.event(&self.cell_view(i, t, y, &zero, &xs));
        }
        debug_assert_eq!(g.len(), line.n_cells());
    }

    /// Every boundary position of state `y` (`N + 1` of them).
    pub(crate) fn boundaries(&self, t: f64, y: &[f64], yp: &[f64]) -> Vec<f64> {
        let n = self.line.n_cells();
        (0..=n).map(|b| self.line.boundary(b, t, y, yp).0).collect()
    }

    /// What the rule sees of cell `i` (0-based) at state `y`, with `xs` its
    /// [`boundaries`](Self::boundaries): growth, age and threshold, and its geometry and
    /// elastic mechanics (the viscous stress at rates `zero`).
    pub(crate) fn cell_view(
        &self,
        i: usize,
        t: f64,
        y: &[f64],
        zero: &[f64],
        xs: &[f64],
    ) -> CellView {
        let line = &self.line;
        let n = line.n_cells();
        let len = |j: usize| -> f64 {
            if (1..=n).contains(&j) {
                xs[j] - xs[j - 1]
            } else {
                f64::NAN
            }
        };
        let j = i + 1;
        let k = line.layout.gi[i];
        let gj = if k == NONE { 1.0 } else { y[k] };
        let mut c = CellView::growth_only(gj * line.g2, t - self.birth[i], self.threshold[i]);
        c.length = len(j);
        c.position = 0.5 * (xs[j - 1] + xs[j]);
        c.neighbour_lengths = [len(j - 1), len(j + 1)];
        if let Ok(e) = line.eval_cell(j, t, y, zero) {
            c.width = e.w;
            c.area = c.length * e.w;
            c.stress = e.sigma;
            c.pressure =
                line.cells.mu[i] * line.energy.line(e.alpha).pressure + line.cells.p_ext[i];
        }
        c
    }

    /// A threshold for a cell born now, from the rule's seeded generator (`NaN` for rules that
    /// draw none): the generator daughters draw from, shared with cells that divide elsewhere
    /// (the proliferating continuum's members).
    pub(crate) fn draw_threshold(&mut self) -> f64 {
        self.rule.draw_threshold(&mut self.rng)
    }

    fn record_invariants(
        &mut self,
        t: f64,
        fired_asc: &[usize],
        before: (Vec<f64>, f64, Vec<[f64; 3]>),
        y: &[f64],
    ) {
        let (xb, sb, cb) = before;
        let (xa, sa, ca) = self.elastic(t, y);
        let Some(rep) = self.check_invariants.as_mut() else {
            return;
        };
        rep.events += 1;
        let nb = cb.len();
        rep.length_change = rep
            .length_change
            .max(((xa[xa.len() - 1] - xa[0]) - (xb[nb] - xb[0])).abs());
        rep.sum_l0g_rel = rep.sum_l0g_rel.max((sa - sb).abs() / sb.abs());
        // old boundary b -> new index b + #(fired cells with index <= b) (1-based cells)
        let mut shift = 0;
        let mut f = fired_asc.iter().peekable();
        for (b, x) in xb.iter().enumerate() {
            if b >= 1 {
                // cell b ends at boundary b; if it divided, the boundaries after it shift
                if f.peek().is_some_and(|&&c| c == b) {
                    f.next();
                    shift += 1;
                }
            }
            rep.boundary_shift = rep.boundary_shift.max((xa[b + shift] - x).abs());
        }
        // old cell c (1-based) -> new c + #(fired < c), daughters at that index and the next
        let mut shift = 0;
        for (c0, old) in cb.iter().enumerate() {
            let c = c0 + 1;
            let divided = fired_asc.binary_search(&c).is_ok();
            let news: &[usize] = if divided { &[0, 1] } else { &[0] };
            for &k in news {
                let new = &ca[c0 + shift + k];
                rep.alpha_jump = rep.alpha_jump.max((new[0] - old[0]).abs());
                rep.sigma_el_jump = rep.sigma_el_jump.max((new[1] - old[1]).abs());
                rep.p_el_jump = rep.p_el_jump.max((new[2] - old[2]).abs());
            }
            if divided {
                shift += 1;
            }
        }
    }
}

impl<E: StrainEnergy> CellArray for Dividing<E> {
    // (the residual is the line's, so is its Jacobian: the line writes it itself)
    integrators::forward_problem!(line: dim, pattern, residual<S: Scalar>, jacobian(&self), atol,
        algebraic, set_threads);
    fn num_events(&self) -> usize {
        self.line.n_cells()
    }
    fn events(&mut self, t: f64, y: &[f64], g: &mut [f64]) {
        if self.capped() {
            g.iter_mut().for_each(|v| *v = -1.0);
            return;
        }
        let g2 = self.line.g2;
        if self.rule.needs_mechanics() {
            self.mechanical_events(t, y, g);
            return;
        }
        let (gi, rule) = (&self.line.layout.gi, &self.rule);
        let (birth, threshold) = (&self.birth, &self.threshold);
        // cells j0.. into `out`, a chunk of views per call of the rule
        let eval = |out: &mut [f64], j0: usize| {
            let mut views = [CellView::growth_only(0.0, 0.0, f64::NAN); EVENT_CHUNK];
            for (c, out) in out.chunks_mut(EVENT_CHUNK).enumerate() {
                let first = j0 + c * EVENT_CHUNK;
                for (view, j) in views.iter_mut().zip(first..first + out.len()) {
                    let k = gi[j];
                    let gj = if k == NONE { 1.0 } else { y[k] };
                    *view = CellView::growth_only(gj * g2, t - birth[j], threshold[j]);
                }
                rule.event_batch(&views[..out.len()], out);
            }
        };
        // every cell's value is its own: two halves give the same values as one sweep
        if g.len() >= PAR_MIN_CELLS && self.line.threads >= 2 {
            let mid = g.len() / 2;
            let (a, b) = g.split_at_mut(mid);
            rayon::join(|| eval(a, 0), || eval(b, mid));
        } else {
            eval(g, 0);
        }
    }
    fn handle_event(
        &mut self,
        t: f64,
        fired: &[usize],
        y: &mut Vec<f64>,
        yp: &[f64],
    ) -> Result<EventAction, ResidualError> {
        // (cell, advance): the fired cells divide at their time, the window's ahead of theirs
        let mut due: Vec<(usize, f64)> = fired.iter().map(|&i| (i + 1, 0.0)).collect();
        due.extend(self.due_within(t, y, yp)?);
        due.sort_unstable_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
        due.dedup_by_key(|d| d.0);
        // with a cap, the highest-index cells divide first (as when split one by one)
        if let Some(cap) = self.max_cells {
            let room = cap.saturating_sub(self.line.n_cells());
            let drop = due.len().saturating_sub(room);
            due.drain(..drop);
        }
        let spare = self.last.take();
        if due.is_empty() {
            return Ok(EventAction::Continue);
        }
        let order: Vec<usize> = due.iter().map(|d| d.0).collect();
        let ahead = self.growth_ahead(&due, yp);
        let before = self.check_invariants.map(|_| self.elastic(t, y));
        let dim_old = y.len();
        self.divide(&order, &ahead, t, y, spare)
            .map_err(|e| ResidualError::Fatal(e.to_string()))?;
        self.yp_event.clear();
        if yp.len() == dim_old {
            self.yp_event.resize(y.len(), 0.0);
            let mut v = std::mem::take(&mut self.yp_event);
            if !self.map_split(t, yp, true, &mut v) {
                v.clear();
            }
            self.yp_event = v;
        }
        // the k-th split in ascending order inserted boundary j + k
        self.new_boundaries.clear();
        self.new_boundaries
            .extend(order.iter().enumerate().map(|(k, &j)| j + k));
        if let Some(b) = before {
            self.record_invariants(t, &order, b, y);
        }
        Ok(EventAction::Resized)
    }

    /// The map of the last division event (see [`integrators::Problem::map_history`]): old
    /// boundaries keep their values; a divided cell's new boundary is the parent's material
    /// midpoint `½(x_{j−1} + x_j)` at every history time (exact: a cell deforms uniformly);
    /// each daughter's `g` is the parent's shifted to 1 at division, `g − g* + 1`, so it keeps
    /// the parent's rate `ġ = G(σ)` (the daughters' stress equals the parent's). Kelvin–Voigt
    /// daughters (`η > 0`) take the parent's relative rate `ġ/g*` instead, which keeps their
    /// stress `σ_e(α) + η(ℓ̇/ℓ − ġ/g)` the parent's (measured on the proliferation bench's line
    /// at η = 1, K = 1e-8, to 10⁴ cells: the absolute rate dropped it by `ηġ/2`, and the first
    /// Newton iterations after each division overshot into the flat of the tanh law, 25.5
    /// steps and 1.5 Newton failures per division against 2.0 and none). The velocity
    /// field is continuous at a division with `η = 0` (forces are), so the mapped `ẏ` is the
    /// solution's own to first order; only `ẍ` kinks (each daughter grows at the parent's
    /// absolute rate). The solver maps `ẏ` at the event and BDF resumes from it at order 1
    /// ([`integrators::Method::resume`]). Off with [`Dividing::carry_history`] `= false`.
    fn map_history(&self, t: f64, old: &[f64], derivative: bool, new: &mut [f64]) -> bool {
        self.carry_history && self.map_split(t, old, derivative, new)
    }

    /// The Jacobian map of the last division event (see
    /// [`integrators::Problem::map_jacobian`]): every unknown outside the divided cells keeps
    /// its entries, moved to its new index, and the rows of the cells within three of a
    /// daughter are evaluated afresh ([`Line::jacobian_rows_into`]), for `∂F/∂y` and `∂F/∂ẏ`:
    /// an O(N) copy and O(k) evaluation for k divisions, instead of a Jacobian of the whole
    /// line (a quarter of a dividing line's instructions at K = 1e-8, one Jacobian per
    /// division). Off with [`Dividing::carry_history`] `= false`, and on a ring.
    fn map_jacobian(
        &self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        jy: &mut Matrix,
        jyp: &mut Matrix,
    ) -> Result<bool, ResidualError> {
        let Some(m) = self.last.as_ref().filter(|_| self.carry_history) else {
            return Ok(false);
        };
        let lay = &self.line.layout;
        if lay.xi[0] != NONE || self.line.right.is_periodic() {
            return Ok(false);
        }
        if m.sources.len() != lay.dim {
            return Ok(false);
        }
        // both daughters of a cell with a Maxwell branch read their parent's a_v (the
        // history's map), but a matrix grows by insertions, whose sources increase: to the
        // Jacobian the second is a new unknown (its rows and every row its column reaches
        // are among the fresh ones)
        let increasing: Vec<usize>;
        let src: &[usize] = if m.stride > 2 {
            let mut last = None;
            increasing = m
                .sources
                .iter()
                .map(|&s| {
                    if s != usize::MAX && last.is_none_or(|l| s > l) {
                        last = Some(s);
                        s
                    } else {
                        usize::MAX
                    }
                })
                .collect();
            &increasing
        } else {
            &m.sources
        };
        let (l, u) = match &*jy {
            Matrix::Banded(b) => (b.lower, b.upper),
            _ => return Ok(false),
        };
        let (runs, fresh) = (&m.runs, &m.fresh);
        if fresh.len() != lay.dim || !(jy.remap(src, fresh) && jyp.remap(src, fresh)) {
            return Ok(false);
        }
        let rows = |&(lo, hi): &(usize, usize)| {
            (lo..=hi)
                .flat_map(|c| [lay.gi[c - 1], lay.vi[c - 1], lay.xi[c]])
                .filter(|&k| k != NONE)
        };
        for &(lo, hi) in runs {
            if !(self.line.jacobian_rows_into(t, y, yp, 0.0, jy, lo..=hi)?
                && self.line.jacobian_rows_into(t, y, yp, 1.0, jyp, lo..=hi)?)
            {
                return Ok(false);
            }
        }
        // those rows of `jyp` hold ∂F/∂y + ∂F/∂ẏ
        for i in runs.iter().flat_map(rows) {
            for j in i.saturating_sub(l)..=(i + u).min(lay.dim - 1) {
                jyp.add(i, j, -jy.get(i, j));
            }
        }
        Ok(true)
    }

    /// Restart derivative after a division, for lines without viscosity (`η = 0` in every
    /// cell; with `η > 0` the consistent `ẏ` is kept).
    ///
    /// * Old boundaries: the velocity the integrator's dense output had at the event, instead
    ///   of the consistent one. With `η = 0`, `Kκẋ = F(x, g)` gives `ẋ = F/(Kκ)`, so a
    ///   position error `δx` within the tolerances (the event state is interpolated) shows up
    ///   in the consistent `ẋ` amplified by `μ/(K L₀)`: at `K = 10⁻⁸` a `δx ≈ 10⁻⁶` of a
    ///   boundary whose neighbours move at 760 gives it a consistent velocity of 310. That
    ///   fast transient decays in `≈ K L₀/μ` and moves `y` by `O(δx)`, but a method restarted
    ///   from it extrapolates it over a whole step: the predictor is off by `h·|Δẋ|`, the error
    ///   test rejects, and Newton diverges in the `tanh` growth law (measured at `N ≈ 1600`,
    ///   `t ≈ 10`, `K = 10⁻⁸`: 4 rejections per division). The slow velocity field is
    ///   continuous at a division with `η = 0` (forces and `σ` are), so the pre-event value is
    ///   the right one to extrapolate. `ġ` stays consistent (`G(σ)` is insensitive to `δx`).
    /// * A new boundary starts at rest: with `η = 0` its consistent velocity is
    ///   `F/(Kκ) = W(σ_d₂ − σ_d₁)/(Kκ) = 0` (the daughters' stresses are equal), while the
    ///   material point it marks moved with the parent's strain rate, at the mean of the parent's
    ///   boundary velocities. It catches up within `τ ≈ K L₀/μ` (10⁻⁸ at `K = 10⁻⁸`), moving
    ///   `y` by `O(|Δv|τ)`, below the tolerances; but a method restarted from the resting value
    ///   extrapolates `x_new` with velocity 0, its first error estimate sees the whole
    ///   `|Δv|·h/2`, and restarts after every division are cut to `h ≈ 2·rtol·x/v` (≈ 10⁻⁵ for an
    ///   exponentially growing line), with rejections and Newton failures. Restarting from the
    ///   smooth value removes that (the corrector still solves the exact residual).
    fn restart_derivative(&mut self, t: f64, y: &[f64], yp: &mut [f64]) {
        if !self.smooth_restart || yp.len() != self.line.layout.dim {
            return;
        }
        // with viscosity the velocities are coupled through `ηα̇` and the consistent ẏ has no
        // resting boundary (measured at K = 1e-5, η = 1, t ≤ 8: averaging the new boundary
        // costs 882 steps against 622 with the consistent ẏ)
        if self.line.cells.eta.iter().any(|&e| e != 0.0) {
            return;
        }
        if self.yp_event.len() == yp.len() {
            for &k in &self.line.layout.xi {
                if k != NONE {
                    yp[k] = self.yp_event[k];
                }
            }
        }
        for &b in &self.new_boundaries {
            let k = self.line.layout.xi[b];
            if k == NONE || b == 0 || b >= self.line.n_cells() {
                continue;
            }
            let (_, vl) = self.line.boundary(b - 1, t, y, yp);
            let (_, vr) = self.line.boundary(b + 1, t, y, yp);
            yp[k] = 0.5 * (vl + vr);
        }
    }
}

impl<E: StrainEnergy> LineModel for Dividing<E> {
    // `breakpoints` forwarded too: a prescribed polynomial-ramp end has a kink at `t_ramp`,
    // where `integrate` must restart rather than step across it.
    crate::line::run::forward_line_model!(line: initial_state, initial_derivative_guess,
        unknown_name, breakpoints);

    /// The line's snapshot, with each cell's `age`, `id` and `ancestor` while the cells have
    /// a [`Lineage`].
    fn observe(
        &self,
        t: f64,
        y: &[f64],
        yp: &[f64],
    ) -> Result<crate::line::observe::Snapshot, ResidualError> {
        let mut s = self.line.observe(t, y, yp)?;
        if let Some(l) = &self.lineage {
            let age = self.birth.iter().map(|b| t - b).collect();
            s.cell_fields.push(("age".into(), age));
            for (name, v) in l.profile_fields() {
                s.cell_fields.push((name.into(), v));
            }
        }
        Ok(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::boundary::RightEnd;
    use crate::cell::TanhGrowth;
    use crate::events::AreaDoubling;
    use crate::line::build::{discrete, LineParams};
    use crate::NeoHookean;

    #[test]
    fn event_functions_on_two_threads_are_the_one_thread_values() {
        let n = PAR_MIN_CELLS + 7;
        let mut p = LineParams::unit_cells(n);
        p.right = RightEnd::Free(None);
        p.growth = Some(std::sync::Arc::new(TanhGrowth::default()));
        let line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
        let mut div = Dividing::new(line, Box::new(AreaDoubling::default()), 0).unwrap();
        let mut y = div.line.initial_state();
        for j in 0..n {
            y[div.line.layout.gi[j]] = 1.0 + (j % 97) as f64 / 100.0;
        }
        let mut values = |threads: usize| {
            div.set_threads(threads);
            let mut g = vec![f64::NAN; n];
            div.events(0.0, &y, &mut g);
            g
        };
        let (one, two) = (values(1), values(2));
        assert!(one
            .iter()
            .zip(&two)
            .all(|(a, b)| a.to_bits() == b.to_bits()));
        // the area rule: g·g₂ − 2 (g₂ = 1 here), in either half of the line
        let g2 = div.line.g2;
        for j in [0, 96, n / 2, n - 1] {
            let g = 1.0 + (j % 97) as f64 / 100.0;
            assert_eq!(two[j], g * g2 - 2.0, "cell {j}");
        }
    }
}
