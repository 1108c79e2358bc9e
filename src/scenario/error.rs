//! [`ScenarioError`]: everything that can be wrong with a scenario file or its overrides. Every
//! variant names the offending key (dotted path from the file's root, e.g. `model.k1`) and, for
//! bad values, the valid range. The CLI maps all of them to exit code 2.

use std::path::PathBuf;
use thiserror::Error;

/// A scenario that cannot be run as written.
///
/// ```
/// use celltissue::scenario::load_str;
/// let text = "name = \"x\"\n[output]\nseries = [1]\n[model]\nkind = \"line\"\nmu = { type = \"gaussian\", base = 1, amplitude = 1, centre = 0.5, width = -1 }";
/// let e = load_str(text, "x.toml".as_ref(), &[]).unwrap_err();
/// assert_eq!(e.key_name(), Some("model.mu.width")); // the innermost key
/// let missing = celltissue::scenario::load("no/such/file.toml", &[]).unwrap_err();
/// assert!(missing.to_string().starts_with("cannot read scenario file"));
/// ```
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ScenarioError {
    /// The file cannot be read.
    #[error("cannot read scenario file `{path}`: {source}")]
    Read {
        /// The path given.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The file is not valid TOML.
    #[error("`{path}` is not valid TOML: {message}")]
    Syntax {
        /// The path given.
        path: PathBuf,
        /// The parser's message (with line and column).
        message: String,
    },
    /// A key is unknown, has the wrong type, or its value is out of range.
    #[error("`{key}`: {message}")]
    Key {
        /// Dotted path of the key, e.g. `model.k1`.
        key: String,
        /// What is wrong and what is valid.
        message: String,
    },
    /// A `--set` argument is malformed or points through a non-table.
    #[error("--set `{arg}`: {message}")]
    Set {
        /// The argument as given.
        arg: String,
        /// What is wrong.
        message: String,
    },
}

impl ScenarioError {
    /// A [`ScenarioError::Key`] from displayable parts.
    /// The message is put in a researcher's words and shortened ([`researcher_words`]).
    ///
    /// ```
    /// use celltissue::scenario::ScenarioError;
    /// let e = ScenarioError::key("model.K", "must be >= 0");
    /// assert_eq!((e.key_name(), e.to_string().as_str()), (Some("model.K"), "`model.K`: must be >= 0"));
    /// ```
    pub fn key(key: impl Into<String>, message: impl Into<String>) -> Self {
        ScenarioError::Key {
            key: shorten(&key.into()),
            message: researcher_words(&message.into()),
        }
    }

    /// A [`ScenarioError::Set`] (argument and message shortened).
    ///
    /// ```
    /// use celltissue::scenario::ScenarioError;
    /// let e = ScenarioError::set("model.K=abc", "not a number");
    /// assert_eq!(e.key_name(), Some("model.K")); // the key before `=`
    /// ```
    pub fn set(arg: &str, message: impl Into<String>) -> Self {
        ScenarioError::Set {
            arg: shorten(arg),
            message: researcher_words(&message.into()),
        }
    }

    /// A [`ScenarioError::Syntax`] (the parser's message shortened: it quotes the line).
    ///
    /// ```
    /// use celltissue::scenario::ScenarioError;
    /// let e = ScenarioError::syntax("run.toml".as_ref(), "expected `=`");
    /// assert!(e.to_string().starts_with("`run.toml` is not valid TOML"), "{e}");
    /// assert_eq!(e.key_name(), None);
    /// ```
    pub fn syntax(path: &std::path::Path, message: &str) -> Self {
        ScenarioError::Syntax {
            path: path.to_path_buf(),
            message: researcher_words(message.trim()),
        }
    }

    /// The offending key, if the error names one.
    ///
    /// ```
    /// use celltissue::scenario::ScenarioError;
    /// assert_eq!(ScenarioError::key("output.series", "empty").key_name(), Some("output.series"));
    /// ```
    pub fn key_name(&self) -> Option<&str> {
        match self {
            ScenarioError::Key { key, .. } => Some(key),
            // a `--set key=value` argument names its key before the `=`
            ScenarioError::Set { arg, .. } => arg.split_once('=').map(|(k, _)| k.trim()),
            _ => None,
        }
    }

    /// Appends a parenthesised note to a key error's message.
    /// Both are shortened (a note may quote user input, e.g. a `--set` argument).
    ///
    /// ```
    /// use celltissue::scenario::ScenarioError;
    /// let e = ScenarioError::key("model.K", "must be >= 0").with_note("from --set model.K=-1");
    /// assert!(e.to_string().ends_with("(from --set model.K=-1)"), "{e}");
    /// ```
    pub fn with_note(self, note: &str) -> Self {
        match self {
            ScenarioError::Key { key, message } => ScenarioError::Key {
                key,
                message: shorten_to(
                    &format!("{message} ({})", shorten_to(note, MAX_MESSAGE_CHARS / 2)),
                    2 * MAX_MESSAGE_CHARS,
                ),
            },
            other => other,
        }
    }

    /// Prefixes the message with the run it came from (used for sweep values).
    ///
    /// ```
    /// use celltissue::scenario::ScenarioError;
    /// let e = ScenarioError::key("model.K", "must be >= 0").in_run("discrete K=-1");
    /// assert!(e.to_string().ends_with("(in run `discrete K=-1`)"), "{e}");
    /// ```
    pub fn in_run(self, run: &str) -> Self {
        match self {
            ScenarioError::Key { key, message } => ScenarioError::Key {
                key,
                message: shorten_to(
                    &format!(
                        "{message} (in run `{}`)",
                        shorten_to(run, MAX_MESSAGE_CHARS / 2)
                    ),
                    2 * MAX_MESSAGE_CHARS,
                ),
            },
            other => other,
        }
    }
}

/// Deserialises `value` into `T`, reporting unknown keys and type errors with their full dotted
/// path below `prefix` (`""` for the root). A whole number written as a float where an integer
/// is expected (`cells = 1e4`, `--set model.cells=100.0`, Python's `cells=1e4`) is read as that
/// integer: the key is converted and the value read again.
pub(crate) fn deserialize_at<T: serde::de::DeserializeOwned>(
    prefix: &str,
    mut value: toml::Value,
) -> Result<T, ScenarioError> {
    // each retry converts one key; a scenario has far fewer integer keys than this
    const MAX_CONVERSIONS: usize = 64;
    for _ in 0..=MAX_CONVERSIONS {
        let e = match serde_path_to_error::deserialize(value.clone()) {
            Ok(t) => return Ok(t),
            Err(e) => e,
        };
        let (path, inner) = located(&e);
        if let Some((_, n)) = integral_float(&inner) {
            if let Some(slot) = value_at(&mut value, &path) {
                if slot.as_float().is_some() {
                    *slot = toml::Value::Integer(n);
                    continue;
                }
            }
        }
        return Err(report(prefix, path, inner));
    }
    Err(ScenarioError::key(
        prefix,
        format!("more than {MAX_CONVERSIONS} whole numbers written as floats"),
    ))
}

/// The path (relative to the deserialised value) and message of a deserialisation error.
fn located(e: &serde_path_to_error::Error<toml::de::Error>) -> (String, String) {
    // toml appends "in `key`" lines that repeat the path named in front
    let mut inner = e
        .inner()
        .to_string()
        .lines()
        .filter(|l| {
            let repeats_path = l.starts_with("in `") && l.ends_with('`');
            !(l.trim().is_empty() || repeats_path)
        })
        .collect::<Vec<_>>()
        .join("\n");
    let mut path = join("", &e.path().to_string());
    // A type that buffers its table (e.g. a tagged field `{ type = "gaussian", … }`) names
    // the key inside it as a leading "`width`: " (see `crate::cell::Field`): extend the path.
    while let Some((inner_key, rest)) = nested_key(&inner) {
        path = join(&path, &inner_key);
        inner = rest;
    }
    (path, inner)
}

/// The error for `inner` at `path` below `prefix`.
fn report(prefix: &str, path: String, inner: String) -> ScenarioError {
    let mut path = join(prefix, &path);
    // Name the unknown or missing field itself, whether or not the path already ends in it.
    if let Some(field) = unknown_field(&inner).or_else(|| missing_field(&inner)) {
        if !(path == field || path.ends_with(&format!(".{field}"))) {
            path = join(&path, &field);
        }
    }
    ScenarioError::key(path, inner)
}

/// A whole number written as a float where an integer is expected: in a message "invalid
/// type: floating point `v`, expected <an integer type>", `v` as written and as the integer,
/// when an `i64` and an `f64` both hold it exactly ([`deserialize_at`] reads it as that integer;
/// a message that still has one says how to write it).
fn integral_float(message: &str) -> Option<(&str, i64)> {
    const PREFIX: &str = "invalid type: floating point `";
    let rest = &message[message.find(PREFIX)? + PREFIX.len()..];
    let (number, after) = rest.split_once('`')?;
    let integer = ["usize", "u64", "u32", "u16", "u8", "i64", "i32"]
        .iter()
        .any(|t| after.starts_with(&format!(", expected {t}")));
    let v: f64 = number.parse().ok()?;
    (integer && v.fract() == 0.0 && v.abs() <= 9.007_199_254_740_992e15)
        .then_some((number, v as i64))
}

/// The value at a serde path such as `grid[1].values[0]` or `mu.seed` inside `value`.
fn value_at<'a>(value: &'a mut toml::Value, path: &str) -> Option<&'a mut toml::Value> {
    let mut at = value;
    for part in path.split('.').filter(|p| !p.is_empty()) {
        let (key, indices) = match part.find('[') {
            Some(i) => (&part[..i], &part[i..]),
            None => (part, ""),
        };
        if !key.is_empty() {
            at = at.as_table_mut()?.get_mut(key)?;
        }
        for index in indices.split(['[', ']']).filter(|s| !s.is_empty()) {
            at = at.as_array_mut()?.get_mut(index.parse::<usize>().ok()?)?;
        }
    }
    Some(at)
}

/// The key and the rest of a message of the form "`key`: rest" or "`key` = value: rest" (the
/// latter keeps "= value: rest"; `key` a dotted bare key).
fn nested_key(message: &str) -> Option<(String, String)> {
    let rest = message.strip_prefix('`')?;
    let (key, after) = rest.split_once('`')?;
    let rest = match (after.strip_prefix(": "), after.strip_prefix(" = ")) {
        (Some(r), _) => r,
        (None, Some(_)) => &after[1..],
        (None, None) => return None,
    };
    let bare = !key.is_empty()
        && key
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "_-.".contains(c));
    bare.then(|| (key.to_string(), rest.to_string()))
}

/// Longest message echoed back, in characters: a 50 MB garbage line must not become a 100 MB
/// error message.
pub const MAX_MESSAGE_CHARS: usize = 400;

/// Serde's and TOML's wording in a researcher's words, shortened for a terminal: Rust type names
/// become what they mean (`usize` → "a non-negative integer"), numbers with more than 17 digits
/// (serde prints `1e300` as 301 digits) are written in scientific notation, and the message is
/// cut at [`MAX_MESSAGE_CHARS`] characters (each line at most that long).
///
/// ```
/// use celltissue::scenario::error::researcher_words;
/// assert_eq!(
///     researcher_words("invalid type: floating point `1e300`, expected usize"),
///     "invalid type: floating point `1e300`, expected a non-negative integer"
/// );
/// let long = format!("invalid value: {}", "1".repeat(300));
/// let short = researcher_words(&long);
/// assert!(short.contains("e299") && short.len() < 50, "{short}");
/// assert!(researcher_words(&"x".repeat(10_000_000)).len() < 1000);
/// // a whole number written as a float, where an integer is expected
/// assert!(researcher_words("invalid type: floating point `100000.0`, expected usize")
///     .ends_with("(TOML reads `100000.0` as a float: write 100000)"));
/// ```
pub fn researcher_words(message: &str) -> String {
    // cut first (cheaply) so that nothing below works on megabytes
    let mut s = shorten_to(message, 4 * MAX_MESSAGE_CHARS);
    let hint = integral_float(&s)
        .map(|(written, n)| format!(" (TOML reads `{written}` as a float: write {n})"));
    for (rust, words) in [
        ("expected usize", "expected a non-negative integer"),
        ("expected u64", "expected a non-negative integer"),
        ("expected u32", "expected a non-negative integer"),
        ("expected i64", "expected an integer"),
        ("expected f64", "expected a number"),
        ("expected a boolean", "expected true or false"),
    ] {
        s = s.replace(rust, words);
    }
    s.push_str(hint.as_deref().unwrap_or(""));
    shorten(&long_numbers_scientific(&s))
}

/// Digit runs longer than 17 characters (optionally with a fractional part) as `d.ddde±x`.
fn long_numbers_scientific(s: &str) -> String {
    let mut out = String::with_capacity(s.len().min(4 * MAX_MESSAGE_CHARS));
    let mut rest = s;
    while let Some(start) = rest.find(|c: char| c.is_ascii_digit()) {
        out.push_str(&rest[..start]);
        let tail = &rest[start..];
        let end = tail
            .find(|c: char| !(c.is_ascii_digit() || c == '.'))
            .unwrap_or(tail.len());
        let run = &tail[..end];
        let digits = run.chars().filter(char::is_ascii_digit).count();
        match run.parse::<f64>() {
            Ok(v) if digits > 17 && v.is_finite() => out.push_str(&format!("{v:e}")),
            _ => out.push_str(run),
        }
        rest = &tail[end..];
        if out.len() > 8 * MAX_MESSAGE_CHARS {
            break;
        }
    }
    out.push_str(rest);
    out
}

/// At most [`MAX_MESSAGE_CHARS`] characters per line and 12 lines, marking what was cut.
pub(crate) fn shorten(s: &str) -> String {
    shorten_to(s, MAX_MESSAGE_CHARS)
}

fn shorten_to(s: &str, max: usize) -> String {
    let mut out = Vec::new();
    for (i, line) in s.lines().enumerate() {
        if i == 12 {
            out.push("… (message cut)".to_string());
            break;
        }
        let n = line.chars().count();
        if n > max {
            let head: String = line.chars().take(max).collect();
            out.push(format!("{head}… (cut)"));
        } else {
            out.push(line.to_string());
        }
    }
    out.join("\n")
}

/// `a.b` from a prefix and a serde path (`.` means the root).
pub(crate) fn join(prefix: &str, path: &str) -> String {
    let path = if path == "." { "" } else { path };
    match (prefix.is_empty(), path.is_empty()) {
        (true, _) => path.to_string(),
        (false, true) => prefix.to_string(),
        (false, false) => format!("{prefix}.{path}"),
    }
}

/// The field name in serde's "unknown field `x`, expected …" message.
fn unknown_field(message: &str) -> Option<String> {
    let rest = message.strip_prefix("unknown field `")?;
    Some(rest.split('`').next()?.to_string())
}

/// The field a "missing field `x`" message names.
fn missing_field(message: &str) -> Option<String> {
    let rest = message.strip_prefix("missing field `")?;
    Some(rest.split('`').next()?.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_set_error_names_the_key_of_its_argument() {
        let e = ScenarioError::set("model.K = 0.1", "conflicts with the sweep");
        assert_eq!(e.key_name(), Some("model.K"));
        assert_eq!(ScenarioError::set("model.K", "no `=`").key_name(), None);
    }

    #[test]
    fn join_handles_root_and_prefix() {
        assert_eq!(join("", "a.b"), "a.b");
        assert_eq!(join("model", "."), "model");
        assert_eq!(join("model", "mu.base"), "model.mu.base");
    }

    #[test]
    fn unknown_field_names_the_field() {
        assert_eq!(
            unknown_field("unknown field `kay`, expected one of `a`").as_deref(),
            Some("kay")
        );
        assert_eq!(unknown_field("invalid type"), None);
    }

    #[test]
    fn a_missing_table_is_named() {
        let v: toml::Value = toml::from_str("name = \"x\"").unwrap();
        #[derive(Debug, serde::Deserialize)]
        #[allow(dead_code)]
        struct Top {
            name: String,
            output: toml::Table,
        }
        let e = deserialize_at::<Top>("", v).unwrap_err();
        assert_eq!(e.key_name(), Some("output"));
        assert!(e.to_string().contains("missing field `output`"), "{e}");
    }
}
