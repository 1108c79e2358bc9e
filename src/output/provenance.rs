//! Provenance recorded in every `summary.json`: what produced the numbers (crate version, git
//! commit and compiler, stamped at build time by `build.rs`), when and where (UTC date, host),
//! how (command line, threads) and with which random seeds.

use serde::Serialize;
use std::collections::BTreeMap;

/// The `"provenance"` object of `summary.json`. Absent facts (no git checkout at build time, no
/// readable host name) are left out, not `null`.
///
/// ```
/// use celltissue::output::provenance::Provenance;
/// let table: toml::Table = toml::from_str("[division]\nrule = \"random_area\"\nseed = 42").unwrap();
/// let p = Provenance::collect(&table, 2);
/// assert_eq!(p.version, env!("CARGO_PKG_VERSION"));
/// assert_eq!(p.seeds["division.seed"].as_integer(), Some(42));
/// let json = serde_json::to_value(&p).unwrap();
/// assert!(json.get("threads").is_some() && json.get("command_line").is_some());
/// ```
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Provenance {
    /// `celltissue` crate version.
    pub version: String,
    /// Git commit of the source tree at build time (`-modified` if it had uncommitted changes).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub git_commit: Option<String>,
    /// `rustc --version` of the compiler that built the binary.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rustc: Option<String>,
    /// Start of the write phase, UTC, RFC 3339.
    pub date: String,
    /// Host name.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub host: Option<String>,
    /// Command line (program and arguments).
    pub command_line: Vec<String>,
    /// Threads a run may use, from the scenario's `solver.threads` (largest over its runs).
    pub threads: usize,
    /// Hardware threads available to the process.
    pub available_parallelism: usize,
    /// Every key named `seed` (or ending in `_seed`) in the scenario as run, by dotted path.
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub seeds: BTreeMap<String, toml::Value>,
}

impl Provenance {
    /// Provenance of this process for a scenario (its table and solver threads).
    ///
    /// ```
    /// let table: toml::Table = toml::from_str("[model]\nmu = { kind = \"random\", seed = 7 }").unwrap();
    /// let p = celltissue::output::provenance::Provenance::collect(&table, 2);
    /// assert_eq!(p.version, env!("CARGO_PKG_VERSION"));
    /// assert_eq!(p.seeds["model.mu.seed"].as_integer(), Some(7));
    /// assert_eq!(p.threads, 2);
    /// ```
    pub fn collect(table: &toml::Table, threads: usize) -> Self {
        let mut seeds = BTreeMap::new();
        find_seeds(table, "", &mut seeds);
        Provenance {
            version: env!("CARGO_PKG_VERSION").into(),
            git_commit: option_env!("CELLTISSUE_GIT_COMMIT").map(Into::into),
            rustc: option_env!("CELLTISSUE_RUSTC_VERSION").map(Into::into),
            date: humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string(),
            host: host_name(),
            command_line: std::env::args().collect(),
            threads,
            available_parallelism: std::thread::available_parallelism().map_or(1, |n| n.get()),
            seeds,
        }
    }
}

/// The host name (Linux `/proc`, else `$HOSTNAME`).
fn host_name() -> Option<String> {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .ok()
        .or_else(|| std::env::var("HOSTNAME").ok())
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
}

fn find_seeds(table: &toml::Table, prefix: &str, out: &mut BTreeMap<String, toml::Value>) {
    for (k, v) in table {
        let path = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        match v {
            toml::Value::Table(t) => find_seeds(t, &path, out),
            toml::Value::Array(a) => {
                for (i, item) in a.iter().enumerate() {
                    if let toml::Value::Table(t) = item {
                        find_seeds(t, &format!("{path}.{i}"), out);
                    }
                }
            }
            _ if k == "seed" || k.ends_with("_seed") => {
                out.insert(path, v.clone());
            }
            _ => {}
        }
    }
}
