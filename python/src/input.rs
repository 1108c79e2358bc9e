//! From Python arguments to a validated [`Scenario`]: a bundled name, a path or a dict, and
//! `set` overrides as a string, a list of strings or a dict.

use crate::errors::{from_scenario, scenario_error};
use celltissue::scenario::{self, Scenario};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use std::path::{Path, PathBuf};

/// The text of a bundled scenario, or a `ScenarioError` listing the names.
pub fn bundled(name: &str) -> PyResult<&'static str> {
    scenario::bundled::text(name).ok_or_else(|| {
        Python::attach(|py| {
            scenario_error(
                py,
                None,
                format!(
                    "`{name}` is neither a scenario file nor a bundled scenario ({})",
                    scenario::bundled::names()
                ),
            )
        })
    })
}

/// Nesting deeper than this is refused (a scenario is at most four tables deep; a dict that
/// holds itself would otherwise recurse without end).
const MAX_DEPTH: usize = 32;

/// A Python value (dict, list, tuple, bool, int, float, str, or a NumPy array or scalar) as
/// TOML, converted directly: NaN and ±inf stay numbers, so the scenario's validation names
/// their key and its range (through JSON they failed as "expected value at column 74").
fn to_toml(py: Python<'_>, value: &Bound<'_, PyAny>, what: &str) -> PyResult<toml::Value> {
    to_toml_at(py, value, what, 0)
}

fn to_toml_at(
    py: Python<'_>,
    value: &Bound<'_, PyAny>,
    what: &str,
    depth: usize,
) -> PyResult<toml::Value> {
    let bad = |message: String| scenario_error(py, None, format!("{what}: {message}"));
    if depth > MAX_DEPTH {
        return Err(bad(format!("nested more than {MAX_DEPTH} levels deep")));
    }
    if value.is_none() {
        return Err(bad("None is not allowed (leave the key out instead)".into()));
    }
    if let Ok(b) = value.cast::<PyBool>() {
        return Ok(toml::Value::Boolean(b.is_true()));
    }
    if let Ok(s) = value.cast::<PyString>() {
        return Ok(toml::Value::String(s.to_cow()?.into_owned()));
    }
    if let Ok(d) = value.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (k, v) in d.iter() {
            let key: String = k
                .extract()
                .map_err(|_| bad("dict keys must be strings".into()))?;
            let inner = to_toml_at(py, &v, &format!("{what}.{key}"), depth + 1)?;
            table.insert(key, inner);
        }
        return Ok(toml::Value::Table(table));
    }
    if value.cast::<PyList>().is_ok() || value.cast::<PyTuple>().is_ok() {
        let items = value
            .try_iter()?
            .enumerate()
            .map(|(i, v)| to_toml_at(py, &v?, &format!("{what}[{i}]"), depth + 1))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(toml::Value::Array(items));
    }
    if let Ok(i) = value.cast::<PyInt>() {
        return i
            .extract::<i64>()
            .map(toml::Value::Integer)
            .map_err(|_| bad(format!("the integer {i} does not fit in 64 bits")));
    }
    if let Ok(f) = value.cast::<PyFloat>() {
        return Ok(toml::Value::Float(f.value()));
    }
    // NumPy arrays and scalars (and anything else with `tolist`): their Python form
    if value.hasattr("tolist")? {
        let plain = value.call_method0("tolist")?;
        if !plain.is(value) {
            return to_toml_at(py, &plain, what, depth + 1);
        }
    }
    Err(bad(format!(
        "a {} cannot be written as TOML (expected a dict, list, number, string or bool)",
        value.get_type().name()?
    )))
}

/// The `key=value` overrides and the keys to remove.
type Overrides = (Vec<String>, Vec<String>);

/// `set` as `key=value` strings, and the keys a dict maps to `None` (removed, as `--unset`).
fn overrides(py: Python<'_>, set: Option<&Bound<'_, PyAny>>) -> PyResult<Overrides> {
    let Some(set) = set else {
        return Ok((Vec::new(), Vec::new()));
    };
    if let Ok(s) = set.cast::<PyString>() {
        return Ok((vec![s.to_cow()?.into_owned()], Vec::new()));
    }
    if let Ok(d) = set.cast::<PyDict>() {
        let (mut out, mut unset) = (Vec::new(), Vec::new());
        for (k, v) in d.iter() {
            let key: String = k.extract().map_err(|_| {
                scenario_error(py, None, "set: dict keys must be dotted key strings".into())
            })?;
            if v.is_none() {
                unset.push(key);
                continue;
            }
            let value = to_toml(py, &v, &format!("set[{key:?}]"))?;
            out.push(format!("{key}={value}"));
        }
        return Ok((out, unset));
    }
    if set.cast::<PyList>().is_ok() || set.cast::<PyTuple>().is_ok() {
        return set
            .extract::<Vec<String>>()
            .map(|v| (v, Vec::new()))
            .map_err(|_| {
                scenario_error(
                    py,
                    None,
                    "set: a list must hold \"key=value\" strings".into(),
                )
            });
    }
    Err(scenario_error(
        py,
        None,
        "set: expected a \"key=value\" string, a list of them or a dict {key: value}".into(),
    ))
}

/// Loads and validates `scenario` with the overrides `set` (a dict's `None` values remove
/// their keys, so that they take their defaults).
pub fn scenario(
    py: Python<'_>,
    scenario: &Bound<'_, PyAny>,
    set: Option<&Bound<'_, PyAny>>,
) -> PyResult<Scenario> {
    let (sets, unsets) = overrides(py, set)?;
    let lib = |r: Result<Scenario, scenario::ScenarioError>| r.map_err(|e| from_scenario(py, &e));
    if let Ok(d) = scenario.cast::<PyDict>() {
        let table = to_toml(py, d.as_any(), "scenario")?;
        let text = toml::to_string(&table)
            .map_err(|e| scenario_error(py, None, format!("scenario: {e}")))?;
        return lib(scenario::load_str_with(
            &text,
            Path::new("<dict>"),
            &sets,
            &unsets,
        ));
    }
    let path: PathBuf = if let Ok(s) = scenario.cast::<PyString>() {
        PathBuf::from(s.to_cow()?.into_owned())
    } else if let Ok(p) = scenario.extract::<PathBuf>() {
        p
    } else {
        return Err(scenario_error(
            py,
            None,
            format!(
                "scenario: expected a bundled name, a path or a dict, got {}",
                scenario.get_type().name()?
            ),
        ));
    };
    if path.exists() || path.extension().is_some() {
        return lib(scenario::load_with(&path, &sets, &unsets));
    }
    let name = path.to_string_lossy();
    let text = bundled(&name)?;
    lib(scenario::load_str_with(
        text,
        Path::new(&format!("{name}.toml")),
        &sets,
        &unsets,
    ))
}
