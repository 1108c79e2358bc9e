//! Substrate interaction of the line (docs/model.md §2.3–§2.5): drag `K·κ` with
//! `κ = (A/A₀)^m = (g·g₂)^m` for any real `m`, the face (shared-boundary) averages, the shared
//! width rule, and the two drag forms:
//!
//! * [`DragForm::Boundary`] (B, canonical): `K κ_{j+1/2} ẋ_j = F_j` per moving boundary;
//! * [`DragForm::Centre`] (C, thesis Appendix A.1 code): `K κ_j (ẋ_{j−1} + ẋ_j) = F_{j−1} + F_j`
//!   per cell. Identical to (B) for uniform `κ`; singular with periodic ends (rejected).

use crate::scalar::Scalar;
use serde::{Deserialize, Serialize};

/// Which force balance moves the boundaries.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DragForm {
    /// Boundary drag (B), canonical.
    #[default]
    Boundary,
    /// Cell-centre drag (C), the thesis code's form (reproduction option).
    Centre,
}

/// How the width of a shared boundary is formed from the two cells' widths.
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

/// Drag factor `κ = (g·g₂)^m` of a cell (1 exactly when `m = 0`).
///
/// ```
/// use celltissue::substrate::drag_factor;
/// assert_eq!(drag_factor(2.0f64, 1.0, 1.0), 2.0);
/// assert_eq!(drag_factor(2.0f64, 1.0, 0.0), 1.0);
/// ```
#[inline]
pub fn drag_factor<S: Scalar>(g: S, g2: f64, m: f64) -> S {
    if m == 0.0 {
        S::from(1.0)
    } else if m == 1.0 {
        g * g2
    } else {
        (g * g2).powf(m)
    }
}
