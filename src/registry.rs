//! Name → constructor registries for the cell laws a scenario picks by name: the division rule
//! (`division = { rule = "<name>", … }`, [`crate::events::rules`]), the growth law
//! (`growth = { law = "<name>", … }`, [`crate::cell::growth_laws`]), the deformation mode
//! ([`crate::modes`]) and the strain energy ([`crate::energy::registry`], with the energy
//! layer's error type). One mechanism for all: a
//! [`Registry`] maps a name to a [`Constructor`] that turns the table's other keys
//! ([`Params`]) into the law, validating them; a [`Named`] value is what a configuration
//! holds — the name, the resolved parameters (echoed in `scenario.toml` and `summary.json`)
//! and the built law.
//!
//! The registries are process-wide (scenarios are deserialized by serde, which carries no
//! context) and behind an `RwLock`; built-ins are inserted on first use. A program that links
//! `celltissue` registers its own law once, before it loads scenarios, and every scenario can
//! name it with the same validation and error messages as the built-in ones.
//!
//! ```
//! use celltissue::registry::{Params, ParamError, Registry};
//! use std::sync::Arc;
//!
//! static SHAPES: Registry<f64> = Registry::new("shape", "shape", || {
//!     vec![("unit", Arc::new(|_: &Params| Ok((1.0, Params::new()))))]
//! });
//! assert_eq!(SHAPES.names(), ["unit"]);
//! SHAPES.register("scaled", Arc::new(|p: &Params| {
//!     let s = p.get("s").and_then(|v| v.as_f64()).ok_or(ParamError::new("s", "missing"))?;
//!     Ok((s, p.clone()))
//! }))?;
//! let p: Params = serde_json::from_str(r#"{"s": 2.5}"#)?;
//! assert_eq!(SHAPES.build("scaled", &p)?.0, 2.5);
//! let e = SHAPES.build("square", &p).unwrap_err().to_string();
//! assert_eq!(e, "`shape` = \"square\": not a registered shape (scaled, unit)");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt;
use std::sync::{Arc, OnceLock, RwLock};

/// A law's parameters: its scenario table without the name key.
pub type Params = serde_json::Map<String, serde_json::Value>;

/// Builds a law from its parameters and returns it with the parameters it resolved (defaults
/// filled in), which is what the configuration echoes. `E` is the layer's error type
/// ([`ParamError`] for rules, growth laws and modes; `EnergyError` for strain energies).
pub type Constructor<T, E = ParamError> =
    Arc<dyn Fn(&Params) -> Result<(T, Params), E> + Send + Sync>;

/// The built-in laws a [`Registry`] starts with: `(name, constructor)` pairs.
pub type Builtins<T, E = ParamError> = fn() -> Vec<(&'static str, Constructor<T, E>)>;

/// A name that no law in a registry has: what a registry's error type is built from.
///
/// ```
/// use celltissue::events::rules::RuleSpec;
/// use celltissue::registry::Params;
/// // a name the registry does not hold: the error lists the registered names
/// let e = RuleSpec::build("mitosis", &Params::new()).unwrap_err();
/// assert_eq!(e.key, "rule");
/// assert!(e.to_string().contains("\"mitosis\": not a registered division rule (age, area,"), "{e}");
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownName {
    /// The key that names the law in a table (`rule`, `law`).
    pub key: &'static str,
    /// What the registry holds ("division rule").
    pub what: &'static str,
    /// The name asked for.
    pub name: String,
    /// The registered names, sorted.
    pub names: Vec<String>,
}

impl From<UnknownName> for ParamError {
    fn from(u: UnknownName) -> Self {
        ParamError {
            key: u.key.to_owned(),
            detail: format!(
                " = \"{}\": not a registered {} ({})",
                u.name,
                u.what,
                u.names.join(", ")
            ),
        }
    }
}

/// A parameter that does not build a law: the key inside the law's table and what is wrong.
/// Displayed as "`key` = value: must be range" or "`key`: message", the form the scenario
/// layer turns into a full key path (`model.division.ratio`).
///
/// ```
/// use celltissue::registry::ParamError;
/// let e = ParamError::range("ratio", 0.5, "finite and > 1");
/// assert_eq!((e.key.as_str(), e.to_string().as_str()), ("ratio", "`ratio` = 0.5: must be finite and > 1"));
/// ```
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("`{key}`{detail}")]
pub struct ParamError {
    /// The key inside the law's table (`ratio`, `sigma0`, …, or the name key itself).
    pub key: String,
    /// What follows the key: " = value: must be range" or ": message".
    detail: String,
}

impl ParamError {
    /// `key`: `message`.
    ///
    /// ```
    /// let e = celltissue::registry::ParamError::new("seed", "must be an integer");
    /// assert_eq!(e.to_string(), "`seed`: must be an integer");
    /// ```
    pub fn new(key: impl Into<String>, message: impl fmt::Display) -> Self {
        Self {
            key: key.into(),
            detail: format!(": {message}"),
        }
    }

    /// `key` = `value`: must be `range`.
    ///
    /// ```
    /// let e = celltissue::registry::ParamError::range("ratio", 0.5, "finite and > 1");
    /// assert_eq!(e.to_string(), "`ratio` = 0.5: must be finite and > 1");
    /// ```
    pub fn range(key: impl Into<String>, value: impl fmt::Display, range: &str) -> Self {
        Self {
            key: key.into(),
            detail: format!(" = {value}: must be {range}"),
        }
    }

    /// Everything after the key (" = 0.5: must be …" or ": …").
    ///
    /// ```
    /// let e = celltissue::registry::ParamError::range("ratio", 0.5, "finite and > 1");
    /// assert_eq!(e.detail(), " = 0.5: must be finite and > 1");
    /// ```
    pub fn detail(&self) -> &str {
        &self.detail
    }
}

/// Checks `v` is finite and `> 0`, naming `key` otherwise (the commonest range of a law's
/// parameter).
///
/// ```
/// use celltissue::registry::positive;
/// assert!(positive("period", 2.0).is_ok());
/// assert_eq!(positive("period", 0.0).unwrap_err().to_string(),
///            "`period` = 0: must be finite and > 0");
/// ```
pub fn positive(key: &str, v: f64) -> Result<(), ParamError> {
    if v > 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(ParamError::range(key, v, "finite and > 0"))
    }
}

/// Deserializes a law's parameters into `L` (so `#[serde(deny_unknown_fields)]` and field
/// defaults apply) and serializes it back, which fills in the defaults. Errors name the key:
/// the unknown or missing field, or the field whose value has the wrong type.
///
/// ```
/// #[derive(serde::Serialize, serde::Deserialize)]
/// #[serde(deny_unknown_fields)]
/// struct Age { period: f64, #[serde(default)] jitter: f64 }
/// use celltissue::registry::{parse, Params};
/// let p: Params = serde_json::from_str(r#"{"period": 2}"#).unwrap();
/// let (age, resolved) = parse::<Age>(&p).unwrap();
/// assert_eq!((age.period, resolved["jitter"].as_f64()), (2.0, Some(0.0)));
/// let p: Params = serde_json::from_str(r#"{"perod": 2}"#).unwrap();
/// assert_eq!(parse::<Age>(&p).err().unwrap().key, "perod");
/// let p: Params = serde_json::from_str(r#"{"period": "two"}"#).unwrap();
/// assert_eq!(parse::<Age>(&p).err().unwrap().key, "period");
/// ```
pub fn parse<L: Serialize + DeserializeOwned>(p: &Params) -> Result<(L, Params), ParamError> {
    let law: L =
        serde_path_to_error::deserialize(serde_json::Value::Object(p.clone())).map_err(|e| {
            let message = e.inner().to_string();
            let path = e.path().to_string();
            let key = quoted_after(&message, "unknown field `")
                .or_else(|| quoted_after(&message, "missing field `"))
                .map(|f| f.to_string())
                .unwrap_or(if path == "." { String::new() } else { path });
            ParamError::new(key, message)
        })?;
    let resolved = match serde_json::to_value(&law) {
        Ok(serde_json::Value::Object(m)) => m,
        _ => p.clone(),
    };
    Ok((law, resolved))
}

/// The constructor of a law type `L`: [`parse`] the parameters into `L`, `check` them, and
/// `wrap` the law into the registry's object (e.g. `Arc<dyn Trait>`). What every typed
/// registration ([`crate::events::rules::register`], [`crate::cell::growth_laws::register`],
/// [`crate::modes::register`]) builds.
///
/// ```
/// use celltissue::registry::{checked, ParamError, Params};
/// #[derive(serde::Serialize, serde::Deserialize)]
/// struct Ratio { ratio: f64 }
/// let ctor = checked::<Ratio, f64>(
///     |r| if r.ratio > 1.0 { Ok(()) } else { Err(ParamError::range("ratio", r.ratio, "> 1")) },
///     |r| r.ratio,
/// );
/// let p: Params = serde_json::from_str(r#"{"ratio": 2.0}"#).unwrap();
/// assert_eq!(ctor(&p).unwrap().0, 2.0);
/// let bad: Params = serde_json::from_str(r#"{"ratio": 0.5}"#).unwrap();
/// assert_eq!(ctor(&bad).unwrap_err().to_string(), "`ratio` = 0.5: must be > 1");
/// ```
pub fn checked<L, T>(check: fn(&L) -> Result<(), ParamError>, wrap: fn(L) -> T) -> Constructor<T>
where
    L: Serialize + DeserializeOwned + 'static,
    T: 'static,
{
    Arc::new(move |p: &Params| {
        let (law, resolved) = parse::<L>(p)?;
        check(&law)?;
        Ok((wrap(law), resolved))
    })
}

/// The text between `prefix` and the next backquote in `message`.
fn quoted_after<'a>(message: &'a str, prefix: &str) -> Option<&'a str> {
    let rest = &message[message.find(prefix)? + prefix.len()..];
    Some(&rest[..rest.find('`')?])
}

/// A registration that cannot be taken.
///
/// ```
/// use celltissue::events::rules;
/// let e = rules::register::<celltissue::events::AgeRule>("area").unwrap_err();
/// assert!(e.to_string().contains("already registered"), "{e}");
/// ```
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum RegistryError {
    /// A name must be `[a-z0-9_]+`.
    #[error("`{0}` is not a valid {1} name (use lower-case letters, digits and `_`)")]
    BadName(String, &'static str),
    /// The name is taken (built-in or registered before).
    #[error("a {1} named `{0}` is already registered")]
    Duplicate(String, &'static str),
}

/// A process-wide map from names to [`Constructor`]s of `T`, seeded with built-ins on first
/// use (`static` with [`Registry::new`]).
///
/// ```
/// use celltissue::registry::{Params, Registry};
/// use std::sync::Arc;
/// static COLOURS: Registry<u32> = Registry::new("colour", "colour", || {
///     vec![("red", Arc::new(|_: &Params| Ok((0xff0000, Params::new()))))]
/// });
/// assert_eq!((COLOURS.what(), COLOURS.key()), ("colour", "colour"));
/// // names are lower-case words, and a name is taken once
/// assert!(COLOURS.register("Blue", Arc::new(|_: &Params| Ok((0x0000ff, Params::new())))).is_err());
/// assert!(COLOURS.register("red", Arc::new(|_: &Params| Ok((1, Params::new())))).is_err());
/// ```
pub struct Registry<T: 'static, E: 'static = ParamError> {
    what: &'static str,
    key: &'static str,
    builtins: Builtins<T, E>,
    map: OnceLock<RwLock<BTreeMap<String, Constructor<T, E>>>>,
}

impl<T: 'static, E: From<UnknownName> + 'static> Registry<T, E> {
    /// A registry of `what` (for messages: "division rule"), selected in a table by the key
    /// `key` (`rule`, `law`), holding `builtins` from the start.
    pub const fn new(what: &'static str, key: &'static str, builtins: Builtins<T, E>) -> Self {
        Self {
            what,
            key,
            builtins,
            map: OnceLock::new(),
        }
    }

    /// What the registry holds, e.g. "division rule".
    ///
    /// ```
    /// use celltissue::registry::{Params, Registry};
    /// use std::sync::Arc;
    /// static SHAPES: Registry<u32> = Registry::new("shape", "shape", || {
    ///     vec![("square", Arc::new(|p: &Params| Ok((4, p.clone()))))]
    /// });
    /// assert_eq!(SHAPES.what(), "shape");
    /// ```
    pub fn what(&self) -> &'static str {
        self.what
    }

    /// The key that names the law in a table (`rule`, `law`).
    ///
    /// ```
    /// use celltissue::registry::{Params, Registry};
    /// use std::sync::Arc;
    /// static SHAPES: Registry<u32> = Registry::new("shape", "shape", || {
    ///     vec![("square", Arc::new(|p: &Params| Ok((4, p.clone()))))]
    /// });
    /// assert_eq!(SHAPES.key(), "shape");
    /// ```
    pub fn key(&self) -> &'static str {
        self.key
    }

    fn lock(&self) -> &RwLock<BTreeMap<String, Constructor<T, E>>> {
        self.map.get_or_init(|| {
            let m = (self.builtins)()
                .into_iter()
                .map(|(n, c)| (n.to_owned(), c))
                .collect();
            RwLock::new(m)
        })
    }

    fn read(&self) -> std::sync::RwLockReadGuard<'_, BTreeMap<String, Constructor<T, E>>> {
        // Inserts are atomic, so a lock poisoned by a panic elsewhere still holds a whole map.
        self.lock().read().unwrap_or_else(|e| e.into_inner())
    }

    /// The registered names, sorted.
    ///
    /// ```
    /// use celltissue::registry::{Params, Registry};
    /// use std::sync::Arc;
    /// static SHAPES: Registry<u32> = Registry::new("shape", "shape", || {
    ///     vec![("square", Arc::new(|p: &Params| Ok((4, p.clone()))))]
    /// });
    /// SHAPES.register("triangle", Arc::new(|p: &Params| Ok((3, p.clone())))).unwrap();
    /// assert_eq!(SHAPES.names(), ["square", "triangle"]);
    /// ```
    pub fn names(&self) -> Vec<String> {
        self.read().keys().cloned().collect()
    }

    /// Builds the law `name` from its parameters; an unknown name lists the registered ones.
    ///
    /// ```
    /// use celltissue::registry::{Params, Registry};
    /// use std::sync::Arc;
    /// static SHAPES: Registry<u32> = Registry::new("shape", "shape", || {
    ///     vec![("square", Arc::new(|p: &Params| Ok((4, p.clone()))))]
    /// });
    /// assert_eq!(SHAPES.build("square", &Params::new())?.0, 4);
    /// let e = SHAPES.build("circle", &Params::new()).unwrap_err();
    /// assert!(e.to_string().contains("not a registered shape (square)"), "{e}");
    /// # Ok::<(), celltissue::registry::ParamError>(())
    /// ```
    pub fn build(&self, name: &str, params: &Params) -> Result<(T, Params), E> {
        let ctor = self.read().get(name).cloned();
        match ctor {
            Some(c) => c(params),
            None => Err(E::from(UnknownName {
                key: self.key,
                what: self.what,
                name: name.to_owned(),
                names: self.names(),
            })),
        }
    }

    /// Registers `ctor` under `name` (`[a-z0-9_]+`, not already taken).
    ///
    /// ```
    /// use celltissue::registry::{Params, Registry};
    /// use std::sync::Arc;
    /// static SHAPES: Registry<u32> = Registry::new("shape", "shape", || {
    ///     vec![("square", Arc::new(|p: &Params| Ok((4, p.clone()))))]
    /// });
    /// SHAPES.register("hexagon", Arc::new(|p: &Params| Ok((6, p.clone())))).unwrap();
    /// assert_eq!(SHAPES.build("hexagon", &Params::new()).unwrap().0, 6);
    /// assert!(SHAPES.register("hexagon", Arc::new(|p: &Params| Ok((6, p.clone())))).is_err());
    /// ```
    pub fn register(&self, name: &str, ctor: Constructor<T, E>) -> Result<(), RegistryError> {
        let valid = !name.is_empty()
            && name
                .chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
        if !valid {
            return Err(RegistryError::BadName(name.to_owned(), self.what));
        }
        let mut m = self.lock().write().unwrap_or_else(|e| e.into_inner());
        if m.contains_key(name) {
            return Err(RegistryError::Duplicate(name.to_owned(), self.what));
        }
        m.insert(name.to_owned(), ctor);
        Ok(())
    }
}

/// Which registry a [`Named`] value resolves in, and the name used when its table has none.
///
/// ```
/// use celltissue::cell::growth_laws::GrowthLaws;
/// use celltissue::events::rules::Rules;
/// use celltissue::registry::Kind;
/// // a growth law may be left unnamed (tanh); a division rule must be named
/// assert_eq!(GrowthLaws::default_name(), Some("tanh"));
/// assert_eq!(Rules::default_name(), None);
/// assert!(Rules::registry().names().contains(&"surface_to_volume".to_string()));
/// ```
pub trait Kind: 'static {
    /// The built law.
    type Law: Clone + Send + Sync + 'static;
    /// The registry.
    fn registry() -> &'static Registry<Self::Law>;
    /// The name assumed when the table omits the name key (`None`: the key is required).
    fn default_name() -> Option<&'static str> {
        None
    }
}

/// A law picked by name in a scenario: the name, its resolved parameters and the law built from
/// them. It deserializes from the law's table (the name key plus parameters, built and
/// validated on the spot) and serializes back to the same table with defaults filled in.
///
/// ```
/// use celltissue::cell::growth_laws::GrowthSpec;
/// let g: GrowthSpec = toml::from_str("sigma0 = 0.2")?; // `law` defaults to "tanh"
/// assert_eq!((g.name(), g.params()["gm"].as_f64()), ("tanh", Some(1.0)));
/// assert_eq!(g.law().rate(0.0).0, 0.5);
/// # Ok::<(), toml::de::Error>(())
/// ```
pub struct Named<K: Kind> {
    name: String,
    params: Params,
    law: K::Law,
}

impl<K: Kind> Named<K> {
    /// Builds the law `name` from `params` in `K`'s registry.
    ///
    /// ```
    /// use celltissue::events::rules::RuleSpec;
    /// use celltissue::registry::Params;
    /// let mut p = Params::new();
    /// p.insert("period".into(), 2.0.into());
    /// let spec = RuleSpec::build("age", &p)?;
    /// assert_eq!(spec.name(), "age");
    /// # Ok::<(), celltissue::registry::ParamError>(())
    /// ```
    pub fn build(name: &str, params: &Params) -> Result<Self, ParamError> {
        let (law, params) = K::registry().build(name, params)?;
        Ok(Self {
            name: name.to_owned(),
            params,
            law,
        })
    }

    /// The name the law is registered under.
    ///
    /// ```
    /// use celltissue::events::rules::RuleSpec;
    /// use celltissue::registry::Params;
    /// let mut p = Params::new();
    /// p.insert("period".into(), 2.0.into());
    /// let spec = RuleSpec::build("age", &p)?;
    /// assert_eq!(spec.name(), "age");
    /// # Ok::<(), celltissue::registry::ParamError>(())
    /// ```
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The resolved parameters.
    ///
    /// ```
    /// use celltissue::events::rules::RuleSpec;
    /// use celltissue::registry::Params;
    /// let mut p = Params::new();
    /// p.insert("period".into(), 2.0.into());
    /// let spec = RuleSpec::build("age", &p)?;
    /// assert_eq!(spec.params()["period"].as_f64(), Some(2.0));
    /// # Ok::<(), celltissue::registry::ParamError>(())
    /// ```
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// The built law.
    ///
    /// ```
    /// use celltissue::events::rules::RuleSpec;
    /// use celltissue::registry::Params;
    /// let mut p = Params::new();
    /// p.insert("period".into(), 2.0.into());
    /// let spec = RuleSpec::build("age", &p)?;
    /// assert_eq!(spec.law().name(), "age 2");
    /// # Ok::<(), celltissue::registry::ParamError>(())
    /// ```
    pub fn law(&self) -> &K::Law {
        &self.law
    }
}

impl<K: Kind> Clone for Named<K> {
    fn clone(&self) -> Self {
        Self {
            name: self.name.clone(),
            params: self.params.clone(),
            law: self.law.clone(),
        }
    }
}

impl<K: Kind> fmt::Debug for Named<K> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} {:?}", self.name, self.params)
    }
}

/// Two laws are equal when they have the same name and resolved parameters.
impl<K: Kind> PartialEq for Named<K> {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name && self.params == other.params
    }
}

impl<K: Kind> Serialize for Named<K> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut table = Params::new();
        table.insert(K::registry().key().to_owned(), self.name.clone().into());
        table.extend(self.params.clone());
        table.serialize(s)
    }
}

impl<K: Kind> Named<K> {
    /// Builds the law from its whole table (the name key plus parameters), with a typed error
    /// naming the key at fault — what deserializing does, without serde's text channel.
    ///
    /// ```
    /// use celltissue::events::rules::RuleSpec;
    /// let t: celltissue::registry::Params =
    ///     serde_json::from_str(r#"{"rule": "age", "period": -1}"#).unwrap();
    /// assert_eq!(RuleSpec::from_table(t).unwrap_err().key, "period");
    /// ```
    pub fn from_table(mut p: Params) -> Result<Self, ParamError> {
        let key = K::registry().key();
        let name = match (p.remove(key), K::default_name()) {
            (Some(serde_json::Value::String(s)), _) => s,
            (None, Some(default)) => default.to_owned(),
            (None, None) => {
                return Err(ParamError::new(
                    key,
                    format!(
                        "missing: name the {} ({})",
                        K::registry().what(),
                        K::registry().names().join(", ")
                    ),
                ))
            }
            (Some(other), _) => {
                return Err(ParamError::new(
                    key,
                    format!(
                        "{other} must be a string naming the {}",
                        K::registry().what()
                    ),
                ))
            }
        };
        Self::build(&name, &p)
    }
}

impl<'de, K: Kind> Deserialize<'de> for Named<K> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        Self::from_table(Params::deserialize(d)?).map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Scale;
    static SCALES: Registry<f64> = Registry::new("scale", "scale", || {
        vec![(
            "fixed",
            Arc::new(|p: &Params| {
                let v = p.get("v").and_then(|v| v.as_f64()).unwrap_or(1.0);
                positive("v", v)?;
                let mut r = Params::new();
                r.insert("v".into(), v.into());
                Ok((v, r))
            }),
        )]
    });
    impl Kind for Scale {
        type Law = f64;
        fn registry() -> &'static Registry<f64> {
            &SCALES
        }
        fn default_name() -> Option<&'static str> {
            Some("fixed")
        }
    }

    #[test]
    fn a_named_law_round_trips_with_its_defaults_filled_in() {
        let n: Named<Scale> = serde_json::from_str("{}").unwrap();
        assert_eq!((n.name(), *n.law()), ("fixed", 1.0));
        let back = serde_json::to_string(&n).unwrap();
        assert_eq!(back, r#"{"scale":"fixed","v":1.0}"#);
        assert_eq!(serde_json::from_str::<Named<Scale>>(&back).unwrap(), n);
        let e = serde_json::from_str::<Named<Scale>>(r#"{"v": -2}"#).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("`v` = -2: must be finite and > 0"),
            "{e}"
        );
        let e = serde_json::from_str::<Named<Scale>>(r#"{"scale": 3}"#).unwrap_err();
        assert!(
            e.to_string().starts_with("`scale`: 3 must be a string"),
            "{e}"
        );
    }

    #[test]
    fn names_are_checked_and_never_replaced() {
        assert_eq!(
            SCALES.register("Fixed", Arc::new(|_: &Params| Ok((0.0, Params::new())))),
            Err(RegistryError::BadName("Fixed".into(), "scale"))
        );
        assert_eq!(
            SCALES.register("fixed", Arc::new(|_: &Params| Ok((0.0, Params::new())))),
            Err(RegistryError::Duplicate("fixed".into(), "scale"))
        );
        assert_eq!(SCALES.build("fixed", &Params::new()).unwrap().0, 1.0);
    }
}
