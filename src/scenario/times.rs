//! Output times in scenario files: an explicit list (`[0, 1, 10, 1000]`) or a range table
//! `{ start, stop, count, spacing = "linear" | "log", zero = false }`. Log spacing needs
//! `start > 0`; `zero = true` prepends `t = 0` (the initial state) to a log range.
//!
//! ```
//! use celltissue::scenario::times::parse_times;
//! let v: toml::Value = toml::from_str::<toml::Table>(
//!     "t = { start = 0.01, stop = 100, count = 5, spacing = \"log\", zero = true }",
//! ).unwrap()["t"].clone();
//! let t = parse_times("output.series", &v).unwrap();
//! assert_eq!(t.len(), 6);
//! assert_eq!(t[0], 0.0);
//! assert!((t[3] - 1.0).abs() < 1e-12);
//! ```

use super::error::{deserialize_at, ScenarioError};
use serde::{Deserialize, Serialize};

/// How a range is spaced.
///
/// ```
/// use celltissue::scenario::times::{Spacing, TimeRange};
/// let r: TimeRange = toml::from_str("start = 1\nstop = 100\ncount = 3\nspacing = \"log\"")?;
/// assert_eq!(r.spacing, Spacing::Log);
/// assert_eq!(r.expand("output.series")?, [1.0, 10.0, 100.0]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Spacing {
    /// Evenly spaced in `t`.
    #[default]
    Linear,
    /// Evenly spaced in `log t` (needs `start > 0`).
    Log,
}

/// A range of output times.
///
/// ```
/// use celltissue::scenario::times::{Spacing, TimeRange};
/// let r = TimeRange { start: 0.01, stop: 100.0, count: 5, spacing: Spacing::Log, zero: true };
/// assert_eq!(r.expand("output.series")?, [0.0, 0.01, 0.1, 1.0, 10.0, 100.0]);
/// let bad = TimeRange { start: 0.0, ..r };
/// assert!(bad.expand("output.series").unwrap_err().to_string().contains("output.series.start"));
/// # Ok::<(), celltissue::scenario::ScenarioError>(())
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeRange {
    /// First time (≥ 0; > 0 for log spacing).
    pub start: f64,
    /// Last time (> `start`).
    pub stop: f64,
    /// Number of times, both ends included (≥ 2).
    pub count: usize,
    /// `"linear"` (default) or `"log"`.
    #[serde(default)]
    pub spacing: Spacing,
    /// Prepend `t = 0` (useful with log spacing).
    #[serde(default)]
    pub zero: bool,
}

impl TimeRange {
    /// The times, after checking the range (errors name `key.start` etc.).
    ///
    /// ```
    /// use celltissue::scenario::times::{Spacing, TimeRange};
    /// let r = TimeRange { start: 0.0, stop: 1.0, count: 5, spacing: Spacing::Linear, zero: false };
    /// assert_eq!(r.expand("output.series")?, [0.0, 0.25, 0.5, 0.75, 1.0]);
    /// # Ok::<(), celltissue::scenario::ScenarioError>(())
    /// ```
    pub fn expand(&self, key: &str) -> Result<Vec<f64>, ScenarioError> {
        let bad = |k: &str, m: String| ScenarioError::key(format!("{key}.{k}"), m);
        if !(self.start.is_finite() && self.start >= 0.0) {
            return Err(bad(
                "start",
                format!("= {} must be finite and >= 0", self.start),
            ));
        }
        if !(self.stop.is_finite() && self.stop > self.start) {
            return Err(bad(
                "stop",
                format!("= {} must be finite and > start", self.stop),
            ));
        }
        if !(2..=1_000_000).contains(&self.count) {
            return Err(bad(
                "count",
                format!("= {} must be from 2 to 1000000", self.count),
            ));
        }
        let n = self.count - 1;
        let mut t: Vec<f64> = match self.spacing {
            Spacing::Linear => (0..=n)
                .map(|k| self.start + (self.stop - self.start) * k as f64 / n as f64)
                .collect(),
            Spacing::Log => {
                if self.start <= 0.0 {
                    return Err(bad(
                        "start",
                        format!(
                            "= {} must be > 0 with spacing = \"log\" (add zero = true for t = 0)",
                            self.start
                        ),
                    ));
                }
                let (a, b) = (self.start.ln(), self.stop.ln());
                (0..=n)
                    .map(|k| round_sig((a + (b - a) * k as f64 / n as f64).exp()))
                    .collect()
            }
        };
        // exact end points despite rounding
        t[0] = self.start;
        t[n] = self.stop;
        if self.zero && self.start > 0.0 {
            t.insert(0, 0.0);
        }
        Ok(t)
    }
}

/// `v` rounded to 12 significant digits, so that log-spaced times hit decades exactly
/// (`10`, not `9.999999999999993`) and match profile times.
fn round_sig(v: f64) -> f64 {
    format!("{v:.11e}").parse().unwrap_or(v)
}

/// Parses a list or range at `key` into increasing, finite, non-negative times.
///
/// ```
/// use celltissue::scenario::times::parse_times;
/// let range: toml::Value = toml::from_str::<toml::Table>("v = { start = 0, stop = 1, count = 3 }")?["v"].clone();
/// assert_eq!(parse_times("output.series", &range)?, [0.0, 0.5, 1.0]);
/// let list = toml::Value::Array(vec![1.into(), 0.5.into()]);
/// assert!(parse_times("output.profiles", &list).is_err()); // not increasing
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn parse_times(key: &str, value: &toml::Value) -> Result<Vec<f64>, ScenarioError> {
    let times = match value {
        toml::Value::Array(items) => items
            .iter()
            .enumerate()
            .map(|(i, v)| match v {
                toml::Value::Float(f) => Ok(*f),
                toml::Value::Integer(n) => Ok(*n as f64),
                other => Err(ScenarioError::key(
                    format!("{key}.{i}"),
                    format!("expected a number, found a {}", other.type_str()),
                )),
            })
            .collect::<Result<Vec<f64>, _>>()?,
        toml::Value::Table(_) => deserialize_at::<TimeRange>(key, value.clone())?.expand(key)?,
        other => {
            return Err(ScenarioError::key(
                key,
                format!(
                    "expected a list of times or a table {{ start, stop, count }}, found a {}",
                    other.type_str()
                ),
            ))
        }
    };
    check_times(key, &times)?;
    Ok(times)
}

/// Non-empty, finite, `≥ 0`, strictly increasing.
///
/// ```
/// use celltissue::scenario::times::check_times;
/// assert!(check_times("output.series", &[0.0, 1.0]).is_ok());
/// let e = check_times("output.series", &[0.0, -1.0]).unwrap_err();
/// assert_eq!(e.key_name(), Some("output.series"));
/// ```
pub fn check_times(key: &str, t: &[f64]) -> Result<(), ScenarioError> {
    if t.is_empty() {
        return Err(ScenarioError::key(key, "needs at least one time"));
    }
    if let Some(bad) = t.iter().find(|v| !(v.is_finite() && **v >= 0.0)) {
        return Err(ScenarioError::key(
            key,
            format!("time {bad} must be finite and >= 0"),
        ));
    }
    if let Some(w) = t.windows(2).find(|w| w[1] <= w[0]) {
        return Err(ScenarioError::key(
            key,
            format!("times must be strictly increasing ({} then {})", w[0], w[1]),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn value(s: &str) -> toml::Value {
        toml::from_str::<toml::Table>(&format!("v = {s}")).unwrap()["v"].clone()
    }

    #[test]
    fn lists_and_linear_ranges() {
        assert_eq!(
            parse_times("k", &value("[0, 1, 10]")).unwrap(),
            vec![0.0, 1.0, 10.0]
        );
        let t = parse_times("k", &value("{ start = 0, stop = 1, count = 5 }")).unwrap();
        assert_eq!(t, vec![0.0, 0.25, 0.5, 0.75, 1.0]);
    }

    #[test]
    fn log_ranges_hit_their_ends() {
        let t = parse_times(
            "k",
            &value("{ start = 1e-3, stop = 1e3, count = 7, spacing = \"log\" }"),
        )
        .unwrap();
        assert_eq!(t.len(), 7);
        assert_eq!((t[0], t[6]), (1e-3, 1e3));
        assert_eq!(t[3], 1.0);
        let t = parse_times(
            "k",
            &value("{ start = 1e-3, stop = 1e3, count = 121, spacing = \"log\" }"),
        )
        .unwrap();
        assert!(t.contains(&10.0) && t.contains(&1.0) && t.contains(&0.01));
    }

    #[test]
    fn bad_times_name_the_key() {
        let e = parse_times("output.series", &value("[0, 2, 1]")).unwrap_err();
        assert_eq!(e.key_name(), Some("output.series"));
        let e = parse_times("output.series", &value("[0, -1]")).unwrap_err();
        assert!(e.to_string().contains(">= 0"));
        let e = parse_times(
            "output.series",
            &value("{ start = 0, stop = 1, count = 1 }"),
        )
        .unwrap_err();
        assert_eq!(e.key_name(), Some("output.series.count"));
        let e = parse_times(
            "output.series",
            &value("{ start = 0, stop = 1, count = 3, spacing = \"log\" }"),
        )
        .unwrap_err();
        assert_eq!(e.key_name(), Some("output.series.start"));
        let e =
            parse_times("output.series", &value("{ start = 0, stop = 1, cnt = 3 }")).unwrap_err();
        assert_eq!(e.key_name(), Some("output.series.cnt"), "{e}");
        let e = parse_times("output.series", &value("[0, \"a\"]")).unwrap_err();
        assert_eq!(e.key_name(), Some("output.series.1"));
        assert!(parse_times("k", &value("[]")).is_err());
        assert!(parse_times("k", &value("3")).is_err());
    }
}
