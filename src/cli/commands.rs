//! `run`, `validate` and `list`.

use super::{catalogue, BAD_INPUT, OK, RUN_FAILED};
use celltissue::observe::{RunRecord, Summary};
use celltissue::output::{self, finite, interrupt};
use celltissue::scenario::{self, execute};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal as _;
use std::path::Path;
use std::sync::atomic::Ordering;
use std::time::Duration;

/// Switches of `celltissue run`.
#[derive(Clone, Copy, Debug, Default)]
pub struct RunFlags {
    /// No progress output.
    pub quiet: bool,
    /// Replace another scenario's outputs in `--out`.
    pub replace: bool,
    /// No PNG plots.
    pub no_plots: bool,
}

/// A progress bar on stderr, or a hidden one when quiet or not on a terminal.
fn bar(len: u64, quiet: bool, template: &str) -> ProgressBar {
    let pb = ProgressBar::new(len);
    if quiet || !std::io::stderr().is_terminal() {
        pb.set_draw_target(ProgressDrawTarget::hidden());
    } else if let Ok(style) = ProgressStyle::with_template(template) {
        pb.set_style(style);
    }
    pb
}

/// Loads and validates, or prints the error (exit code 2).
fn load(path: &Path, sets: &[String]) -> Result<scenario::Scenario, i32> {
    scenario::load(path, sets).map_err(|e| {
        eprintln!("error: {e}");
        BAD_INPUT
    })
}

/// `celltissue run`.
pub fn run(path: &Path, out: &Path, sets: &[String], flags: RunFlags) -> i32 {
    let quiet = flags.quiet;
    let scenario = match load(path, sets) {
        Ok(s) => s,
        Err(code) => return code,
    };
    // the directory is checked (and claimed in its manifest) before anything runs
    let prepared = match output::manifest::prepare(out, &scenario.name, flags.replace) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {e}");
            return BAD_INPUT;
        }
    };
    let stop = interrupt::install();
    let total = scenario.runs.len();
    let terminal = std::io::stderr().is_terminal();
    let pb = bar(
        total as u64,
        quiet,
        "{spinner} [{elapsed_precise}] {bar:30} {pos}/{len} runs  {msg}",
    );
    let mut runs: Vec<RunRecord> = Vec::new();
    let mut interrupted: Vec<String> = Vec::new();
    for (k, spec) in scenario.runs.iter().enumerate() {
        if stop.load(Ordering::SeqCst) {
            interrupted.extend(scenario.runs[k..].iter().map(|s| s.label.clone()));
            break;
        }
        pb.set_message(spec.label.clone());
        log::info!("run {}/{total}: {}", k + 1, spec.label);
        // the run goes on a worker thread so that an interrupt need not wait for it
        let (spec_owned, dir) = (spec.clone(), out.to_path_buf());
        let worker = std::thread::Builder::new()
            .name(format!("run {}", k + 1))
            .stack_size(64 << 20)
            .spawn(move || {
                let mut rec = execute::run_spec_in(&spec_owned, Some(&dir));
                finite::sanitize(&mut rec);
                rec
            });
        let handle = match worker {
            Ok(h) => h,
            Err(e) => {
                eprintln!("error: cannot start a run: {e}");
                return RUN_FAILED;
            }
        };
        while !handle.is_finished() && !stop.load(Ordering::SeqCst) {
            pb.tick();
            std::thread::sleep(Duration::from_millis(20));
        }
        if !handle.is_finished() {
            interrupted.extend(scenario.runs[k..].iter().map(|s| s.label.clone()));
            break;
        }
        let rec = match handle.join() {
            Ok(r) => r,
            Err(_) => {
                eprintln!("error: run `{}` panicked", spec.label);
                return RUN_FAILED;
            }
        };
        let line = format!(
            "[{}/{total}] {}: {} steps, {:.3} s{}",
            k + 1,
            rec.label,
            rec.stats.steps,
            rec.stats.wall_seconds,
            rec.error
                .as_ref()
                .map(|e| format!(" — FAILED: {e}"))
                .unwrap_or_default()
        );
        if !quiet {
            if terminal {
                pb.println(line);
            } else {
                eprintln!("{line}");
            }
        }
        pb.inc(1);
        runs.push(rec);
    }
    pb.finish_and_clear();
    let summary = Summary {
        scenario: scenario.name.clone(),
        runs,
    };
    let threads = scenario
        .runs
        .iter()
        .map(|r| r.solver.threads)
        .max()
        .unwrap_or(1);
    let wpb = bar(
        output::WRITE_STAGES,
        quiet,
        "{spinner} writing [{elapsed_precise}] {bar:30} {pos}/{len}  {msg}",
    );
    let opts = output::WriteOptions {
        no_plots: flags.no_plots,
        provenance: Some(output::provenance::Provenance::collect(
            &scenario.table,
            threads,
        )),
        interrupted: interrupted.clone(),
        progress: Some(wpb.clone()),
    };
    let written = output::write_all_with(out, &scenario, &summary, &opts);
    wpb.finish_and_clear();
    if let Err(e) = output::manifest::finish(out, &scenario.name, &prepared) {
        eprintln!("warning: {e}");
    }
    let written = match written {
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
    if !interrupted.is_empty() {
        eprintln!(
            "interrupted: {} run(s) not finished (listed in summary.json): {}",
            interrupted.len(),
            interrupted.join(", ")
        );
        return interrupt::INTERRUPTED;
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
