//! [`ScenarioError`]: everything that can be wrong with a scenario file or its overrides. Every
//! variant names the offending key (dotted path from the file's root, e.g. `model.k1`) and, for
//! bad values, the valid range. The CLI maps all of them to exit code 2.

use std::path::PathBuf;
use thiserror::Error;

/// A scenario that cannot be run as written.
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
    pub fn key(key: impl Into<String>, message: impl Into<String>) -> Self {
        ScenarioError::Key {
            key: key.into(),
            message: message.into(),
        }
    }

    /// The offending key, if the error names one.
    pub fn key_name(&self) -> Option<&str> {
        match self {
            ScenarioError::Key { key, .. } => Some(key),
            _ => None,
        }
    }

    /// Prefixes the message with the run it came from (used for sweep values).
    pub fn in_run(self, run: &str) -> Self {
        match self {
            ScenarioError::Key { key, message } => ScenarioError::Key {
                key,
                message: format!("{message} (in run `{run}`)"),
            },
            other => other,
        }
    }
}

/// Deserialises `value` into `T`, reporting unknown keys and type errors with their full dotted
/// path below `prefix` (`""` for the root).
pub(crate) fn deserialize_at<T: serde::de::DeserializeOwned>(
    prefix: &str,
    value: toml::Value,
) -> Result<T, ScenarioError> {
    serde_path_to_error::deserialize(value).map_err(|e| {
        let inner = e.inner().to_string();
        let mut path = join(prefix, &e.path().to_string());
        // Name the unknown field itself, whether or not the path already ends in it.
        if let Some(field) = unknown_field(&inner) {
            if !(path == field || path.ends_with(&format!(".{field}"))) {
                path = join(&path, &field);
            }
        }
        ScenarioError::key(path, inner)
    })
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
