//! The division-rule registry: what `division = { rule = "<name>", … }` in a scenario resolves
//! to (a [`crate::registry::Registry`] of [`DivisionRule`]s).
//!
//! Built in: `area` ([`AreaDoubling`]), `age` ([`AgeRule`]), `random_area`
//! ([`RandomThreshold`]) and `surface_to_volume` ([`SurfaceToVolume`]). A program adds its own
//! rule type with [`register`]; from then on its scenarios can name it, its parameters parsed
//! (with `#[serde(deny_unknown_fields)]` and defaults) and checked
//! ([`DivisionRule::check`]) like the built-ins' (`docs/guide-division-rule.md`).
//!
//! ```
//! use celltissue::events::{rules, CellView, DivisionConfig, DivisionRule};
//!
//! /// Divide when the cell's current length reaches `critical`.
//! #[derive(serde::Serialize, serde::Deserialize)]
//! #[serde(deny_unknown_fields)]
//! struct Length { critical: f64 }
//! impl DivisionRule for Length {
//!     fn event(&self, c: &CellView) -> f64 { c.length - self.critical }
//!     fn name(&self) -> String { format!("length {}", self.critical) }
//!     fn needs_mechanics(&self) -> bool { true }
//! }
//!
//! rules::register::<Length>("length_doc")?;
//! let c: DivisionConfig = toml::from_str("rule = \"length_doc\"\ncritical = 1.5")?;
//! assert_eq!(c.build().name(), "length 1.5");
//! assert!(rules::names().contains(&"length_doc".to_string()));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use super::division::{AgeRule, AreaDoubling, DivisionRule, RandomThreshold, SurfaceToVolume};
use crate::registry::{checked, Constructor, Kind, Named, Registry, RegistryError};
use serde::de::DeserializeOwned;
use serde::Serialize;
use std::sync::Arc;

/// A division rule as a configuration holds it: name, resolved parameters, built rule.
pub type RuleSpec = Named<Rules>;

/// The registry of division rules (selected by the `rule` key; no default name).
///
/// ```
/// use celltissue::events::rules::RuleSpec;
/// let spec: RuleSpec = toml::from_str("rule = \"age\"\nperiod = 2.5")?;
/// assert_eq!((spec.name(), spec.params()["period"].as_f64()), ("age", Some(2.5)));
/// assert_eq!(spec.law().name(), "age 2.5");
/// # Ok::<(), toml::de::Error>(())
/// ```
pub struct Rules;

static RULES: Registry<Arc<dyn DivisionRule>> = Registry::new("division rule", "rule", || {
    vec![
        ("area", typed::<AreaDoubling>()),
        ("age", typed::<AgeRule>()),
        ("random_area", typed::<RandomThreshold>()),
        ("surface_to_volume", typed::<SurfaceToVolume>()),
    ]
});

impl Kind for Rules {
    type Law = Arc<dyn DivisionRule>;
    fn registry() -> &'static Registry<Self::Law> {
        &RULES
    }
}

/// The constructor of a rule type: parse the parameters into `R`, then [`DivisionRule::check`].
fn typed<R>() -> Constructor<Arc<dyn DivisionRule>>
where
    R: DivisionRule + Serialize + DeserializeOwned + 'static,
{
    checked::<R, _>(R::check, |rule| Arc::new(rule))
}

/// Registers the rule type `R` under `name` (`[a-z0-9_]+`, not taken): scenarios may then write
/// `division = { rule = "<name>", <parameters of R> }`.
///
/// ```
/// let e = celltissue::events::rules::register::<celltissue::events::AgeRule>("age");
/// assert_eq!(e.unwrap_err().to_string(), "a division rule named `age` is already registered");
/// ```
pub fn register<R>(name: &str) -> Result<(), RegistryError>
where
    R: DivisionRule + Serialize + DeserializeOwned + 'static,
{
    RULES.register(name, typed::<R>())
}

/// Registers a constructor under `name`, for a rule built otherwise than by deserializing a
/// type.
///
/// ```
/// use celltissue::events::rules::{register_with, RuleSpec};
/// use celltissue::events::{AgeRule, DivisionRule};
/// use celltissue::registry::{positive, Params};
/// use std::sync::Arc;
/// // a rule given by its rate: cells divide at age 1/rate
/// register_with("clock", Arc::new(|p: &Params| {
///     let rate = p.get("rate").and_then(|v| v.as_f64()).unwrap_or(1.0);
///     positive("rate", rate)?;
///     let rule: Arc<dyn DivisionRule> = Arc::new(AgeRule { period: 1.0 / rate });
///     Ok((rule, p.clone()))
/// }))?;
/// let spec: RuleSpec = toml::from_str("rule = \"clock\"\nrate = 4.0").unwrap();
/// assert_eq!(spec.law().name(), "age 0.25");
/// assert!(toml::from_str::<RuleSpec>("rule = \"clock\"\nrate = -1.0").is_err());
/// # Ok::<(), celltissue::registry::RegistryError>(())
/// ```
pub fn register_with(
    name: &str,
    ctor: Constructor<Arc<dyn DivisionRule>>,
) -> Result<(), RegistryError> {
    RULES.register(name, ctor)
}

/// The registered rule names, sorted.
///
/// ```
/// let names = celltissue::events::rules::names();
/// assert!(["age", "area", "random_area", "surface_to_volume"]
///     .iter().all(|n| names.contains(&n.to_string())));
/// ```
pub fn names() -> Vec<String> {
    RULES.names()
}
