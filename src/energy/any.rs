//! [`AnyEnergy`]: the closed set of built-in laws, selected at run time (scenario files, CLI).

use super::{
    EnergyError, Gent, Hgo, LineResponse, MooneyRivlin, NeoHookean, Ogden, ShearResponse,
    SheetResponse, StrainEnergy,
};
use num_dual::DualNum;
use serde::{Deserialize, Serialize};

/// One of the built-in laws, chosen at run time. Deserializes from a table tagged by
/// `law = "neo_hookean" | "mooney_rivlin" | "ogden" | "hgo" | "gent"` with that law's parameters
/// (validated by its constructor; unknown fields are rejected). Implements [`StrainEnergy`] by
/// delegation, so closed-form overrides are kept.
///
/// | `law` | parameters |
/// |---|---|
/// | `neo_hookean` | `mu` |
/// | `mooney_rivlin` | `c1`, `c2` |
/// | `ogden` | `terms = [[mu_p, alpha_p], …]` |
/// | `hgo` | `c`, `k1`, `k2`, `theta` (radians) |
/// | `gent` | `mu`, `jm` |
///
/// ```
/// use celltissue::{AnyEnergy, StrainEnergy};
/// let law: AnyEnergy = serde_json::from_str(r#"{"law": "ogden", "terms": [[1.0, 2.0]]}"#)?;
/// assert!((law.line(1.0).dsigma - 4.0).abs() < 1e-12);
/// let bad = serde_json::from_str::<AnyEnergy>(r#"{"law": "neo_hookean", "mu": -1}"#);
/// assert!(bad.unwrap_err().to_string().contains("mu = -1 must be finite and > 0"));
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "law", rename_all = "snake_case")]
pub enum AnyEnergy {
    /// [`NeoHookean`].
    NeoHookean(NeoHookean),
    /// [`MooneyRivlin`].
    MooneyRivlin(MooneyRivlin),
    /// [`Ogden`].
    Ogden(Ogden),
    /// [`Hgo`].
    Hgo(Hgo),
    /// [`Gent`].
    Gent(Gent),
}

impl AnyEnergy {
    /// The `law` tag of this variant.
    ///
    /// ```
    /// use celltissue::{AnyEnergy, NeoHookean};
    /// assert_eq!(AnyEnergy::from(NeoHookean::new(1.0).unwrap()).name(), "neo_hookean");
    /// ```
    pub fn name(&self) -> &'static str {
        match self {
            Self::NeoHookean(_) => "neo_hookean",
            Self::MooneyRivlin(_) => "mooney_rivlin",
            Self::Ogden(_) => "ogden",
            Self::Hgo(_) => "hgo",
            Self::Gent(_) => "gent",
        }
    }
}

macro_rules! delegate {
    ($self:ident, $e:ident => $body:expr) => {
        match $self {
            AnyEnergy::NeoHookean($e) => $body,
            AnyEnergy::MooneyRivlin($e) => $body,
            AnyEnergy::Ogden($e) => $body,
            AnyEnergy::Hgo($e) => $body,
            AnyEnergy::Gent($e) => $body,
        }
    };
}

impl StrainEnergy for AnyEnergy {
    #[inline]
    fn energy<D: DualNum<Primitive = f64> + Copy>(&self, l: [D; 3]) -> D {
        delegate!(self, e => e.energy(l))
    }
    #[inline]
    fn shear_modulus(&self) -> f64 {
        delegate!(self, e => e.shear_modulus())
    }
    #[inline]
    fn admissible(&self, l: [f64; 3]) -> Result<(), EnergyError> {
        match self {
            AnyEnergy::Gent(e) => e.admissible(l),
            // the other built-in laws are defined for every positive stretch
            _ => Ok(()),
        }
    }
    #[inline]
    fn line(&self, a: f64) -> LineResponse {
        delegate!(self, e => e.line(a))
    }
    #[inline]
    fn sheet(&self, l1: f64, l2: f64) -> SheetResponse {
        delegate!(self, e => e.sheet(l1, l2))
    }
    #[inline]
    fn shear(&self, t: f64) -> ShearResponse {
        delegate!(self, e => e.shear(t))
    }
}

macro_rules! from_law {
    ($($t:ident),*) => {$(
        impl From<$t> for AnyEnergy {
            fn from(e: $t) -> Self {
                AnyEnergy::$t(e)
            }
        }
    )*};
}
from_law!(NeoHookean, MooneyRivlin, Ogden, Hgo, Gent);
