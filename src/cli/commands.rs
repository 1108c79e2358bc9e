//! `run`, `validate` and `list`: `run` loads and validates a scenario, claims its output
//! directory (manifest), runs the chosen share of its runs (`--jobs`, `--shard`) on a worker
//! thread so that SIGINT/SIGTERM keep the finished runs, then hands the records to the writers.

use super::catalogue::{self, Source};
use super::{merge, BAD_INPUT, OK, RUN_FAILED};
use crate::observe::{RunRecord, Summary};
use crate::output::{self, finite, interrupt};
use crate::scenario::parallel::{run_parallel, Shard};
use crate::scenario::{self, accuracy_check, execute};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use integrators::interrupt::Interrupt;
use std::io::IsTerminal as _;
use std::path::Path;
use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Switches of `celltissue run`.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// No progress output.
    pub quiet: bool,
    /// Replace another scenario's outputs in `--out`.
    pub replace: bool,
    /// No PNG plots.
    pub no_plots: bool,
    /// Runs at once (≥ 1).
    pub jobs: usize,
    /// `--shard` as given (`i/n` or `auto`).
    pub shard: Option<String>,
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
fn load(source: &Source, sets: &[String], unsets: &[String]) -> Result<scenario::Scenario, i32> {
    let loaded = match source {
        Source::File(path) if !path.exists() && path.extension().is_none() => {
            eprintln!(
                "error: `{}` is neither a scenario file nor a bundled scenario ({})",
                path.display(),
                scenario::bundled::names()
            );
            return Err(BAD_INPUT);
        }
        Source::File(path) => scenario::load_with(path, sets, unsets),
        Source::Embedded { text, .. } => {
            scenario::load_str_with(text, &source.display_path(), sets, unsets)
        }
    };
    loaded.map_err(|e| {
        eprintln!("error: {e}");
        BAD_INPUT
    })
}

/// How a run ended, as far as an interrupt is concerned.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Ended {
    /// Ran to its end (or failed on its own).
    Complete,
    /// Stopped by the interrupt: its record holds what it computed.
    Stopped,
    /// The interrupt came before it started: named, not written.
    NotStarted,
}

/// A run's record as the runs' thread kept it, and how it ended.
type Finished = (RunRecord, Ended);

/// How long after the first SIGINT/SIGTERM the runs' thread is given to hand over the records
/// of its stopped solves (a solve stops before its next step; what runs outside the solver,
/// building a model or its analytic reference, is not interrupted).
const STOP_GRACE: Duration = Duration::from_secs(5);

/// `celltissue run`.
pub fn run(
    source: &Source,
    out: &Path,
    sets: &[String],
    unsets: &[String],
    opts: RunOptions,
) -> i32 {
    let quiet = opts.quiet;
    let scenario = match load(source, sets, unsets) {
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
    if opts.jobs == 0 {
        eprintln!("error: `--jobs`: must be an integer ≥ 1 (got 0)");
        return BAD_INPUT;
    }
    let indices: Vec<usize> = match shard {
        Some(s) => s.indices(scenario.runs.len()),
        None => (0..scenario.runs.len()).collect(),
    };
    // the records of every run this process runs are held until they are written
    let values: f64 = indices
        .iter()
        .map(|&i| scenario.runs[i].profile_values())
        .sum();
    if let Err(e) = scenario::limits::check_profiles(values, indices.len()) {
        eprintln!("error: {e}");
        return BAD_INPUT;
    }
    // the directory is checked (and claimed in its manifest) before anything runs
    let prepared = match output::manifest::prepare(out, &scenario.name, opts.replace) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {e}");
            return BAD_INPUT;
        }
    };
    let stop = interrupt::install();
    let total = indices.len();
    let terminal = std::io::stderr().is_terminal();
    let pb = bar(
        total as u64,
        quiet,
        "{spinner} [{elapsed_precise}] {bar:30} {pos}/{len} runs  {msg}",
    );
    // finished records by position in `indices`, kept as they finish so an interrupt keeps
    // them, each with whether the interrupt cut it short
    let done: Arc<Mutex<Vec<Option<Finished>>>> = Arc::new(Mutex::new(vec![None; total]));
    // raised at the first signal: every solve stops before its next step, keeping its steps
    let solves = Interrupt::new();
    let worker = {
        let (scenario, indices, done, stop, pb, solves) = (
            scenario.clone(),
            indices.clone(),
            Arc::clone(&done),
            Arc::clone(&stop),
            pb.clone(),
            solves.clone(),
        );
        let jobs = opts.jobs;
        // woken as soon as the runs end, instead of at the next progress tick
        let main = std::thread::current();
        std::thread::Builder::new()
            .name("runs".into())
            .stack_size(64 << 20)
            .spawn(move || {
                // a run's place in `indices` (its spec is borrowed from `scenario.runs`)
                let position = |spec: &scenario::RunSpec| {
                    indices
                        .iter()
                        .position(|&k| std::ptr::eq(&scenario.runs[k], spec))
                };
                let mut k = 0;
                // a discrete run that repeats an earlier one of these runs is not solved again:
                // it gets that run's record once the runs are done (below)
                let source = |i: usize| scenario.runs[i].repeats.filter(|s| indices.contains(s));
                let solve: Vec<usize> = indices
                    .iter()
                    .copied()
                    .filter(|&i| source(i).is_none())
                    .collect();
                // a run's progress line; `repeated`: the run whose solve it repeats
                let mut report = |rec: &RunRecord, repeated: Option<&str>| {
                    if stop.load(Ordering::SeqCst) {
                        return;
                    }
                    k += 1;
                    let line = match repeated {
                        Some(of) => {
                            format!("[{k}/{total}] {}: as `{of}` (not solved again)", rec.label)
                        }
                        None => format!(
                            "[{k}/{total}] {}: {} steps, {:.3} s{}{}",
                            rec.label,
                            rec.stats.steps,
                            rec.stats.wall_seconds,
                            rec.accuracy_check
                                .as_ref()
                                .filter(|c| c.failed.is_none())
                                .map(|c| format!(
                                    "; at rtol {}: {:.2}·rtol",
                                    integrators::error::short_number(c.rtol),
                                    c.stretch_over_rtol.max(c.series_stretch_over_rtol)
                                ))
                                .unwrap_or_default(),
                            rec.error
                                .as_ref()
                                .map(|e| format!(" — FAILED: {e}"))
                                .unwrap_or_default()
                        ),
                    };
                    if !quiet {
                        if terminal {
                            pb.println(line);
                        } else {
                            eprintln!("{line}");
                        }
                    }
                    pb.inc(1);
                };
                let solved = run_parallel(
                    &scenario,
                    &solve,
                    jobs,
                    |spec| {
                        log::info!("run: {}", spec.label);
                        let (mut rec, ended) = if solves.is_raised() {
                            (
                                execute::not_run(spec, "interrupted before it started"),
                                Ended::NotStarted,
                            )
                        } else {
                            let rec = solves.scope(|| execute::run_spec(spec));
                            let cut = rec.error.is_some() && solves.is_raised();
                            (rec, if cut { Ended::Stopped } else { Ended::Complete })
                        };
                        finite::sanitize(&mut rec);
                        // solved here because its source is in another shard: the same note
                        // as where it is not solved again, so merged shards equal one run
                        rec.notes.extend(execute::repeat_note(&scenario, spec));
                        // the record itself is kept where an interrupt finds it; the runner
                        // gets its label and counters only, so no profile is ever copied
                        // (240 MB at 10⁶ cells and three times)
                        let Some(p) = position(spec) else {
                            return rec;
                        };
                        let Ok(mut d) = done.lock() else {
                            return rec;
                        };
                        let light = rec.without_data();
                        d[p] = Some((rec, ended));
                        light
                    },
                    |rec| report(rec, None),
                );
                let runs = solved.map(|solved| {
                    let mut solved = solved.into_iter();
                    let mut runs = Vec::with_capacity(indices.len());
                    for (p, &i) in indices.iter().enumerate() {
                        let spec = &scenario.runs[i];
                        let Some(src) = source(i) else {
                            runs.extend(solved.next());
                            continue;
                        };
                        let from = indices.iter().position(|&j| j == src);
                        let Ok(mut d) = done.lock() else {
                            runs.push(execute::not_run(spec, "its results were lost"));
                            continue;
                        };
                        let Some((source, ended)) = from.and_then(|f| d[f].clone()) else {
                            runs.push(execute::not_run(spec, "interrupted before it started"));
                            continue;
                        };
                        let of = source.label.clone();
                        let rec = execute::repeated(&scenario, spec, source);
                        let light = rec.without_data();
                        d[p] = Some((rec, ended));
                        drop(d);
                        report(&light, Some(&of));
                        runs.push(light);
                    }
                    runs
                });
                main.unpark();
                runs
            })
    };
    let handle = match worker {
        Ok(h) => h,
        Err(e) => {
            eprintln!("error: cannot start the runs: {e}");
            return RUN_FAILED;
        }
    };
    // after the first signal the solves stop within a step; a worker still busy after
    // `STOP_GRACE` (a long step, a long write of its own) is left to the exit
    let mut deadline = None;
    while !handle.is_finished() {
        if stop.load(Ordering::SeqCst) {
            let d = *deadline.get_or_insert_with(|| {
                solves.raise();
                Instant::now() + STOP_GRACE
            });
            if Instant::now() >= d {
                break;
            }
        }
        pb.tick();
        std::thread::park_timeout(Duration::from_millis(20));
    }
    let (runs, interrupted): (Vec<RunRecord>, Vec<String>) = if handle.is_finished() {
        match handle.join() {
            Ok(Ok(light)) => {
                // each run's full record, from where the worker kept it (in the same order);
                // the runs the interrupt cut short are named
                let kept = done.lock().map(|mut d| std::mem::take(&mut *d));
                let mut kept = kept.unwrap_or_default().into_iter();
                let (mut runs, mut cut) = (Vec::new(), Vec::new());
                for r in light {
                    match kept.next().flatten() {
                        Some((rec, ended)) => keep(rec, ended, &mut runs, &mut cut),
                        None => runs.push(r),
                    }
                }
                (runs, cut)
            }
            Ok(Err(e)) => {
                eprintln!("error: {e}");
                return BAD_INPUT;
            }
            Err(_) => {
                eprintln!("error: a run panicked");
                return RUN_FAILED;
            }
        }
    } else {
        // still busy after the grace: keep what finished, name the rest (the worker is
        // left to the exit)
        let d = done.lock().map(|d| d.clone()).unwrap_or_default();
        let mut runs = Vec::new();
        let mut rest = Vec::new();
        for (slot, &k) in d.into_iter().zip(&indices) {
            match slot {
                Some((r, ended)) => keep(r, ended, &mut runs, &mut rest),
                None => rest.push(scenario.runs[k].label.clone()),
            }
        }
        (runs, rest)
    };
    pb.finish_and_clear();
    if let Some(shard) = shard {
        if interrupted.is_empty() {
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
                    if let Err(e) = output::manifest::finish(out, &scenario.name, &prepared) {
                        eprintln!("warning: {e}");
                    }
                    report_failures(&runs, &[])
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    RUN_FAILED
                }
            };
        }
        eprintln!(
            "interrupted: shard not written ({} run(s) not finished)",
            interrupted.len()
        );
        return interrupt::INTERRUPTED;
    }
    let summary = Summary {
        scenario: scenario.name.clone(),
        runs,
    };
    let code = write_outputs(out, &scenario, &summary, &opts, &interrupted);
    if let Err(e) = output::manifest::finish(out, &scenario.name, &prepared) {
        eprintln!("warning: {e}");
    }
    if !interrupted.is_empty() {
        eprintln!(
            "interrupted: {} run(s) not finished (listed in summary.json): {}",
            interrupted.len(),
            interrupted.join(", ")
        );
        return interrupt::INTERRUPTED;
    }
    code
}

/// Files a run's record by how it ended: written unless it never started, named in `cut`
/// unless it ran to its end.
fn keep(rec: RunRecord, ended: Ended, runs: &mut Vec<RunRecord>, cut: &mut Vec<String>) {
    if ended != Ended::Complete {
        cut.push(rec.label.clone());
    }
    if ended != Ended::NotStarted {
        runs.push(rec);
    }
}

/// Writes every output of a finished scenario and reports what was written and what failed;
/// returns the exit code. Shared by `run` and `merge`.
pub fn write_outputs(
    out: &Path,
    scenario: &scenario::Scenario,
    summary: &Summary,
    opts: &RunOptions,
    interrupted: &[String],
) -> i32 {
    let quiet = opts.quiet;
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
    let wopts = output::WriteOptions {
        no_plots: opts.no_plots,
        provenance: Some(output::provenance::Provenance::collect(
            &scenario.table,
            threads,
        )),
        interrupted: interrupted.to_vec(),
        progress: Some(wpb.clone()),
    };
    let written = output::write_all_with(out, scenario, summary, &wopts);
    wpb.finish_and_clear();
    log::debug!("write phase done");
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
        for l in &written.left_out {
            eprintln!("note: {l}");
        }
        eprintln!(
            "wrote {} data files and {} plots to {}",
            written.data.len(),
            written.plots.len(),
            out.display()
        );
    }
    for r in &summary.runs {
        if let Some(w) = r.accuracy_check.as_ref().and_then(accuracy_check::verdict) {
            eprintln!("warning: {}: {w}", r.label);
        }
    }
    let code = report_failures(&summary.runs, interrupted);
    if code != OK {
        return code;
    }
    if !written.plot_errors.is_empty() {
        return RUN_FAILED;
    }
    OK
}

/// Prints the failed runs, if any (a run an interrupt stopped, named in `interrupted`, is
/// reported as interrupted instead); returns the exit code.
fn report_failures(runs: &[crate::observe::RunRecord], interrupted: &[String]) -> i32 {
    let failed: Vec<&str> = runs
        .iter()
        .filter(|r| r.error.is_some() && !interrupted.contains(&r.label))
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
pub fn validate(source: &Source, sets: &[String], unsets: &[String]) -> i32 {
    match load(source, sets, unsets) {
        Ok(s) => {
            let repeats = s.runs.iter().filter(|r| r.repeats.is_some()).count();
            println!(
                "{}: ok — {} run(s): {}{}",
                s.name,
                s.runs.len(),
                s.runs
                    .iter()
                    .map(|r| r.label.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
                match repeats {
                    0 => String::new(),
                    k => format!(
                        " ({k} discrete run(s) repeat an earlier one's solve: the sweep changes \
                         only the continuum there)"
                    ),
                }
            );
            OK
        }
        Err(code) => code,
    }
}

/// `celltissue list`: the catalogue (files on disk, then the embedded scenarios they do not
/// shadow), one line each: name, description, where it comes from.
pub fn list() -> i32 {
    let sources = catalogue::sources();
    if sources.is_empty() {
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
    let rows: Vec<(String, String, String)> = sources
        .iter()
        .map(|src| {
            let text = match src {
                Source::File(p) => std::fs::read_to_string(p).ok(),
                Source::Embedded { text, .. } => Some(text.to_string()),
            };
            let path = src.display_path();
            let (name, desc) = text
                .and_then(|t| toml::from_str::<toml::Table>(&t).ok())
                .map(|t| {
                    let get = |k: &str| t.get(k).and_then(|v| v.as_str()).unwrap_or("").to_string();
                    (get("name"), get("description"))
                })
                .unwrap_or_else(|| (String::new(), "(unreadable scenario file)".into()));
            let name = if name.is_empty() {
                path.file_stem()
                    .unwrap_or_default()
                    .to_string_lossy()
                    .into_owned()
            } else {
                name
            };
            (name, desc, path.display().to_string())
        })
        .collect();
    let w = rows.iter().map(|r| r.0.len()).max().unwrap_or(0);
    for (name, desc, path) in rows {
        println!("{name:<w$}  {desc}  [{path}]");
    }
    OK
}
