//! Data files: `summary.json` (the issue #3 schema, via [`crate::observe::Summary`]),
//! `series_<label>.csv`, `profiles_<label>.csv` (long format), `divisions_<label>.csv`, and the
//! resolved `scenario.toml`. File names come from run labels via [`slug`].

use super::OutputError;
use crate::observe::{RunRecord, Summary};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

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
    std::fs::write(path, text).map_err(|source| OutputError::Write {
        path: path.to_path_buf(),
        source,
    })?;
    Ok(path.to_path_buf())
}

/// Writes `summary.json` (pretty-printed) after checking that every number is finite.
pub fn write_summary(dir: &Path, summary: &Summary) -> Result<PathBuf, OutputError> {
    super::finite::check_summary(summary).map_err(OutputError::NonFinite)?;
    let text =
        serde_json::to_string_pretty(summary).map_err(|e| OutputError::Serialize(e.to_string()))?;
    write(&dir.join("summary.json"), &text)
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
        if !rec.profiles.is_empty() {
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
