//! Data files: `summary.json` (metadata, provenance and series — the profiles go to the run's
//! `.npz`, see [`super::npz`]), `series_<label>.csv`, `profiles_<label>.csv` (long format, up to
//! [`PROFILE_CSV_MAX_ROWS`] rows), `divisions_<label>.csv`, `run_<label>.npz` and the resolved
//! `scenario.toml`. File names come from run labels via [`slug`]; every file is written
//! atomically ([`super::atomic`]).

use super::provenance::Provenance;
use super::OutputError;
use crate::observe::{DivisionRecord, ModelKind, RunRecord, RunStats, Series, Summary};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Most rows of a `profiles_<label>.csv`: above this (e.g. 10⁶ cells × 4 times) formatting
/// text would cost more than the solve, and the profiles are only in the run's `.npz`.
pub const PROFILE_CSV_MAX_ROWS: usize = 200_000;

/// One run as written to `summary.json`: the record without its profiles, which are named by
/// time and stored in `arrays`.
#[derive(Serialize)]
struct RunEntry<'a> {
    label: &'a str,
    model: ModelKind,
    parameters: &'a serde_json::Value,
    series: &'a Series,
    /// Times of the profiles in the `.npz`.
    profile_times: Vec<f64>,
    /// The run's array file (series, profiles, divisions), relative to the directory.
    arrays: String,
    stats: &'a RunStats,
    #[serde(skip_serializing_if = "<[DivisionRecord]>::is_empty")]
    divisions: &'a [DivisionRecord],
    #[serde(skip_serializing_if = "Option::is_none")]
    error: &'a Option<String>,
}

/// `summary.json`.
#[derive(Serialize)]
struct SummaryFile<'a> {
    scenario: &'a str,
    #[serde(skip_serializing_if = "Option::is_none")]
    provenance: Option<&'a Provenance>,
    /// Runs not finished when the program was interrupted (SIGINT/SIGTERM): absent from `runs`.
    #[serde(skip_serializing_if = "<[String]>::is_empty")]
    interrupted: &'a [String],
    runs: Vec<RunEntry<'a>>,
}

/// The `.npz` file name of each run, in order.
pub fn npz_names(summary: &Summary) -> Vec<String> {
    unique_slugs(summary.runs.iter().map(|r| r.label.as_str()))
        .into_iter()
        .map(|s| format!("run_{s}.npz"))
        .collect()
}

/// A label as a file-name part: spaces become `_`, characters outside `[A-Za-z0-9._=+-]` `_`.
///
/// ```
/// assert_eq!(celltissue::output::files::slug("discrete K=0.01"), "discrete_K=0.01");
/// assert_eq!(celltissue::output::files::slug("a/b c"), "a_b_c");
/// ```
pub fn slug(label: &str) -> String {
    let s: String = label
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "._=+-".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() {
        "run".into()
    } else {
        s
    }
}

/// Unique slugs for a list of labels (a suffix `_2`, `_3`… on repeats).
pub fn unique_slugs<'a>(labels: impl Iterator<Item = &'a str>) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for l in labels {
        let base = slug(l);
        let mut s = base.clone();
        let mut k = 2;
        while out.contains(&s) {
            s = format!("{base}_{k}");
            k += 1;
        }
        out.push(s);
    }
    out
}

fn write(path: &Path, text: &str) -> Result<PathBuf, OutputError> {
    super::atomic::write(path, text.as_bytes()).map_err(|source| OutputError::Write {
        path: path.to_path_buf(),
        source,
    })?;
    Ok(path.to_path_buf())
}

/// Writes `summary.json` (pretty-printed; profiles only by time, see [`npz_names`]) after
/// checking that every number is finite.
pub fn write_summary(dir: &Path, summary: &Summary) -> Result<PathBuf, OutputError> {
    write_summary_with(dir, summary, None, &[])
}

/// [`write_summary`] with the provenance and the labels of interrupted runs.
pub fn write_summary_with(
    dir: &Path,
    summary: &Summary,
    provenance: Option<&Provenance>,
    interrupted: &[String],
) -> Result<PathBuf, OutputError> {
    super::finite::check_summary(summary).map_err(OutputError::NonFinite)?;
    let file = SummaryFile {
        scenario: &summary.scenario,
        provenance,
        interrupted,
        runs: summary
            .runs
            .iter()
            .zip(npz_names(summary))
            .map(|(r, arrays)| RunEntry {
                label: &r.label,
                model: r.model,
                parameters: &r.parameters,
                series: &r.series,
                profile_times: r.profiles.iter().map(|p| p.t).collect(),
                arrays,
                stats: &r.stats,
                divisions: &r.divisions,
                error: &r.error,
            })
            .collect(),
    };
    let text =
        serde_json::to_string_pretty(&file).map_err(|e| OutputError::Serialize(e.to_string()))?;
    write(&dir.join("summary.json"), &text)
}

/// Writes each run's `.npz` (see [`super::npz`]); returns their paths.
pub fn write_arrays(dir: &Path, summary: &Summary) -> Result<Vec<PathBuf>, OutputError> {
    let mut out = Vec::new();
    for (rec, name) in summary.runs.iter().zip(npz_names(summary)) {
        let path = dir.join(name);
        super::npz::write_npz_file(&path, rec).map_err(|source| OutputError::Write {
            path: path.clone(),
            source,
        })?;
        out.push(path);
    }
    Ok(out)
}

/// The series of one run as CSV text: `t,length,max_pressure,min_pressure,max_stretch,
/// min_stretch,<extra series in name order>`.
pub fn series_csv(rec: &RunRecord) -> String {
    let s = &rec.series;
    let mut cols: Vec<(&str, &Vec<f64>)> = vec![
        ("t", &s.t),
        ("length", &s.length),
        ("max_pressure", &s.max_pressure),
        ("min_pressure", &s.min_pressure),
        ("max_stretch", &s.max_stretch),
        ("min_stretch", &s.min_stretch),
    ];
    cols.extend(s.extra.iter().map(|(k, v)| (k.as_str(), v)));
    table(&cols, s.t.len(), None)
}

/// The profiles of one run as long-format CSV: one row per cell (node) per time,
/// `t,X,x,stretch,pressure,<extra fields>`. Extra fields missing at some time are left empty.
pub fn profiles_csv(rec: &RunRecord) -> String {
    let mut extra: Vec<&str> = rec
        .profiles
        .iter()
        .flat_map(|p| p.extra.keys().map(String::as_str))
        .collect();
    extra.sort_unstable();
    extra.dedup();
    let mut out = String::from("t,X,x,stretch,pressure");
    for k in &extra {
        out.push(',');
        out.push_str(k);
    }
    out.push('\n');
    for p in &rec.profiles {
        let mut cols: Vec<(&str, &Vec<f64>)> = vec![
            ("X", &p.x_ref),
            ("x", &p.x),
            ("stretch", &p.stretch),
            ("pressure", &p.pressure),
        ];
        let empty = Vec::new();
        cols.extend(
            extra
                .iter()
                .map(|k| (*k, p.extra.get(*k).unwrap_or(&empty))),
        );
        let rows = p.x_ref.len();
        let body = table(&cols, rows, Some(p.t));
        out.push_str(body.split_once('\n').map_or("", |(_, b)| b));
    }
    out
}

/// Division events as CSV: `t,parent,x,x_over_length,cells_after`.
pub fn divisions_csv(rec: &RunRecord) -> String {
    let mut out = String::from("t,parent,x,x_over_length,cells_after\n");
    for d in &rec.divisions {
        let _ = writeln!(
            out,
            "{},{},{},{},{}",
            d.t, d.parent, d.x, d.x_over_length, d.cells_after
        );
    }
    out
}

/// Columns to CSV with a header; a leading constant `t` column if `t` is given; short columns
/// leave empty cells.
fn table(cols: &[(&str, &Vec<f64>)], rows: usize, t: Option<f64>) -> String {
    let mut out = String::new();
    let header: Vec<&str> = t
        .iter()
        .map(|_| "t")
        .chain(cols.iter().map(|c| c.0))
        .collect();
    out.push_str(&header.join(","));
    out.push('\n');
    for i in 0..rows {
        let mut first = true;
        if let Some(t) = t {
            let _ = write!(out, "{t}");
            first = false;
        }
        for (_, v) in cols {
            if !first {
                out.push(',');
            }
            first = false;
            if let Some(x) = v.get(i) {
                let _ = write!(out, "{x}");
            }
        }
        out.push('\n');
    }
    out
}

/// Writes the CSV files of every run; returns their paths.
pub fn write_csvs(dir: &Path, summary: &Summary) -> Result<Vec<PathBuf>, OutputError> {
    let slugs = unique_slugs(summary.runs.iter().map(|r| r.label.as_str()));
    let mut files = Vec::new();
    for (rec, s) in summary.runs.iter().zip(&slugs) {
        files.push(write(
            &dir.join(format!("series_{s}.csv")),
            &series_csv(rec),
        )?);
        let rows: usize = rec.profiles.iter().map(|p| p.x_ref.len()).sum();
        if !rec.profiles.is_empty() && rows <= PROFILE_CSV_MAX_ROWS {
            files.push(write(
                &dir.join(format!("profiles_{s}.csv")),
                &profiles_csv(rec),
            )?);
        }
        if !rec.divisions.is_empty() {
            files.push(write(
                &dir.join(format!("divisions_{s}.csv")),
                &divisions_csv(rec),
            )?);
        }
    }
    Ok(files)
}

/// Writes the scenario table as run (after `--set`) to `scenario.toml`.
pub fn write_scenario(dir: &Path, table: &toml::Table) -> Result<PathBuf, OutputError> {
    let text = toml::to_string_pretty(table).map_err(|e| OutputError::Serialize(e.to_string()))?;
    write(
        &dir.join("scenario.toml"),
        &format!("# the scenario as run (after --set overrides)\n{text}"),
    )
}
