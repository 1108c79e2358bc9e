//! Substrate interaction (docs/model.md §2.3–§2.5): drag `K·κ` with the [`Dissipation`] law
//! `κ(A/A₀)` — the thesis's [`PowerLawDrag`] `κ = (A/A₀)^m` for any real `m`, `(g·g₂)^m` on the
//! line and `(λ₁λ₂)^m` on the sheet — the face (shared-boundary) averages, the shared
//! width rule, and the two drag forms:
//!
//! * [`DragForm::Boundary`] (B, canonical): `K κ_{j+1/2} ẋ_j = F_j` per moving boundary;
//! * [`DragForm::Centre`] (C, thesis Appendix A.1 code): `K κ_j (ẋ_{j−1} + ẋ_j) = F_{j−1} + F_j`
//!   per cell. Identical to (B) for uniform `κ`; singular with periodic ends (rejected).

use crate::scalar::Scalar;
use serde::{Deserialize, Serialize};

/// Which force balance moves the boundaries.
///
/// ```
/// use celltissue::line::LineConfig;
/// use celltissue::substrate::DragForm;
/// let cfg: LineConfig = toml::from_str("drag_form = \"centre\"")?; // the thesis code's form
/// assert_eq!(cfg.drag_form, DragForm::Centre);
/// # Ok::<(), toml::de::Error>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DragForm {
    /// Boundary drag (B), canonical.
    #[default]
    Boundary,
    /// Cell-centre drag (C), the thesis code's form (reproduction option).
    Centre,
}

/// What the free-end node of a continuum grid carries as drag (docs/model.md §3.3a, "The free
/// end's drag"). On the discrete line (one segment per cell) both are the tip boundary's own
/// `K`; they differ on a grid of `n ≠ N` segments.
///
/// * [`FreeEndDrag::Segment`] (default, the canonical scheme): its segment's drag, `K h/L`, so
///   that as `h → 0` the end is the continuum's stress-free end; the discrete line of `N` cells
///   then differs from the continuum by `O(1/N)` at a free end.
/// * [`FreeEndDrag::Cells`]: half its segment's drag plus the tip boundary's own half cell,
///   `K (h/L + 1)/2`, the drag the discrete line's last boundary carries beyond the distributed
///   drag; a grid of any `n` then approximates the line of `N` cells to `O(1/N²)`.
///
/// ```
/// use celltissue::line::build::{continuum, LineParams};
/// use celltissue::substrate::FreeEndDrag;
/// use celltissue::boundary::RightEnd;
/// let mut p = LineParams::unit_cells(4);
/// p.right = RightEnd::Free(None);
/// p.k = 1.0.into();
/// p.free_end_drag = FreeEndDrag::Cells;
/// let line = continuum(celltissue::NeoHookean::new(1.0)?, &p, 8)?; // h = 1/2
/// assert_eq!(line.k_face()[8], 0.75); // (1/2 + 1)/2
/// assert_eq!(line.k_face()[4], 0.5);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FreeEndDrag {
    /// The end node's segment's drag `K h/L` (the continuum's free end).
    #[default]
    Segment,
    /// `K (h/L + 1)/2`: half the segment's drag and half the tip boundary's (the cells' end).
    Cells,
}

impl FreeEndDrag {
    /// The boundaries a free end's face carries when its segment holds `c` cells across the
    /// end: `c` ([`FreeEndDrag::Segment`]) or `(c + 1)/2` ([`FreeEndDrag::Cells`]: half the
    /// segment's and half the tip boundary's own); 1 for a single cell either way.
    ///
    /// ```
    /// use celltissue::substrate::FreeEndDrag;
    /// assert_eq!(FreeEndDrag::Segment.end_face(0.5), 0.5);
    /// assert_eq!(FreeEndDrag::Cells.end_face(0.5), 0.75);
    /// assert_eq!(FreeEndDrag::Cells.end_face(1.0), 1.0);
    /// ```
    pub fn end_face(self, c: f64) -> f64 {
        match self {
            FreeEndDrag::Segment => c,
            FreeEndDrag::Cells => 0.5 * (c + 1.0),
        }
    }
}

/// How the width of a shared boundary is formed from the two cells' widths.
///
/// ```
/// use celltissue::line::LineConfig;
/// use celltissue::substrate::WidthRule;
/// let cfg: LineConfig = toml::from_str("width = \"min\"")?; // the true contact length
/// assert_eq!(cfg.width, WidthRule::Min);
/// assert_eq!(WidthRule::Min.face(0.8f64, 1.2), 0.8);
/// # Ok::<(), toml::de::Error>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WidthRule {
    /// `½(W_j + W_{j+1})` (default; the thesis's upscaling choice).
    #[default]
    Mean,
    /// `min(W_j, W_{j+1})`, the true contact length (2.11).
    Min,
}

impl WidthRule {
    /// Shared width of two cells.
    ///
    /// ```
    /// use celltissue::substrate::WidthRule;
    /// assert_eq!(WidthRule::Mean.face(1.0f64, 3.0), 2.0);
    /// assert_eq!(WidthRule::Min.face(1.0f64, 3.0), 1.0);
    /// ```
    #[inline]
    pub fn face<S: Scalar>(self, a: S, b: S) -> S {
        match self {
            WidthRule::Mean => (a + b) * 0.5,
            WidthRule::Min => {
                if a.re() <= b.re() {
                    a
                } else {
                    b
                }
            }
        }
    }
}

/// A substrate dissipation law: the drag factor `κ(A/A₀)` multiplying the drag coefficient `K`
/// of a cell whose area ratio (current over reference contact area) is `A/A₀` (docs/model.md §2.3;
/// docs/model.md §2.3). The line passes `A/A₀ = g·g₂` (its cells' contact area grows with
/// growth only), the uniaxial sheet `λ₁λ₂`. Generic over the scalar so the residual's dual
/// evaluation differentiates it exactly.
///
/// ```
/// use celltissue::substrate::{Dissipation, PowerLawDrag};
/// /// Drag saturating at large area: κ = 2a/(1 + a).
/// struct Saturating;
/// impl Dissipation for Saturating {
///     fn kappa<S: celltissue::scalar::Scalar>(&self, area: S) -> S {
///         area * 2.0 / (area + 1.0)
///     }
/// }
/// assert_eq!(Saturating.kappa(1.0f64), 1.0);
/// assert_eq!(PowerLawDrag { m: 2.0 }.kappa(3.0f64), 9.0);
/// ```
pub trait Dissipation: Send + Sync {
    /// `κ(A/A₀)`, with `κ(1) = 1` for the drag coefficient to keep its meaning.
    fn kappa<S: Scalar>(&self, area_ratio: S) -> S;
}

/// The thesis's power law `κ = (A/A₀)^m` for any real `m` (`m = 0`: area-independent drag).
/// `m = 0` and `m = 1` are evaluated without `powf` (exactly 1 and `A/A₀`).
///
/// ```
/// use celltissue::substrate::{Dissipation, PowerLawDrag};
/// assert_eq!(PowerLawDrag { m: 0.0 }.kappa(1.7f64), 1.0); // κ = 1: area-independent
/// assert_eq!(PowerLawDrag { m: 1.0 }.kappa(1.7f64), 1.7); // κ = A/A₀
/// assert!((PowerLawDrag { m: 0.5 }.kappa(4.0f64) - 2.0).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PowerLawDrag {
    /// Exponent `m`.
    pub m: f64,
}

impl Dissipation for PowerLawDrag {
    #[inline(always)]
    fn kappa<S: Scalar>(&self, area_ratio: S) -> S {
        if self.m == 0.0 {
            S::from(1.0)
        } else if self.m == 1.0 {
            area_ratio
        } else {
            area_ratio.powf(self.m)
        }
    }
}

/// Drag factor `κ = (g·g₂)^m` of a line cell: [`PowerLawDrag`] at the area ratio `g·g₂`
/// (1 exactly when `m = 0`).
///
/// ```
/// use celltissue::substrate::drag_factor;
/// assert_eq!(drag_factor(2.0f64, 1.0, 1.0), 2.0);
/// assert_eq!(drag_factor(2.0f64, 1.0, 0.0), 1.0);
/// ```
#[inline]
pub fn drag_factor<S: Scalar>(g: S, g2: f64, m: f64) -> S {
    if m == 0.0 {
        // not even the product: the line without growth has g ≡ 1
        return S::from(1.0);
    }
    PowerLawDrag { m }.kappa(g * g2)
}
