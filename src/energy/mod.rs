//! Strain energies (MODEL.md §1): the [`StrainEnergy`] trait — a user writes only
//! `W(λ₁, λ₂, λ₃)`, generic over the scalar — and the responses the cell arrays need, derived by
//! forward-mode AD (hand-written closed forms may override them for speed):
//!
//! * [`LineResponse`]: plane-strain cell of the line (§1.2), `σ_el(a)`, `dσ_el/da`, `p_el(a)`;
//! * [`SheetResponse`]: quasi-3D uniaxial sheet cell (§1.4), `σ₁₁, σ₂₂, p` and the 2×2 tangent;
//! * [`ShearResponse`]: simple-shear cell (§1.5), `τ(T)` and `dτ/dT`.
//!
//! SKELETON: trait contract fixed; provided methods and the sample laws are filled in by the
//! energy work item.

use num_dual::DualNum;

/// Plane-strain response of a line cell at axial stretch `a` (deformation `diag(a, 1/a, 1)`,
/// `σ₂₂ = 0`), MODEL.md §1.2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineResponse {
    /// Axial elastic Cauchy stress `σ_el(a) = a·Ŵ'(a)` (tension positive).
    pub sigma: f64,
    /// Tangent `dσ_el/da`.
    pub dsigma: f64,
    /// Elastic pressure `p_el = a₂·W₂` at `(a, 1/a, 1)`.
    pub pressure: f64,
    /// `dp_el/da`.
    pub dpressure: f64,
}

/// Quasi-3D sheet-cell response at `(λ₁, λ₂)`, `λ₃ = 1/(λ₁λ₂)`, `σ₃₃ = 0` (MODEL.md §1.4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SheetResponse {
    /// `σ₁₁ = λ₁ ∂₁Ŵ`.
    pub s11: f64,
    /// `σ₂₂ = λ₂ ∂₂Ŵ`.
    pub s22: f64,
    /// Pressure `p = λ₃ W₃`.
    pub pressure: f64,
    /// Tangent `∂σᵢᵢ/∂λₖ`, row `i` (0: σ₁₁, 1: σ₂₂), column `k`.
    pub tangent: [[f64; 2]; 2],
}

/// Simple-shear response at amount of shear `T = tan θ` (MODEL.md §1.5).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShearResponse {
    /// Shear stress `τ = dŴ/dT`.
    pub tau: f64,
    /// `dτ/dT`.
    pub dtau: f64,
}

/// An incompressible hyperelastic law given by its strain energy `W(λ₁, λ₂, λ₃)` in the principal
/// stretches (for fibre laws: the stretches along the cell axes).
///
/// Implement [`energy`](StrainEnergy::energy) generically over `D: DualNum<Primitive = f64>` and
/// [`shear_modulus`](StrainEnergy::shear_modulus); the responses used by the cell arrays are then
/// derived by forward-mode AD. Override them with closed forms if you want speed; tests check
/// they agree with AD.
pub trait StrainEnergy: Send + Sync {
    /// `W(λ₁, λ₂, λ₃)`, generic over the scalar so AD can differentiate it.
    fn energy<D: DualNum<Primitive = f64> + Copy>(&self, l: [D; 3]) -> D;

    /// Small-strain shear modulus `μ` (so `dσ_el/da(1) = 4μ` in the line).
    fn shear_modulus(&self) -> f64;

    /// Plane-strain line response at axial stretch `a > 0` (AD by default).
    fn line(&self, a: f64) -> LineResponse;

    /// Sheet response at `(λ₁, λ₂)` (AD by default).
    fn sheet(&self, l1: f64, l2: f64) -> SheetResponse;

    /// Simple-shear response at `T` (AD by default).
    fn shear(&self, t: f64) -> ShearResponse;
}
