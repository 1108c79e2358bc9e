//! [`DensityContinuum`]: the proliferating continuum on the conservative grid — a growing
//! continuum [`Line`] (segments of material width `h`) that also carries the relative cell
//! density `r_i = ρ_i/ρ₀` and the reference length per unit `X` of its current cells, and
//! divides whole segments by events (see the [module docs](super) for the model).

use crate::array::CellArray;
use crate::energy::StrainEnergy;
use crate::events::{DivisionLog, EventError};
use crate::line::array::NONE;
use crate::line::run::LineModel;
use crate::line::Line;
use crate::observe::DivisionRecord;
use crate::scalar::Scalar;
use integrators::{EventAction, ResidualError};

/// The proliferating continuum (see the [module docs](super)).
///
/// ```no_run
/// use celltissue::proliferation::DensityContinuum;
/// use celltissue::line::build::{continuum, LineParams};
/// use celltissue::line::run::{integrate, SolveSettings};
/// use celltissue::boundary::RightEnd;
/// use celltissue::cell::TanhGrowth;
/// use celltissue::{ArrayProblem, NeoHookean};
/// use std::sync::Arc;
/// let mut p = LineParams::unit_cells(100);
/// p.right = RightEnd::Free(None);
/// p.k = 1e-5.into();
/// p.growth = Some(Arc::new(TanhGrowth::default()));
/// let line = continuum(NeoHookean::new(1.0).unwrap(), &p, 50).unwrap();
/// let model = DensityContinuum::new(line, 100, 2.0).unwrap();
/// let mut prob = ArrayProblem::new(model);
/// integrate(&mut prob, &SolveSettings::default(), &[0.0, 3.0]);
/// println!("N(3) = {}", prob.array.cells());
/// ```
pub struct DensityContinuum<E: StrainEnergy> {
    /// The growing continuum line (segment `i`: reference length `h ℓ_i`, growth `g_i`).
    pub line: Line<E>,
    /// Relative cell density `r_i = ρ_i/ρ₀ = 2^{k_i}` of each segment.
    pub density: Vec<f64>,
    /// Area ratio at division (2).
    pub ratio: f64,
    /// Cells each segment holds at `t = 0` (`N₀/n` each for cells of equal length;
    /// [`segment_cells`](crate::line::build::segment_cells) for unequal ones).
    pub initial_cells: Vec<f64>,
    /// One record per segment division (`parent` = segment, `cells_after` = rounded `N`).
    pub log: DivisionLog,
    /// `(t, N)` after each segment division (`N` is not an integer in general).
    pub history: Vec<(f64, f64)>,
    /// No division once `N` reaches this.
    pub max_cells: Option<f64>,
    base_face: Vec<f64>,
    base_cell: Vec<f64>,
}

impl<E: StrainEnergy> DensityContinuum<E> {
    /// Wraps a growing continuum line built for `n0` initial cells; segments divide when
    /// `g g₂` reaches `ratio`.
    ///
    /// ```
    /// use celltissue::proliferation::DensityContinuum;
    /// use celltissue::line::{continuum, LineParams};
    /// let mut p = LineParams::unit_cells(10);
    /// p.right = celltissue::boundary::RightEnd::Free(None);
    /// p.growth = Some(std::sync::Arc::new(celltissue::cell::TanhGrowth::default()));
    /// let line = continuum(celltissue::NeoHookean::new(1.0)?, &p, 5)?;
    /// let model = DensityContinuum::new(line, 10, 2.0)?;
    /// assert_eq!(model.cells(), 10.0); // 5 segments of 2 cells each
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn new(line: Line<E>, n0: usize, ratio: f64) -> Result<Self, EventError> {
        let n = line.n_cells();
        Self::with_initial_cells(line, vec![n0 as f64 / n as f64; n], ratio)
    }

    /// As [`DensityContinuum::new`], with the cells each segment holds at `t = 0` given (one
    /// per segment, from [`segment_cells`](crate::line::build::segment_cells) when the cells'
    /// reference lengths differ).
    ///
    /// ```
    /// use celltissue::proliferation::DensityContinuum;
    /// use celltissue::line::build::{continuum, segment_cells, LineParams};
    /// let mut p = LineParams::unit_cells(3);
    /// p.ref_lengths = vec![0.5, 0.5, 2.0]; // two short cells, then a long one
    /// p.right = celltissue::boundary::RightEnd::Free(None);
    /// p.growth = Some(std::sync::Arc::new(celltissue::cell::TanhGrowth::default()));
    /// let line = continuum(celltissue::NeoHookean::new(1.0)?, &p, 3)?;
    /// let model = DensityContinuum::with_initial_cells(line, segment_cells(&p, 3), 2.0)?;
    /// assert_eq!(model.initial_cells, [2.0, 0.5, 0.5]); // segments of length 1
    /// assert_eq!(model.cells(), 3.0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn with_initial_cells(
        line: Line<E>,
        initial_cells: Vec<f64>,
        ratio: f64,
    ) -> Result<Self, EventError> {
        if !line.is_growing() {
            return Err(EventError::Unsupported(
                "a proliferating continuum without growth".into(),
            ));
        }
        if line.right.is_periodic() {
            return Err(EventError::Unsupported(
                "a proliferating continuum on a ring".into(),
            ));
        }
        if !(ratio > 1.0 && ratio.is_finite()) {
            return Err(EventError::Unsupported(format!(
                "division area ratio {ratio} (must be > 1)"
            )));
        }
        let n = line.n_cells();
        if initial_cells.len() != n || initial_cells.iter().any(|c| !(*c > 0.0 && c.is_finite())) {
            return Err(EventError::Unsupported(format!(
                "initial cell counts for {n} segments must be {n} finite positive numbers"
            )));
        }
        Ok(Self {
            density: vec![1.0; n],
            ratio,
            initial_cells,
            log: DivisionLog::default(),
            history: Vec::new(),
            max_cells: None,
            base_face: line.k_face.clone(),
            base_cell: line.cells.k_cell.clone(),
            line,
        })
    }

    /// Number of cells `N = ∫ρ dX = Σ r_i c_i` (`c_i` the [`initial_cells`](Self::initial_cells)).
    ///
    /// ```
    /// use celltissue::proliferation::DensityContinuum;
    /// use celltissue::line::{continuum, LineParams};
    /// let mut p = LineParams::unit_cells(10);
    /// p.right = celltissue::boundary::RightEnd::Free(None);
    /// p.growth = Some(std::sync::Arc::new(celltissue::cell::TanhGrowth::default()));
    /// let line = continuum(celltissue::NeoHookean::new(1.0)?, &p, 5)?;
    /// let model = DensityContinuum::new(line, 10, 2.0)?;
    /// assert_eq!(model.cells(), 10.0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn cells(&self) -> f64 {
        self.density
            .iter()
            .zip(&self.initial_cells)
            .map(|(r, c)| r * c)
            .sum()
    }

    /// `N(t)` from the history (right-continuous).
    ///
    /// ```
    /// use celltissue::proliferation::DensityContinuum;
    /// use celltissue::line::{continuum, LineParams};
    /// let mut p = LineParams::unit_cells(10);
    /// p.right = celltissue::boundary::RightEnd::Free(None);
    /// p.growth = Some(std::sync::Arc::new(celltissue::cell::TanhGrowth::default()));
    /// let line = continuum(celltissue::NeoHookean::new(1.0)?, &p, 5)?;
    /// let model = DensityContinuum::new(line, 10, 2.0)?;
    /// assert_eq!(model.cells_at(0.0), 10.0); // nothing divided yet
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn cells_at(&self, t: f64) -> f64 {
        self.history
            .iter()
            .take_while(|h| h.0 <= t)
            .last()
            .map_or_else(|| self.initial_cells.iter().sum(), |h| h.1)
    }

    /// Drag of face `b` and cell `i` from the densities (boundaries per unit X ∝ ρ).
    fn update_drag(&mut self, i: usize) {
        let n = self.density.len();
        let r = &self.density;
        for b in [i, i + 1] {
            let rf = match b {
                0 => r[0],
                b if b == n => r[n - 1],
                b => 0.5 * (r[b - 1] + r[b]),
            };
            // (the tip boundary's own half cell, if the grid carries it, is one boundary
            // whatever the density)
            let tip = if b == n { self.line.k_tip } else { 0.0 };
            self.line.k_face[b] = (self.base_face[b] - tip) * rf + tip;
        }
        self.line.cells.k_cell[i] = self.base_cell[i] * r[i];
    }
}

impl<E: StrainEnergy> CellArray for DensityContinuum<E> {
    // (the residual is the line's, so is its Jacobian: the line writes it itself)
    integrators::forward_problem!(line: dim, pattern, residual<S: Scalar>, jacobian(&self), atol,
        algebraic, set_threads);
    fn num_events(&self) -> usize {
        self.line.n_cells()
    }
    fn events(&mut self, _t: f64, y: &[f64], g: &mut [f64]) {
        let capped = self.max_cells.is_some_and(|m| self.cells() >= m);
        for (i, out) in g.iter_mut().enumerate() {
            let k = self.line.layout.gi[i];
            *out = if capped || k == NONE {
                -1.0
            } else {
                y[k] * self.line.g2 - self.ratio
            };
        }
    }
    fn handle_event(
        &mut self,
        t: f64,
        fired: &[usize],
        y: &mut Vec<f64>,
        _yp: &[f64],
    ) -> Result<EventAction, ResidualError> {
        let n = self.line.n_cells();
        let l = self.line.boundary(n, t, y, y).0 - self.line.boundary(0, t, y, y).0;
        for &i in fired {
            let k = self.line.layout.gi[i];
            let g = y[k];
            // ℓ ← ℓ g (cells' reference length per unit X), g ← 1: α and Σ L₀g unchanged
            self.line.cells.l0[i] *= g;
            y[k] = 1.0;
            self.density[i] *= 2.0;
            self.update_drag(i);
            let xc =
                0.5 * (self.line.boundary(i, t, y, y).0 + self.line.boundary(i + 1, t, y, y).0);
            let cells = self.cells();
            self.history.push((t, cells));
            self.log.push(DivisionRecord {
                t,
                parent: i + 1,
                x: xc,
                x_over_length: xc / l,
                cells_after: cells.round() as usize,
                age: None,
                cell: None,
                daughters: None,
            });
        }
        // L₀ and K changed in place: the line must re-detect its uniform fields
        self.line.refresh_uniform_fields();
        Ok(EventAction::Modified)
    }
}

impl<E: StrainEnergy> LineModel for DensityContinuum<E> {
    // `breakpoints` forwarded too: a prescribed polynomial-ramp end has a kink at `t_ramp`,
    // where `integrate` must restart rather than step across it.
    crate::line::run::forward_line_model!(line: initial_state, initial_derivative_guess,
        unknown_name, breakpoints);
    fn observe(
        &self,
        t: f64,
        y: &[f64],
        yp: &[f64],
    ) -> Result<crate::line::observe::Snapshot, ResidualError> {
        let mut s = self.line.observe(t, y, yp)?;
        s.cell_counts = Some(
            self.density
                .iter()
                .zip(&self.initial_cells)
                .map(|(r, c)| r * c)
                .collect(),
        );
        Ok(s)
    }
}
