//! Shards of a sweep (`run --shard i/n`) and `celltissue merge`.
//!
//! A shard's output directory holds `shard.json` — the scenario as run (TOML text, after
//! `--set`), the shard's index and count, and the shard's run records with their indices in
//! scenario order — plus any snapshot files its runs wrote (sheet VTK/PNG, named by run).
//! `merge` checks that the shards come from the same scenario and cover every run exactly
//! once, copies the snapshot files, and writes the outputs from the records in scenario
//! order with the same writers as `run`, so the merged directory is what one `run` writes
//! (timing fields aside).

use super::{commands, BAD_INPUT, RUN_FAILED};
use crate::observe::{RunRecord, Summary};
use crate::output;
use crate::scenario::{self, parallel::Shard, Scenario};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// File name of a shard's records.
pub const SHARD_FILE: &str = "shard.json";
/// Value of `format` in `shard.json`.
const FORMAT: &str = "celltissue-shard/1";

/// One run of a shard.
#[derive(Serialize, Deserialize)]
struct ShardRun {
    /// Position of the run in the scenario (0-based).
    index: usize,
    /// What the run produced.
    record: RunRecord,
}

/// The contents of `shard.json`.
#[derive(Serialize, Deserialize)]
struct ShardFile {
    format: String,
    /// Scenario name.
    scenario: String,
    /// The scenario table as run, as TOML text.
    table: String,
    /// Number of runs of the whole scenario.
    total: usize,
    shard: usize,
    count: usize,
    runs: Vec<ShardRun>,
}

/// Why shards cannot be written or merged.
#[derive(Debug, thiserror::Error)]
pub enum MergeError {
    /// A file cannot be read or written.
    #[error("`{path}`: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// A shard file is malformed.
    #[error("`{path}` is not a celltissue shard file: {message}")]
    Format { path: PathBuf, message: String },
    /// The shards do not fit together.
    #[error("{0}")]
    Mismatch(String),
    /// The scenario stored in a shard no longer validates.
    #[error("the scenario in `{path}`: {source}")]
    Scenario {
        path: PathBuf,
        source: scenario::ScenarioError,
    },
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> MergeError + '_ {
    move |source| MergeError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Writes `out/shard.json` (via a temporary file and a rename, so a shard file is either
/// complete or absent); returns its path.
pub fn write_shard(
    out: &Path,
    scenario: &Scenario,
    shard: Shard,
    indices: &[usize],
    records: &[RunRecord],
) -> Result<PathBuf, MergeError> {
    std::fs::create_dir_all(out).map_err(io(out))?;
    let file = ShardFile {
        format: FORMAT.into(),
        scenario: scenario.name.clone(),
        table: toml::to_string(&scenario.table)
            .map_err(|e| MergeError::Mismatch(format!("cannot serialise the scenario: {e}")))?,
        total: scenario.runs.len(),
        shard: shard.index,
        count: shard.count,
        runs: indices
            .iter()
            .zip(records)
            .map(|(&index, record)| ShardRun {
                index,
                record: record.clone(),
            })
            .collect(),
    };
    let path = out.join(SHARD_FILE);
    let tmp = out.join(format!(".{SHARD_FILE}.tmp"));
    let text = serde_json::to_string(&file)
        .map_err(|e| MergeError::Mismatch(format!("cannot serialise the records: {e}")))?;
    std::fs::write(&tmp, text).map_err(io(&tmp))?;
    std::fs::rename(&tmp, &path).map_err(io(&path))?;
    Ok(path)
}

/// Reads the shards and puts their records back in scenario order.
fn collect(dirs: &[PathBuf]) -> Result<(Scenario, Summary), MergeError> {
    let mut first: Option<(PathBuf, ShardFile)> = None;
    let mut slots: Vec<Option<(RunRecord, PathBuf)>> = Vec::new();
    let mut seen_shards: Vec<usize> = Vec::new();
    for dir in dirs {
        let path = dir.join(SHARD_FILE);
        if !path.is_file() {
            return Err(MergeError::Mismatch(format!(
                "`{}` is not the output of `celltissue run --shard I/N` (it has no {SHARD_FILE})",
                dir.display()
            )));
        }
        let text = std::fs::read_to_string(&path).map_err(io(&path))?;
        let mut file: ShardFile = serde_json::from_str(&text).map_err(|e| MergeError::Format {
            path: path.clone(),
            message: e.to_string(),
        })?;
        if file.format != FORMAT {
            return Err(MergeError::Format {
                path,
                message: format!("format `{}`, expected `{FORMAT}`", file.format),
            });
        }
        let runs = std::mem::take(&mut file.runs);
        let shard = file.shard;
        match &first {
            None => {
                slots = (0..file.total).map(|_| None).collect();
                first = Some((path.clone(), file));
            }
            Some((p0, f0)) => {
                if f0.table != file.table || f0.total != file.total || f0.count != file.count {
                    return Err(MergeError::Mismatch(format!(
                        "`{}` and `{}` are shards of different runs (scenario, --set \
                         overrides or shard count differ)",
                        p0.display(),
                        path.display()
                    )));
                }
                if seen_shards.contains(&file.shard) {
                    return Err(MergeError::Mismatch(format!(
                        "shard {}/{} is given twice (again in `{}`)",
                        file.shard,
                        file.count,
                        dir.display()
                    )));
                }
            }
        }
        seen_shards.push(shard);
        for run in runs {
            let slot = slots.get_mut(run.index).ok_or_else(|| MergeError::Format {
                path: path.clone(),
                message: format!("run index {} out of range", run.index),
            })?;
            if let Some((_, other)) = slot {
                return Err(MergeError::Mismatch(format!(
                    "run {} (`{}`) is in both `{}` and `{}`",
                    run.index,
                    run.record.label,
                    other.display(),
                    dir.display()
                )));
            }
            *slot = Some((run.record, dir.clone()));
        }
    }
    let (path, file) = first.ok_or_else(|| MergeError::Mismatch("no shards given".into()))?;
    let table: toml::Table = toml::from_str(&file.table).map_err(|e| MergeError::Format {
        path: path.clone(),
        message: format!("scenario: {e}"),
    })?;
    let scenario =
        scenario::resolve(table).map_err(|source| MergeError::Scenario { path, source })?;
    let missing: Vec<&str> = slots
        .iter()
        .zip(&scenario.runs)
        .filter(|(s, _)| s.is_none())
        .map(|(_, spec)| spec.label.as_str())
        .collect();
    if !missing.is_empty() || scenario.runs.len() != slots.len() {
        let mut absent: Vec<usize> = (0..file.count).collect();
        absent.retain(|k| !seen_shards.contains(k));
        return Err(MergeError::Mismatch(format!(
            "incomplete: {} of {} runs missing ({}); shards not given: {}",
            missing.len(),
            slots.len(),
            missing.join(", "),
            absent
                .iter()
                .map(|k| format!("{k}/{}", file.count))
                .collect::<Vec<_>>()
                .join(", ")
        )));
    }
    let runs = slots.into_iter().flatten().map(|(r, _)| r).collect();
    Ok((
        scenario,
        Summary {
            scenario: file.scenario,
            runs,
        },
    ))
}

/// Copies every file of `from` except `shard.json` into `to` (the snapshots runs wrote).
fn copy_snapshots(from: &Path, to: &Path) -> Result<(), MergeError> {
    for entry in std::fs::read_dir(from).map_err(io(from))? {
        let entry = entry.map_err(io(from))?;
        let path = entry.path();
        let name = entry.file_name();
        if !path.is_file() || name == SHARD_FILE || name.to_string_lossy().starts_with('.') {
            continue;
        }
        let target = to.join(&name);
        std::fs::copy(&path, &target).map_err(io(&target))?;
    }
    Ok(())
}

/// `celltissue merge DIR… --out OUT`: exit code 0, 1 (a run failed or a file could not be
/// written) or 2 (the shards do not fit together; nothing is written).
pub fn merge(dirs: &[PathBuf], out: &Path, quiet: bool) -> i32 {
    let (scenario, summary) = match collect(dirs) {
        Ok(x) => x,
        Err(e) => {
            eprintln!("error: {e}");
            return BAD_INPUT;
        }
    };
    // the output directory is claimed in its manifest, as `run` does
    let prepared = match output::manifest::prepare(out, &summary.scenario, false) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {e}");
            return BAD_INPUT;
        }
    };
    if let Err(e) = std::fs::create_dir_all(out)
        .map_err(io(out))
        .and_then(|()| dirs.iter().try_for_each(|d| copy_snapshots(d, out)))
    {
        eprintln!("error: {e}");
        return RUN_FAILED;
    }
    let opts = commands::RunOptions {
        quiet,
        ..Default::default()
    };
    let code = commands::write_outputs(out, &scenario, &summary, &opts, &[]);
    if let Err(e) = output::manifest::finish(out, &summary.scenario, &prepared) {
        eprintln!("warning: {e}");
    }
    code
}
