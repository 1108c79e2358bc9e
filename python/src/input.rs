//! From Python arguments to a validated [`Scenario`]: a bundled name, a path or a dict, and
//! `set` overrides as a string, a list of strings or a dict.

use crate::errors::{from_scenario, scenario_error};
use celltissue::scenario::{self, Scenario};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString, PyTuple};
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

/// A Python value (dict, list, number, string, bool) as TOML, via its JSON form.
fn to_toml(py: Python<'_>, value: &Bound<'_, PyAny>, what: &str) -> PyResult<toml::Value> {
    let json: String = py
        .import("json")?
        .call_method1("dumps", (value,))
        .map_err(|e| scenario_error(py, None, format!("{what}: not JSON-like data: {e}")))?
        .extract()?;
    let v: serde_json::Value = serde_json::from_str(&json)
        .map_err(|e| scenario_error(py, None, format!("{what}: {e}")))?;
    toml::Value::try_from(v).map_err(|e| {
        scenario_error(
            py,
            None,
            format!("{what}: cannot be written as TOML ({e}; None is not allowed)"),
        )
    })
}

/// `set` as `key=value` strings.
fn overrides(py: Python<'_>, set: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<String>> {
    let Some(set) = set else {
        return Ok(Vec::new());
    };
    if let Ok(s) = set.cast::<PyString>() {
        return Ok(vec![s.to_cow()?.into_owned()]);
    }
    if let Ok(d) = set.cast::<PyDict>() {
        let mut out = Vec::new();
        for (k, v) in d.iter() {
            let key: String = k.extract().map_err(|_| {
                scenario_error(py, None, "set: dict keys must be dotted key strings".into())
            })?;
            let value = to_toml(py, &v, &format!("set[{key:?}]"))?;
            out.push(format!("{key}={value}"));
        }
        return Ok(out);
    }
    if set.cast::<PyList>().is_ok() || set.cast::<PyTuple>().is_ok() {
        return set.extract::<Vec<String>>().map_err(|_| {
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

/// Loads and validates `scenario` with the overrides `set`.
pub fn scenario(
    py: Python<'_>,
    scenario: &Bound<'_, PyAny>,
    set: Option<&Bound<'_, PyAny>>,
) -> PyResult<Scenario> {
    let sets = overrides(py, set)?;
    let lib = |r: Result<Scenario, scenario::ScenarioError>| r.map_err(|e| from_scenario(py, &e));
    if let Ok(d) = scenario.cast::<PyDict>() {
        let table = to_toml(py, d.as_any(), "scenario")?;
        let text = toml::to_string(&table)
            .map_err(|e| scenario_error(py, None, format!("scenario: {e}")))?;
        return lib(scenario::load_str(&text, Path::new("<dict>"), &sets));
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
        return lib(scenario::load(&path, &sets));
    }
    let name = path.to_string_lossy();
    let text = bundled(&name)?;
    lib(scenario::load_str(
        text,
        Path::new(&format!("{name}.toml")),
        &sets,
    ))
}
