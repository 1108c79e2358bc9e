//! Observables of the line (docs/model.md §6): a per-cell [`Snapshot`] at `(t, y, ẏ)` and its
//! reductions (length, end reaction, pressure/stretch extremes), turned into
//! [`crate::observe::Profile`]s and series rows.

use super::array::Line;
use crate::array::CellArray;
use crate::boundary::RightEnd;
use crate::energy::StrainEnergy;
use crate::observe::Profile;
use integrators::ResidualError;
use std::collections::BTreeMap;

/// Every per-cell quantity at one time (cells `1..=N` at index `0..N`).
///
/// ```
/// use celltissue::line::build::{discrete, LineParams};
/// use celltissue::NeoHookean;
/// let line = discrete(NeoHookean::new(1.0).unwrap(), &LineParams::unit_cells(5)).unwrap();
/// let y = line.initial_state();
/// let s = line.snapshot(0.0, &y, &vec![0.0; y.len()]).unwrap();
/// assert_eq!((s.length(), s.min_stretch(), s.max_pressure()), (5.0, 1.0, 1.0)); // at rest: p = μ
/// assert_eq!(s.x, [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Snapshot {
    /// Time.
    pub t: f64,
    /// Boundary positions `x₀..x_N`.
    pub x: Vec<f64>,
    /// Reference centres `X_{j−1/2}`.
    pub x_ref: Vec<f64>,
    /// Current centres.
    pub centre: Vec<f64>,
    /// Total stretch `λ`.
    pub lambda: Vec<f64>,
    /// Elastic stretch `α`.
    pub alpha: Vec<f64>,
    /// Full axial stress `σ`.
    pub sigma: Vec<f64>,
    /// Elastic stress `σ_el`.
    pub sigma_el: Vec<f64>,
    /// Pressure `p = p_el(α) − η α̇ α⁻²`.
    pub pressure: Vec<f64>,
    /// Width `W`.
    pub width: Vec<f64>,
    /// Drag factor `κ`.
    pub kappa: Vec<f64>,
    /// Growth stretch `g`.
    pub g: Vec<f64>,
    /// Growth rate `ġ`.
    pub g_dot: Vec<f64>,
    /// Energy scale `μ`.
    pub mu: Vec<f64>,
    /// Cells each entry stands for, where that is not one each: the segments of a continuum
    /// grid (`h/L` over cells of length `L`), of a proliferating continuum (its density, or a
    /// cell-number grid's segment sizes), the nodes of the thesis scheme (the cells within half
    /// a spacing). Series count `N` and average per cell with these weights; profiles carry
    /// them as `segment_cells`.
    pub cell_counts: Option<Vec<f64>>,
    /// A Maxwell branch's viscous stretch `a_v` per cell (`None` without a branch).
    pub viscous: Option<Vec<f64>>,
    /// Further per-cell fields a model adds to its profiles by name (a dividing line's cell
    /// `age`, `id` and `ancestor`).
    pub cell_fields: Vec<(String, Vec<f64>)>,
}

impl Snapshot {
    /// Current length `l = x_N − x₀`.
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// // four unit cells between a wall and an end held at 4; the first cell stretched to 1.2
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(4))?;
    /// let s = line.snapshot(0.0, &[1.2, 2.0, 3.0], &[0.0; 3])?;
    /// assert_eq!(s.length(), 4.0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn length(&self) -> f64 {
        self.x[self.x.len() - 1] - self.x[0]
    }
    /// End reaction `W_N σ_N` (force needed to hold the right end).
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// // four unit cells between a wall and an end held at 4; the first cell stretched to 1.2
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(4))?;
    /// let s = line.snapshot(0.0, &[1.2, 2.0, 3.0], &[0.0; 3])?;
    /// // the last cell (x₃ = 3 to the end at 4) is at its rest length: nothing pulls the end
    /// assert_eq!(s.end_reaction(), 0.0);
    /// // compressed to 0.8, it pushes: W σ = (1/0.8)(0.8² − 0.8⁻²)
    /// let c = line.snapshot(0.0, &[1.0, 2.0, 3.2], &[0.0; 3])?;
    /// assert!((c.end_reaction() - 1.25 * (0.64 - 1.0 / 0.64)).abs() < 1e-12);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn end_reaction(&self) -> f64 {
        let n = self.sigma.len();
        self.width[n - 1] * self.sigma[n - 1]
    }
    /// Maximum pressure.
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// // four unit cells between a wall and an end held at 4; the first cell stretched to 1.2
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(4))?;
    /// let s = line.snapshot(0.0, &[1.2, 2.0, 3.0], &[0.0; 3])?;
    /// // p = μα⁻²: the compressed second cell (α = 0.8) has the largest
    /// assert!((s.max_pressure() - 1.0 / 0.64).abs() < 1e-12);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn max_pressure(&self) -> f64 {
        self.pressure
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max)
    }
    /// Minimum pressure.
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// // four unit cells between a wall and an end held at 4; the first cell stretched to 1.2
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(4))?;
    /// let s = line.snapshot(0.0, &[1.2, 2.0, 3.0], &[0.0; 3])?;
    /// assert!((s.min_pressure() - 1.0 / 1.44).abs() < 1e-12); // the stretched first cell
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn min_pressure(&self) -> f64 {
        self.pressure.iter().copied().fold(f64::INFINITY, f64::min)
    }
    /// Maximum elastic stretch.
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// // four unit cells between a wall and an end held at 4; the first cell stretched to 1.2
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(4))?;
    /// let s = line.snapshot(0.0, &[1.2, 2.0, 3.0], &[0.0; 3])?;
    /// assert!((s.max_stretch() - 1.2).abs() < 1e-15);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn max_stretch(&self) -> f64 {
        self.alpha.iter().copied().fold(f64::NEG_INFINITY, f64::max)
    }
    /// Minimum elastic stretch.
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// // four unit cells between a wall and an end held at 4; the first cell stretched to 1.2
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(4))?;
    /// let s = line.snapshot(0.0, &[1.2, 2.0, 3.0], &[0.0; 3])?;
    /// assert!((s.min_stretch() - 0.8).abs() < 1e-15);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn min_stretch(&self) -> f64 {
        self.alpha.iter().copied().fold(f64::INFINITY, f64::min)
    }

    /// The profile record (X, x = current centres, stretch = α, pressure, plus `g`, `sigma`,
    /// `width`, `length` (current cell length), `lambda`, `kappa`, `mu` in `extra`, and for a
    /// proliferating continuum `segment_cells`, the cells each segment stands for).
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// // four unit cells between a wall and an end held at 4; the first cell stretched to 1.2
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(4))?;
    /// let s = line.snapshot(0.0, &[1.2, 2.0, 3.0], &[0.0; 3])?;
    /// let p = s.profile();
    /// assert_eq!(p.x_ref, [0.5, 1.5, 2.5, 3.5]); // reference centres
    /// assert!((p.x[0] - 0.6).abs() < 1e-15); // current centre of the first cell
    /// assert!(p.extra.contains_key("sigma") && !p.extra.contains_key("g")); // g only when growing
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn profile(&self) -> Profile {
        let mut extra = BTreeMap::new();
        extra.insert("sigma".to_string(), self.sigma.clone());
        extra.insert("width".to_string(), self.width.clone());
        // the current cell lengths x_j − x_{j−1}: with the centres, the cells' ends exactly
        // (`Profile::cell_ends`), whatever their reference lengths after divisions (a grid of
        // nodes, the thesis's continuum scheme, has no cells between its boundaries)
        if self.x.len() == self.centre.len() + 1 {
            extra.insert(
                "length".to_string(),
                self.x.windows(2).map(|w| w[1] - w[0]).collect(),
            );
        }
        extra.insert("lambda".to_string(), self.lambda.clone());
        extra.insert("kappa".to_string(), self.kappa.clone());
        extra.insert("mu".to_string(), self.mu.clone());
        // a proliferating continuum's segments stand for several cells each: its cell density
        if let Some(counts) = &self.cell_counts {
            extra.insert("segment_cells".to_string(), counts.clone());
        }
        if let Some(a) = &self.viscous {
            extra.insert("viscous".to_string(), a.clone());
        }
        if self.g.iter().any(|&g| g != 1.0) || self.g_dot.iter().any(|&g| g != 0.0) {
            extra.insert("g".to_string(), self.g.clone());
            extra.insert("g_dot".to_string(), self.g_dot.clone());
        }
        for (name, v) in &self.cell_fields {
            extra.insert(name.clone(), v.clone());
        }
        Profile {
            t: self.t,
            x_ref: self.x_ref.clone(),
            x: self.centre.clone(),
            stretch: self.alpha.clone(),
            pressure: self.pressure.clone(),
            extra,
        }
    }
}

impl<E: StrainEnergy> Line<E> {
    /// All per-cell quantities at `(t, y, ẏ)`.
    ///
    /// ```
    /// use celltissue::line::build::{LineParams, discrete};
    /// use celltissue::NeoHookean;
    /// let line = discrete(NeoHookean::new(1.0).unwrap(), &LineParams::unit_cells(4)).unwrap();
    /// let y = line.initial_state();
    /// let s = line.snapshot(0.0, &y, &vec![0.0; y.len()]).unwrap();
    /// assert_eq!(s.length(), 4.0);
    /// assert_eq!(s.max_pressure(), 1.0); // p = μ α⁻² at rest
    /// ```
    pub fn snapshot(&self, t: f64, y: &[f64], yp: &[f64]) -> Result<Snapshot, ResidualError> {
        let n = self.n_cells();
        // every vector allocated at its final size (pushing into empty ones at N = 10⁶ cost
        // a realloc copy per doubling), and one streaming pass that looks each boundary up once
        let cells = || Vec::with_capacity(n);
        let mut s = Snapshot {
            t,
            x: Vec::with_capacity(n + 1),
            x_ref: self.cells.x_ref.clone(),
            centre: cells(),
            lambda: cells(),
            alpha: cells(),
            sigma: cells(),
            sigma_el: cells(),
            pressure: cells(),
            width: cells(),
            kappa: cells(),
            g: cells(),
            g_dot: cells(),
            mu: self.cells.mu.clone(),
            cell_counts: self.segment_cells.clone().filter(|c| c.len() == n),
            viscous: self.maxwell.as_ref().map(|_| cells()),
            cell_fields: Vec::new(),
        };
        let mut left = self.boundary(0, t, y, yp);
        s.x.push(left.0);
        for j in 1..=n {
            let (c, right) = self.eval_cell_from(j, t, y, yp, left)?;
            let i = j - 1;
            let resp = self.energy.line(c.alpha);
            let mut p = self.cells.mu[i] * resp.pressure
                - self.cells.eta[i] * c.alpha_dot / (c.alpha * c.alpha)
                + self.cells.p_ext[i];
            if let Some(b) = &self.maxwell {
                // the branch's lateral stress joins the pressure (docs/viscoelasticity.md)
                let av = y[self.layout.vi[i]];
                p += b.pressure(&self.energy, c.alpha, av);
                if let Some(v) = s.viscous.as_mut() {
                    v.push(av);
                }
                if !b.elastic {
                    p -= self.cells.mu[i] * resp.pressure;
                }
            }
            s.x.push(right.0);
            s.centre.push(0.5 * (left.0 + right.0));
            left = right;
            s.lambda.push(c.lam);
            s.alpha.push(c.alpha);
            s.sigma.push(c.sigma);
            s.sigma_el.push(c.sigma_el);
            s.pressure.push(p);
            s.width.push(c.w);
            s.kappa.push(c.kappa);
            s.g.push(c.g);
            // ġ = G(σ) is the growth row itself: read at the output's state it holds to the
            // state's accuracy, where the interpolated ẏ erred by 22·rtol (rtol 1e-8, a
            // dividing line; the stretch by 1)
            s.g_dot.push(match (self.layout.gi[i], &self.growth) {
                (super::array::NONE, _) => 0.0,
                (_, Some(law)) => law.value(c.sigma),
                (k, None) => yp[k],
            });
        }
        Ok(s)
    }

    /// Whether the right end is prescribed (then [`Snapshot::end_reaction`] is the holding force).
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(4))?;
    /// assert!(line.has_prescribed_end());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn has_prescribed_end(&self) -> bool {
        matches!(self.right, RightEnd::Prescribed(_))
    }

    /// `dim()` shortcut usable without importing [`CellArray`].
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(4))?;
    /// assert_eq!(line.num_unknowns(), 3); // x₁, x₂, x₃
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn num_unknowns(&self) -> usize {
        CellArray::dim(self)
    }
}
