//! Builders: one physical description ([`LineParams`]) → a [`Line`] on either discretisation.
//!
//! * [`discrete`] — N cells with their own reference lengths; drag `K(X_j)` per boundary.
//! * [`continuum`] — the conservative scheme of docs/model.md §3.3a: `n` segments of length
//!   `h = l₀/n`, fields sampled at segment centres, drag `K` times the cell boundaries each node
//!   stands for (`h/L` for cells of equal length `L`, since `K` is drag per cell boundary; a
//!   census of unequal cells counts them; a free end's node also the tip boundary's own half
//!   cell under [`FreeEndDrag::Cells`]). With `n = N` and unit cells it *is* the
//!   discrete model (same type, same residual), so `n` is independent of `N`.
//! * [`cell_groups`] — the cell-number grid's line: segments of whole cells.
//! * [`segment_cells`] — the cells each continuum segment holds (a density continuum's start).

use super::array::{Cells, Layout, Line};
use super::homogenise::homogenised;
use super::LineError;
use crate::boundary::RightEnd;
use crate::cell::{Active, Field, GrowthLaw, MaxwellBranch, Sampling};
use crate::energy::StrainEnergy;
use crate::substrate::{DragForm, FreeEndDrag, WidthRule};
use std::f64::consts::PI;
use std::sync::Arc;

/// A line independent of its discretisation: the cells' reference lengths, material fields of
/// `X`, substrate, boundary conditions, active stress and growth.
///
/// ```
/// use celltissue::line::build::{LineParams, discrete, continuum};
/// use celltissue::boundary::{Ramp, RightEnd};
/// use celltissue::NeoHookean;
/// let mut p = LineParams::unit_cells(100);
/// p.right = RightEnd::Prescribed(Ramp::Exponential { l0: 100.0, k1: 0.1, t_ramp: 1.0 });
/// p.k = 1.0.into();
/// let d = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
/// let c = continuum(NeoHookean::new(1.0).unwrap(), &p, 25).unwrap();
/// assert_eq!(d.n_cells(), 100);
/// assert_eq!(c.n_cells(), 25);
/// ```
#[derive(Clone)]
pub struct LineParams {
    /// Reference length of each cell (`N = len`).
    pub ref_lengths: Vec<f64>,
    /// Energy scale field `μ(X)` (the shear modulus for a unit-modulus law).
    pub mu: Field,
    /// Viscosity field `η(X)`.
    pub eta: Field,
    /// Drag field `K(X)` (per boundary).
    pub k: Field,
    /// Active-amplitude field `A(X)` (used only if `active` is set).
    pub active_amp: Field,
    /// Where fields are sampled.
    pub sampling: Sampling,
    /// Drag-area exponent `m`.
    pub m: f64,
    /// Lateral growth stretch `g₂`.
    pub g2: f64,
    /// Aspect ratio `γ₀`.
    pub gamma0: f64,
    /// Shared-width rule.
    pub width: WidthRule,
    /// Drag form.
    pub form: DragForm,
    /// A continuum grid's free-end drag ([`FreeEndDrag`]; the discrete line is the same either
    /// way).
    pub free_end_drag: FreeEndDrag,
    /// Right end.
    pub right: RightEnd,
    /// Active stress.
    pub active: Option<Active>,
    /// Growth law.
    pub growth: Option<Arc<dyn GrowthLaw>>,
    /// Maxwell branch (Maxwell or standard linear solid cells; docs/viscoelasticity.md).
    pub maxwell: Option<MaxwellBranch>,
    /// External pressure field `p_e(X)` on the cells' lateral faces (docs/model.md §8.2).
    pub p_ext: Field,
    /// Absolute tolerance in cell units.
    pub atol_cell: f64,
}

impl LineParams {
    /// `n` unit cells, μ = 1, η = 0, K = 0, m = 0, γ₀ = g₂ = 1, wall + fixed length `n`.
    ///
    /// ```
    /// use celltissue::line::LineParams;
    /// let p = LineParams::unit_cells(8);
    /// assert_eq!((p.ref_lengths.len(), p.total_length()), (8, 8.0));
    /// ```
    pub fn unit_cells(n: usize) -> Self {
        Self {
            ref_lengths: vec![1.0; n],
            mu: Field::Constant(1.0),
            eta: Field::Constant(0.0),
            k: Field::Constant(0.0),
            active_amp: Field::Constant(1.0),
            sampling: Sampling::Centres,
            m: 0.0,
            g2: 1.0,
            gamma0: 1.0,
            width: WidthRule::Mean,
            form: DragForm::Boundary,
            free_end_drag: FreeEndDrag::Segment,
            right: RightEnd::Prescribed(crate::boundary::Ramp::Constant(n as f64)),
            active: None,
            growth: None,
            maxwell: None,
            p_ext: Field::Constant(0.0),
            atol_cell: 1e-8,
        }
    }

    /// `l₀ = Σ L₀,j`.
    ///
    /// ```
    /// let mut p = celltissue::line::LineParams::unit_cells(2);
    /// p.ref_lengths = vec![0.5, 1.5];
    /// assert_eq!(p.total_length(), 2.0);
    /// ```
    pub fn total_length(&self) -> f64 {
        sum_and_check(&self.ref_lengths).0
    }

    /// Checks every parameter; returns `l₀ = Σ L₀,j` (the same sum as
    /// [`total_length`](Self::total_length)), found in the pass that checks the lengths.
    fn check(&self) -> Result<f64, LineError> {
        if self.ref_lengths.is_empty() {
            return Err(LineError::invalid("cells", "0", ">= 1"));
        }
        let (total, all_ok) = sum_and_check(&self.ref_lengths);
        if !all_ok {
            let l = self
                .ref_lengths
                .iter()
                .find(|l| !(**l > 0.0 && l.is_finite()))
                .expect("a bad length exists");
            return Err(LineError::invalid("ref_lengths", l, "finite and > 0"));
        }
        if self.form == DragForm::Centre && self.right.is_periodic() {
            return Err(LineError::CentreFormPeriodic);
        }
        if !(self.gamma0 > 0.0 && self.gamma0.is_finite()) {
            return Err(LineError::invalid("gamma0", self.gamma0, "finite and > 0"));
        }
        if !(self.g2 > 0.0 && self.g2.is_finite()) {
            return Err(LineError::invalid("g2", self.g2, "finite and > 0"));
        }
        if !self.m.is_finite() {
            return Err(LineError::invalid("m", self.m, "finite"));
        }
        self.mu.validate("mu", true).map_err(LineError::Field)?;
        self.eta.validate("eta", false).map_err(LineError::Field)?;
        self.k.validate("K", false).map_err(LineError::Field)?;
        Ok(total)
    }
}

/// `Σ v` and whether every entry is finite and positive, in one branch-free pass. The sum runs
/// in eight interleaved partial sums combined pairwise (a single running sum is one 4-cycle
/// addition per cell in sequence: at N = 10⁴ that was ≈ 5 % of a 100-segment continuum solve).
fn sum_and_check(v: &[f64]) -> (f64, bool) {
    const LANES: usize = 8;
    let mut part = [0.0; LANES];
    let mut all_ok = true;
    let mut chunks = v.chunks_exact(LANES);
    for chunk in &mut chunks {
        for (p, &l) in part.iter_mut().zip(chunk) {
            *p += l;
            all_ok &= l > 0.0 && l.is_finite();
        }
    }
    for (p, &l) in part.iter_mut().zip(chunks.remainder()) {
        *p += l;
        all_ok &= l > 0.0 && l.is_finite();
    }
    let [a, b, c, d, e, f, g, h] = part;
    (((a + b) + (c + d)) + ((e + f) + (g + h)), all_ok)
}

/// Where the cells of `ref_lengths` lie along `X`, for a continuum grid over cells of unequal
/// lengths: the cell count `C(X) = j + (X − B_j)/L_j` inside cell `j` (`B_j` its left end), so
/// that a stretch `[a, b]` of the line holds `C(b) − C(a)` cells and boundaries, and the cell
/// holding a point, where a per-cell list is read.
pub(crate) struct CellCensus {
    /// `B_0 = 0, …, B_N = l₀`.
    bounds: Vec<f64>,
}

impl CellCensus {
    /// The census of `lengths`, or `None` when they are all equal: then every count is the
    /// uniform `h/L` and a per-cell list is read by position alike.
    pub(crate) fn of_unequal(lengths: &[f64]) -> Option<Self> {
        let first = *lengths.first()?;
        if lengths.iter().all(|&l| l == first) {
            return None;
        }
        Some(Self::new(lengths))
    }

    fn new(lengths: &[f64]) -> Self {
        let mut bounds = Vec::with_capacity(lengths.len() + 1);
        let mut acc = 0.0;
        bounds.push(acc);
        for l in lengths {
            acc += l;
            bounds.push(acc);
        }
        Self { bounds }
    }

    /// The cell holding `x` (0-based; the first or last beyond the ends).
    fn holder(&self, x: f64) -> usize {
        let n = self.bounds.len() - 1;
        self.bounds.partition_point(|&b| b <= x).clamp(1, n) - 1
    }

    /// `C(x)`, clamped to `[0, N]`.
    pub(crate) fn count_to(&self, x: f64) -> f64 {
        let j = self.holder(x);
        let (a, b) = (self.bounds[j], self.bounds[j + 1]);
        j as f64 + ((x - a) / (b - a)).clamp(0.0, 1.0)
    }

    /// The reference length of the cell holding `x`.
    pub(crate) fn length_at(&self, x: f64) -> f64 {
        let j = self.holder(x);
        self.bounds[j + 1] - self.bounds[j]
    }

    /// `f` at the points `xs` of a line of length `l0`: a per-cell list with one value per
    /// cell is read at the cell holding each point, any other field as [`Field::sample`].
    pub(crate) fn sample(&self, f: &Field, xs: &[f64], l0: f64) -> Vec<f64> {
        match f {
            Field::PerCell { values } if values.len() + 1 == self.bounds.len() => {
                xs.iter().map(|&x| values[self.holder(x)]).collect()
            }
            _ => f.sample(xs, l0),
        }
    }
}

/// How the entries of a built line (its cells, or the segments of a continuum grid) read the
/// fields of [`LineParams`].
///
/// A cell reads a field at its sample point: its centre, or its left end under
/// [`Sampling::IntegerPoints`]. A segment reads a field that jumps from cell to cell (a list, a
/// piecewise field) as the cell holding its centre reads it, and a smooth field at its centre,
/// moved under `integer_points` by half the holding cell to the left. The cells' values of a
/// smooth field `f` are then `f(X − L/2)` at their centres `X`, one curve through the segments
/// too, so a grid refined past the cells converges to the discrete line's field rather than
/// to one displaced by half a cell.
struct FieldReader {
    /// Where a smooth field is read, one point per entry.
    smooth: Vec<f64>,
    /// On a grid: the cells' sample points and the cell holding each segment's centre.
    cells: Option<(Vec<f64>, Vec<usize>)>,
    l0: f64,
}

impl FieldReader {
    /// The reader of a line whose entries lie between `bounds` (centres `centres`); `grid`
    /// when they are not the cells of `p`.
    fn new(p: &LineParams, bounds: &[f64], centres: &[f64], grid: bool) -> Self {
        let n = centres.len();
        let l0 = bounds[n];
        if !grid {
            return Self {
                smooth: sample_points(p.sampling, bounds),
                cells: None,
                l0,
            };
        }
        let census = CellCensus::new(&p.ref_lengths);
        let holders: Vec<usize> = centres.iter().map(|&x| census.holder(x)).collect();
        let cell_points = sample_points(p.sampling, &census.bounds);
        let smooth = centres
            .iter()
            .zip(&holders)
            .map(|(&x, &j)| match p.sampling {
                Sampling::Centres => x,
                Sampling::IntegerPoints => x - 0.5 * (census.bounds[j + 1] - census.bounds[j]),
            })
            .collect();
        Self {
            smooth,
            cells: Some((cell_points, holders)),
            l0,
        }
    }

    /// `f` on every entry.
    fn read(&self, f: &Field) -> Vec<f64> {
        match (&self.cells, f) {
            (
                Some((points, holders)),
                Field::PerCell { .. } | Field::Piecewise { .. } | Field::Random { .. },
            ) => {
                let cell_values = f.sample(points, self.l0);
                holders.iter().map(|&j| cell_values[j]).collect()
            }
            _ => f.sample(&self.smooth, self.l0),
        }
    }
}

/// The points where the cells between `bounds` read a field: their centres, or their left
/// ends under [`Sampling::IntegerPoints`].
pub(crate) fn sample_points(sampling: Sampling, bounds: &[f64]) -> Vec<f64> {
    match sampling {
        Sampling::Centres => bounds.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect(),
        Sampling::IntegerPoints => bounds[..bounds.len() - 1].to_vec(),
    }
}

/// What each entry of a built line stands for in the cells of [`LineParams::ref_lengths`]:
/// the cells each segment holds and the boundaries each face carries (the factors of its drag,
/// since `K` is drag per cell boundary; 1 on the discrete line), and on a continuum grid over
/// cells of unequal lengths their [`CellCensus`] (where per-cell lists are read).
struct Census {
    cell: Vec<f64>,
    face: Vec<f64>,
    cells: Option<CellCensus>,
}

impl Census {
    /// `scale` cells per segment and boundaries per face: one on the discrete line, `h/L` on a
    /// grid of segments of length `h` over equal cells of length `L`.
    fn uniform(n: usize, scale: f64) -> Self {
        Self {
            cell: vec![scale; n],
            face: vec![scale; n + 1],
            cells: None,
        }
    }

    /// The segments `[X_i, X_{i+1}]` of a grid over the unequal cells of `lengths` (faces
    /// `X_0 = 0 … X_n = l₀`): segment `i` holds `C(X_{i+1}) − C(X_i)` cells; an interior face
    /// carries the boundaries between its neighbours' centres, an end face its segment's length
    /// over the end cell's (`h/L` on every face for equal cells), and on a `ring` the face
    /// where the ends meet the boundaries between the last centre and the first.
    fn grid(census: CellCensus, faces: &[f64], ring: bool) -> Self {
        let n = faces.len() - 1;
        let c: Vec<f64> = faces.iter().map(|&x| census.count_to(x)).collect();
        let mid: Vec<f64> = faces.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect();
        let cells = census.bounds.len() as f64 - 1.0;
        let seam = census.count_to(mid[0]) + (cells - census.count_to(mid[n - 1]));
        let face = (0..=n)
            .map(|b| match b {
                b if ring && (b == 0 || b == n) => seam,
                0 => (faces[1] - faces[0]) / census.length_at(faces[0]),
                b if b == n => (faces[n] - faces[n - 1]) / census.length_at(faces[n]),
                b => census.count_to(mid[b]) - census.count_to(mid[b - 1]),
            })
            .collect();
        Self {
            cell: c.windows(2).map(|w| w[1] - w[0]).collect(),
            face,
            cells: Some(census),
        }
    }
}

/// `p` with its random fields drawn once per cell, as per-cell lists (`None` when it has
/// none): a continuum grid then sees the tissue the discrete line sees (the cell where each
/// of its points lies, or the effective values of the cells a segment holds), rather than
/// fresh draws per segment.
pub(crate) fn drawn_per_cell(p: &LineParams) -> Option<LineParams> {
    let fields = [&p.mu, &p.eta, &p.k, &p.active_amp, &p.p_ext];
    if !fields.iter().any(|f| matches!(f, Field::Random { .. })) {
        return None;
    }
    let n = p.ref_lengths.len();
    let draw = |f: &Field| f.drawn_per_cell(n);
    Some(LineParams {
        mu: draw(&p.mu),
        eta: draw(&p.eta),
        k: draw(&p.k),
        active_amp: draw(&p.active_amp),
        p_ext: draw(&p.p_ext),
        ..p.clone()
    })
}

/// Builds a line of `lengths.len()` cells (or segments) whose drags are `K` times what the
/// [`Census`] says each stands for.
fn assemble<E: StrainEnergy>(
    energy: E,
    p: &LineParams,
    lengths: Vec<f64>,
    census: Census,
) -> Result<Line<E>, LineError> {
    let n = lengths.len();
    let l0_total: f64 = lengths.iter().sum();
    let mut bounds = Vec::with_capacity(n + 1);
    bounds.push(0.0);
    let mut acc = 0.0;
    for l in &lengths {
        acc += l;
        bounds.push(acc);
    }
    let centres: Vec<f64> = (0..n).map(|i| 0.5 * (bounds[i] + bounds[i + 1])).collect();
    let grid = lengths != p.ref_lengths;
    let reader = FieldReader::new(p, &bounds, &centres, grid);
    let sample = |f: &Field| reader.read(f);
    // segments of several cells of a per-cell list take the cells' effective values
    let mixed = grid.then(|| homogenised(p, &bounds)).flatten();
    let per_segment_k =
        mixed.is_some() || matches!(p.k, Field::PerCell { .. } | Field::Random { .. });
    let (mu, eta, k_sampled, active_amp, p_ext) = match mixed {
        Some(v) => (v.mu, v.eta, v.k, v.active_amp, v.p_ext),
        None => (
            sample(&p.mu),
            sample(&p.eta),
            sample(&p.k),
            sample(&p.active_amp),
            sample(&p.p_ext),
        ),
    };
    // values per cell or segment have none at the faces: average the neighbours (on a ring
    // the seam's are the last and the first)
    let k_face: Vec<f64> = if per_segment_k {
        let ring = p.right.is_periodic();
        (0..=n)
            .map(|b| {
                let l = match b {
                    0 if ring => k_sampled[n - 1],
                    0 => k_sampled[0],
                    _ => k_sampled[b - 1],
                };
                let r = match b {
                    _ if b < n => k_sampled[b],
                    _ if ring => k_sampled[0],
                    _ => k_sampled[n - 1],
                };
                let c = census.face[b];
                0.5 * (l * c + r * c)
            })
            .collect()
    } else {
        bounds
            .iter()
            .zip(&census.face)
            .map(|(&x, &c)| p.k.eval(x, l0_total) * c)
            .collect()
    };
    let k_cell: Vec<f64> = k_sampled
        .iter()
        .zip(&census.cell)
        .map(|(k, c)| k * c)
        .collect();
    if let Some(bad) = p_ext.iter().find(|x| !x.is_finite()) {
        return Err(LineError::invalid(
            "external_pressure",
            bad,
            "finite at every cell",
        ));
    }
    let phase = centres.iter().map(|&x| 2.0 * PI * x / l0_total).collect();
    for (key, v) in [("mu", &mu), ("eta", &eta), ("K", &k_cell)] {
        if let Some(bad) = v.iter().find(|x| !x.is_finite() || **x < 0.0) {
            return Err(LineError::invalid(
                key,
                bad,
                "finite and >= 0 at every cell",
            ));
        }
    }
    if let Some(bad) = mu.iter().find(|x| **x <= 0.0) {
        return Err(LineError::invalid("mu", bad, "> 0 at every cell"));
    }
    let right = match &p.right {
        RightEnd::Prescribed(r) => RightEnd::Prescribed(r.clone()),
        other => other.clone(),
    };
    let mut line = Line {
        energy,
        cells: Cells {
            l0: lengths,
            x_ref: centres,
            mu,
            eta,
            k_cell,
            active_amp,
            phase,
            p_ext,
        },
        k_face,
        k_tip: 0.0,
        m: p.m,
        g2: p.g2,
        gamma0: p.gamma0,
        width: p.width,
        form: p.form,
        right,
        active: p.active,
        growth: p.growth.clone(),
        maxwell: p.maxwell,
        l0_total,
        period: l0_total,
        atol_cell: p.atol_cell,
        threads: 1,
        layout: Layout::default(),
        uniform: Default::default(),
        segment_cells: None,
    };
    line.rebuild_layout();
    if line.layout.dim == 0 {
        return Err(LineError::invalid(
            "cells",
            n,
            ">= 2 for a prescribed right end without growth (no unknowns otherwise)",
        ));
    }
    Ok(line)
}

/// The discrete model: one cell per entry of `p.ref_lengths`.
///
/// ```
/// use celltissue::line::build::{discrete, LineParams};
/// use celltissue::{CellArray, NeoHookean};
/// let line = discrete(NeoHookean::new(1.0)?, &LineParams::unit_cells(5))?;
/// assert_eq!((line.n_cells(), line.l0_total()), (5, 5.0));
/// assert_eq!(line.dim(), 4); // x₁ … x₄ (x₀ = 0 and the prescribed x₅ are not unknowns)
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn discrete<E: StrainEnergy>(energy: E, p: &LineParams) -> Result<Line<E>, LineError> {
    p.check()?;
    assemble(
        energy,
        p,
        p.ref_lengths.clone(),
        Census::uniform(p.ref_lengths.len(), 1.0),
    )
}

/// The conservative continuum scheme with `n` segments of length `h = l₀/n` (docs/model.md §3.3a).
///
/// ```
/// use celltissue::line::build::{continuum, LineParams};
/// use celltissue::NeoHookean;
/// let line = continuum(NeoHookean::new(1.0)?, &LineParams::unit_cells(100), 20)?;
/// assert_eq!((line.n_cells(), line.l0_total()), (20, 100.0)); // 20 segments of h = 5
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn continuum<E: StrainEnergy>(
    energy: E,
    p: &LineParams,
    n: usize,
) -> Result<Line<E>, LineError> {
    let l0 = p.check()?;
    if n == 0 {
        return Err(LineError::invalid("nodes", n, ">= 1"));
    }
    let drawn = drawn_per_cell(p);
    let p = drawn.as_ref().unwrap_or(p);
    let h = l0 / n as f64;
    let mut census = match CellCensus::of_unequal(&p.ref_lengths) {
        None => Census::uniform(n, h / (l0 / p.ref_lengths.len() as f64)),
        Some(cells) => Census::grid(cells, &grid_faces(h, n), p.right.is_periodic()),
    };
    // the tip boundary's own half cell beyond the distributed drag: the end face carries
    // (c + 1)/2 boundaries instead of its segment's c (the same on n = N segments, c = 1)
    let tip = (p.right.is_free() && p.free_end_drag == FreeEndDrag::Cells).then(|| {
        let c = census.face[n];
        census.face[n] = FreeEndDrag::Cells.end_face(c);
        c
    });
    // its records count the tissue's cells, not its segments
    let counts = census.cell.clone();
    let mut line = assemble(energy, p, vec![h; n], census)?;
    if let Some(c) = tip {
        line.k_tip = line.k_face[n] / (c + 1.0);
    }
    line.segment_cells = counts.iter().any(|&c| c != 1.0).then_some(counts);
    Ok(line)
}

/// The cell-number grid's line: `n` segments of `N/n` consecutive cells each (`n` must divide
/// `N`), each as long as its cells together, with the drag of that many boundaries; for cells
/// of equal length the same as [`continuum`] on `n` segments.
///
/// ```
/// use celltissue::line::build::{cell_groups, LineParams};
/// let mut p = LineParams::unit_cells(4);
/// p.ref_lengths = vec![0.5, 1.5, 1.0, 3.0];
/// let line = cell_groups(celltissue::NeoHookean::new(1.0)?, &p, 2)?;
/// assert_eq!(line.cells().l0, [2.0, 4.0]);
/// assert!(cell_groups(celltissue::NeoHookean::new(1.0)?, &p, 3).is_err()); // 3 ∤ 4
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn cell_groups<E: StrainEnergy>(
    energy: E,
    p: &LineParams,
    n: usize,
) -> Result<Line<E>, LineError> {
    p.check()?;
    let cells = p.ref_lengths.len();
    if n == 0 || !cells.is_multiple_of(n) {
        return Err(LineError::invalid(
            "nodes",
            n,
            &format!("a divisor of cells = {cells} (whole cells per segment)"),
        ));
    }
    let Some(census) = CellCensus::of_unequal(&p.ref_lengths) else {
        return continuum(energy, p, n);
    };
    let drawn = drawn_per_cell(p);
    let p = drawn.as_ref().unwrap_or(p);
    let c = cells / n;
    let lengths = p.ref_lengths.chunks(c).map(|g| g.iter().sum()).collect();
    let mut counts = Census::uniform(n, c as f64);
    counts.cells = Some(census);
    assemble(energy, p, lengths, counts)
}

/// The cells each of the `n` segments of [`continuum`]'s grid (length `h = l₀/n`) holds, in
/// the cells of `p.ref_lengths`: `h/L` each for cells of equal length `L`, else the part of
/// each cell that falls in the segment, added up (a density continuum's initial density).
///
/// ```
/// use celltissue::line::build::{segment_cells, LineParams};
/// let mut p = LineParams::unit_cells(4);
/// assert_eq!(segment_cells(&p, 2), [2.0, 2.0]);
/// p.ref_lengths = vec![0.5, 0.5, 0.5, 2.5]; // l₀ = 4: three short cells and a long one
/// let c = segment_cells(&p, 2); // [0, 2] holds 3 cells and 0.5/2.5 of the fourth
/// assert!((c[0] - 3.2).abs() < 1e-15 && (c[1] - 0.8).abs() < 1e-15);
/// ```
pub fn segment_cells(p: &LineParams, n: usize) -> Vec<f64> {
    let l0 = p.total_length();
    let h = l0 / n as f64;
    match CellCensus::of_unequal(&p.ref_lengths) {
        None => vec![h / (l0 / p.ref_lengths.len() as f64); n],
        Some(cells) => Census::grid(cells, &grid_faces(h, n), false).cell,
    }
}

/// The faces `0, h, 2h, … nh` of a grid of `n` segments, accumulated as the builder places
/// its segments.
fn grid_faces(h: f64, n: usize) -> Vec<f64> {
    std::iter::once(0.0)
        .chain((1..=n).scan(0.0, |acc, _| {
            *acc += h;
            Some(*acc)
        }))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::NeoHookean;

    #[test]
    fn a_per_cell_drag_list_gives_each_boundary_its_neighbours_mean_and_a_ring_its_seam() {
        let law = NeoHookean::new(1.0).unwrap();
        let mut p = LineParams::unit_cells(4);
        p.k = Field::PerCell {
            values: vec![1.0, 2.0, 3.0, 5.0],
        };
        assert_eq!(
            discrete(law, &p).unwrap().k_face(),
            [1.0, 1.5, 2.5, 4.0, 5.0]
        );
        // on a ring the seam joins the last cell to the first: the same face, both ways round
        p.right = RightEnd::Periodic { gauge: true };
        let ring = discrete(law, &p).unwrap();
        assert_eq!((ring.k_face()[0], ring.k_face()[4]), (3.0, 3.0));
    }

    #[test]
    fn bad_reference_lengths_are_named_and_good_ones_give_l0() {
        let law = NeoHookean::new(1.0).unwrap();
        let mut p = LineParams::unit_cells(7);
        p.ref_lengths[3] = 0.5;
        assert_eq!(p.check().unwrap(), p.total_length());
        assert_eq!(continuum(law, &p, 3).unwrap().l0_total, 6.5);
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            p.ref_lengths[5] = bad;
            for e in [discrete(law, &p).err(), continuum(law, &p, 3).err()] {
                let msg = e.expect("rejected").to_string();
                assert!(msg.contains("ref_lengths"), "{bad}: {msg}");
            }
        }
    }

    /// A grid over unequal cells counts every cell once: the segments' counts add up to N,
    /// a segment inside one cell holds h/L of it, a per-cell list is read where each centre
    /// is; equal cells take the uniform factor h/L.
    #[test]
    fn the_census_of_unequal_cells_counts_each_cell_once() {
        let lengths: Vec<f64> = (0..37)
            .map(|i| 0.3 + (0.71 * i as f64).sin().abs())
            .collect();
        let l0: f64 = lengths.iter().sum();
        for n in [5, 37, 100, 1000] {
            let h = l0 / n as f64;
            let census = CellCensus::of_unequal(&lengths).unwrap();
            let c = Census::grid(census, &grid_faces(h, n), false);
            let total: f64 = c.cell.iter().sum();
            assert!((total - 37.0).abs() < 1e-11, "n={n}: {total}");
            assert!(c.cell.iter().chain(&c.face).all(|&v| v > 0.0));
            // the interior faces carry every boundary between the first and last centres
            let inner: f64 = c.face[1..n].iter().sum();
            let cc = CellCensus::new(&lengths);
            let span = cc.count_to(l0 - 0.5 * h) - cc.count_to(0.5 * h);
            assert!((inner - span).abs() < 1e-11, "n={n}: {inner} {span}");
            // on a ring the faces where the ends meet are one, and every boundary is counted
            // once: N faces' worth in all
            let ring = Census::grid(CellCensus::new(&lengths), &grid_faces(h, n), true);
            assert_eq!(ring.face[0], ring.face[n]);
            let all: f64 = ring.face[..n].iter().sum();
            assert!((all - 37.0).abs() < 1e-11, "n={n}: {all}");
        }
        let census = CellCensus::new(&[1.0, 3.0]);
        assert_eq!(
            (census.holder(0.5), census.holder(1.0), census.holder(9.0)),
            (0, 1, 1)
        );
        assert_eq!(census.count_to(2.5), 1.5);
        let list = Field::PerCell {
            values: vec![7.0, 9.0],
        };
        assert_eq!(census.sample(&list, &[0.5, 1.5, 3.9], 4.0), [7.0, 9.0, 9.0]);
        assert!(CellCensus::of_unequal(&[0.5; 4]).is_none());
    }

    #[test]
    fn the_lane_sum_is_the_sum_and_finds_any_bad_length() {
        // every remainder length; non-uniform lengths, so the summation order shows
        for n in [1, 7, 8, 9, 1003] {
            let v: Vec<f64> = (0..n)
                .map(|i| 0.5 + (0.37 * i as f64).sin().abs())
                .collect();
            let sequential: f64 = v.iter().sum();
            let (sum, ok) = sum_and_check(&v);
            assert!(ok);
            assert!((sum - sequential).abs() <= 1e-14 * sequential, "n={n}");
            for i in [0, n / 2, n - 1] {
                let mut w = v.clone();
                w[i] = -w[i];
                assert!(!sum_and_check(&w).1, "n={n} i={i}");
            }
        }
    }
}
