//! `--set dotted.key=value` overrides, applied to the raw TOML table *before* it is deserialised,
//! so an override is checked exactly like the same key written in the file (unknown key, wrong
//! type and range errors all name it). Sweeps use the same mechanism for each swept value.
//!
//! ```
//! use celltissue::scenario::overrides::{apply, parse_set};
//! let mut t: toml::Table = toml::from_str("[model]\nK = 1.0").unwrap();
//! let (path, value) = parse_set("model.K=0.1").unwrap();
//! apply(&mut t, &path, value).unwrap();
//! assert_eq!(t["model"]["K"].as_float(), Some(0.1));
//! // bare words become strings
//! let (path, value) = parse_set("solver.method=radau").unwrap();
//! apply(&mut t, &path, value).unwrap();
//! assert_eq!(t["solver"]["method"].as_str(), Some("radau"));
//! ```

use super::error::ScenarioError;
use toml::{Table, Value};

/// Most parts of a dotted key (`--set`, `sweep.parameter`): deeper keys cannot name anything
/// in a scenario, and a 10 000-part key would otherwise build a 10 000-deep table.
pub const MAX_KEY_PARTS: usize = 16;

/// Longest dotted key, in bytes.
pub const MAX_KEY_CHARS: usize = 256;

/// Splits `dotted.key=value` into the key path and a TOML value. The value is parsed as TOML
/// (`0.1`, `10`, `true`, `[1, 2]`, `{ type = "gaussian", … }`, `"text"`); anything that does not
/// parse is taken as a plain string (so `solver.method=radau` works without quotes).
///
/// ```
/// use celltissue::scenario::overrides::parse_set;
/// let (path, value) = parse_set("model.mu.width=0.2")?;
/// assert_eq!((path, value), (vec!["model".into(), "mu".into(), "width".into()], toml::Value::Float(0.2)));
/// let (_, method) = parse_set("solver.method=radau")?;
/// assert_eq!(method.as_str(), Some("radau")); // a bare word is a string
/// assert!(parse_set("model.K").is_err()); // no `=`
/// # Ok::<(), celltissue::scenario::ScenarioError>(())
/// ```
pub fn parse_set(arg: &str) -> Result<(Vec<String>, Value), ScenarioError> {
    let bad = |message: &str| ScenarioError::set(arg, message);
    let (key, raw) = arg
        .split_once('=')
        .ok_or_else(|| bad("expected `dotted.key=value`"))?;
    if key.split('.').count() > MAX_KEY_PARTS || key.len() > MAX_KEY_CHARS {
        return Err(bad(&format!(
            "the key is too long: at most {MAX_KEY_PARTS} dotted parts and {MAX_KEY_CHARS} \
             characters (scenario keys are at most 4 deep, e.g. model.mu.width)"
        )));
    }
    let path = parse_path(key).ok_or_else(|| bad("the key must be dotted names, e.g. model.K"))?;
    Ok((path, parse_value(raw.trim())))
}

/// Splits a dotted key into its parts (`None` if any part is empty or not a bare TOML key).
///
/// ```
/// use celltissue::scenario::overrides::parse_path;
/// assert_eq!(parse_path("output.profiles.0"), Some(vec!["output".into(), "profiles".into(), "0".into()]));
/// assert_eq!(parse_path("model..K"), None);
/// ```
pub fn parse_path(key: &str) -> Option<Vec<String>> {
    if key.split('.').count() > MAX_KEY_PARTS || key.len() > MAX_KEY_CHARS {
        return None;
    }
    let parts: Vec<String> = key
        .trim()
        .split('.')
        .map(|s| s.trim().to_string())
        .collect();
    let bare = |s: &String| {
        !s.is_empty()
            && s.chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    };
    parts.iter().all(bare).then_some(parts)
}

/// A TOML value from text; unparsable text becomes a string.
///
/// ```
/// use celltissue::scenario::overrides::parse_value;
/// assert_eq!(parse_value("[1, 2]").as_array().map(|a| a.len()), Some(2));
/// assert_eq!(parse_value("{ type = \"gaussian\" }")["type"].as_str(), Some("gaussian"));
/// assert_eq!(parse_value("bdf").as_str(), Some("bdf"));
/// ```
pub fn parse_value(raw: &str) -> Value {
    let doc = format!("v = {raw}");
    match toml::from_str::<Table>(&doc) {
        Ok(mut t) => t
            .remove("v")
            .unwrap_or_else(|| Value::String(raw.to_string())),
        Err(_) => Value::String(raw.to_string()),
    }
}

/// Sets `path` in `table` to `value`, creating missing intermediate tables (a misspelt name then
/// fails deserialisation as an unknown key, naming it). Numeric parts index into arrays.
/// Fails if the path runs through a value that is neither a table nor an array.
///
/// ```
/// use celltissue::scenario::overrides::{apply, parse_set};
/// let mut t: toml::Table = toml::from_str("[model]\nK = 1.0\n[output]\nprofiles = [1, 10]")?;
/// let (path, v) = parse_set("model.K=0.1")?;
/// apply(&mut t, &path, v)?;
/// let (path, v) = parse_set("output.profiles.1=5")?;
/// apply(&mut t, &path, v)?;
/// assert_eq!(t["model"]["K"].as_float(), Some(0.1));
/// assert_eq!(t["output"]["profiles"][1].as_integer(), Some(5));
/// // through a number: an error naming the key
/// let (path, v) = parse_set("model.K.x=1")?;
/// assert!(apply(&mut t, &path, v).unwrap_err().to_string().contains("model.K.x"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn apply(table: &mut Table, path: &[String], value: Value) -> Result<(), ScenarioError> {
    let dotted = path.join(".");
    let (last, parents) = path
        .split_last()
        .ok_or_else(|| ScenarioError::key("", "empty key"))?;
    let mut node: &mut Table = table;
    let mut walked: Vec<&str> = Vec::new();
    for (i, part) in parents.iter().enumerate() {
        walked.push(part);
        let entry = node
            .entry(part.clone())
            .or_insert_with(|| Value::Table(Table::new()));
        match entry {
            Value::Table(t) => node = t,
            Value::Array(items) => {
                let rest = &path[i + 1..];
                return set_in_array(items, &walked.join("."), rest, value, &dotted);
            }
            other => {
                return Err(ScenarioError::key(
                    dotted,
                    format!(
                        "`{}` is a {}, not a table, so it has no key `{}`",
                        walked.join("."),
                        other.type_str(),
                        path[i + 1]
                    ),
                ))
            }
        }
    }
    node.insert(last.clone(), value);
    Ok(())
}

/// Removes the key at `path` (`--unset`), so that it takes its default: a key the scenario
/// does not have is an error naming it (a misspelt key must not pass silently).
///
/// ```
/// use celltissue::scenario::overrides::{parse_path, remove};
/// let mut t: toml::Table = toml::from_str("[solver]\nmethod = \"bdf\"\njacobian_age = 100").unwrap();
/// remove(&mut t, &parse_path("solver.jacobian_age").unwrap()).unwrap();
/// assert!(t["solver"].get("jacobian_age").is_none());
/// let e = remove(&mut t, &parse_path("solver.jacobian_ag").unwrap()).unwrap_err();
/// assert_eq!(e.key_name(), Some("solver.jacobian_ag"));
/// ```
pub fn remove(table: &mut Table, path: &[String]) -> Result<(), ScenarioError> {
    let dotted = path.join(".");
    let absent = || {
        ScenarioError::key(
            dotted.clone(),
            "cannot be unset: the scenario does not have this key",
        )
    };
    let (last, parents) = path.split_last().ok_or_else(absent)?;
    let mut node: &mut Table = table;
    for part in parents {
        node = match node.get_mut(part) {
            Some(Value::Table(t)) => t,
            _ => return Err(absent()),
        };
    }
    node.remove(last).map(|_| ()).ok_or_else(absent)
}

fn set_in_array(
    items: &mut [Value],
    at: &str,
    rest: &[String],
    value: Value,
    dotted: &str,
) -> Result<(), ScenarioError> {
    let idx: usize = rest[0].parse().map_err(|_| {
        ScenarioError::key(
            dotted,
            format!("`{at}` is an array; index it with a number"),
        )
    })?;
    let len = items.len();
    let item = items.get_mut(idx).ok_or_else(|| {
        ScenarioError::key(
            dotted,
            format!("index {idx} is out of range for `{at}` (length {len})"),
        )
    })?;
    if rest.len() == 1 {
        *item = value;
        return Ok(());
    }
    match item {
        Value::Table(t) => {
            apply(t, &rest[1..], value).map_err(|e| ScenarioError::key(dotted, strip_key(e)))
        }
        other => Err(ScenarioError::key(
            dotted,
            format!("`{at}.{idx}` is a {}, not a table", other.type_str()),
        )),
    }
}

fn strip_key(e: ScenarioError) -> String {
    match e {
        ScenarioError::Key { message, .. } => message,
        other => other.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(s: &str) -> Table {
        toml::from_str(s).unwrap()
    }

    #[test]
    fn values_parse_as_toml_or_string() {
        assert_eq!(parse_value("0.1").as_float(), Some(0.1));
        assert_eq!(parse_value("10").as_integer(), Some(10));
        assert_eq!(parse_value("true").as_bool(), Some(true));
        assert_eq!(parse_value("radau").as_str(), Some("radau"));
        assert_eq!(parse_value("\"bdf\"").as_str(), Some("bdf"));
        assert_eq!(parse_value("[1, 2]").as_array().map(|a| a.len()), Some(2));
        let v = parse_value("{ type = \"gaussian\", base = 1 }");
        assert_eq!(v["type"].as_str(), Some("gaussian"));
    }

    #[test]
    fn set_replaces_and_creates_keys() {
        let mut t = table("[model]\nK = 1.0\n[solver]\nrtol = 1e-6");
        let (p, v) = parse_set("model.K=0.1").unwrap();
        apply(&mut t, &p, v).unwrap();
        assert_eq!(t["model"]["K"].as_float(), Some(0.1));
        let (p, v) = parse_set("model.active.beta=-1").unwrap();
        apply(&mut t, &p, v).unwrap();
        assert_eq!(t["model"]["active"]["beta"].as_integer(), Some(-1));
        assert_eq!(t["solver"]["rtol"].as_float(), Some(1e-6));
    }

    #[test]
    fn set_indexes_arrays() {
        let mut t = table("[output]\nprofiles = [0.0, 1.0]");
        let (p, v) = parse_set("output.profiles.1=5").unwrap();
        apply(&mut t, &p, v).unwrap();
        assert_eq!(t["output"]["profiles"][1].as_integer(), Some(5));
        let (p, v) = parse_set("output.profiles.7=5").unwrap();
        let e = apply(&mut t, &p, v).unwrap_err().to_string();
        assert!(
            e.contains("output.profiles.7") && e.contains("out of range"),
            "{e}"
        );
    }

    #[test]
    fn set_through_a_scalar_names_the_key() {
        let mut t = table("[model]\nK = 1.0");
        let (p, v) = parse_set("model.K.x=1").unwrap();
        let e = apply(&mut t, &p, v).unwrap_err();
        assert_eq!(e.key_name(), Some("model.K.x"));
        assert!(e.to_string().contains("not a table"));
    }

    #[test]
    fn malformed_set_arguments_are_rejected() {
        assert!(parse_set("model.K").is_err());
        assert!(parse_set("model..K=1").is_err());
        assert!(parse_set("=1").is_err());
        assert!(parse_set("model.K =2").is_ok());
    }
}
