//! Heterogeneous material fields of the reference position `X` (docs/model.md §2.1): `μ(X)`, `η(X)`,
//! `K(X)`, active amplitude. A [`Field`] is sampled once, at build time, at cell centres
//! `X_{j−1/2}` (default) or at integer points (the left boundary `X_{j−1}` of each cell;
//! reproduces the thesis's 2.267, docs/model.md §5.2) — see [`Sampling`].

use serde::{Deserialize, Serialize};
use std::fmt;
use std::sync::Arc;

/// A scalar field of the reference position `X ∈ [0, l₀]`.
///
/// ```
/// use celltissue::cell::Field;
/// // the stiff cluster (2.82): μ = 1 + exp(−(X−l₀/2)²/(2(l₀/10)²))
/// let mu = Field::gaussian_bump(1.0, 1.0, 0.5, 0.1);
/// assert!((mu.eval(50.0, 100.0) - 2.0).abs() < 1e-15);
/// assert_eq!(Field::Constant(3.0).eval(7.0, 100.0), 3.0);
/// ```
///
/// In a scenario file a field is either a number (`mu = 2.0`) or a table with a `type`:
/// `{ type = "gaussian", base = 1, amplitude = 1, centre = 0.5, width = 0.1 }`,
/// `{ type = "piecewise", breaks = [0.5], values = [1, 3] }`, `{ type = "per_cell", values = [..] }`,
/// `{ type = "random", low = 0.5, high = 2, seed = 1 }`, `{ type = "constant", value = 1 }`.
//
// The serde derive (with `remote = "Self"`, so that the derived code is an inherent
// `Field::serialize` called by the hand-written impl below) writes the tagged tables; the
// hand-written impls add the plain-number form of `Constant` and `"closure"`. Tables are read
// through `FieldTable` (below), so that an error names the key inside the table
// (`mu.width`, not `mu`).
///
/// A per-cell parameter (`μ`, `η`, `K`…) as a function of the reference position:
///
/// ```
/// use celltissue::cell::Field;
/// assert_eq!(Field::Constant(2.0).eval(30.0, 100.0), 2.0);
/// // (2.82): 1 + exp(−(X − 50)²/(2·10²)) on l₀ = 100
/// let bump = Field::gaussian_bump(1.0, 1.0, 0.5, 0.1);
/// assert_eq!(bump.eval(50.0, 100.0), 2.0);
/// let ramp = Field::closure(|x, l0| 1.0 + x / l0);
/// assert_eq!(ramp.sample(&[0.0, 50.0], 100.0), [1.0, 1.5]);
/// ```
#[derive(Clone, Serialize)]
#[serde(remote = "Self", tag = "type", rename_all = "snake_case")]
pub enum Field {
    /// The same value everywhere.
    #[serde(skip_serializing)]
    Constant(f64),
    /// `base + amplitude·exp(−(X − b)²/(2c²))` with `b = centre·l₀`, `c = width·l₀` (2.82:
    /// base 1, amplitude 1, centre ½, width 1/10).
    Gaussian {
        /// Value far from the bump.
        base: f64,
        /// Height of the bump.
        amplitude: f64,
        /// Centre as a fraction of `l₀`.
        centre: f64,
        /// Standard deviation as a fraction of `l₀`.
        width: f64,
    },
    /// Piecewise constant: `values[i]` on `[breaks[i−1], breaks[i])` in units of `X/l₀`
    /// (`breaks` has one entry fewer than `values`, increasing).
    Piecewise {
        /// Interior break points, as fractions of `l₀`.
        breaks: Vec<f64>,
        /// One value per piece.
        values: Vec<f64>,
    },
    /// One value per cell (segment), in order; the number must match the cells sampled.
    PerCell {
        /// Values.
        values: Vec<f64>,
    },
    /// Independent uniform values in `[low, high]` per sample, from a seeded generator
    /// (splitmix64; the same seed gives the same field on every platform). A line's builders
    /// draw one per cell, so both discretisations see the same tissue: a finer continuum grid
    /// reads the cell where each of its points lies, a coarser one its cells' effective values.
    Random {
        /// Lower bound.
        low: f64,
        /// Upper bound.
        high: f64,
        /// Seed.
        seed: u64,
    },
    /// Any function of `(X, l₀)` (not serialisable; serialises as `"closure"`).
    #[serde(skip)]
    Closure(FieldFn),
}

/// The table forms of a [`Field`] as read from a scenario, externally tagged after the `type`
/// key is taken out (serde's internally tagged enums buffer the table and lose the path of an
/// error inside it).
#[derive(Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
enum FieldTable {
    Constant {
        value: f64,
    },
    Gaussian {
        base: f64,
        amplitude: f64,
        centre: f64,
        width: f64,
    },
    Piecewise {
        breaks: Vec<f64>,
        values: Vec<f64>,
    },
    PerCell {
        values: Vec<f64>,
    },
    Random {
        low: f64,
        high: f64,
        seed: u64,
    },
}

impl From<FieldTable> for Field {
    fn from(t: FieldTable) -> Self {
        match t {
            FieldTable::Constant { value } => Field::Constant(value),
            FieldTable::Gaussian {
                base,
                amplitude,
                centre,
                width,
            } => Field::Gaussian {
                base,
                amplitude,
                centre,
                width,
            },
            FieldTable::Piecewise { breaks, values } => Field::Piecewise { breaks, values },
            FieldTable::PerCell { values } => Field::PerCell { values },
            FieldTable::Random { low, high, seed } => Field::Random { low, high, seed },
        }
    }
}

/// A field's parameters out of range ([`Field::validate`]): the innermost key (`mu.width`)
/// and a message that names it.
///
/// ```
/// use celltissue::cell::Field;
/// let e = Field::Constant(-1.0).validate("mu", true).unwrap_err();
/// assert_eq!(e.key, "mu");
/// assert_eq!(e.to_string(), "mu = -1 must be finite and > 0");
/// ```
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{message}")]
pub struct FieldError {
    /// The innermost key: the field's own key, or `key.parameter` (`mu.width`).
    pub key: String,
    /// The message (it starts with the key).
    pub message: String,
}

/// An error inside a field table, turned into serde's error by the deserializer.
#[derive(Debug, thiserror::Error)]
enum FieldTableError {
    /// At a key inside the table (reported as "`key`: message", which the scenario loader
    /// turns into `mu.width`).
    #[error("`{key}`: {message}")]
    At { key: String, message: String },
    /// Without a key inside the table.
    #[error("{0}")]
    Table(String),
}

/// A field from its table: the `type` key selects the variant; an error inside the table is
/// reported as "`key`: message" (the scenario loader turns that into `mu.width`).
fn field_from_table(mut table: toml::Table) -> Result<Field, FieldTableError> {
    let kind = match table.remove("type") {
        Some(toml::Value::String(s)) => s,
        Some(other) => {
            return Err(FieldTableError::At {
                key: "type".into(),
                message: format!(
                    "expected a string (constant | gaussian | piecewise | per_cell | random), found a {}",
                    other.type_str()
                ),
            })
        }
        None => return Err(FieldTableError::Table("missing field `type`".into())),
    };
    let mut tagged = toml::Table::new();
    tagged.insert(kind, toml::Value::Table(table));
    serde_path_to_error::deserialize::<_, FieldTable>(toml::Value::Table(tagged))
        .map(Field::from)
        .map_err(|e| {
            // the path starts with the variant name; drop it
            let path = e.path().to_string();
            let inner = e.inner().to_string();
            match path.split_once('.') {
                Some((_, key)) if !key.is_empty() => FieldTableError::At {
                    key: key.to_string(),
                    message: inner,
                },
                _ => FieldTableError::Table(inner),
            }
        })
}

impl Serialize for Field {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Field::Constant(v) => s.serialize_f64(*v),
            Field::Closure(_) => s.serialize_str("closure"),
            tagged => Field::serialize(tagged, s),
        }
    }
}

impl<'de> Deserialize<'de> for Field {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = Field;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number, a list of numbers (one per cell) or a table with `type` = constant | gaussian | piecewise | per_cell | random")
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut s: A) -> Result<Field, A::Error> {
                // a list of numbers is the `per_cell` field of those values
                let mut values = Vec::with_capacity(s.size_hint().unwrap_or(0).min(1 << 20));
                while let Some(v) = s.next_element::<f64>()? {
                    values.push(v);
                }
                Ok(Field::PerCell { values })
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<Field, E> {
                Ok(Field::Constant(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Field, E> {
                Ok(Field::Constant(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Field, E> {
                Ok(Field::Constant(v as f64))
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, m: A) -> Result<Field, A::Error> {
                use serde::de::Error;
                let table =
                    toml::Table::deserialize(serde::de::value::MapAccessDeserializer::new(m))?;
                field_from_table(table).map_err(A::Error::custom)
            }
        }
        d.deserialize_any(V)
    }
}

/// A user field function `f(X, l₀)` (what [`Field::closure`] wraps).
///
/// ```
/// use celltissue::cell::{Field, FieldFn};
/// use std::sync::Arc;
/// let f = Field::Closure(FieldFn(Arc::new(|x, _| 2.0 * x)));
/// assert_eq!(f.eval(3.0, 10.0), 6.0);
/// ```
#[derive(Clone)]
pub struct FieldFn(pub Arc<dyn Fn(f64, f64) -> f64 + Send + Sync>);

impl fmt::Debug for Field {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Field::Constant(v) => write!(f, "Constant({v})"),
            Field::Gaussian {
                base,
                amplitude,
                centre,
                width,
            } => write!(
                f,
                "Gaussian {{ base: {base}, amplitude: {amplitude}, centre: {centre}, width: {width} }}"
            ),
            Field::Piecewise { breaks, values } => {
                write!(f, "Piecewise {{ breaks: {breaks:?}, values: {values:?} }}")
            }
            Field::PerCell { values } => write!(f, "PerCell({} values)", values.len()),
            Field::Random { low, high, seed } => {
                write!(f, "Random {{ low: {low}, high: {high}, seed: {seed} }}")
            }
            Field::Closure(_) => write!(f, "Closure"),
        }
    }
}

impl PartialEq for Field {
    fn eq(&self, other: &Self) -> bool {
        format!("{self:?}") == format!("{other:?}")
    }
}

impl Default for Field {
    fn default() -> Self {
        Field::Constant(1.0)
    }
}

impl From<f64> for Field {
    fn from(v: f64) -> Self {
        Field::Constant(v)
    }
}

/// Narrowest gaussian bump, as a fraction of `l₀`: a line has at most 10⁸ cells, so a narrower
/// bump lies between samples, and its squared width could underflow (`0/0` at the centre).
pub const MIN_GAUSSIAN_WIDTH: f64 = 1e-10;

/// Where a field is sampled for each cell.
///
/// ```
/// use celltissue::cell::{Field, Sampling};
/// use celltissue::line::build::{discrete, LineParams};
/// use celltissue::NeoHookean;
/// let mut p = LineParams::unit_cells(4);
/// p.mu = Field::closure(|x, _| 1.0 + x);
/// p.sampling = Sampling::IntegerPoints; // μ_j at X_{j−1}: 1, 2, 3, 4
/// let line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
/// assert_eq!(line.cells().mu, [1.0, 2.0, 3.0, 4.0]);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Sampling {
    /// Initial cell (segment) centres `X_{j−1/2}` (default).
    #[default]
    Centres,
    /// Integer points: the initial left boundary `X_{j−1}` of each cell (thesis code's grid).
    IntegerPoints,
}

/// splitmix64 step (public-domain reference algorithm by S. Vigna).
fn splitmix64(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

impl Field {
    /// The stiff-cluster bump `base + amplitude·exp(−(X − centre·l₀)²/(2(width·l₀)²))`.
    ///
    /// ```
    /// use celltissue::cell::Field;
    /// // a stiff cluster: μ = 1 + 4 at the middle of a line of length 100, width 5 % of it
    /// let mu = Field::gaussian_bump(1.0, 4.0, 0.5, 0.05);
    /// assert_eq!(mu.eval(50.0, 100.0), 5.0);
    /// assert!((mu.eval(0.0, 100.0) - 1.0).abs() < 1e-20);
    /// ```
    pub fn gaussian_bump(base: f64, amplitude: f64, centre: f64, width: f64) -> Self {
        Field::Gaussian {
            base,
            amplitude,
            centre,
            width,
        }
    }

    /// A field from a closure `f(X, l₀)`.
    ///
    /// ```
    /// use celltissue::cell::Field;
    /// let f = Field::closure(|x, l0| 1.0 + x / l0);
    /// assert_eq!(f.eval(50.0, 100.0), 1.5);
    /// ```
    pub fn closure(f: impl Fn(f64, f64) -> f64 + Send + Sync + 'static) -> Self {
        Field::Closure(FieldFn(Arc::new(f)))
    }

    /// Value at one point `X` for a line of reference length `l0`. `PerCell` and `Random`
    /// have no pointwise value: they return the first value / the midpoint of the range (use
    /// [`Field::sample`]).
    ///
    /// ```
    /// use celltissue::cell::Field;
    /// assert_eq!(Field::Constant(2.0).eval(3.0, 10.0), 2.0);
    /// assert_eq!(Field::closure(|x, l0| x / l0).eval(2.5, 10.0), 0.25);
    /// ```
    pub fn eval(&self, x: f64, l0: f64) -> f64 {
        match self {
            Field::Constant(v) => *v,
            Field::Gaussian {
                base,
                amplitude,
                centre,
                width,
            } => {
                let b = centre * l0;
                let c = width * l0;
                base + amplitude * (-(x - b) * (x - b) / (2.0 * c * c)).exp()
            }
            Field::Piecewise { breaks, values } => {
                let s = x / l0;
                let i = breaks.iter().take_while(|&&b| s >= b).count();
                values[i.min(values.len().saturating_sub(1))]
            }
            Field::PerCell { values } => values.first().copied().unwrap_or(f64::NAN),
            Field::Random { low, high, .. } => 0.5 * (low + high),
            Field::Closure(f) => (f.0)(x, l0),
        }
    }

    /// Samples the field at the points `xs` (one per cell) of a line of length `l0`.
    /// `PerCell` values are resampled (nearest cell by centre) if their count differs from
    /// `xs.len()` — so a per-cell list given for N cells also drives a continuum grid.
    ///
    /// ```
    /// use celltissue::cell::Field;
    /// // per-cell values given for 2 cells drive a 4-segment continuum grid by nearest centre
    /// let f = Field::PerCell { values: vec![1.0, 3.0] };
    /// assert_eq!(f.sample(&[0.25, 0.75, 1.25, 1.75], 2.0), [1.0, 1.0, 3.0, 3.0]);
    /// ```
    pub fn sample(&self, xs: &[f64], l0: f64) -> Vec<f64> {
        match self {
            Field::PerCell { values } => {
                let nv = values.len();
                if nv == xs.len() || nv == 0 {
                    return values.clone();
                }
                xs.iter()
                    .map(|&x| {
                        let i = ((x / l0) * nv as f64).floor();
                        values[(i.max(0.0) as usize).min(nv - 1)]
                    })
                    .collect()
            }
            Field::Random { low, high, seed } => {
                let mut s = *seed;
                xs.iter()
                    .map(|_| {
                        let u = (splitmix64(&mut s) >> 11) as f64 / (1u64 << 53) as f64;
                        low + (high - low) * u
                    })
                    .collect()
            }
            _ => xs.iter().map(|&x| self.eval(x, l0)).collect(),
        }
    }

    /// This field with a random one drawn once for each of `cells` cells, as a per-cell list
    /// (any other field unchanged): sampled on a grid of any size, it then gives every point
    /// the value of the cell where it lies, as the discrete cells see it.
    ///
    /// ```
    /// use celltissue::cell::Field;
    /// let f = Field::Random { low: 0.5, high: 2.0, seed: 3 };
    /// let per_cell = f.drawn_per_cell(4);
    /// let cells = per_cell.sample(&[0.5, 1.5, 2.5, 3.5], 4.0);
    /// assert_eq!(cells, f.sample(&[0.0; 4], 4.0)); // the same four draws
    /// // eight points, two in each cell, share their cell's value
    /// let fine = per_cell.sample(&[0.25, 0.75, 1.25, 1.75, 2.25, 2.75, 3.25, 3.75], 4.0);
    /// assert!(fine.chunks(2).zip(&cells).all(|(pair, c)| pair == [*c, *c]));
    /// ```
    pub fn drawn_per_cell(&self, cells: usize) -> Field {
        match self {
            Field::Random { .. } => Field::PerCell {
                values: self.sample(&vec![0.0; cells], 1.0),
            },
            other => other.clone(),
        }
    }

    /// An upper bound of every sample of the field, whatever the grid: the constant, the
    /// gaussian's `base + max(amplitude, 0)`, the largest piecewise or per-cell value, the
    /// random range's `high`; `None` for a program's function.
    ///
    /// ```
    /// use celltissue::cell::Field;
    /// assert_eq!(Field::gaussian_bump(1.0, 2.0, 0.5, 0.1).upper_bound(), Some(3.0));
    /// assert_eq!(Field::gaussian_bump(1.0, -0.5, 0.5, 0.1).upper_bound(), Some(1.0));
    /// assert_eq!(Field::Random { low: 0.5, high: 2.0, seed: 1 }.upper_bound(), Some(2.0));
    /// ```
    pub fn upper_bound(&self) -> Option<f64> {
        match self {
            Field::Constant(v) => Some(*v),
            Field::Gaussian {
                base, amplitude, ..
            } => Some(base + amplitude.max(0.0)),
            Field::Piecewise { values, .. } | Field::PerCell { values } => {
                values.iter().copied().reduce(f64::max)
            }
            Field::Random { high, .. } => Some(*high),
            Field::Closure(_) => None,
        }
    }

    /// Whether every sample of the field is exactly 0 whatever the grid (a zero constant, a
    /// gaussian with base and amplitude 0, piecewise or per-cell values all 0, a random range
    /// `[0, 0]`). Used to reject a drag that leaves a ring's rigid translation undetermined.
    ///
    /// ```
    /// use celltissue::cell::Field;
    /// assert!(Field::Random { low: 0.0, high: 0.0, seed: 1 }.is_identically_zero());
    /// assert!(!Field::Random { low: 0.0, high: 1.0, seed: 1 }.is_identically_zero());
    /// ```
    pub fn is_identically_zero(&self) -> bool {
        match self {
            Field::Constant(v) => *v == 0.0,
            Field::Gaussian {
                base, amplitude, ..
            } => *base == 0.0 && *amplitude == 0.0,
            Field::Piecewise { values, .. } | Field::PerCell { values } => {
                values.iter().all(|v| *v == 0.0)
            }
            Field::Random { low, high, .. } => *low == 0.0 && *high == 0.0,
            Field::Closure(_) => false,
        }
    }

    /// Checks the field's own parameters; `key` names it in the message. `positive` demands
    /// every sampled value be `> 0` (else `≥ 0`).
    ///
    /// ```
    /// use celltissue::cell::Field;
    /// let bad = Field::gaussian_bump(1.0, 1.0, f64::NAN, 0.1);
    /// assert_eq!(bad.validate("mu", true).unwrap_err().key, "mu.centre");
    /// assert!(Field::Constant(0.0).validate("eta", false).is_ok());
    /// assert!(Field::Constant(0.0).validate("mu", true).is_err()); // μ must be > 0
    /// // a subnormal value (below 2.2e-308 in magnitude) is named, not run
    /// assert_eq!(Field::Constant(5e-324).validate("K", false).unwrap_err().key, "K");
    /// ```
    pub fn validate(&self, key: &str, positive: bool) -> Result<(), FieldError> {
        let sign = if positive {
            Sign::Positive
        } else {
            Sign::NonNegative
        };
        self.validate_range(key, sign)?;
        self.validate_normal(key)
    }

    /// Checks the field's own parameters as [`Field::validate`] does, for a field of either
    /// sign (an external pressure): every value finite, a list not empty.
    ///
    /// ```
    /// use celltissue::cell::Field;
    /// assert!(Field::Constant(-0.5).validate_signed("external_pressure").is_ok());
    /// let empty = Field::PerCell { values: vec![] };
    /// assert_eq!(empty.validate_signed("external_pressure").unwrap_err().key, "external_pressure");
    /// ```
    pub fn validate_signed(&self, key: &str) -> Result<(), FieldError> {
        self.validate_range(key, Sign::Any)?;
        self.validate_normal(key)
    }

    /// Rejects a nonzero value below the smallest normal double (`f64::MIN_POSITIVE`,
    /// 2.2e-308) in magnitude: such a value keeps only a few significant bits, and the terms
    /// it scales underflow to zero in the solver's matrices (a drag `K = 5e-324` made the
    /// consistent initialisation's `∂F/∂ẏ` exactly singular). Zero itself stays allowed.
    fn validate_normal(&self, key: &str) -> Result<(), FieldError> {
        let found = match self {
            Field::Constant(v) => subnormal(*v).then_some(("", *v)),
            Field::Gaussian {
                base, amplitude, ..
            } => [
                ("base", *base),
                ("amplitude", *amplitude),
                ("amplitude", base + amplitude),
            ]
            .into_iter()
            .find(|&(_, v)| subnormal(v)),
            Field::Piecewise { values, .. } | Field::PerCell { values } => {
                values.iter().find(|v| subnormal(**v)).map(|v| ("", *v))
            }
            Field::Random { low, high, .. } => [*low, *high]
                .into_iter()
                .find(|&v| subnormal(v))
                .map(|v| ("", v)),
            Field::Closure(_) => None,
        };
        match found {
            None => Ok(()),
            Some((sub, v)) => Err(FieldError {
                key: if sub.is_empty() {
                    key.to_string()
                } else {
                    format!("{key}.{sub}")
                },
                message: format!(
                    "{key}{}{sub} = {}",
                    if sub.is_empty() { "" } else { "." },
                    subnormal_text(v)
                ),
            }),
        }
    }

    /// The range part of [`validate`](Self::validate).
    fn validate_range(&self, key: &str, sign: Sign) -> Result<(), FieldError> {
        let err = |sub: &str, message: String| FieldError {
            key: if sub.is_empty() {
                key.to_string()
            } else {
                format!("{key}.{sub}")
            },
            message,
        };
        let bad = |v: f64| {
            !v.is_finite()
                || match sign {
                    Sign::Positive => v <= 0.0,
                    Sign::NonNegative => v < 0.0,
                    Sign::Any => false,
                }
        };
        let range = match sign {
            Sign::Positive => " and > 0",
            Sign::NonNegative => " and >= 0",
            Sign::Any => "",
        };
        match self {
            Field::Constant(v) if bad(*v) => {
                Err(err("", format!("{key} = {v} must be finite{range}")))
            }
            Field::Gaussian {
                base,
                amplitude,
                centre,
                width,
            } => {
                if bad(*base) {
                    Err(err(
                        "base",
                        format!("{key}.base = {base} must be finite{range}"),
                    ))
                } else if !amplitude.is_finite() || bad(base + amplitude) {
                    Err(err("amplitude", format!(
                        "{key}.amplitude = {amplitude} must be finite, with base + amplitude = {} finite{range}",
                        base + amplitude
                    )))
                } else if !centre.is_finite() {
                    Err(err("centre", format!(
                        "{key}.centre = {centre} must be finite (a fraction of l0, usually in [0, 1])"
                    )))
                } else if !(*width >= MIN_GAUSSIAN_WIDTH && width.is_finite()) {
                    Err(err(
                        "width",
                        format!(
                        "{key}.width = {width} must be finite and >= {MIN_GAUSSIAN_WIDTH:e} (a \
                         fraction of l0; narrower bumps fall between samples and their \
                         squared width underflows)"
                    ),
                    ))
                } else {
                    Ok(())
                }
            }
            Field::Piecewise { breaks, values } => {
                if values.len() != breaks.len() + 1 {
                    Err(err(
                        "",
                        format!(
                            "{key}: piecewise needs len(values) = len(breaks) + 1 (got {} and {})",
                            values.len(),
                            breaks.len()
                        ),
                    ))
                } else if let Some(v) = values.iter().find(|v| bad(**v)) {
                    Err(err(
                        "",
                        format!("{key}: piecewise value {v} must be finite{range}"),
                    ))
                } else if let Some(b) = breaks.iter().find(|b| !b.is_finite()) {
                    Err(err("breaks", format!("{key}.breaks: {b} must be finite")))
                } else if breaks.windows(2).any(|w| w[1] <= w[0]) {
                    Err(err("", format!("{key}: piecewise breaks must increase")))
                } else {
                    Ok(())
                }
            }
            Field::PerCell { values } => {
                if values.is_empty() {
                    Err(err("", format!("{key}: per_cell values must not be empty")))
                } else if let Some(v) = values.iter().find(|v| bad(**v)) {
                    Err(err(
                        "",
                        format!("{key}: per_cell value {v} must be finite{range}"),
                    ))
                } else {
                    Ok(())
                }
            }
            Field::Random { low, high, .. } => {
                if bad(*low) || bad(*high) || high < low {
                    Err(err(
                        "",
                        format!(
                        "{key}: random range [{low}, {high}] must be finite{range}, with low <= high"
                    ),
                    ))
                } else {
                    Ok(())
                }
            }
            _ => Ok(()),
        }
    }
}

/// The values a field may take.
#[derive(Clone, Copy)]
enum Sign {
    Positive,
    NonNegative,
    Any,
}

/// Whether `v` is nonzero and below the smallest normal double (`f64::MIN_POSITIVE`,
/// 2.2e-308) in magnitude: a value that keeps only a few significant bits, and whose products
/// underflow (what [`Field::validate`] and the scenario loader reject).
pub(crate) fn subnormal(v: f64) -> bool {
    v != 0.0 && v.abs() < f64::MIN_POSITIVE
}

/// Why a [`subnormal`] value is rejected, after its `key = ` (one text for every layer).
pub(crate) fn subnormal_text(v: f64) -> String {
    format!(
        "{v:e} is subnormal: a nonzero value must be at least {:e} in magnitude (the smallest \
         normal double; below it the value keeps only a few digits and what it scales \
         underflows to 0), or exactly 0",
        f64::MIN_POSITIVE
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn random_is_seeded_and_in_range() {
        let xs: Vec<f64> = (0..1000).map(|j| j as f64 + 0.5).collect();
        let f = Field::Random {
            low: 0.5,
            high: 2.0,
            seed: 7,
        };
        let a = f.sample(&xs, 1000.0);
        assert_eq!(a, f.sample(&xs, 1000.0));
        assert!(a.iter().all(|&v| (0.5..=2.0).contains(&v)));
        let mean = a.iter().sum::<f64>() / 1000.0;
        assert!((mean - 1.25).abs() < 0.05, "{mean}");
    }

    #[test]
    fn piecewise_and_per_cell() {
        let f = Field::Piecewise {
            breaks: vec![0.5],
            values: vec![1.0, 3.0],
        };
        assert_eq!(f.sample(&[10.0, 60.0], 100.0), vec![1.0, 3.0]);
        let p = Field::PerCell {
            values: vec![1.0, 2.0],
        };
        assert_eq!(
            p.sample(&[0.25, 0.75, 1.25, 1.75], 2.0),
            vec![1.0, 1.0, 2.0, 2.0]
        );
        assert!(p.validate("mu", true).is_ok());
        assert!(Field::Constant(-1.0).validate("mu", true).is_err());
    }

    #[test]
    fn serde_forms_round_trip_and_errors_name_the_problem() {
        let de = |s: &str| serde_json::from_str::<Field>(s).map_err(|e| e.to_string());
        let ser = |f: &Field| serde_json::to_string(f).unwrap();
        // numbers and the constant table are constants; a constant serialises as a number
        assert_eq!(de("2.5").unwrap(), Field::Constant(2.5));
        assert_eq!(de("2").unwrap(), Field::Constant(2.0));
        assert_eq!(
            de(r#"{"type":"constant","value":3}"#).unwrap(),
            Field::Constant(3.0)
        );
        assert_eq!(ser(&Field::Constant(2.5)), "2.5");
        assert_eq!(ser(&Field::closure(|x, _| x)), r#""closure""#);
        for (f, json) in [
            (
                Field::gaussian_bump(1.0, 2.0, 0.5, 0.1),
                r#"{"type":"gaussian","base":1.0,"amplitude":2.0,"centre":0.5,"width":0.1}"#,
            ),
            (
                Field::Piecewise {
                    breaks: vec![0.5],
                    values: vec![1.0, 3.0],
                },
                r#"{"type":"piecewise","breaks":[0.5],"values":[1.0,3.0]}"#,
            ),
            (
                Field::PerCell {
                    values: vec![1.0, 2.0],
                },
                r#"{"type":"per_cell","values":[1.0,2.0]}"#,
            ),
            (
                Field::Random {
                    low: 0.5,
                    high: 2.0,
                    seed: 7,
                },
                r#"{"type":"random","low":0.5,"high":2.0,"seed":7}"#,
            ),
        ] {
            assert_eq!(ser(&f), json);
            assert_eq!(de(json).unwrap(), f);
        }
        // errors: unknown type, unknown field, missing field, wrong kind
        let unknown = de(r#"{"type":"bump"}"#).unwrap_err();
        assert!(
            unknown.contains("unknown variant `bump`")
                && unknown.contains("`constant`, `gaussian`, `piecewise`, `per_cell`, `random`")
                && !unknown.contains("closure"),
            "{unknown}"
        );
        let extra = de(r#"{"type":"constant","value":1,"scale":2}"#).unwrap_err();
        assert!(extra.contains("unknown field `scale`"), "{extra}");
        let missing = de(r#"{"type":"random","low":0.5,"high":2}"#).unwrap_err();
        assert!(missing.contains("missing field `seed`"), "{missing}");
        let wrong = de(r#""mu""#).unwrap_err();
        assert!(
            wrong.contains("a list of numbers (one per cell) or a table with `type`"),
            "{wrong}"
        );
        // a list of numbers is a per-cell field; anything else in it is named
        assert_eq!(
            de("[1, 2.5, 3]").unwrap(),
            Field::PerCell {
                values: vec![1.0, 2.5, 3.0]
            }
        );
        let not_a_number = de(r#"[1, "a"]"#).unwrap_err();
        assert!(not_a_number.contains("expected f64"), "{not_a_number}");
    }
}
