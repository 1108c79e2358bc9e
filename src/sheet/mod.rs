//! # Chapter 4: sheets of cells and the simple-shear column (docs/model.md §1.4–1.5, §4)
//!
//! * [`UniaxialSheet`] — `N × M` quasi-3D cells on a substrate (docs/model.md §4.1): unknowns are the
//!   shared-face positions `x_b(j,k)` and `y_b(j,k)`; each cell is a cuboid with stretches
//!   `λ₁, λ₂, λ₃ = 1/(λ₁λ₂)`, stresses from **any** [`StrainEnergy`] via
//!   [`StrainEnergy::sheet`], drag `K·κ`, `κ = (λ₁λ₂)^m`, a fixed edge `x = 0`, a prescribed edge
//!   `x = l(t)`, a fixed base `y = 0` and a free (zero-traction) or periodic side. The continuum
//!   (docs/model.md §4.3) is the same array on an `n × m` grid of reference cells `h_X × h_Y` with
//!   per-face drag `K h_X h_Y / γ₀` (conservative scheme).
//! * [`ShearColumn`] — the simple-shear column in its canonical edge form (docs/model.md §4.4), on `M`
//!   cells (discrete) or `m` segments (continuum); [`ShearCellCentre`] — the thesis's
//!   cell-centre form (4.85)–(4.98), kept for comparison (§4.5).
//! * [`exact`] — steady states of the sheet for any law, and the closed-form continuum series and
//!   exact discrete solutions of the shear column (§4.6).
//! * [`observe`] — the Chapter 4 observables (§6): pressures, mean height, `mean λ₃/mean λ₂`, the
//!   shared-boundary mismatch `W_err` (4.76)–(4.77), shear angles and their spread.
//! * [`vtk`] — the sheet as a VTK grid (one hexahedron per cell) for ParaView; the writers of
//!   [`crate::output`] draw it, and the PNG snapshots, from the run's profiles
//!   ([`observe::sheet_cells`]).
//! * [`config`] and [`run`] — serde configurations with range-checked validation and the
//!   `run_sheet` / `run_shear` entry points that return a [`crate::observe::RunRecord`].
//!
//! All residuals are written once, generically over [`Scalar`]; the integrators build the sparse
//! (sheet) or banded (shear) Jacobian from AD directional derivatives by column colouring.

use crate::scalar::Scalar;

pub mod config;
pub mod exact;
pub mod observe;
pub mod ramp;
pub mod run;
pub mod shear;
pub mod uniaxial;
pub mod vtk;

pub use config::{
    ConfigError, GrowthDirections, RightEdge, ShearConfig, ShearForm, SheetConfig, TopBoundary,
};
pub use ramp::Ramp;
pub use run::{run_shear, run_sheet, RunError};
pub use shear::{ShearCellCentre, ShearColumn};
pub use uniaxial::UniaxialSheet;

#[cfg(doc)]
use crate::energy::StrainEnergy;

/// Applies a function of two scalars whose value `f` and partial derivatives `(fa, fb)` at
/// `(a.re(), b.re())` are known: the result carries `f` and the chain-rule derivative
/// `fa·da + fb·db`. Used to lift the sheet's `σ(λ₁, λ₂)` into a generic residual.
///
/// ```
/// use celltissue::sheet::lift2;
/// use num_dual::Dual64;
/// // f(a, b) = a·b at (2, 3), with a carrying derivative 1 and b derivative 10
/// let r = lift2(Dual64::new(2.0, 1.0), Dual64::new(3.0, 10.0), 6.0, 3.0, 2.0);
/// assert_eq!((r.re, r.eps), (6.0, 3.0 + 20.0));
/// ```
#[inline]
pub fn lift2<S: Scalar>(a: S, b: S, f: f64, fa: f64, fb: f64) -> S {
    a.lift(f, fa) + b.lift(0.0, fb)
}
