//! `run`, `validate` and `list`.

use super::{catalogue, BAD_INPUT, OK, RUN_FAILED};
use celltissue::output::{self, finite};
use celltissue::scenario::{self, execute};
use std::path::Path;

/// Loads and validates, or prints the error (exit code 2).
fn load(path: &Path, sets: &[String]) -> Result<scenario::Scenario, i32> {
    scenario::load(path, sets).map_err(|e| {
        eprintln!("error: {e}");
        BAD_INPUT
    })
}

/// `celltissue run`.
pub fn run(path: &Path, out: &Path, sets: &[String], quiet: bool) -> i32 {
    let scenario = match load(path, sets) {
        Ok(s) => s,
        Err(code) => return code,
    };
    let total = scenario.runs.len();
    let mut k = 0;
    let summary = execute::run_all(
        &scenario,
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
    let written = match output::write_all(out, &scenario, &summary) {
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
    let failed: Vec<&str> = summary
        .runs
        .iter()
        .filter(|r| r.error.is_some())
        .map(|r| r.label.as_str())
        .collect();
    if !failed.is_empty() {
        eprintln!(
            "error: {} run(s) failed: {}",
            failed.len(),
            failed.join(", ")
        );
        return RUN_FAILED;
    }
    if !written.plot_errors.is_empty() {
        return RUN_FAILED;
    }
    OK
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
