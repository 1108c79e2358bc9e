//! Forward-mode AD of a [`StrainEnergy`] into the cell responses (docs/model.md §1.2, §1.4, §1.5).
//!
//! These are the default bodies of [`StrainEnergy::line`], [`StrainEnergy::sheet`] and
//! [`StrainEnergy::shear`]; they are public so that laws with hand-written overrides can be
//! tested against them. All are allocation-free and evaluate `W` exactly once:
//!
//! * line — `W` in [`Dual2`]`<`[`Dual64`]`>`: the outer second-order dual follows the path
//!   `(a, 1/a, 1)` (giving `Ŵ, Ŵ', Ŵ''`), the inner dual perturbs `λ₂` alone (giving `W₂` and
//!   its total `a`-derivative along the path);
//! * sheet — `W` in [`Dual2SVec64`]`<3>` with `λ₁ = l₁ + d₁`, `λ₂ = l₂ + d₂`,
//!   `λ₃ = 1/(λ₁λ₂) + d₃`: gradient `(∂₁Ŵ, ∂₂Ŵ, W₃)` and the Hessian block `∂ᵢ∂ₖŴ`;
//! * shear — `W(λ₊(T), λ₋(T), 1)` in [`Dual2_64`], and the pressure from one [`Dual64`]
//!   gradient; both read `W` at the principal stretches, so they hold for a law symmetric in its
//!   in-plane stretches ([`symmetric_in_plane`]), not for one with material directions.
//!
//! ```
//! use celltissue::{energy::ad, NeoHookean};
//! let law = NeoHookean::new(1.0).unwrap();
//! let r = ad::line(&law, 1.5); // AD, bypassing the closed-form override
//! assert!((r.sigma - (1.5f64.powi(2) - 1.5f64.powi(-2))).abs() < 1e-13);
//! ```

use super::{LineResponse, ShearResponse, SheetResponse, StrainEnergy};
use num_dual::{Dual2, Dual2SVec64, Dual2_64, Dual64, DualNum};

/// Plane-strain line response by AD: `σ_el = aŴ'`, `dσ_el/da = Ŵ' + aŴ''`, `p_el = a₂W₂`,
/// `dp_el/da`, with `Ŵ(a) = W(a, 1/a, 1)` (docs/model.md §1.2).
///
/// ```
/// use celltissue::{energy::ad, Ogden};
/// let law = Ogden::new(vec![(1.0, 2.0)]).unwrap(); // = neo-Hookean μ = 1
/// let r = ad::line(&law, 2.0);
/// assert!((r.dsigma - 2.0 * (2.0 + 0.125)).abs() < 1e-12); // 2μ(a + a⁻³)
/// assert!((r.pressure - 0.25).abs() < 1e-14);               // μa⁻²
/// ```
#[inline]
pub fn line<E: StrainEnergy + ?Sized>(law: &E, a: f64) -> LineResponse {
    type D = Dual2<Dual64>;
    let one = Dual64::from_re(1.0);
    let zero = Dual64::from_re(0.0);
    let l1: D = Dual2::new(Dual64::from_re(a), one, zero);
    // λ₂ = 1/a along the path, plus an independent inner perturbation δ₂.
    let l2: D = l1.recip() + Dual2::from_re(Dual64::new(0.0, 1.0));
    let l3: D = Dual2::from_re(one);
    let w = law.energy([l1, l2, l3]);
    let dw = w.v1.re; // Ŵ'
    let d2w = w.v2.re; // Ŵ''
    let w2 = w.re.eps; // W₂ at (a, 1/a, 1)
    let dw2 = w.v1.eps; // d/da W₂(a, 1/a, 1)
    let inv = 1.0 / a;
    LineResponse {
        sigma: a * dw,
        dsigma: dw + a * d2w,
        pressure: inv * w2,
        dpressure: inv * (dw2 - inv * w2),
    }
}

/// Quasi-3D sheet response by AD (docs/model.md §1.4): `σ₁₁ = λ₁∂₁Ŵ`, `σ₂₂ = λ₂∂₂Ŵ`, `p = λ₃W₃`,
/// tangent `∂σᵢᵢ/∂λₖ = δᵢₖ∂ᵢŴ + λᵢ∂ᵢ∂ₖŴ`, with `Ŵ(λ₁, λ₂) = W(λ₁, λ₂, 1/(λ₁λ₂))`.
///
/// ```
/// use celltissue::{energy::ad, MooneyRivlin};
/// let law = MooneyRivlin::new(0.3, 0.2).unwrap(); // μ = 1
/// let r = ad::sheet(&law, 1.0, 1.0);
/// assert!((r.tangent[0][0] - 4.0).abs() < 1e-13 && (r.tangent[1][0] - 2.0).abs() < 1e-13);
/// ```
#[inline]
pub fn sheet<E: StrainEnergy + ?Sized>(law: &E, l1: f64, l2: f64) -> SheetResponse {
    type D = Dual2SVec64<3>;
    let x1 = D::from_re(l1).derivative(0);
    let x2 = D::from_re(l2).derivative(1);
    let x3 = (x1 * x2).recip() + D::from_re(0.0).derivative(2);
    let w = law.energy([x1, x2, x3]);
    let g = |k: usize| w.v1.0.as_ref().map_or(0.0, |m| m[(0, k)]);
    let h = |i: usize, k: usize| w.v2.0.as_ref().map_or(0.0, |m| m[(i, k)]);
    let (w1, w2, w3) = (g(0), g(1), g(2));
    let l3 = 1.0 / (l1 * l2);
    let h12 = h(0, 1);
    SheetResponse {
        s11: l1 * w1,
        s22: l2 * w2,
        pressure: l3 * w3,
        tangent: [[w1 + l1 * h(0, 0), l1 * h12], [l2 * h12, w2 + l2 * h(1, 1)]],
    }
}

/// Simple-shear response by AD (docs/model.md §1.5): `τ = dŴ/dT`, `dτ/dT = d²Ŵ/dT²` with
/// `Ŵ(T) = W(λ₊, λ₋, 1)`, `λ± = √(1 + T²/4) ± T/2`: the energy of the shear for a law that
/// depends on the principal stretches alone (an isotropic law).
///
/// ```
/// use celltissue::{energy::ad, NeoHookean};
/// let r = ad::shear(&NeoHookean::new(2.0).unwrap(), 0.7);
/// assert!((r.tau - 1.4).abs() < 1e-13); // τ = μT
/// ```
#[inline]
pub fn shear<E: StrainEnergy + ?Sized>(law: &E, t: f64) -> ShearResponse {
    let (lp, lm) = shear_stretches(Dual2_64::from_re(t).derivative());
    let w = law.energy([lp, lm, Dual2_64::from_re(1.0)]);
    ShearResponse {
        tau: w.v1,
        dtau: w.v2,
    }
}

/// The principal in-plane stretches `(λ₊, λ₋) = (√(1+T²/4) + T/2, √(1+T²/4) − T/2)` of a simple
/// shear `T`, the smaller one taken as the reciprocal of the larger (`λ₊λ₋ = 1`): as a
/// difference it loses its digits as `|T|` grows (relative error about `T²ε`, 1e-8 at
/// `T = 10⁴`), and with them the stress and its derivative that a law reading `λ₋` (Ogden
/// with `α < 0`) computes from it.
///
/// ```
/// use celltissue::energy::ad::shear_stretches;
/// let (lp, lm) = shear_stretches(1e4f64);
/// assert!((lp * lm - 1.0).abs() < 1e-15 && (lm - 1e-4).abs() < 1e-12);
/// let (lp, lm) = shear_stretches(-1.5f64); // T < 0 swaps them: λ₊ = 1/2, λ₋ = 2
/// assert!((lp - 0.5).abs() < 1e-15 && (lm - 2.0).abs() < 1e-15);
/// ```
pub fn shear_stretches<D: DualNum<Primitive = f64> + Copy>(t: D) -> (D, D) {
    let root = (t * t * 0.25 + 1.0).sqrt();
    let half = t * 0.5;
    if t.re() >= 0.0 {
        let big = root + half;
        (big, big.recip())
    } else {
        let big = root - half;
        (big.recip(), big)
    }
}

/// Pressure of a simple-shear cell from `σ₂₂ = 0` (docs/model.md §1.5), for a law that depends
/// on the principal stretches alone: with `λ± = √(1+T²/4) ± T/2`, `λ₃ = 1`, principal stresses
/// `t_i = λ_i ∂W/∂λ_i` and Eulerian principal directions `n±` (eigenvectors of `B = FFᵀ`),
/// `p = t₊ n₊,₂² + t₋ n₋,₂²`. Neo-Hookean gives `p = μ`.
///
/// ```
/// use celltissue::{energy::ad, Gent, NeoHookean};
/// // neo-Hookean: p = μ at every amount of shear
/// for t in [0.0, 0.5, 2.0] {
///     assert!((ad::shear_pressure(&NeoHookean::new(1.5).unwrap(), t) - 1.5).abs() < 1e-12);
/// }
/// // Gent (μ = 1, J_m = 3): p = μ/(1 − T²/J_m) stiffens towards the lock
/// let gent = Gent::new(1.0, 3.0).unwrap();
/// assert!((ad::shear_pressure(&gent, 1.0) - 1.5).abs() < 1e-12);
/// ```
pub fn shear_pressure<E: StrainEnergy + ?Sized>(law: &E, t: f64) -> f64 {
    let (lp, lm) = shear_stretches(t);
    let d = |i: usize| {
        let mut l = [Dual64::from(lp), Dual64::from(lm), Dual64::from(1.0)];
        l[i].eps = 1.0;
        law.energy(l).eps
    };
    let (tp, tm) = (lp * d(0), lm * d(1));
    // B = [[1+T², T], [T, 1]]; eigenvector for eigenvalue λ² is (T, λ² − 1 − T²) or (λ² − 1, T).
    let n2 = |lam2: f64| {
        let v = (lam2 - 1.0, t);
        let nrm = (v.0 * v.0 + v.1 * v.1).sqrt();
        if nrm == 0.0 {
            None
        } else {
            Some((v.1 / nrm).powi(2))
        }
    };
    match (n2(lp * lp), n2(lm * lm)) {
        (Some(a), Some(b)) => tp * a + tm * b,
        // T = 0: B = I, any basis; σ₂₂ = t₂ − p with t₂ the in-plane stretch stress (both equal).
        _ => tm,
    }
}

/// Whether `W(λ₁, λ₂, λ₃) = W(λ₂, λ₁, λ₃)` at sample stretches (in-plane stretches 1 ± ε for
/// ε from 0.2 down to 10⁻³, where the law admits them), to 10⁻¹⁰ relative: the default of
/// [`StrainEnergy::shear_is_exact`]. A law symmetric in its in-plane stretches is read as a
/// function of the principal stretches (isotropic in the plane), which is what
/// [`shear`] and [`shear_pressure`] assume; one that is not reads its stretches along the cell's
/// axes (a material direction), and simple shear turns the principal axes away from them.
///
/// ```
/// use celltissue::energy::{ad, Expression};
/// use celltissue::NeoHookean;
/// assert!(ad::symmetric_in_plane(&NeoHookean::new(1.0).unwrap()));
/// let fibre = Expression::new("mu/2*(I1 - 3) + k*(l1^2 - 1)^2", [("mu", 1.0), ("k", 1.0)]).unwrap();
/// assert!(!ad::symmetric_in_plane(&fibre));
/// ```
pub fn symmetric_in_plane<E: StrainEnergy + ?Sized>(law: &E) -> bool {
    for eps in [0.2, 0.05, 1e-2, 1e-3] {
        for (a, b) in [(1.0 + eps, 1.0 - 0.5 * eps), (1.0 - eps, 1.0 + 2.0 * eps)] {
            let c = 1.0 / (a * b);
            if law.admissible([a, b, c]).is_err() || law.admissible([b, a, c]).is_err() {
                continue;
            }
            let (x, y) = (law.energy([a, b, c]), law.energy([b, a, c]));
            if x.is_finite() && y.is_finite() && (x - y).abs() > 1e-10 * x.abs().max(y.abs()) {
                return false;
            }
        }
    }
    true
}
