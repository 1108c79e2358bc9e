//! [`AnyEnergy`]: the closed set of built-in laws, selected at run time (scenario files, CLI).

use super::registry::{self, Params, Registered};
use super::{
    EnergyError, Expression, Gent, Hgo, LineResponse, MooneyRivlin, NeoHookean, Ogden,
    ShearResponse, SheetResponse, StrainEnergy,
};
use num_dual::DualNum;
use serde::ser::{Error as _, SerializeMap};
use serde::{Deserialize, Serialize, Serializer};

/// A strain energy chosen at run time. Deserializes from a table tagged by `law = "<name>"` (built in: `neo_hookean`, `mooney_rivlin`, `ogden`, `hgo`, `gent`, `expression`)
/// with that law's parameters, looked up in the [`registry`] (validated by the law's
/// constructor; unknown fields are rejected). Implements [`StrainEnergy`] by delegation, so
/// closed-form overrides are kept.
///
/// | `law` | parameters |
/// |---|---|
/// | `neo_hookean` | `mu` |
/// | `mooney_rivlin` | `c1`, `c2` |
/// | `ogden` | `terms = [[mu_p, alpha_p], …]` |
/// | `hgo` | `c`, `k1`, `k2`, `theta` (radians) |
/// | `gent` | `mu`, `jm` |
/// | `expression` | `W = "<formula>"` and its parameters by name ([`Expression`]) |
/// | a name given to [`registry::register`] | that law's fields |
///
/// ```
/// use celltissue::{AnyEnergy, StrainEnergy};
/// let law: AnyEnergy = serde_json::from_str(r#"{"law": "ogden", "terms": [[1.0, 2.0]]}"#)?;
/// assert!((law.line(1.0).dsigma - 4.0).abs() < 1e-12);
/// let bad = serde_json::from_str::<AnyEnergy>(r#"{"law": "neo_hookean", "mu": -1}"#);
/// assert!(bad.unwrap_err().to_string().contains("mu = -1 must be finite and > 0"));
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(try_from = "Params")]
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
    /// A formula written in the scenario ([`Expression`]).
    Expression(Expression),
    /// A law a program registered by name ([`registry::register`]).
    Registered(Registered),
}

impl TryFrom<Params> for AnyEnergy {
    type Error = EnergyError;
    fn try_from(mut p: Params) -> Result<Self, EnergyError> {
        match p.remove("law") {
            Some(serde_json::Value::String(name)) => registry::build(&name, &p),
            Some(other) => Err(EnergyError::Params {
                law: String::new(),
                message: format!(
                    "law must be a string naming a strain energy ({}), found {other}",
                    registry::names().join(", ")
                ),
            }),
            None => Err(EnergyError::Params {
                law: String::new(),
                message: format!(
                    "missing field `law` (one of {})",
                    registry::names().join(", ")
                ),
            }),
        }
    }
}

impl AnyEnergy {
    /// The `law` tag of this variant.
    ///
    /// ```
    /// use celltissue::{AnyEnergy, NeoHookean};
    /// assert_eq!(AnyEnergy::from(NeoHookean::new(1.0).unwrap()).name(), "neo_hookean");
    /// ```
    pub fn name(&self) -> &str {
        match self {
            Self::NeoHookean(_) => "neo_hookean",
            Self::MooneyRivlin(_) => "mooney_rivlin",
            Self::Ogden(_) => "ogden",
            Self::Hgo(_) => "hgo",
            Self::Gent(_) => "gent",
            Self::Expression(_) => "expression",
            Self::Registered(r) => r.name(),
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
            AnyEnergy::Expression($e) => $body,
            AnyEnergy::Registered($e) => $body,
        }
    };
}

/// A computation generic over the strain energy, run by [`AnyEnergy::visit`] with the law the
/// enum holds, so that the computation is compiled for each concrete law and dispatches once.
///
/// ```
/// use celltissue::{AnyEnergy, LawVisitor, NeoHookean, StrainEnergy};
/// struct Stresses<'a>(&'a [f64]);
/// impl LawVisitor for Stresses<'_> {
///     type Output = Vec<f64>;
///     fn visit<E: StrainEnergy>(self, law: &E) -> Vec<f64> {
///         self.0.iter().map(|&a| law.line(a).sigma).collect()
///     }
/// }
/// let law = AnyEnergy::from(NeoHookean::new(1.0).unwrap());
/// assert_eq!(law.visit(Stresses(&[1.0])), [0.0]);
/// ```
pub trait LawVisitor {
    /// What the computation returns.
    type Output;
    /// The computation with the concrete law.
    fn visit<E: StrainEnergy>(self, law: &E) -> Self::Output;
}

impl AnyEnergy {
    /// Runs `v` with the law this enum holds (one dispatch for the whole computation).
    ///
    /// ```
    /// use celltissue::{AnyEnergy, LawVisitor, NeoHookean, StrainEnergy};
    /// struct Modulus;
    /// impl LawVisitor for Modulus {
    ///     type Output = f64;
    ///     fn visit<E: StrainEnergy>(self, law: &E) -> f64 { law.shear_modulus() }
    /// }
    /// assert_eq!(AnyEnergy::from(NeoHookean::new(2.5).unwrap()).visit(Modulus), 2.5);
    /// ```
    pub fn visit<V: LawVisitor>(&self, v: V) -> V::Output {
        delegate!(self, e => v.visit(e))
    }
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
    // Always inlined: a line whose cells differ (a Gaussian μ, stiff clusters) evaluates its
    // law per cell outside the blocked sweeps, and a call per cell was 4.7 % of the
    // instructions of such a run (10⁴ cells; the match itself is one predictable branch).
    #[inline(always)]
    fn line(&self, a: f64) -> LineResponse {
        delegate!(self, e => e.line(a))
    }
    #[inline(always)]
    fn as_any_energy(&self) -> Option<&AnyEnergy> {
        Some(self)
    }
    #[inline]
    fn sheet(&self, l1: f64, l2: f64) -> SheetResponse {
        delegate!(self, e => e.sheet(l1, l2))
    }
    #[inline]
    fn shear(&self, t: f64) -> ShearResponse {
        delegate!(self, e => e.shear(t))
    }
    #[inline]
    fn shear_pressure(&self, t: f64) -> f64 {
        delegate!(self, e => e.shear_pressure(t))
    }
    fn shear_is_exact(&self) -> bool {
        delegate!(self, e => e.shear_is_exact())
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
from_law!(NeoHookean, MooneyRivlin, Ogden, Hgo, Gent, Expression);

/// Serializes as the scenario table: `law` first, then the law's own fields.
impl Serialize for AnyEnergy {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let inner = delegate!(self, e => serde_json::to_value(e)).map_err(S::Error::custom)?;
        let fields = match inner {
            serde_json::Value::Object(m) => m,
            other => {
                return Err(S::Error::custom(format!(
                    "law fields must be a table, got {other}"
                )))
            }
        };
        let mut m = s.serialize_map(Some(fields.len() + 1))?;
        m.serialize_entry("law", self.name())?;
        for (k, v) in &fields {
            m.serialize_entry(k, v)?;
        }
        m.end()
    }
}
