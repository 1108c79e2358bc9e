//! The name → constructor registry of strain energies: what `law = { law = "<name>", … }` in a
//! scenario (the line's `law`, the sheet's and shear column's `energy`) resolves to.
//!
//! Built in: `neo_hookean`, `mooney_rivlin`, `ogden`, `hgo` and `expression` (a formula,
//! [`super::Expression`]). A program that links `celltissue` adds its own law with
//! [`register`] (any [`StrainEnergy`] that deserializes from its parameters); from then on every
//! scenario it loads can name that law, with the same validation and error messages as the
//! built-in ones. It is a [`crate::registry::Registry`] like the division rules' and growth
//! laws' (process-wide, read-mostly, behind an `RwLock`), with the energy layer's own error
//! type [`EnergyError`].
//!
//! ```
//! use celltissue::energy::registry;
//! use celltissue::{AnyEnergy, StrainEnergy};
//! use num_dual::DualNum;
//!
//! /// Yeoh-type law W = C₁(I₁−3) + C₂(I₁−3)², μ = 2C₁.
//! #[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
//! #[serde(deny_unknown_fields)]
//! struct Yeoh { c1: f64, c2: f64 }
//! impl StrainEnergy for Yeoh {
//!     fn energy<D: DualNum<Primitive = f64> + Copy>(&self, l: [D; 3]) -> D {
//!         let j1 = l[0] * l[0] + l[1] * l[1] + l[2] * l[2] - 3.0;
//!         j1 * self.c1 + j1 * j1 * self.c2
//!     }
//!     fn shear_modulus(&self) -> f64 { 2.0 * self.c1 }
//! }
//!
//! registry::register::<Yeoh>("yeoh_doc")?;
//! let law: AnyEnergy = toml::from_str("law = \"yeoh_doc\"\nc1 = 0.5\nc2 = 0.1")?;
//! assert_eq!(law.name(), "yeoh_doc");
//! assert!((law.line(1.0).dsigma - 4.0).abs() < 1e-12);
//! assert!(registry::names().contains(&"yeoh_doc".to_string()));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use super::{
    AnyEnergy, EnergyError, Expression, Gent, Hgo, LineResponse, MooneyRivlin, NeoHookean, Ogden,
    ShearResponse, SheetResponse, StrainEnergy,
};
use crate::registry::{Registry, RegistryError, UnknownName};
use num_dual::{Dual2, Dual2SVec64, Dual2_64, Dual64, DualNum, HyperDual64};
use serde::de::DeserializeOwned;
use serde::Serialize;
use std::any::Any;
use std::fmt;
use std::sync::Arc;

/// A law's parameters: the scenario table without its `law` key.
pub type Params = serde_json::Map<String, serde_json::Value>;

/// Builds a law from its parameters (errors name the offending parameter).
pub type Constructor = Arc<dyn Fn(&Params) -> Result<AnyEnergy, EnergyError> + Send + Sync>;

static LAWS: Registry<AnyEnergy, EnergyError> = Registry::new("strain energy", "law", || {
    vec![
        ("neo_hookean", typed::<NeoHookean>("neo_hookean")),
        ("mooney_rivlin", typed::<MooneyRivlin>("mooney_rivlin")),
        ("ogden", typed::<Ogden>("ogden")),
        ("hgo", typed::<Hgo>("hgo")),
        ("gent", typed::<Gent>("gent")),
        ("expression", stored(Arc::new(expression))),
    ]
});

impl From<UnknownName> for EnergyError {
    fn from(u: UnknownName) -> Self {
        EnergyError::UnknownLaw {
            name: u.name,
            valid: u.names.join(", "),
        }
    }
}

/// A law constructor as the registry stores it: the parameters echoed as given.
fn stored(ctor: Constructor) -> crate::registry::Constructor<AnyEnergy, EnergyError> {
    Arc::new(move |p: &Params| Ok((ctor(p)?, p.clone())))
}

/// A constructor for a built-in law that deserializes (and so validates) its parameters.
fn typed<L>(name: &'static str) -> crate::registry::Constructor<AnyEnergy, EnergyError>
where
    L: DeserializeOwned + Into<AnyEnergy>,
{
    stored(Arc::new(move |p: &Params| {
        Ok(parse_params::<L>(name, p)?.into())
    }))
}

fn parse_params<L: DeserializeOwned>(name: &str, p: &Params) -> Result<L, EnergyError> {
    serde_json::from_value(serde_json::Value::Object(p.clone())).map_err(|e| EnergyError::Params {
        law: name.to_owned(),
        message: e.to_string(),
    })
}

/// `expression`: `W` (a formula string) and numeric parameters.
fn expression(p: &Params) -> Result<AnyEnergy, EnergyError> {
    let formula = match p.get("W") {
        Some(serde_json::Value::String(s)) => s,
        Some(other) => {
            return Err(EnergyError::Params {
                law: "expression".into(),
                message: format!(
                    "W must be a string formula such as \"mu/2*(I1 - 3)\", found {other}"
                ),
            })
        }
        None => {
            return Err(EnergyError::Params {
                law: "expression".into(),
                message: "missing field `W` (the strain energy, e.g. W = \"mu/2*(I1 - 3)\")".into(),
            })
        }
    };
    let mut params = Vec::with_capacity(p.len());
    for (k, v) in p.iter().filter(|(k, _)| *k != "W") {
        let x = v.as_f64().ok_or_else(|| EnergyError::Params {
            law: "expression".into(),
            message: format!("{k} = {v} must be a number (a parameter of W)"),
        })?;
        params.push((k.as_str(), x));
    }
    Ok(AnyEnergy::Expression(Expression::new(formula, params)?))
}

/// The registered law names, sorted.
///
/// ```
/// let names = celltissue::energy::registry::names();
/// assert!(names.contains(&"expression".to_string()) && names.contains(&"hgo".to_string()));
/// ```
pub fn names() -> Vec<String> {
    LAWS.names()
}

/// Builds the law `name` from its parameters.
///
/// ```
/// use celltissue::energy::registry;
/// let p = serde_json::json!({"mu": 2.0}).as_object().unwrap().clone();
/// assert_eq!(registry::build("neo_hookean", &p)?.name(), "neo_hookean");
/// let err = registry::build("yeoh", &p).unwrap_err().to_string();
/// assert!(err.starts_with("unknown variant `yeoh`; valid laws: expression, gent, hgo,"));
/// # Ok::<(), celltissue::EnergyError>(())
/// ```
pub fn build(name: &str, params: &Params) -> Result<AnyEnergy, EnergyError> {
    LAWS.build(name, params).map(|(law, _)| law)
}

/// Registers a user law under `name`: scenarios may then write
/// `law = { law = "<name>", <parameters> }`, the parameters deserialized into `L` (so
/// `#[serde(deny_unknown_fields)]` and `#[serde(try_from = …)]` validation apply). Names are
/// `[a-z0-9_]+`; a name already registered (built-in or not) is refused.
///
/// ```
/// use celltissue::energy::registry;
/// let err = registry::register::<celltissue::NeoHookean>("hgo").unwrap_err();
/// assert_eq!(err.to_string(), "a strain energy named `hgo` is already registered");
/// ```
pub fn register<L>(name: &str) -> Result<(), EnergyError>
where
    L: StrainEnergy + Serialize + DeserializeOwned + Clone + fmt::Debug + 'static,
{
    let law_name: Arc<str> = Arc::from(name);
    register_with(
        name,
        Arc::new(move |p: &Params| {
            let law: L = parse_params(&law_name, p)?;
            Ok(AnyEnergy::Registered(Registered::new(
                law_name.clone(),
                p.clone(),
                law,
            )))
        }),
    )
}

/// Registers a constructor under `name` (for laws built some other way than by deserializing a
/// type, e.g. a fixed formula: `Arc::new(|p| …)`). Same naming rules as [`register`].
///
/// ```
/// use celltissue::energy::registry;
/// use celltissue::registry::Params;
/// use celltissue::{AnyEnergy, NeoHookean, StrainEnergy};
/// use std::sync::Arc;
/// // a neo-Hookean law given by its Young's modulus E = 3μ
/// registry::register_with("young_neo_hookean", Arc::new(|p: &Params| {
///     let young = p.get("E").and_then(|v| v.as_f64()).unwrap_or(3.0);
///     Ok(AnyEnergy::NeoHookean(NeoHookean::new(young / 3.0)?))
/// }))?;
/// let p = serde_json::json!({"E": 6.0}).as_object().unwrap().clone();
/// assert_eq!(registry::build("young_neo_hookean", &p)?.shear_modulus(), 2.0);
/// # Ok::<(), celltissue::EnergyError>(())
/// ```
pub fn register_with(name: &str, ctor: Constructor) -> Result<(), EnergyError> {
    LAWS.register(name, stored(ctor)).map_err(|e| match e {
        RegistryError::Duplicate(name, _) => EnergyError::DuplicateLaw(name),
        RegistryError::BadName(name, _) => EnergyError::BadLawName(name),
    })
}

/// The object-safe face of a user law (the [`StrainEnergy`] trait itself is generic over the
/// scalar, so it cannot be a trait object): the responses, and the energy at every scalar type
/// the crate evaluates `W` in.
trait DynLaw: Send + Sync + fmt::Debug {
    fn dyn_shear_modulus(&self) -> f64;
    fn dyn_line(&self, a: f64) -> LineResponse;
    fn dyn_sheet(&self, l1: f64, l2: f64) -> SheetResponse;
    fn dyn_shear(&self, t: f64) -> ShearResponse;
    fn dyn_shear_pressure(&self, t: f64) -> f64;
    fn dyn_shear_is_exact(&self) -> bool;
    /// Writes `W(l)` into `out` if `l`'s scalar is one of the supported types.
    fn energy_any(&self, l: &dyn Any, out: &mut dyn Any) -> bool;
}

/// Tries `W` at one concrete scalar type `T`.
fn energy_at<T, L>(law: &L, l: &dyn Any, out: &mut dyn Any) -> bool
where
    T: DualNum<Primitive = f64> + Copy,
    L: StrainEnergy,
{
    match (l.downcast_ref::<[T; 3]>(), out.downcast_mut::<T>()) {
        (Some(l), Some(out)) => {
            *out = law.energy(*l);
            true
        }
        _ => false,
    }
}

impl<L: StrainEnergy + fmt::Debug> DynLaw for L {
    fn dyn_shear_modulus(&self) -> f64 {
        StrainEnergy::shear_modulus(self)
    }
    fn dyn_line(&self, a: f64) -> LineResponse {
        StrainEnergy::line(self, a)
    }
    fn dyn_sheet(&self, l1: f64, l2: f64) -> SheetResponse {
        StrainEnergy::sheet(self, l1, l2)
    }
    fn dyn_shear(&self, t: f64) -> ShearResponse {
        StrainEnergy::shear(self, t)
    }
    fn dyn_shear_pressure(&self, t: f64) -> f64 {
        StrainEnergy::shear_pressure(self, t)
    }
    fn dyn_shear_is_exact(&self) -> bool {
        StrainEnergy::shear_is_exact(self)
    }
    fn energy_any(&self, l: &dyn Any, out: &mut dyn Any) -> bool {
        energy_at::<f64, L>(self, l, out)
            || energy_at::<Dual64, L>(self, l, out)
            || energy_at::<Dual2<Dual64>, L>(self, l, out)
            || energy_at::<Dual2SVec64<3>, L>(self, l, out)
            || energy_at::<Dual2_64, L>(self, l, out)
            || energy_at::<HyperDual64, L>(self, l, out)
    }
}

/// A user law registered with [`register`], as held by [`AnyEnergy::Registered`]: its name,
/// the parameters it was built from (for serialization and equality) and the law itself.
///
/// ```
/// use celltissue::energy::registry;
/// use celltissue::AnyEnergy;
/// registry::register::<celltissue::NeoHookean>("my_neo_hookean")?;
/// let p = serde_json::json!({"mu": 1.5}).as_object().unwrap().clone();
/// match registry::build("my_neo_hookean", &p)? {
///     AnyEnergy::Registered(r) => {
///         assert_eq!((r.name(), r.params()["mu"].as_f64()), ("my_neo_hookean", Some(1.5)))
///     }
///     other => panic!("not a registered law: {other:?}"),
/// }
/// # Ok::<(), celltissue::EnergyError>(())
/// ```
#[derive(Clone)]
pub struct Registered {
    name: Arc<str>,
    params: Params,
    law: Arc<dyn DynLaw>,
}

impl fmt::Debug for Registered {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Registered")
            .field("name", &self.name)
            .field("law", &self.law)
            .finish()
    }
}

impl PartialEq for Registered {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name && self.params == other.params
    }
}

impl Registered {
    fn new<L: StrainEnergy + fmt::Debug + 'static>(name: Arc<str>, params: Params, law: L) -> Self {
        Self {
            name,
            params,
            law: Arc::new(law),
        }
    }

    /// The name the law was registered under.
    ///
    /// ```
    /// use celltissue::energy::registry;
    /// use celltissue::AnyEnergy;
    /// registry::register::<celltissue::NeoHookean>("nh_again")?;
    /// let p = serde_json::json!({"mu": 3.0}).as_object().unwrap().clone();
    /// let AnyEnergy::Registered(r) = registry::build("nh_again", &p)? else { panic!() };
    /// assert_eq!(r.name(), "nh_again");
    /// # Ok::<(), celltissue::EnergyError>(())
    /// ```
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The parameters it was built from.
    ///
    /// ```
    /// use celltissue::energy::registry;
    /// use celltissue::AnyEnergy;
    /// registry::register::<celltissue::NeoHookean>("nh_again")?;
    /// let p = serde_json::json!({"mu": 3.0}).as_object().unwrap().clone();
    /// let AnyEnergy::Registered(r) = registry::build("nh_again", &p)? else { panic!() };
    /// assert_eq!(r.params()["mu"].as_f64(), Some(3.0));
    /// # Ok::<(), celltissue::EnergyError>(())
    /// ```
    pub fn params(&self) -> &Params {
        &self.params
    }
}

impl StrainEnergy for Registered {
    /// `W` at `f64`, `Dual64`, `Dual2<Dual64>`, `Dual2SVec64<3>`, `Dual2_64` and `HyperDual64`
    /// (every scalar the crate evaluates a law in); NaN for any other scalar type, since a
    /// type-erased law cannot be evaluated generically.
    #[inline]
    fn energy<D: DualNum<Primitive = f64> + Copy>(&self, l: [D; 3]) -> D {
        let mut out = D::from(f64::NAN);
        self.law.energy_any(&l, &mut out);
        out
    }
    fn shear_modulus(&self) -> f64 {
        self.law.dyn_shear_modulus()
    }
    fn line(&self, a: f64) -> LineResponse {
        self.law.dyn_line(a)
    }
    fn sheet(&self, l1: f64, l2: f64) -> SheetResponse {
        self.law.dyn_sheet(l1, l2)
    }
    fn shear(&self, t: f64) -> ShearResponse {
        self.law.dyn_shear(t)
    }
    fn shear_pressure(&self, t: f64) -> f64 {
        self.law.dyn_shear_pressure(t)
    }
    fn shear_is_exact(&self) -> bool {
        self.law.dyn_shear_is_exact()
    }
}

impl Serialize for Registered {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.params.serialize(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn registered_law_matches_its_generic_evaluation() {
        #[derive(Clone, Debug, Serialize, serde::Deserialize)]
        struct Twice {
            mu: f64,
        }
        impl StrainEnergy for Twice {
            fn energy<D: DualNum<Primitive = f64> + Copy>(&self, l: [D; 3]) -> D {
                (l[0] * l[0] + l[1] * l[1] + l[2] * l[2] - 3.0) * self.mu
            }
            fn shear_modulus(&self) -> f64 {
                2.0 * self.mu
            }
        }
        register::<Twice>("twice_test").unwrap();
        let p = serde_json::json!({"mu": 0.5}).as_object().unwrap().clone();
        let law = build("twice_test", &p).unwrap();
        let reference = NeoHookean::new(1.0).unwrap();
        assert!((law.line(1.3).sigma - reference.line(1.3).sigma).abs() < 1e-13);
        // The type-erased energy answers at the crate's scalar types …
        let l = [Dual64::new(1.2, 1.0), Dual64::from(0.9), Dual64::from(1.0)];
        let (a, b) = (law.energy(l), reference.energy(l));
        assert!((a.re - b.re).abs() < 1e-14 && (a.eps - b.eps).abs() < 1e-14);
        // … and NaN, not a wrong number, at any other.
        let l3 = [num_dual::Dual3_64::from(1.2); 3];
        assert!(law.energy(l3).re.is_nan());
        // Serialization round trip through the registry.
        let s = serde_json::to_string(&law).unwrap();
        assert_eq!(s, r#"{"law":"twice_test","mu":0.5}"#);
        assert_eq!(serde_json::from_str::<AnyEnergy>(&s).unwrap(), law);
        assert!(register_with("Bad-Name", Arc::new(expression)).is_err());
    }
}
