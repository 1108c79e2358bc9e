//! `run`, `validate` and `list`.

use super::{catalogue, merge, BAD_INPUT, OK, RUN_FAILED};
use celltissue::observe::Summary;
use celltissue::output::{self, finite};
use celltissue::scenario::parallel::{run_parallel, Shard};
use celltissue::scenario::{self, execute};
use std::path::Path;

/// How `run` schedules the scenario's runs.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// No progress lines.
    pub quiet: bool,
    /// Runs at once (≥ 1).
    pub jobs: usize,
    /// `--shard` as given (`i/n` or `auto`).
    pub shard: Option<String>,
}

/// Loads and validates, or prints the error (exit code 2).
fn load(path: &Path, sets: &[String]) -> Result<scenario::Scenario, i32> {
    scenario::load(path, sets).map_err(|e| {
        eprintln!("error: {e}");
        BAD_INPUT
    })
}

/// `celltissue run`.
pub fn run(path: &Path, out: &Path, sets: &[String], opts: RunOptions) -> i32 {
    let quiet = opts.quiet;
    let scenario = match load(path, sets) {
        Ok(s) => s,
        Err(code) => return code,
    };
    let shard = match opts.shard.as_deref().map(|s| match s {
        "auto" => Shard::from_slurm(|k| std::env::var(k).ok()),
        s => s.parse(),
    }) {
        None => None,
        Some(Ok(s)) => Some(s),
        Some(Err(e)) => {
            eprintln!("error: {e}");
            return BAD_INPUT;
        }
    };
    if let Some(sweep) = &scenario.sweep {
        let swept = sets
            .iter()
            .filter_map(|a| scenario::overrides::parse_set(a).ok());
        for (key, _) in swept.filter(|(k, _)| k.join(".") == sweep.key) {
            eprintln!(
                "warning: --set {} is replaced by each value of the sweep over `{}`; \
                 use --set sweep.values=[...] to change the swept values",
                key.join("."),
                sweep.key
            );
        }
    }
    let indices: Vec<usize> = match shard {
        Some(s) => s.indices(scenario.runs.len()),
        None => (0..scenario.runs.len()).collect(),
    };
    let total = indices.len();
    let mut k = 0;
    let runs = run_parallel(
        &scenario,
        &indices,
        opts.jobs,
        |spec| {
            let mut rec = execute::run_spec_in(spec, Some(out));
            finite::sanitize(&mut rec);
            rec
        },
        |rec| {
            k += 1;
            if !quiet {
                eprintln!(
                    "[{k}/{total}] {}: {} steps, {:.3} s{}",
                    rec.label,
                    rec.stats.steps,
                    rec.stats.wall_seconds,
                    rec.error
                        .as_ref()
                        .map(|e| format!(" — FAILED: {e}"))
                        .unwrap_or_default()
                );
            }
        },
    );
    let runs = match runs {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: {e}");
            return BAD_INPUT;
        }
    };
    if let Some(shard) = shard {
        return match merge::write_shard(out, &scenario, shard, &indices, &runs) {
            Ok(path) => {
                if !quiet {
                    eprintln!(
                        "wrote shard {}/{} ({} of {} runs) to {}",
                        shard.index,
                        shard.count,
                        runs.len(),
                        scenario.runs.len(),
                        path.display()
                    );
                }
                report_failures(&runs)
            }
            Err(e) => {
                eprintln!("error: {e}");
                RUN_FAILED
            }
        };
    }
    let summary = Summary {
        scenario: scenario.name.clone(),
        runs,
    };
    write_outputs(out, &scenario, &summary, quiet)
}

/// Writes every output of a finished scenario and reports what was written and what failed;
/// returns the exit code. Shared by `run` and `merge`.
pub fn write_outputs(
    out: &Path,
    scenario: &scenario::Scenario,
    summary: &Summary,
    quiet: bool,
) -> i32 {
    let written = match output::write_all(out, scenario, summary) {
        Ok(w) => w,
        Err(e) => {
            eprintln!("error: {e}");
            return RUN_FAILED;
        }
    };
    for e in &written.plot_errors {
        eprintln!("warning: plot not written: {e}");
    }
    if !quiet {
        eprintln!(
            "wrote {} data files and {} plots to {}",
            written.data.len(),
            written.plots.len(),
            out.display()
        );
    }
    let code = report_failures(&summary.runs);
    if code != OK {
        return code;
    }
    if !written.plot_errors.is_empty() {
        return RUN_FAILED;
    }
    OK
}

/// Prints the failed runs, if any; returns the exit code.
fn report_failures(runs: &[celltissue::observe::RunRecord]) -> i32 {
    let failed: Vec<&str> = runs
        .iter()
        .filter(|r| r.error.is_some())
        .map(|r| r.label.as_str())
        .collect();
    if failed.is_empty() {
        return OK;
    }
    eprintln!(
        "error: {} run(s) failed: {}",
        failed.len(),
        failed.join(", ")
    );
    RUN_FAILED
}

/// `celltissue validate`.
pub fn validate(path: &Path, sets: &[String]) -> i32 {
    match load(path, sets) {
        Ok(s) => {
            println!(
                "{}: ok — {} run(s): {}",
                s.name,
                s.runs.len(),
                s.runs
                    .iter()
                    .map(|r| r.label.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            );
            OK
        }
        Err(code) => code,
    }
}

/// `celltissue list`.
pub fn list() -> i32 {
    let files = catalogue::files();
    if files.is_empty() {
        eprintln!(
            "no scenarios found in {}",
            catalogue::dirs()
                .iter()
                .map(|d| d.display().to_string())
                .collect::<Vec<_>>()
                .join(" or ")
        );
        return RUN_FAILED;
    }
    let rows: Vec<(String, String, String)> = files
        .iter()
        .map(|p| {
            let (name, desc) = std::fs::read_to_string(p)
                .ok()
                .and_then(|t| toml::from_str::<toml::Table>(&t).ok())
                .map(|t| {
                    let get = |k: &str| t.get(k).and_then(|v| v.as_str()).unwrap_or("").to_string();
                    (get("name"), get("description"))
                })
                .unwrap_or_else(|| (String::new(), "(unreadable scenario file)".into()));
            let name = if name.is_empty() {
                p.file_stem()
                    .unwrap_or_default()
                    .to_string_lossy()
                    .into_owned()
            } else {
                name
            };
            (name, desc, p.display().to_string())
        })
        .collect();
    let w = rows.iter().map(|r| r.0.len()).max().unwrap_or(0);
    for (name, desc, path) in rows {
        println!("{name:<w$}  {desc}  [{path}]");
    }
    OK
}
