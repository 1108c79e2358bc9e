//! The uniaxial sheet as a [`CellArray`] (docs/model.md §4.1–4.3).
//!
//! **Unknowns, column by column.** For every column of cells `j = 1..n`: first the `m` y-face
//! positions of that column (`y_b(j, 1..m)` for a free top, `y_b(j, 0..m−1)` when periodic), then
//! (for `j < n`) the `m` x-face positions `x_b(j, 1..m)` between columns `j` and `j + 1`. Every
//! equation touches only its own and the neighbouring column blocks, so the Jacobian is
//! block-tridiagonal with blocks of size `2m`; it is declared as a [`Pattern::Sparse`] built from
//! its entries (no dense `dim × dim` matrix anywhere).
//!
//! With a Maxwell branch ([`SheetParams::branch`]) each column block starts with the `2m`
//! viscous stretches `a₁, a₂` of its cells (`(j, k)` at [`UniaxialSheet::iq`] and the next
//! index), so the blocks are `4m` wide.
//!
//! **Equations** (per face, primes = neighbouring cell; `D = K h_X h_Y / γ₀` is the per-face drag,
//! `= K` for the discrete model):
//! `D κ ẋ_b(j,k) = H W (σ₁₁' − σ₁₁)`, `D κ ẏ_b(j,k) = H L (σ₂₂' − σ₂₂)`, and for a free top
//! `D κ ẏ_b(j,m) = −H L σ₂₂(j,m)` with the top cell's own `H`, `L` (a free edge's faces carry
//! `K h_X (h_Y/γ₀ + 1)/2` or its x counterpart instead of `D` with
//! [`FreeEndDrag::Cells`]). A cell's `σᵢᵢ` is the law's
//! (unless the cell is a Maxwell cell) plus the branch's `μ_m/μ · σᵢᵢ(λ₁/a₁, λ₂/a₂)` plus the
//! Kelvin–Voigt stress `η(α̇ᵢ − α̇₃)` minus the external pressure `p_e(X)` on its upper face;
//! each viscous stretch has the row `ȧᵢ − aᵢ·2 dev(σ_m)ᵢᵢ/η_m = 0` (docs/viscoelasticity.md,
//! "The sheet" and "Kelvin–Voigt in the sheet"; docs/external_pressure.md). With `η > 0` the
//! face rows hold the face velocities of the neighbouring cells too, inside the same pattern.

use super::config::{GrowthDirections, RightEdge, TopBoundary};
use super::ramp::Ramp;
use crate::array::CellArray;
use crate::cell::{Field, GrowthLaw, MaxwellBranch, ViscousBranch};
use crate::energy::{SheetResponse, StrainEnergy};
use crate::line::homogenise::{jumps_between_cells, segment_means};
use crate::scalar::Scalar;
use crate::substrate::FreeEndDrag;
use integrators::{Pattern, SparsityPattern};
use std::cell::RefCell;

mod fields;
mod residual;
use std::sync::Arc;

/// Physical parameters of a sheet (docs/model.md §0.3, §4.1). The grid is chosen separately
/// ([`UniaxialSheet::discrete`] or [`UniaxialSheet::continuum`]).
///
/// ```
/// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
/// let p = SheetParams { cells_x: 4, cells_y: 2, drag_exponent: 1.0, ..Default::default() };
/// let sheet = UniaxialSheet::discrete(celltissue::NeoHookean::new(1.0)?, &p)?;
/// assert_eq!((sheet.grid(), sheet.l0(), sheet.w0()), ((4, 2), 4.0, 2.0));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct SheetParams {
    /// Number of cells in x, `N` (so `l₀ = N`).
    pub cells_x: usize,
    /// Number of rows of cells in y, `M` (so `w₀ = M γ₀`).
    pub cells_y: usize,
    /// Planar aspect ratio `γ₀ = W₀/L₀`.
    pub gamma0: f64,
    /// Height aspect ratio `β₀ = H₀/L₀`.
    pub beta0: f64,
    /// Substrate drag per boundary `K` (boundary form; `K = K_th/2`, docs/model.md §4.2).
    pub drag: f64,
    /// Drag–area exponent `m` in `κ = (λ₁λ₂)^m`.
    pub drag_exponent: f64,
    /// Fractional shortening `k₁` of the prescribed edge.
    pub k1: f64,
    /// Ramp shape of `l(t)`.
    pub ramp: Ramp,
    /// Free (zero-traction) or periodic side `y = w₀`.
    pub top: TopBoundary,
    /// Maxwell branch of every cell (Maxwell or standard-linear-solid cells), if any.
    pub branch: Option<MaxwellBranch>,
    /// Kelvin–Voigt viscosity `η ≥ 0` of every cell (including the factor 2, as on the line):
    /// `η α̇ᵢ` in each principal direction ([`kelvin_voigt_sheet`](crate::cell::kelvin_voigt_sheet)); 0 for elastic cells.
    pub eta: f64,
    /// External pressure `p_e(X)` on each cell's upper face `z = H`, a field of the reference
    /// position `X` sampled at the cell (segment) centres; constant along `Y`.
    pub external_pressure: Field,
    /// Prescribed (the ramp) or free side `x = l`.
    pub right: RightEdge,
    /// Growth of the cells' in-plane reference lengths, if any.
    pub growth: Option<SheetGrowth>,
    /// A continuum grid's drag on its free edges (the free top's `y` faces, a free side's `x`
    /// faces; [`FreeEndDrag`], as on the line): `Cells` adds the edge cells' own half cell of
    /// drag, so that the grid approximates the discrete sheet to second order.
    pub free_end_drag: FreeEndDrag,
}

/// Stress-dependent growth of a sheet's cells (docs/sheet_growth.md): growth stretches `g₁`,
/// `g₂` with `ġᵢ = G(σᵢᵢ)` in the growing directions; the law sees `λᵢ/gᵢ`.
///
/// ```
/// use celltissue::cell::TanhGrowth;
/// use celltissue::sheet::uniaxial::{SheetGrowth, SheetParams, UniaxialSheet};
/// use celltissue::sheet::{GrowthDirections, RightEdge};
/// use std::sync::Arc;
/// let p = SheetParams {
///     right: RightEdge::Free,
///     growth: Some(SheetGrowth { law: Arc::new(TanhGrowth::default()), directions: GrowthDirections::Both }),
///     ..Default::default()
/// };
/// let sheet = UniaxialSheet::discrete(celltissue::NeoHookean::new(1.0)?, &p)?;
/// let y = sheet.initial_state();
/// assert_eq!((y[sheet.ig(1, 1)], y[sheet.ig(1, 1) + 1]), (1.0, 1.0)); // g₁, g₂ at rest
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone)]
pub struct SheetGrowth {
    /// The growth law `G`.
    pub law: Arc<dyn GrowthLaw>,
    /// The directions that grow.
    pub directions: GrowthDirections,
}

impl std::fmt::Debug for SheetGrowth {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "SheetGrowth {{ directions: {:?} }}", self.directions)
    }
}

/// The drag of a face on a free edge of a grid whose segments hold `along` cells along the
/// edge and `across` cells across it: its segment's, `face_drag = K along·across`, or with
/// [`FreeEndDrag::Cells`] half of it plus the edge cells' own half faces, `K along (across + 1)/2`
/// (the discrete sheet's edge face carries `K`, half a cell beyond the distributed drag;
/// docs/model.md §3.3a).
fn edge_drag(p: &SheetParams, face_drag: f64, along: f64, across: f64) -> f64 {
    match p.free_end_drag {
        FreeEndDrag::Segment => face_drag,
        FreeEndDrag::Cells => p.drag * along * FreeEndDrag::Cells.end_face(across),
    }
}

impl Default for SheetParams {
    /// The thesis defaults: `N = M = 10`, `γ₀ = β₀ = 1`, `K = ½` (`K_th = 1`), `m = 0`,
    /// `k₁ = 0.1`, exponential ramp, free top.
    fn default() -> Self {
        Self {
            cells_x: 10,
            cells_y: 10,
            gamma0: 1.0,
            beta0: 1.0,
            drag: 0.5,
            drag_exponent: 0.0,
            k1: 0.1,
            ramp: Ramp::default(),
            top: TopBoundary::Free,
            branch: None,
            eta: 0.0,
            external_pressure: Field::Constant(0.0),
            right: RightEdge::Prescribed,
            growth: None,
            free_end_drag: FreeEndDrag::Segment,
        }
    }
}

/// Per-cell quantities in `f64`, for observers and writers.
///
/// ```
/// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
/// let sheet = UniaxialSheet::discrete(celltissue::NeoHookean::new(1.0)?, &SheetParams::default())?;
/// let y = sheet.initial_state();
/// let c = sheet.cells(0.0, &y, &vec![0.0; y.len()])[0]; // column 1, row 1
/// assert_eq!((c.j, c.k, c.x, c.stretch), (1, 1, [0.0, 1.0], [1.0, 1.0, 1.0]));
/// assert_eq!((c.growth, c.viscous), ([1.0, 1.0], [1.0, 1.0]));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SheetCell {
    /// Column index `j = 1..n`.
    pub j: usize,
    /// Row index `k = 1..m`.
    pub k: usize,
    /// Cell extent in x: `[x_b(j−1,k), x_b(j,k)]`.
    pub x: [f64; 2],
    /// Cell extent in y: `[y_b(j,k−1), y_b(j,k)]`.
    pub y: [f64; 2],
    /// Reference centre `(X, Y)`.
    pub reference: [f64; 2],
    /// Stretches `λ₁, λ₂, λ₃`.
    pub stretch: [f64; 3],
    /// Height `H = β₀ λ₃`.
    pub height: f64,
    /// Pressure `p = λ₃ W₃`.
    pub pressure: f64,
    /// `σ₁₁`.
    pub s11: f64,
    /// `σ₂₂`.
    pub s22: f64,
    /// Drag factor `κ = (λ₁λ₂)^m`.
    pub kappa: f64,
    /// Viscous stretches `(a₁, a₂)` of the Maxwell branch (`(1, 1)` without one).
    pub viscous: [f64; 2],
    /// Growth stretches `(g₁, g₂)` (`(1, 1)` without growth).
    pub growth: [f64; 2],
}

impl Default for SheetCell {
    /// A unit cell at the origin: extents, position, pressure, stresses, height and indices 0;
    /// the stretches, `κ` and the viscous and growth stretches 1 (so that the ratios of
    /// [`SheetCell::elastic_stretch`] are defined).
    fn default() -> Self {
        Self {
            j: 0,
            k: 0,
            x: [0.0; 2],
            y: [0.0; 2],
            reference: [0.0; 2],
            stretch: [1.0; 3],
            height: 0.0,
            pressure: 0.0,
            s11: 0.0,
            s22: 0.0,
            kappa: 1.0,
            viscous: [1.0; 2],
            growth: [1.0; 2],
        }
    }
}

impl SheetCell {
    /// The in-plane stretches relative to the grown cell, `αᵢ = λᵢ / gᵢ`: what the cell law
    /// sees and what sets its pressure (`λᵢ` itself without growth). `λ₃` is already elastic,
    /// the height's reference is not grown.
    ///
    /// ```
    /// use celltissue::sheet::uniaxial::SheetCell;
    /// let c = SheetCell { stretch: [3.0, 1.5, 0.5], growth: [2.0, 1.5], ..Default::default() };
    /// assert_eq!(c.elastic_stretch(), [1.5, 1.0]);
    /// ```
    pub fn elastic_stretch(&self) -> [f64; 2] {
        [
            self.stretch[0] / self.growth[0],
            self.stretch[1] / self.growth[1],
        ]
    }
}

/// A uniaxial sheet of `n × m` cells (or continuum segments) as a [`CellArray`].
///
/// ```
/// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
/// use celltissue::{ArrayProblem, CellArray, NeoHookean};
/// let sheet = UniaxialSheet::discrete(NeoHookean::new(1.0)?, &SheetParams::default())?;
/// let y0 = sheet.initial_state();
/// assert_eq!(y0.len(), sheet.dim());
/// let _problem = ArrayProblem::new(sheet); // an integrators::Problem
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct UniaxialSheet<E: StrainEnergy> {
    law: E,
    params: SheetParams,
    n: usize,
    m: usize,
    hx: f64,
    hy: f64,
    face_drag: f64,
    /// The drag of a free top's `y` faces and of a free side's `x` faces (`face_drag` unless
    /// [`FreeEndDrag::Cells`]).
    top_drag: f64,
    side_drag: f64,
    pattern: Pattern,
    /// Per-cell response cache keyed by the exact `(λ₁, λ₂)` values: all colours of one AD
    /// Jacobian share the real parts, so the law is evaluated once per cell per Jacobian.
    cache: RefCell<Vec<(f64, f64, SheetResponse)>>,
    /// The same for the branch, keyed by the elastic stretches `(λ₁/a₁, λ₂/a₂)`.
    branch_cache: RefCell<Vec<(f64, f64, SheetResponse)>>,
    /// `p_e` of each column `j = 1..n` (index `j − 1`).
    p_ext: Vec<f64>,
    /// Whether any `p_e` is non-zero (the residual skips it otherwise).
    pressure: bool,
    /// Unknowns per column block: `2m`, plus `2m` with a branch and `2m` with growth.
    block: usize,
    /// Offset of the growth stretches in a block: 0, or `2m` with a branch.
    growth_at: usize,
    /// Offset of the face unknowns in a block: `2m` per branch and growth.
    faces: usize,
    /// Offset of the x-face unknowns in a block, `faces + m`.
    x_faces: usize,
    atol_cell: Option<f64>,
}

/// Why a sheet could not be built.
///
/// ```
/// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
/// let p = SheetParams { gamma0: -1.0, ..Default::default() };
/// let e = UniaxialSheet::discrete(celltissue::NeoHookean::new(1.0)?, &p).err().unwrap();
/// assert_eq!(e.to_string(), "gamma0 = -1 is out of range: > 0");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SheetBuildError {
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
}

fn check(
    ok: bool,
    key: &'static str,
    value: f64,
    expected: &'static str,
) -> Result<(), SheetBuildError> {
    if ok {
        Ok(())
    } else {
        Err(SheetBuildError::Range {
            key,
            value,
            expected,
        })
    }
}

impl<E: StrainEnergy> UniaxialSheet<E> {
    /// The discrete model: `N × M` cells of reference size `1 × γ₀`.
    ///
    /// ```
    /// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
    /// let p = SheetParams { cells_x: 6, cells_y: 3, ..Default::default() };
    /// let sheet = UniaxialSheet::discrete(celltissue::NeoHookean::new(1.0)?, &p)?;
    /// // unit cells: the grid is the cells, the spacing their reference size 1 × γ₀
    /// assert_eq!((sheet.grid(), sheet.spacing()), ((6, 3), (1.0, 1.0)));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn discrete(law: E, params: &SheetParams) -> Result<Self, SheetBuildError> {
        Self::continuum(law, params, params.cells_x, params.cells_y)
    }

    /// The conservative continuum scheme on an `n × m` grid (docs/model.md §4.3): reference cells
    /// `h_X = N/n`, `h_Y = Mγ₀/m`, per-face drag `K h_X h_Y/γ₀`. With `n = N`, `m = M` this is the
    /// discrete model.
    ///
    /// ```
    /// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
    /// let p = SheetParams { cells_x: 6, cells_y: 3, ..Default::default() };
    /// // the same 6 × 3 sheet resolved on a 12 × 12 grid: a quarter-cell in y
    /// let sheet = UniaxialSheet::continuum(celltissue::NeoHookean::new(1.0)?, &p, 12, 12)?;
    /// assert_eq!((sheet.l0(), sheet.w0(), sheet.spacing()), (6.0, 3.0, (0.5, 0.25)));
    /// assert!(UniaxialSheet::continuum(celltissue::NeoHookean::new(1.0)?, &p, 0, 12).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn continuum(
        law: E,
        params: &SheetParams,
        n: usize,
        m: usize,
    ) -> Result<Self, SheetBuildError> {
        let p = params;
        check(p.cells_x >= 1, "cells_x", p.cells_x as f64, ">= 1")?;
        check(p.cells_y >= 1, "cells_y", p.cells_y as f64, ">= 1")?;
        check(n >= 1, "grid n", n as f64, ">= 1")?;
        check(m >= 1, "grid m", m as f64, ">= 1")?;
        check(
            p.gamma0 > 0.0 && p.gamma0.is_finite(),
            "gamma0",
            p.gamma0,
            "> 0",
        )?;
        check(
            p.beta0 > 0.0 && p.beta0.is_finite(),
            "beta0",
            p.beta0,
            "> 0",
        )?;
        check(p.drag >= 0.0 && p.drag.is_finite(), "drag", p.drag, ">= 0")?;
        check(p.eta >= 0.0 && p.eta.is_finite(), "eta", p.eta, ">= 0")?;
        check(
            p.drag_exponent.is_finite(),
            "drag_exponent",
            p.drag_exponent,
            "finite",
        )?;
        check(p.k1 < 1.0 && p.k1 > -1.0, "k1", p.k1, "(-1, 1)")?;
        check(
            p.growth.is_some() || p.right == RightEdge::Prescribed,
            "right",
            f64::NAN,
            "prescribed unless the sheet grows (nothing drives a free sheet)",
        )?;
        check(p.ramp.t_ramp() > 0.0, "t_ramp", p.ramp.t_ramp(), "> 0")?;
        check(
            !(p.top == TopBoundary::Periodic && p.drag == 0.0),
            "drag",
            p.drag,
            "> 0 for a periodic side (rigid y-translation is a null mode)",
        )?;
        let hx = p.cells_x as f64 / n as f64;
        let hy = p.cells_y as f64 * p.gamma0 / m as f64;
        let centres: Vec<f64> = (1..=n).map(|j| (j as f64 - 0.5) * hx).collect();
        // a random pressure is drawn per cell column, the same on every grid; a column of
        // segments over several cell columns takes their mean (the sheet's μ is uniform:
        // docs/model.md §3.3, "Cell-scale heterogeneity")
        let columns = p.external_pressure.drawn_per_cell(p.cells_x);
        let width = p.cells_x as f64;
        let p_ext = jumps_between_cells(&columns, p.cells_x)
            .then(|| {
                let mids: Vec<f64> = (0..p.cells_x).map(|c| c as f64 + 0.5).collect();
                let faces: Vec<f64> = (0..=n).map(|j| j as f64 * hx).collect();
                let per_column = columns.sample(&mids, width);
                segment_means(&vec![1.0; p.cells_x], &faces, &per_column)
            })
            .flatten()
            .unwrap_or_else(|| columns.sample(&centres, width));
        if let Some(&bad) = p_ext.iter().find(|v| !v.is_finite()) {
            return Err(SheetBuildError::Range {
                key: "external_pressure",
                value: bad,
                expected: "finite at every cell",
            });
        }
        let growth_at = if p.branch.is_some() { 2 * m } else { 0 };
        let face_drag = p.drag * hx * hy / p.gamma0;
        let faces = growth_at + if p.growth.is_some() { 2 * m } else { 0 };
        let mut s = Self {
            law,
            params: p.clone(),
            n,
            m,
            hx,
            hy,
            face_drag,
            top_drag: edge_drag(p, face_drag, hx, hy / p.gamma0),
            side_drag: edge_drag(p, face_drag, hy / p.gamma0, hx),
            pattern: Pattern::Dense,
            cache: RefCell::new(Vec::new()),
            branch_cache: RefCell::new(Vec::new()),
            pressure: p_ext.iter().any(|&v| v != 0.0),
            p_ext,
            block: faces + 2 * m,
            growth_at,
            faces,
            x_faces: faces + m,
            atol_cell: None,
        };
        s.pattern = Pattern::Sparse(Arc::new(s.build_pattern()));
        s.cache = RefCell::new(vec![(f64::NAN, f64::NAN, zero_response()); n * m]);
        if s.params.branch.is_some() {
            s.branch_cache = RefCell::new(vec![(f64::NAN, f64::NAN, zero_response()); n * m]);
        }
        Ok(s)
    }

    /// Sets per-unknown absolute tolerances to `atol × h` (cell-sized units): `h_X` for x-faces,
    /// `h_Y` for y-faces. Without it the solver's scalar `atol` is used.
    ///
    /// ```
    /// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
    /// use celltissue::CellArray;
    /// let sheet = UniaxialSheet::continuum(celltissue::NeoHookean::new(1.0)?, &SheetParams::default(), 20, 40)?
    ///     .with_cell_atol(1e-8);
    /// // each face position's tolerance is atol times its segment's size (h_X = 0.5, h_Y = 0.25)
    /// let atol = sheet.atol().unwrap();
    /// assert_eq!((atol[sheet.iy(1, 1)], atol[sheet.ix(1, 1)]), (0.25e-8, 0.5e-8));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn with_cell_atol(mut self, atol: f64) -> Self {
        self.atol_cell = Some(atol);
        self
    }

    /// The strain-energy law.
    ///
    /// ```
    /// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
    /// let p = SheetParams { cells_x: 6, cells_y: 3, gamma0: 0.5, ..Default::default() };
    /// let sheet = UniaxialSheet::continuum(celltissue::NeoHookean::new(2.0)?, &p, 12, 3)?;
    /// use celltissue::StrainEnergy;
    /// assert_eq!(sheet.law().shear_modulus(), 2.0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn law(&self) -> &E {
        &self.law
    }
    /// The physical parameters.
    ///
    /// ```
    /// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
    /// let p = SheetParams { cells_x: 6, cells_y: 3, gamma0: 0.5, ..Default::default() };
    /// let sheet = UniaxialSheet::continuum(celltissue::NeoHookean::new(2.0)?, &p, 12, 3)?;
    /// assert_eq!((sheet.params().cells_x, sheet.params().gamma0), (6, 0.5));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn params(&self) -> &SheetParams {
        &self.params
    }
    /// Grid size `(n, m)` (cells or continuum segments in x and y).
    ///
    /// ```
    /// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
    /// let p = SheetParams { cells_x: 6, cells_y: 3, gamma0: 0.5, ..Default::default() };
    /// let sheet = UniaxialSheet::continuum(celltissue::NeoHookean::new(2.0)?, &p, 12, 3)?;
    /// assert_eq!(sheet.grid(), (12, 3)); // the continuum grid, not the cells
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn grid(&self) -> (usize, usize) {
        (self.n, self.m)
    }
    /// Reference cell size `(h_X, h_Y)`.
    ///
    /// ```
    /// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
    /// let p = SheetParams { cells_x: 6, cells_y: 3, gamma0: 0.5, ..Default::default() };
    /// let sheet = UniaxialSheet::continuum(celltissue::NeoHookean::new(2.0)?, &p, 12, 3)?;
    /// assert_eq!(sheet.spacing(), (0.5, 0.5)); // h_X = N/n, h_Y = Mγ₀/m
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn spacing(&self) -> (f64, f64) {
        (self.hx, self.hy)
    }
    /// Reference length `l₀ = N`.
    ///
    /// ```
    /// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
    /// let p = SheetParams { cells_x: 6, cells_y: 3, gamma0: 0.5, ..Default::default() };
    /// let sheet = UniaxialSheet::continuum(celltissue::NeoHookean::new(2.0)?, &p, 12, 3)?;
    /// assert_eq!(sheet.l0(), 6.0); // N cells of unit length
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn l0(&self) -> f64 {
        self.params.cells_x as f64
    }
    /// Reference width `w₀ = M γ₀`.
    ///
    /// ```
    /// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
    /// let p = SheetParams { cells_x: 6, cells_y: 3, gamma0: 0.5, ..Default::default() };
    /// let sheet = UniaxialSheet::continuum(celltissue::NeoHookean::new(2.0)?, &p, 12, 3)?;
    /// assert_eq!(sheet.w0(), 1.5); // M rows of width γ₀
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn w0(&self) -> f64 {
        self.params.cells_y as f64 * self.params.gamma0
    }
    /// The prescribed length `l(t)` (the ramp; see [`Self::right_edge`] for a free edge).
    ///
    /// ```
    /// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
    /// let sheet = UniaxialSheet::discrete(celltissue::NeoHookean::new(1.0)?, &SheetParams::default())?;
    /// // the exponential ramp shortens the 10-cell sheet by k₁ = 10 %
    /// assert_eq!(sheet.length(0.0), 10.0);
    /// assert!((sheet.length(50.0) - 9.0).abs() < 1e-12);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn length(&self, t: f64) -> f64 {
        self.params.ramp.length(self.l0(), self.params.k1, t)
    }

    /// The prescribed edge's velocity `l'(t)` (0 for a free edge, whose velocity is an unknown).
    fn length_rate(&self, t: f64) -> f64 {
        if self.free_right() {
            0.0
        } else {
            self.params.ramp.length_rate(self.l0(), self.params.k1, t)
        }
    }

    /// Index of the unknown `y_b(j, k)` (`j = 1..n`; `k = 1..m` free top, `k = 0..m−1` periodic).
    ///
    /// ```
    /// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
    /// let sheet = UniaxialSheet::discrete(celltissue::NeoHookean::new(1.0)?, &SheetParams::default())?;
    /// let y = sheet.initial_state();
    /// // the top face of column 2 starts at y = M γ₀ = 10
    /// assert_eq!(y[sheet.iy(2, 10)], 10.0);
    /// assert_eq!(sheet.yb(&y, 2, 10), 10.0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn iy(&self, j: usize, k: usize) -> usize {
        let base = (j - 1) * self.block + self.faces;
        match self.params.top {
            TopBoundary::Free => base + k - 1,
            TopBoundary::Periodic => base + k,
        }
    }
    /// Index of the unknown `x_b(j, k)` (`j = 1..n−1`, and `j = n` with a free right edge;
    /// `k = 1..m`).
    ///
    /// ```
    /// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
    /// let sheet = UniaxialSheet::discrete(celltissue::NeoHookean::new(1.0)?, &SheetParams::default())?;
    /// let y = sheet.initial_state();
    /// // the face between columns 3 and 4 of row 5 starts at x = 3
    /// assert_eq!(y[sheet.ix(3, 5)], 3.0);
    /// assert_eq!(sheet.xb(&y, 0.0, 3, 5), 3.0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn ix(&self, j: usize, k: usize) -> usize {
        (j - 1) * self.block + self.x_faces + k - 1
    }
    /// Index of cell `(j, k)`'s viscous stretch `a₁` (`a₂` is the next unknown), with a
    /// Maxwell branch (`j = 1..n`, `k = 1..m`).
    ///
    /// ```
    /// use celltissue::cell::MaxwellBranch;
    /// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
    /// let p = SheetParams { cells_x: 2, cells_y: 2, branch: Some(MaxwellBranch::maxwell(1.0, 1.0)?), ..Default::default() };
    /// let sheet = UniaxialSheet::discrete(celltissue::NeoHookean::new(1.0)?, &p)?;
    /// // each column block starts with its cells' viscous stretches (a₁, a₂)
    /// assert_eq!((sheet.iq(1, 1), sheet.iq(1, 2), sheet.iq(2, 1)), (0, 2, sheet.iq(1, 1) + 4 + 4));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn iq(&self, j: usize, k: usize) -> usize {
        (j - 1) * self.block + 2 * (k - 1)
    }
    /// Index of cell `(j, k)`'s growth stretch `g₁` (`g₂` is the next unknown), when the
    /// sheet grows.
    ///
    /// ```
    /// use celltissue::cell::TanhGrowth;
    /// use celltissue::sheet::uniaxial::{SheetGrowth, SheetParams, UniaxialSheet};
    /// use celltissue::sheet::GrowthDirections;
    /// let p = SheetParams {
    ///     growth: Some(SheetGrowth { law: std::sync::Arc::new(TanhGrowth::default()), directions: GrowthDirections::Both }),
    ///     ..Default::default()
    /// };
    /// let sheet = UniaxialSheet::discrete(celltissue::NeoHookean::new(1.0)?, &p)?;
    /// let y = sheet.initial_state();
    /// assert_eq!((y[sheet.ig(3, 4)], y[sheet.ig(3, 4) + 1]), (1.0, 1.0)); // g₁, g₂ at rest
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn ig(&self, j: usize, k: usize) -> usize {
        (j - 1) * self.block + self.growth_at + 2 * (k - 1)
    }
    /// Whether the side `x = l` is free (its face positions are unknowns).
    fn free_right(&self) -> bool {
        self.params.right == RightEdge::Free
    }
    /// Whether `x_b(j, k)` is an unknown (`j ≥ 1`; the last column's only on a free edge).
    fn x_is_unknown(&self, j: usize) -> bool {
        j >= 1 && (j < self.n || self.free_right())
    }
    /// The growth, if any.
    ///
    /// ```
    /// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
    /// let p = SheetParams { cells_x: 6, cells_y: 3, gamma0: 0.5, ..Default::default() };
    /// let sheet = UniaxialSheet::continuum(celltissue::NeoHookean::new(2.0)?, &p, 12, 3)?;
    /// assert!(sheet.growth().is_none());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn growth(&self) -> Option<&SheetGrowth> {
        self.params.growth.as_ref()
    }
    /// Mean position of the side `x = l` over the rows: `l(t)` when prescribed.
    ///
    /// ```
    /// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
    /// let sheet = UniaxialSheet::discrete(celltissue::NeoHookean::new(1.0)?, &SheetParams::default())?;
    /// let y = sheet.initial_state();
    /// // a prescribed edge follows the ramp whatever the state
    /// assert_eq!(sheet.right_edge(2.0, &y), sheet.length(2.0));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn right_edge(&self, t: f64, y: &[f64]) -> f64 {
        let lt = self.length(t);
        (1..=self.m)
            .map(|k| self.xb_s(y, lt, self.n, k))
            .sum::<f64>()
            / self.m as f64
    }
    /// The Maxwell branch, if any.
    ///
    /// ```
    /// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
    /// let p = SheetParams { cells_x: 6, cells_y: 3, gamma0: 0.5, ..Default::default() };
    /// let sheet = UniaxialSheet::continuum(celltissue::NeoHookean::new(2.0)?, &p, 12, 3)?;
    /// assert!(sheet.branch().is_none());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn branch(&self) -> Option<&MaxwellBranch> {
        self.params.branch.as_ref()
    }
    /// The sampled external pressure of each column (index `j − 1`).
    ///
    /// ```
    /// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
    /// let p = SheetParams { cells_x: 6, cells_y: 3, gamma0: 0.5, ..Default::default() };
    /// let sheet = UniaxialSheet::continuum(celltissue::NeoHookean::new(2.0)?, &p, 12, 3)?;
    /// assert_eq!(sheet.external_pressure(), [0.0; 12]); // one per column of the grid
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn external_pressure(&self) -> &[f64] {
        &self.p_ext
    }

    /// Whether `y_b(j,k)` is an unknown (else it is the fixed base or the periodic image).
    fn y_is_unknown(&self, k: usize) -> bool {
        match self.params.top {
            TopBoundary::Free => k >= 1,
            TopBoundary::Periodic => k < self.m,
        }
    }

    /// The initial state `x_b = j h_X`, `y_b = k h_Y` (and relaxed branches, `a₁ = a₂ = 1`).
    ///
    /// ```
    /// use celltissue::cell::MaxwellBranch;
    /// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
    /// use celltissue::CellArray;
    /// let p = SheetParams { branch: Some(MaxwellBranch::maxwell(1.0, 2.0)?), ..Default::default() };
    /// let sheet = UniaxialSheet::discrete(celltissue::NeoHookean::new(1.0)?, &p)?;
    /// let y = sheet.initial_state();
    /// assert_eq!(y.len(), sheet.dim());
    /// // relaxed branches: a₁ = a₂ = 1 in every cell
    /// assert_eq!((y[sheet.iq(4, 7)], y[sheet.iq(4, 7) + 1]), (1.0, 1.0));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn initial_state(&self) -> Vec<f64> {
        let mut y = vec![0.0; self.dim()];
        for j in 1..=self.n {
            for k in 1..=self.m {
                if let Some(b) = &self.params.branch {
                    let q = self.iq(j, k);
                    y[q] = b.initial();
                    y[q + 1] = b.initial();
                }
                if self.params.growth.is_some() {
                    y[self.ig(j, k)] = 1.0;
                    y[self.ig(j, k) + 1] = 1.0;
                }
            }
            for k in 0..=self.m {
                if self.y_is_unknown(k) {
                    y[self.iy(j, k)] = k as f64 * self.hy;
                }
            }
            if self.x_is_unknown(j) {
                for k in 1..=self.m {
                    y[self.ix(j, k)] = j as f64 * self.hx;
                }
            }
        }
        y
    }

    /// `x_b(j, k)` for `j = 0..n` (boundary values included).
    ///
    /// ```
    /// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
    /// let sheet = UniaxialSheet::discrete(celltissue::NeoHookean::new(1.0)?, &SheetParams::default())?;
    /// let y = sheet.initial_state();
    /// // the wall x = 0 and the prescribed edge x = l(t) are not unknowns but are reported
    /// assert_eq!((sheet.xb(&y, 1.0, 0, 3), sheet.xb(&y, 1.0, 10, 3)), (0.0, sheet.length(1.0)));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn xb(&self, y: &[f64], t: f64, j: usize, k: usize) -> f64 {
        self.xb_s(y, self.length(t), j, k)
    }
    /// `y_b(j, k)` for `k = 0..m` (base / periodic image included).
    ///
    /// ```
    /// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
    /// use celltissue::sheet::TopBoundary;
    /// let p = SheetParams { top: TopBoundary::Periodic, ..Default::default() };
    /// let sheet = UniaxialSheet::discrete(celltissue::NeoHookean::new(1.0)?, &p)?;
    /// let y = sheet.initial_state();
    /// // periodic in y: the top face is the image of the bottom one, one width w₀ up
    /// assert_eq!(sheet.yb(&y, 1, 10), sheet.yb(&y, 1, 0) + sheet.w0());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn yb(&self, y: &[f64], j: usize, k: usize) -> f64 {
        self.yb_s(y, j, k)
    }

    #[inline]
    fn xb_s<S: Scalar>(&self, y: &[S], lt: f64, j: usize, k: usize) -> S {
        if j == 0 {
            S::from(0.0)
        } else if j == self.n && !self.free_right() {
            S::from(lt)
        } else {
            y[self.ix(j, k)]
        }
    }

    /// The velocity `ẏ_b(j, k)` from the rates `yp` (the periodic image moves with `y_b(j, 0)`).
    #[inline]
    fn yb_rate_s<S: Scalar>(&self, yp: &[S], j: usize, k: usize) -> S {
        match self.params.top {
            TopBoundary::Free if k == 0 => S::from(0.0),
            TopBoundary::Periodic if k == self.m => yp[self.iy(j, 0)],
            _ => yp[self.iy(j, k)],
        }
    }

    #[inline]
    fn yb_s<S: Scalar>(&self, y: &[S], j: usize, k: usize) -> S {
        match self.params.top {
            TopBoundary::Free => {
                if k == 0 {
                    S::from(0.0)
                } else {
                    y[self.iy(j, k)]
                }
            }
            TopBoundary::Periodic => {
                if k == self.m {
                    y[self.iy(j, 0)] + self.w0()
                } else {
                    y[self.iy(j, k)]
                }
            }
        }
    }

    /// Indices of cell `(j, k)`'s internal variables: its viscous stretches `a₁, a₂` (with a
    /// branch) and growth stretches `g₁, g₂` (when growing). Stretches in cell units, each
    /// with a differential row of its own.
    fn internal(&self, j: usize, k: usize) -> impl Iterator<Item = usize> {
        let q = self.params.branch.is_some().then(|| self.iq(j, k));
        let g = self.params.growth.is_some().then(|| self.ig(j, k));
        q.into_iter().chain(g).flat_map(|i| [i, i + 1])
    }

    /// Unknown indices a cell's state depends on.
    fn cell_deps(&self, j: usize, k: usize, out: &mut Vec<usize>) {
        out.extend(self.internal(j, k));
        for jj in [j - 1, j] {
            if self.x_is_unknown(jj) {
                out.push(self.ix(jj, k));
            }
        }
        for kk in [k - 1, k] {
            if self.y_is_unknown(kk) {
                out.push(self.iy(j, kk));
            } else if self.params.top == TopBoundary::Periodic && kk == self.m {
                out.push(self.iy(j, 0));
            }
        }
    }

    fn build_pattern(&self) -> SparsityPattern {
        let mut entries = Vec::with_capacity(self.dim() * 12);
        let mut deps = Vec::with_capacity(16);
        let mut add = |row: usize, cells: &[(usize, usize)], entries: &mut Vec<(usize, usize)>| {
            deps.clear();
            for &(j, k) in cells {
                self.cell_deps(j, k, &mut deps);
            }
            for &c in deps.iter() {
                entries.push((row, c));
            }
        };
        for j in 1..=self.n {
            for k in 1..=self.m {
                for row in self.internal(j, k) {
                    add(row, &[(j, k)], &mut entries);
                }
            }
            for k in 0..=self.m {
                if !self.y_is_unknown(k) {
                    continue;
                }
                let row = self.iy(j, k);
                match (self.params.top, k) {
                    (TopBoundary::Free, k) if k == self.m => add(row, &[(j, k)], &mut entries),
                    (TopBoundary::Periodic, 0) => add(row, &[(j, self.m), (j, 1)], &mut entries),
                    _ => add(row, &[(j, k), (j, k + 1)], &mut entries),
                }
            }
            if j < self.n {
                for k in 1..=self.m {
                    add(self.ix(j, k), &[(j, k), (j + 1, k)], &mut entries);
                }
            } else if self.free_right() {
                for k in 1..=self.m {
                    add(self.ix(j, k), &[(j, k)], &mut entries);
                }
            }
        }
        SparsityPattern::from_entries(self.dim(), &entries)
    }
}

fn zero_response() -> SheetResponse {
    SheetResponse {
        s11: 0.0,
        s22: 0.0,
        pressure: 0.0,
        tangent: [[0.0; 2]; 2],
    }
}
