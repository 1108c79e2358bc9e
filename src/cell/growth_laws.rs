//! The growth-law registry: what `growth = { law = "<name>", … }` in a line scenario resolves
//! to (a [`crate::registry::Registry`] of [`GrowthLaw`]s; `law` may be left out for the
//! thesis's `tanh`).
//!
//! Built in: `tanh` ([`TanhGrowth`], `{ sigma0 = 0.1, gm = 1 }`). A program adds its own law
//! type with [`register`] (any [`GrowthLaw`], so any [`super::GrowthRate`], that
//! deserializes from its parameters); its parameters are parsed and checked
//! ([`GrowthLaw::check`]) like the built-in's (`docs/guide-growth-law.md`).
//!
//! ```
//! use celltissue::cell::{growth_laws, GrowthRate, GrowthSpec};
//! use celltissue::num_dual::DualNum;
//!
//! /// ġ = G_m/(1 + exp(−(σ − σ_c)/0.05)): G_m well above σ_c, 0 well below (a switch).
//! #[derive(serde::Serialize, serde::Deserialize)]
//! #[serde(deny_unknown_fields)]
//! struct Switch { sigma_c: f64, gm: f64 }
//! impl GrowthRate for Switch {
//!     fn growth_rate<D: DualNum<Primitive = f64> + Copy>(&self, s: D) -> D {
//!         (((s - self.sigma_c) * -20.0).exp() + 1.0).recip() * self.gm
//!     }
//! }
//!
//! growth_laws::register::<Switch>("switch_doc")?;
//! let g: GrowthSpec = toml::from_str("law = \"switch_doc\"\nsigma_c = 0.0\ngm = 2.0")?;
//! assert_eq!(g.law().rate(0.0).0, 1.0); // G_m/2 at the switch
//! let tanh: GrowthSpec = toml::from_str("sigma0 = 0.2")?; // no `law`: the thesis's tanh
//! assert_eq!((tanh.name(), tanh.params()["gm"].as_f64()), ("tanh", Some(1.0)));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use super::growth::{GrowthLaw, TanhGrowth};
use crate::registry::{
    checked, Constructor, Kind, Named, ParamError, Params, Registry, RegistryError,
};
use serde::de::DeserializeOwned;
use serde::Serialize;
use std::sync::Arc;

/// A growth law as a configuration holds it: name, resolved parameters, built law.
pub type GrowthSpec = Named<GrowthLaws>;

/// The registry of growth laws (selected by the `law` key; default `tanh`).
///
/// ```
/// use celltissue::cell::growth_laws::{GrowthLaws, GrowthSpec};
/// use celltissue::registry::Kind;
/// let g: GrowthSpec = toml::from_str("sigma0 = 0.5")?; // no `law` key: the default
/// assert_eq!((g.name(), GrowthLaws::default_name()), ("tanh", Some("tanh")));
/// assert_eq!(g.law().rate(0.0).0, 0.5); // G(0) = G_m/2
/// # Ok::<(), toml::de::Error>(())
/// ```
pub struct GrowthLaws;

static LAWS: Registry<Arc<dyn GrowthLaw>> = Registry::new("growth law", "law", || {
    vec![("tanh", typed::<TanhGrowth>())]
});

impl Kind for GrowthLaws {
    type Law = Arc<dyn GrowthLaw>;
    fn registry() -> &'static Registry<Self::Law> {
        &LAWS
    }
    fn default_name() -> Option<&'static str> {
        Some("tanh")
    }
}

/// The constructor of a law type: parse the parameters into `L`, then [`GrowthLaw::check`].
fn typed<L>() -> Constructor<Arc<dyn GrowthLaw>>
where
    L: GrowthLaw + Serialize + DeserializeOwned + 'static,
{
    checked::<L, _>(L::check, |law| Arc::new(law))
}

/// Registers the law type `L` under `name` (`[a-z0-9_]+`, not taken): line scenarios may then
/// write `growth = { law = "<name>", <parameters of L> }`.
///
/// ```
/// let e = celltissue::cell::growth_laws::register::<celltissue::cell::TanhGrowth>("tanh");
/// assert_eq!(e.unwrap_err().to_string(), "a growth law named `tanh` is already registered");
/// ```
pub fn register<L>(name: &str) -> Result<(), RegistryError>
where
    L: GrowthLaw + Serialize + DeserializeOwned + 'static,
{
    LAWS.register(name, typed::<L>())
}

/// The registered law names, sorted.
///
/// ```
/// assert!(celltissue::cell::growth_laws::names().contains(&"tanh".to_string()));
/// ```
pub fn names() -> Vec<String> {
    LAWS.names()
}

/// The thesis's tanh law as a configuration entry (checked like a scenario's).
///
/// ```
/// use celltissue::cell::{growth_laws, TanhGrowth};
/// let g = growth_laws::tanh(TanhGrowth::default())?;
/// assert_eq!(g.law().rate(0.0).0, 0.5);
/// let e = growth_laws::tanh(TanhGrowth { sigma0: 0.0, gm: 1.0 }).unwrap_err();
/// assert_eq!(e.to_string(), "`sigma0` = 0: must be finite and > 0");
/// # Ok::<(), celltissue::registry::ParamError>(())
/// ```
pub fn tanh(law: TanhGrowth) -> Result<GrowthSpec, ParamError> {
    let params: Params = match serde_json::to_value(law) {
        Ok(serde_json::Value::Object(m)) => m,
        _ => Params::new(),
    };
    GrowthSpec::build("tanh", &params)
}
