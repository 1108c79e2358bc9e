//! Cell laws (docs/model.md §1–§2.3, §2.7): everything about one cell except its strain energy
//! (which is any [`crate::StrainEnergy`]):
//!
//! * [`Field`] — heterogeneous material fields of the reference position `X` (μ scale, η, K,
//!   active amplitude), sampled at cell centres or integer points ([`Sampling`]);
//! * [`GrowthRate`] / [`GrowthLaw`] / [`TanhGrowth`] — stress-controlled growth `ġ = G(σ)`,
//!   written generically over the scalar, derivative by AD; [`growth_laws`] is their registry
//!   by name (`growth = { law = "tanh", … }` in a scenario);
//! * [`Active`] — the travelling active-stress wave (2.83);
//! * [`ViscosityModel`] / [`MaxwellBranch`] — Kelvin–Voigt, Maxwell and standard-linear-solid
//!   viscosity, the branch's viscous stretch an internal variable ([`ViscousBranch`]).
//!
//! The line ([`crate::line`]) holds the sampled per-cell values in plain `Vec`s, so the residual
//! loops run on `f64` slices and inserting a cell (division) is one `Vec::insert` per field.

mod active;
mod field;
mod growth;
pub mod growth_laws;
mod viscosity;

pub use active::Active;
pub(crate) use field::{subnormal, subnormal_text};
pub use field::{Field, FieldError, FieldFn, Sampling};
pub(crate) use growth::growth_at;
pub use growth::{GrowthLaw, GrowthRate, TanhGrowth};
pub use growth_laws::GrowthSpec;
pub use viscosity::{
    kelvin_voigt_sheet, MaxwellBranch, ViscosityError, ViscosityModel, ViscousBranch,
};
