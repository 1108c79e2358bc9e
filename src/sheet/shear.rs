//! The simple-shear column (docs/model.md §1.5, §4.4–4.6).
//!
//! * [`ShearColumn`] — the canonical **edge form**: state `x_{e,k}`, the x-position of the top
//!   edge of cell `k` (base `x_{e,0} = 0` fixed), `T_k = (x_{e,k} − x_{e,k−1})/h`,
//!   `D ẋ_{e,k} = β₀(τ_{k+1} − τ_k)` and `D ẋ_{e,m} = F_A − β₀ τ_m`; tridiagonal Jacobian. On `M`
//!   cells (`h = γ₀`, `D = K`) it is the discrete model; on `m` segments (`h = Mγ₀/m`,
//!   `D = K h/γ₀`) it is the conservative scheme for `K x_t = β₀γ₀ ∂_y(τ(x_y))`.
//! * [`ShearCellCentre`] — the thesis's cell-centre form (4.85)–(4.98): state `x_{c,k}`,
//!   `K_th ẋ_{c,k} = F_{k−1/2} + F_{k+1/2}` with `F_{1/2} = 0`, edges rebuilt by the alternating
//!   sums `x_{e,k} = 2x_{c,k} − x_{e,k−1}`. Every `T_k` depends on all centres below it, so the
//!   Jacobian is dense lower-Hessenberg (declared [`Pattern::Dense`]: fine for the small `M` of
//!   the thesis, `O(M³)` per factorisation). It is exactly the edge form with `K = K_th/2`.
//!
//! **Kelvin–Voigt viscosity** ([`ShearParams::eta`]): `τ_k = τ(T_k) + (η/2) Ṫ_k`, the Newtonian
//! shear stress `2η_dim D₁₂` with `D₁₂ = Ṫ/2` and the dimensionless `η = 2η_dim/(μ₀t₀)` of the
//! line, so the small-strain retardation time is the line's `t_k = η/(2μ)`. The viscous stress
//! has no normal part (`D₁₁ = D₂₂ = 0`), so the pressure is the elastic one
//! (docs/viscoelasticity.md, "Kelvin–Voigt in the shear column").

use crate::array::CellArray;
use crate::energy::StrainEnergy;
use crate::scalar::Scalar;
use integrators::{Pattern, ResidualError};

/// Physical parameters of the shear column (docs/model.md §4.4).
///
/// ```
/// use celltissue::sheet::shear::{ShearColumn, ShearParams};
/// let p = ShearParams { cells: 4, force: 0.2, ..Default::default() };
/// // the edge form on 8 segments: one unknown per moving edge
/// let col = ShearColumn::continuum(celltissue::NeoHookean::new(1.0).unwrap(), &p, 8).unwrap();
/// assert_eq!(col.initial_state().len(), 8);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct ShearParams {
    /// Number of cells `M` (so `w₀ = Mγ₀`).
    pub cells: usize,
    /// Planar aspect ratio `γ₀` (cell height in the column's y direction).
    pub gamma0: f64,
    /// Height aspect ratio `β₀` (each x-face has area `β₀`).
    pub beta0: f64,
    /// Drag per edge `K` (edge form; `K = K_th/2`).
    pub drag: f64,
    /// Applied shear force `F_A` on the top edge.
    pub force: f64,
    /// Kelvin–Voigt viscosity `η ≥ 0` of every cell (including the factor 2, as on the line):
    /// `τ += (η/2) Ṫ`.
    pub eta: f64,
}

impl Default for ShearParams {
    /// `M = 10`, `γ₀ = β₀ = 1`, `K = ½` (`K_th = 1`), `F_A = 1` (docs/model.md §5.6).
    fn default() -> Self {
        Self {
            cells: 10,
            gamma0: 1.0,
            beta0: 1.0,
            drag: 0.5,
            force: 1.0,
            eta: 0.0,
        }
    }
}

/// Per-cell shear quantities in `f64`.
///
/// ```
/// use celltissue::sheet::shear::{ShearColumn, ShearParams};
/// let p = ShearParams { cells: 2, eta: 0.5, ..Default::default() };
/// let col = ShearColumn::continuum(celltissue::NeoHookean::new(1.0).unwrap(), &p, 2).unwrap();
/// // edges at x = 0.1 and 0.3 above the fixed base, the top one moving at speed 0.4
/// let f = col.fields(&[0.1, 0.3], &[0.0, 0.4]);
/// assert_eq!(f.x_edge, [0.0, 0.1, 0.3]);
/// assert!((f.tan_theta[1] - 0.2).abs() < 1e-12 && (f.x_centre[1] - 0.2).abs() < 1e-12);
/// // σ₁₂ = μ T + (η/2) Ṫ with Ṫ = 0.4 in the top cell
/// assert!((f.tau[1] - (0.2 + 0.25 * 0.4)).abs() < 1e-12);
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ShearFields {
    /// Reference centre heights `y` of the cells (or segments).
    pub y_ref: Vec<f64>,
    /// Edge positions `x_{e,0..m}` (length `m + 1`, `x_{e,0} = 0`).
    pub x_edge: Vec<f64>,
    /// Centre positions `x_{c,k} = (x_{e,k−1} + x_{e,k})/2`.
    pub x_centre: Vec<f64>,
    /// Amount of shear `T_k = tan θ_k`.
    pub tan_theta: Vec<f64>,
    /// Shear angle `θ_k` (radians).
    pub theta: Vec<f64>,
    /// Shear stress `σ₁₂ = τ(T_k)`.
    pub tau: Vec<f64>,
    /// Pressure from `σ₂₂ = 0` (`= μ` for neo-Hookean).
    pub pressure: Vec<f64>,
}

/// The canonical edge form of the shear column as a [`CellArray`] (tridiagonal Jacobian).
///
/// ```
/// use celltissue::sheet::shear::{ShearColumn, ShearParams};
/// use celltissue::{CellArray, NeoHookean};
/// let col = ShearColumn::discrete(NeoHookean::new(1.0)?, &ShearParams::default())?;
/// assert_eq!(col.dim(), col.initial_state().len());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct ShearColumn<E: StrainEnergy> {
    law: E,
    params: ShearParams,
    m: usize,
    h: f64,
    edge_drag: f64,
}

/// Why a shear column could not be built.
///
/// ```
/// use celltissue::sheet::shear::{ShearColumn, ShearParams};
/// let p = ShearParams { drag: -1.0, ..Default::default() };
/// let e = ShearColumn::continuum(celltissue::NeoHookean::new(1.0).unwrap(), &p, 10).err().unwrap();
/// assert!(e.to_string().starts_with("drag = -1 is out of range"), "{e}");
/// ```
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ShearBuildError {
    /// A parameter is out of range.
    #[error("{key} = {value} is out of range: {expected}")]
    Range {
        /// Parameter name.
        key: &'static str,
        /// Offending value.
        value: f64,
        /// Valid range.
        expected: &'static str,
    },
    /// The law has material directions and no simple-shear response of its own
    /// ([`StrainEnergy::shear_is_exact`]).
    #[error("{}", LAW_WITHOUT_SHEAR)]
    Law,
}

/// Why the column refuses a law whose [`StrainEnergy::shear_is_exact`] is `false`.
pub const LAW_WITHOUT_SHEAR: &str = "the law reads its in-plane stretches along the cell's axes (W(l1, l2, l3) differs from W(l2, l1, l3), as a fibre law's does) and has no simple-shear response of its own; simple shear turns the principal axes away from the cell's, so write W symmetric in l1 and l2 (or in I1, I2), or use `hgo` for fibres";

fn check_params(p: &ShearParams, m: usize) -> Result<(), ShearBuildError> {
    let bad = |key, value, expected| {
        Err(ShearBuildError::Range {
            key,
            value,
            expected,
        })
    };
    if p.cells < 1 {
        return bad("cells", p.cells as f64, ">= 1");
    }
    if m < 1 {
        return bad("grid m", m as f64, ">= 1");
    }
    if !(p.gamma0 > 0.0 && p.gamma0.is_finite()) {
        return bad("gamma0", p.gamma0, "> 0");
    }
    if !(p.beta0 > 0.0 && p.beta0.is_finite()) {
        return bad("beta0", p.beta0, "> 0");
    }
    if !(p.drag > 0.0 && p.drag.is_finite()) {
        return bad("drag", p.drag, "> 0");
    }
    if !p.force.is_finite() {
        return bad("force", p.force, "finite");
    }
    if !(p.eta >= 0.0 && p.eta.is_finite()) {
        return bad("eta", p.eta, ">= 0");
    }
    Ok(())
}

fn check_law<E: StrainEnergy>(law: &E) -> Result<(), ShearBuildError> {
    if law.shear_is_exact() {
        Ok(())
    } else {
        Err(ShearBuildError::Law)
    }
}

impl<E: StrainEnergy> ShearColumn<E> {
    /// The discrete column of `M` cells.
    ///
    /// ```
    /// use celltissue::sheet::shear::{ShearColumn, ShearParams};
    /// let col = ShearColumn::discrete(celltissue::NeoHookean::new(1.0)?, &ShearParams::default())?;
    /// assert_eq!((col.segments(), col.spacing()), (10, 1.0)); // M cells of height γ₀
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn discrete(law: E, params: &ShearParams) -> Result<Self, ShearBuildError> {
        Self::continuum(law, params, params.cells)
    }

    /// The conservative continuum scheme on `m` segments of height `h = Mγ₀/m`, edge drag
    /// `K h/γ₀` (docs/model.md §4.6). With `m = M` this is the discrete model.
    ///
    /// ```
    /// use celltissue::sheet::shear::{ShearColumn, ShearParams};
    /// // 10 cells of height γ₀ = 1 resolved on 40 segments
    /// let col = ShearColumn::continuum(celltissue::NeoHookean::new(1.0)?, &ShearParams::default(), 40)?;
    /// assert_eq!((col.segments(), col.spacing()), (40, 0.25));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn continuum(law: E, params: &ShearParams, m: usize) -> Result<Self, ShearBuildError> {
        check_params(params, m)?;
        check_law(&law)?;
        let h = params.cells as f64 * params.gamma0 / m as f64;
        Ok(Self {
            law,
            params: params.clone(),
            m,
            h,
            edge_drag: params.drag * h / params.gamma0,
        })
    }

    /// The physical parameters.
    ///
    /// ```
    /// use celltissue::sheet::shear::{ShearColumn, ShearParams};
    /// let p = ShearParams { cells: 5, gamma0: 2.0, ..Default::default() };
    /// let col = ShearColumn::continuum(celltissue::NeoHookean::new(1.5)?, &p, 20)?;
    /// assert_eq!(col.params().cells, 5);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn params(&self) -> &ShearParams {
        &self.params
    }
    /// Number of cells or segments.
    ///
    /// ```
    /// use celltissue::sheet::shear::{ShearColumn, ShearParams};
    /// let p = ShearParams { cells: 5, gamma0: 2.0, ..Default::default() };
    /// let col = ShearColumn::continuum(celltissue::NeoHookean::new(1.5)?, &p, 20)?;
    /// assert_eq!(col.segments(), 20);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn segments(&self) -> usize {
        self.m
    }
    /// Segment height `h`.
    ///
    /// ```
    /// use celltissue::sheet::shear::{ShearColumn, ShearParams};
    /// let p = ShearParams { cells: 5, gamma0: 2.0, ..Default::default() };
    /// let col = ShearColumn::continuum(celltissue::NeoHookean::new(1.5)?, &p, 20)?;
    /// assert_eq!(col.spacing(), 0.5); // Mγ₀/m
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn spacing(&self) -> f64 {
        self.h
    }
    /// The law.
    ///
    /// ```
    /// use celltissue::sheet::shear::{ShearColumn, ShearParams};
    /// let p = ShearParams { cells: 5, gamma0: 2.0, ..Default::default() };
    /// let col = ShearColumn::continuum(celltissue::NeoHookean::new(1.5)?, &p, 20)?;
    /// use celltissue::StrainEnergy;
    /// assert_eq!(col.law().shear_modulus(), 1.5);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn law(&self) -> &E {
        &self.law
    }
    /// Initial state `x_e ≡ 0` (docs/model.md §4.4, (4.89)).
    ///
    /// ```
    /// use celltissue::sheet::shear::{ShearColumn, ShearParams};
    /// let col = ShearColumn::discrete(celltissue::NeoHookean::new(1.0)?, &ShearParams::default())?;
    /// assert!(col.initial_state().iter().all(|&x| x == 0.0)); // unsheared
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn initial_state(&self) -> Vec<f64> {
        vec![0.0; self.m]
    }

    /// Per-cell fields from the edge state `y = x_{e,1..m}` and its rate `yp` (which enters
    /// only through the Kelvin–Voigt stress).
    ///
    /// ```
    /// use celltissue::sheet::shear::{ShearColumn, ShearParams};
    /// let col = ShearColumn::discrete(celltissue::NeoHookean::new(1.0)?, &ShearParams { cells: 2, ..Default::default() })?;
    /// let f = col.fields(&[0.5, 0.5], &[0.0, 0.0]); // the top cell unsheared
    /// assert_eq!((f.tan_theta[0], f.tan_theta[1]), (0.5, 0.0));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn fields(&self, y: &[f64], yp: &[f64]) -> ShearFields {
        let with_base = |v: &[f64]| [&[0.0], v].concat();
        let mut f = fields_from_edges(&self.law, &with_base(y), self.h);
        add_viscous_shear(&mut f, self.params.eta, &with_base(yp), self.h);
        f
    }
}

/// Adds the Kelvin–Voigt shear stress `(η/2) Ṫ_k` to `f.tau`, given the edge velocities
/// `ẋ_{e,0..m}` and the segment height `h`.
fn add_viscous_shear(f: &mut ShearFields, eta: f64, edge_rates: &[f64], h: f64) {
    if eta > 0.0 {
        for (tau, v) in f.tau.iter_mut().zip(edge_rates.windows(2)) {
            *tau += 0.5 * eta * (v[1] - v[0]) / h;
        }
    }
}

/// Per-cell fields from edge positions `x_{e,0..m}` and segment height `h`.
///
/// ```
/// use celltissue::sheet::shear::fields_from_edges;
/// // two cells of height 1, each sheared by tan θ = 0.2
/// let f = fields_from_edges(&celltissue::NeoHookean::new(1.0).unwrap(), &[0.0, 0.2, 0.4], 1.0);
/// assert!(f.tan_theta.iter().all(|t| (t - 0.2).abs() < 1e-12));
/// assert!(f.tau.iter().all(|s| (s - 0.2).abs() < 1e-12)); // σ₁₂ = μ tan θ
/// assert_eq!(f.y_ref, [0.5, 1.5]);
/// ```
pub fn fields_from_edges<E: StrainEnergy>(law: &E, xe: &[f64], h: f64) -> ShearFields {
    let m = xe.len() - 1;
    let mut f = ShearFields {
        x_edge: xe.to_vec(),
        ..Default::default()
    };
    for k in 1..=m {
        let t = (xe[k] - xe[k - 1]) / h;
        f.y_ref.push((k as f64 - 0.5) * h);
        f.x_centre.push(0.5 * (xe[k] + xe[k - 1]));
        f.tan_theta.push(t);
        f.theta.push(t.atan());
        f.tau.push(law.shear(t).tau);
        f.pressure.push(law.shear_pressure(t));
    }
    f
}

impl<E: StrainEnergy> CellArray for ShearColumn<E> {
    fn dim(&self) -> usize {
        self.m
    }

    fn pattern(&self) -> Pattern {
        Pattern::Banded { lower: 1, upper: 1 }
    }

    fn residual<S: Scalar>(
        &self,
        _t: f64,
        y: &[S],
        yp: &[S],
        r: &mut [S],
    ) -> Result<(), ResidualError> {
        let m = self.m;
        let b0 = self.params.beta0;
        let inv_h = 1.0 / self.h;
        let half_eta = 0.5 * self.params.eta;
        // cell k = 1..m between edges k−1 and k: T_k from y, Ṫ_k from yp
        let shear = |v: &[S], k: usize| -> S {
            let lo = if k == 1 { S::from(0.0) } else { v[k - 2] };
            (v[k - 1] - lo) * inv_h
        };
        let tau = |k: usize| -> S {
            let tt = shear(y, k);
            let s = self.law.shear(tt.re());
            let elastic = tt.lift(s.tau, s.dtau);
            if half_eta > 0.0 {
                elastic + shear(yp, k) * half_eta
            } else {
                elastic
            }
        };
        let mut below = tau(1);
        for k in 1..=m {
            let force = if k < m {
                let above = tau(k + 1);
                let f = (above - below) * b0;
                below = above;
                f
            } else {
                -below * b0 + self.params.force
            };
            r[k - 1] = yp[k - 1] * self.edge_drag - force;
        }
        Ok(())
    }

    /// A Kelvin–Voigt cell's shear stress reads its shear rate.
    fn outputs_read_rates(&self) -> bool {
        self.params.eta != 0.0
    }

    /// Edge `k` tested through its cell's shear `tan θ_k = (x_k − x_{k−1})/h`
    /// (docs/model.md §8.1): differenced with edge `k − 1`; the first edge (above the fixed
    /// base) is an anchor measured in segment heights, and also against its distance to the
    /// base (the first cell's own shear).
    fn error_map(&self) -> Option<integrators::ErrorMap> {
        use integrators::Row;
        let rows = (0..self.m)
            .map(|k| match k {
                0 => Row::Anchor { size: self.h },
                _ => Row::Difference { partner: k - 1 },
            })
            .collect();
        let map = integrators::ErrorMap::from_rows(rows).ok()?;
        match self.m {
            0 => Some(map),
            // the first cell's shear x₁/h: also against the edge's distance to the base
            _ => map
                .with_end_at(0, self.h, integrators::error_map::fixed(0.0))
                .ok(),
        }
    }
}

/// The thesis's cell-centre form of the shear column (docs/model.md §4.5), for comparison only.
///
/// ```
/// use celltissue::sheet::shear::{ShearCellCentre, ShearParams};
/// let col = ShearCellCentre::new(celltissue::NeoHookean::new(1.0).unwrap(), &ShearParams::default()).unwrap();
/// let x0 = col.initial_state();
/// let f = col.fields(&x0, &x0); // unsheared and at rest: x_c = 0 for every cell
/// assert_eq!(f.tan_theta.len(), 10);
/// assert!(f.tan_theta.iter().all(|t| t.abs() < 1e-15));
/// ```
///
/// State `x_{c,1..M}`; drag coefficient `K_th` (`= 2K`). Dense Jacobian: use small `M`.
pub struct ShearCellCentre<E: StrainEnergy> {
    law: E,
    params: ShearParams,
    k_th: f64,
}

impl<E: StrainEnergy> ShearCellCentre<E> {
    /// Builds the cell-centre form with `K_th = 2 params.drag` (so it matches the edge form with
    /// the same `params`).
    ///
    /// ```
    /// use celltissue::sheet::shear::{ShearCellCentre, ShearParams};
    /// let p = ShearParams { drag: 0.3, ..Default::default() };
    /// let col = ShearCellCentre::new(celltissue::NeoHookean::new(1.0)?, &p)?;
    /// assert_eq!(col.k_th(), 0.6); // the thesis's coefficient, twice the edge form's K
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn new(law: E, params: &ShearParams) -> Result<Self, ShearBuildError> {
        check_params(params, params.cells)?;
        check_law(&law)?;
        Ok(Self {
            law,
            params: params.clone(),
            k_th: 2.0 * params.drag,
        })
    }

    /// The thesis drag coefficient `K_th`.
    ///
    /// ```
    /// use celltissue::sheet::shear::{ShearCellCentre, ShearParams};
    /// let col = ShearCellCentre::new(celltissue::NeoHookean::new(1.0)?, &ShearParams { cells: 3, ..Default::default() })?;
    /// assert_eq!(col.k_th(), 1.0); // 2K with the default K = ½
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn k_th(&self) -> f64 {
        self.k_th
    }

    /// Initial state `x_c ≡ 0` ((4.89); the thesis's (4.98f) `x_c = ½` is inconsistent, §7).
    ///
    /// ```
    /// use celltissue::sheet::shear::{ShearCellCentre, ShearParams};
    /// let col = ShearCellCentre::new(celltissue::NeoHookean::new(1.0)?, &ShearParams { cells: 3, ..Default::default() })?;
    /// assert_eq!(col.initial_state(), [0.0; 3]);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn initial_state(&self) -> Vec<f64> {
        vec![0.0; self.params.cells]
    }

    /// Edge positions `x_{e,0..M}` from centres by the alternating sums (4.93)–(4.95).
    ///
    /// ```
    /// use celltissue::sheet::shear::ShearCellCentre;
    /// use celltissue::NeoHookean;
    /// // centres at 0.5 and 1.5 above a fixed base: edges at 1 and 2 (uniform shear)
    /// let xe = ShearCellCentre::<NeoHookean>::edges(&[0.5f64, 1.5]);
    /// assert_eq!(xe, [0.0, 1.0, 2.0]);
    /// ```
    pub fn edges<S: Scalar>(xc: &[S]) -> Vec<S> {
        let mut xe = Vec::with_capacity(xc.len() + 1);
        xe.push(S::from(0.0));
        for (k, &c) in xc.iter().enumerate() {
            let prev = xe[k];
            xe.push(c * 2.0 - prev);
        }
        xe
    }

    /// Per-cell fields from the centre state `xc` and its rate `xc_rate` (which enters only
    /// through the Kelvin–Voigt stress).
    ///
    /// ```
    /// use celltissue::sheet::shear::{ShearCellCentre, ShearParams};
    /// let col = ShearCellCentre::new(celltissue::NeoHookean::new(1.0)?, &ShearParams { cells: 3, ..Default::default() })?;
    /// // centres 0.5, 1.5, 2.5: edges at 1, 2, 3, every cell sheared by tan θ = 1
    /// let f = col.fields(&[0.5, 1.5, 2.5], &[0.0; 3]);
    /// assert_eq!(f.x_edge, [0.0, 1.0, 2.0, 3.0]);
    /// assert!(f.tan_theta.iter().all(|&t| t == 1.0));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn fields(&self, xc: &[f64], xc_rate: &[f64]) -> ShearFields {
        let h = self.params.gamma0;
        let mut f = fields_from_edges(&self.law, &Self::edges(xc), h);
        add_viscous_shear(&mut f, self.params.eta, &Self::edges(xc_rate), h);
        f
    }
}

impl<E: StrainEnergy> CellArray for ShearCellCentre<E> {
    fn dim(&self) -> usize {
        self.params.cells
    }

    /// A Kelvin–Voigt cell's shear stress reads its shear rate.
    fn outputs_read_rates(&self) -> bool {
        self.params.eta != 0.0
    }

    fn pattern(&self) -> Pattern {
        Pattern::Dense
    }

    /// Centre `k` tested through its difference with centre `k − 1`, which is
    /// `γ₀ (T_k + T_{k−1})/2`, the mean shear of the two cells; the first centre (`γ₀ T₁/2`
    /// above the fixed base) is an anchor of half a cell height. The tests are then
    /// translation invariant, as the edge form's are, instead of measuring centres that slide
    /// far against `rtol·|x_c|` (docs/model.md §8.1); the first centre is also tested against
    /// its own distance to the base, as the edge form's first edge is. The exact `T_k` is an alternating sum
    /// over every centre below it, which no two-term row expresses: a cell-to-cell alternation
    /// of the shear errors is seen only through the anchor.
    fn error_map(&self) -> Option<integrators::ErrorMap> {
        use integrators::Row;
        let rows = (0..self.params.cells)
            .map(|k| match k {
                0 => Row::Anchor {
                    size: 0.5 * self.params.gamma0,
                },
                _ => Row::Difference { partner: k - 1 },
            })
            .collect();
        let map = integrators::ErrorMap::from_rows(rows).ok()?;
        match self.params.cells {
            0 => Some(map),
            // the first centre's height above the base, γ₀T₁/2: also against its own size
            _ => map
                .with_end_at(
                    0,
                    0.5 * self.params.gamma0,
                    integrators::error_map::fixed(0.0),
                )
                .ok(),
        }
    }

    fn residual<S: Scalar>(
        &self,
        _t: f64,
        y: &[S],
        yp: &[S],
        r: &mut [S],
    ) -> Result<(), ResidualError> {
        let m = self.params.cells;
        let b0 = self.params.beta0;
        let xe = Self::edges(y);
        let inv_h = 1.0 / self.params.gamma0;
        let half_eta = 0.5 * self.params.eta;
        let ve = if half_eta > 0.0 {
            Self::edges(yp)
        } else {
            Vec::new()
        };
        let tau: Vec<S> = (1..=m)
            .map(|k| {
                let tt = (xe[k] - xe[k - 1]) * inv_h;
                let s = self.law.shear(tt.re());
                let elastic = tt.lift(s.tau, s.dtau);
                if half_eta > 0.0 {
                    elastic + (ve[k] - ve[k - 1]) * (inv_h * half_eta)
                } else {
                    elastic
                }
            })
            .collect();
        // F_{k+1/2}, k = 0..m: F_{1/2} = 0, F_{k+1/2} = β₀(τ_{k+1} − τ_k), F_{m+1/2} = F_A − β₀τ_m
        let face = |k: usize| -> S {
            if k == 0 {
                S::from(0.0)
            } else if k < m {
                (tau[k] - tau[k - 1]) * b0
            } else {
                -tau[m - 1] * b0 + self.params.force
            }
        };
        for k in 1..=m {
            r[k - 1] = yp[k - 1] * self.k_th - (face(k - 1) + face(k));
        }
        Ok(())
    }
}
