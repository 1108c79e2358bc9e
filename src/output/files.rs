//! Data files: `summary.json` (metadata, provenance and series — the profiles go to the run's
//! `.npz`, see [`super::npz`]), `series_<label>.csv`, `profiles_<label>.csv` (long format, up to
//! [`PROFILE_CSV_MAX_ROWS`] rows), `divisions_<label>.csv`, `run_<label>.npz` and the resolved
//! `scenario.toml`. File names come from run labels via [`slug`]; every file is written
//! atomically ([`super::atomic`]).

use super::number::push_f64;
use super::provenance::Provenance;
use super::OutputError;
use crate::observe::{DivisionRecord, ModelKind, RunRecord, RunStats, Summary};
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
    parameters: serde_json::Value,
    series: serde_json::Map<String, serde_json::Value>,
    /// Times of the profiles in the `.npz`.
    profile_times: Vec<f64>,
    /// The run's array file (series, profiles, divisions), relative to the directory.
    arrays: String,
    stats: &'a RunStats,
    #[serde(skip_serializing_if = "<[DivisionRecord]>::is_empty")]
    divisions: &'a [DivisionRecord],
    #[serde(skip_serializing_if = "Option::is_none")]
    error: &'a Option<String>,
    #[serde(skip_serializing_if = "<[String]>::is_empty")]
    notes: &'a [String],
    /// The analytic reference's label and series (its profiles are in the `.npz`).
    #[serde(skip_serializing_if = "Option::is_none")]
    reference: Option<ReferenceEntry<'a>>,
    /// The run against itself at a tighter tolerance (`solver.accuracy_check`).
    #[serde(skip_serializing_if = "Option::is_none")]
    accuracy_check: &'a Option<crate::observe::AccuracyCheck>,
}

/// A run's analytic reference as written to `summary.json`.
#[derive(Serialize)]
struct ReferenceEntry<'a> {
    label: &'a str,
    series: &'a crate::observe::ReferenceSeries,
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

/// Whether a record is a shear column (whose series and profiles reuse the line's fields for
/// other quantities, docs/model.md §6).
fn is_shear(rec: &RunRecord) -> bool {
    rec.parameters.get("kind").and_then(|k| k.as_str()) == Some("shear")
}

/// The series of a run by their output names, in output order. A shear column's fields are
/// named for what they hold: `max_tan_theta`/`min_tan_theta` (the line's `max/min_stretch`),
/// and its `length` (a copy of `top_displacement`) is left out.
///
/// ```
/// use celltissue::observe::*;
/// let mut rec = RunRecord { label: "r".into(), model: ModelKind::Discrete,
///     parameters: serde_json::json!({"kind": "shear"}), series: Series::default(),
///     profiles: vec![], stats: RunStats::default(), divisions: vec![], error: None, notes: vec![],
///     reference: None, accuracy_check: None };
/// let names: Vec<String> = celltissue::output::files::series_columns(&rec)
///     .into_iter().map(|c| c.0).collect();
/// assert_eq!(names, ["t", "max_pressure", "min_pressure", "max_tan_theta", "min_tan_theta"]);
/// ```
pub fn series_columns(rec: &RunRecord) -> Vec<(String, &Vec<f64>)> {
    let s = &rec.series;
    let shear = is_shear(rec);
    let mut cols: Vec<(String, &Vec<f64>)> = vec![("t".into(), &s.t)];
    if !shear {
        cols.push(("length".into(), &s.length));
    }
    cols.push(("max_pressure".into(), &s.max_pressure));
    cols.push(("min_pressure".into(), &s.min_pressure));
    let (mx, mn) = if shear {
        ("max_tan_theta", "min_tan_theta")
    } else {
        ("max_stretch", "min_stretch")
    };
    cols.push((mx.into(), &s.max_stretch));
    cols.push((mn.into(), &s.min_stretch));
    cols.extend(s.extra.iter().map(|(k, v)| (k.clone(), v)));
    cols
}

/// The output name of a profile field of `rec`: a shear column's `X` is the reference height
/// `Y` and its `stretch` is `tan_theta`.
///
/// ```
/// use celltissue::observe::*;
/// use celltissue::output::files::profile_field_name;
/// let rec = RunRecord { label: "discrete N=10".into(), model: ModelKind::Discrete,
///     parameters: serde_json::json!({}), series: Series::default(), profiles: vec![],
///     stats: RunStats::default(), divisions: vec![], error: None, notes: vec![], reference: None, accuracy_check: None };
/// assert_eq!(profile_field_name(&rec, "stretch"), "stretch"); // a line keeps its names
/// ```
pub fn profile_field_name<'a>(rec: &RunRecord, field: &'a str) -> &'a str {
    match (is_shear(rec), field) {
        (true, "X") => "Y",
        (true, "stretch") => "tan_theta",
        _ => field,
    }
}

/// A run's parameters as written: `null` (absent) options removed at every depth, a nested
/// `config` object dropped when every entry of it is repeated at the top level, and `law`
/// dropped when it repeats `energy` — each law appears once.
///
/// ```
/// let p = serde_json::json!({"law": {"mu": 1}, "energy": {"mu": 1}, "drag": null,
///     "config": {"law": {"mu": 1}, "drag": null}});
/// let c = celltissue::output::files::clean_parameters(&p);
/// assert_eq!(c, serde_json::json!({"energy": {"mu": 1}}));
/// ```
pub fn clean_parameters(p: &serde_json::Value) -> serde_json::Value {
    fn strip(v: &serde_json::Value) -> serde_json::Value {
        match v {
            serde_json::Value::Object(m) => m
                .iter()
                .filter(|(_, x)| !x.is_null())
                .map(|(k, x)| (k.clone(), strip(x)))
                .collect::<serde_json::Map<_, _>>()
                .into(),
            serde_json::Value::Array(a) => a.iter().map(strip).collect::<Vec<_>>().into(),
            other => other.clone(),
        }
    }
    let mut v = strip(p);
    if let serde_json::Value::Object(m) = &mut v {
        let redundant = m
            .get("config")
            .and_then(|c| c.as_object())
            .is_some_and(|c| c.iter().all(|(k, x)| m.get(k) == Some(x)));
        if redundant {
            m.remove("config");
        }
        if m.get("energy").is_some() && m.get("energy") == m.get("law") {
            // sheets and shear columns run with `energy` (the scenario key)
            m.remove("law");
        }
    }
    v
}

/// The `.npz` file name of each run, in order.
///
/// ```
/// use celltissue::observe::{ModelKind, RunRecord, Summary};
/// let run = |label: &str| RunRecord {
///     label: label.into(), model: ModelKind::Discrete, parameters: serde_json::Value::Null,
///     series: Default::default(), profiles: vec![], stats: Default::default(), divisions: vec![], error: None, notes: vec![],
///     reference: None, accuracy_check: None,
/// };
/// let s = Summary { scenario: "demo".into(), runs: vec![run("discrete"), run("continuum")] };
/// assert_eq!(celltissue::output::files::npz_names(&s), ["run_discrete.npz", "run_continuum.npz"]);
/// ```
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
///
/// ```
/// use celltissue::output::files::unique_slugs;
/// let s = unique_slugs(["discrete K=1", "discrete K=1", "continuum"].into_iter());
/// assert_eq!(s.len(), 3);
/// assert_ne!(s[0], s[1]); // a repeated label gets a distinct file name
/// ```
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
///
/// ```
/// use celltissue::observe::*;
/// let rec = RunRecord { label: "discrete".into(), model: ModelKind::Discrete,
///     parameters: serde_json::json!({}), series: Series::default(), profiles: vec![],
///     stats: RunStats::default(), divisions: vec![], error: None, notes: vec![], reference: None, accuracy_check: None };
/// let summary = Summary { scenario: "demo".into(), runs: vec![rec] };
/// let dir = std::env::temp_dir().join(format!("ct_summary_doc_{}", std::process::id()));
/// std::fs::create_dir_all(&dir).unwrap();
/// let path = celltissue::output::files::write_summary(&dir, &summary).unwrap();
/// let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
/// assert_eq!(json["runs"][0]["arrays"], "run_discrete.npz");
/// # std::fs::remove_dir_all(&dir).unwrap();
/// ```
pub fn write_summary(dir: &Path, summary: &Summary) -> Result<PathBuf, OutputError> {
    write_summary_with(dir, summary, None, &[])
}

/// [`write_summary`] with the provenance and the labels of interrupted runs.
pub(crate) fn write_summary_with(
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
                parameters: clean_parameters(&r.parameters),
                series: series_columns(r)
                    .into_iter()
                    .map(|(k, v)| (k, serde_json::json!(v)))
                    .collect(),
                profile_times: r.profiles.iter().map(|p| p.t).collect(),
                arrays,
                stats: &r.stats,
                divisions: &r.divisions,
                error: &r.error,
                notes: &r.notes,
                reference: r.reference.as_ref().map(|x| ReferenceEntry {
                    label: &x.label,
                    series: &x.series,
                }),
                accuracy_check: &r.accuracy_check,
            })
            .collect(),
    };
    let text =
        serde_json::to_string_pretty(&file).map_err(|e| OutputError::Serialize(e.to_string()))?;
    write(&dir.join("summary.json"), &text)
}

/// Writes each run's `.npz` (see [`super::npz`]); returns their paths.
pub(crate) fn write_arrays(dir: &Path, summary: &Summary) -> Result<Vec<PathBuf>, OutputError> {
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
/// min_stretch,<extra series in name order>` (shear columns: see [`series_columns`]).
///
/// ```
/// use celltissue::observe::{ModelKind, RunRecord};
/// use celltissue::runner::OutputTimes;
/// use celltissue::sheet::{run_sheet, SheetConfig};
/// use celltissue::SolveSettings;
/// let cfg = SheetConfig { cells_x: 2, cells_y: 2, ..Default::default() };
/// let rec: RunRecord = run_sheet(&cfg, &cfg.law, ModelKind::Discrete, None,
///                                &SolveSettings::default(), &OutputTimes::at(&[0.0, 1.0]))?;
/// let csv = celltissue::output::files::series_csv(&rec);
/// assert!(csv.starts_with("t,length,max_pressure"));
/// assert_eq!(csv.lines().count(), 3); // header and two times
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn series_csv(rec: &RunRecord) -> String {
    let named = series_columns(rec);
    let cols: Vec<(&str, &Vec<f64>)> = named.iter().map(|(k, v)| (k.as_str(), *v)).collect();
    table(&cols, rec.series.t.len(), None)
}

/// The profiles of one run as long-format CSV: one row per cell (node) per time,
/// `t,X,x,stretch,pressure,<extra fields>`. Extra fields missing at some time are left empty.
///
/// ```
/// use celltissue::observe::*;
/// let mut rec = RunRecord { label: "discrete".into(), model: ModelKind::Discrete,
///     parameters: serde_json::json!({}), series: Series::default(), profiles: vec![],
///     stats: RunStats::default(), divisions: vec![], error: None, notes: vec![], reference: None, accuracy_check: None };
/// rec.profiles.push(Profile { t: 1.0, x_ref: vec![0.5, 1.5], x: vec![0.45, 1.35],
///                             stretch: vec![0.9, 0.9], pressure: vec![1.2, 1.2], ..Default::default() });
/// let csv = celltissue::output::files::profiles_csv(&rec);
/// assert_eq!(csv.lines().collect::<Vec<_>>(),
///            ["t,X,x,stretch,pressure", "1.0,0.5,0.45,0.9,1.2", "1.0,1.5,1.35,0.9,1.2"]);
/// ```
pub fn profiles_csv(rec: &RunRecord) -> String {
    let mut extra: Vec<&str> = rec
        .profiles
        .iter()
        .flat_map(|p| p.extra.keys().map(String::as_str))
        .collect();
    extra.sort_unstable();
    extra.dedup();
    let mut out = format!(
        "t,{},x,{},pressure",
        profile_field_name(rec, "X"),
        profile_field_name(rec, "stretch")
    );
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

/// Division events as CSV: `t,parent,x,x_over_length,cells_after`, then `age` (the dividing
/// cell's cycle time, [`DivisionRecord::age`]) when the model follows individual cells, and
/// `cell,daughter_1,daughter_2` (their identities, [`DivisionRecord::cell`]) when it traces
/// their lineage.
///
/// ```
/// use celltissue::observe::{DivisionRecord, ModelKind, RunRecord};
/// let mut rec = RunRecord { label: "discrete".into(), model: ModelKind::Discrete, parameters: Default::default(),
///     series: Default::default(), profiles: vec![], stats: Default::default(), divisions: vec![], error: None, notes: vec![],
///     reference: None, accuracy_check: None,
/// };
/// rec.divisions.push(DivisionRecord { t: 2.5, parent: 7, x: 6.5, x_over_length: 0.5, cells_after: 11,
///                                     age: Some(2.5), cell: Some(6), daughters: Some([10, 11]) });
/// let csv = celltissue::output::files::divisions_csv(&rec);
/// assert_eq!(csv.lines().collect::<Vec<_>>(), [
///     "t,parent,x,x_over_length,cells_after,age,cell,daughter_1,daughter_2",
///     "2.5,7,6.5,0.5,11,2.5,6,10,11",
/// ]);
/// ```
pub fn divisions_csv(rec: &RunRecord) -> String {
    use crate::events::log::{division_columns, DivisionColumn};
    let columns = division_columns(&rec.divisions);
    let names: Vec<&str> = columns.iter().map(|c| c.0).collect();
    let mut out = names.join(",");
    out.push('\n');
    for k in 0..rec.divisions.len() {
        for (j, (_, column)) in columns.iter().enumerate() {
            if j > 0 {
                out.push(',');
            }
            match column {
                DivisionColumn::F64(v) => push_f64(&mut out, v[k]),
                DivisionColumn::I64(v) => {
                    let _ = write!(out, "{}", v[k]);
                }
            }
        }
        out.push('\n');
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
            push_f64(&mut out, t);
            first = false;
        }
        for (_, v) in cols {
            if !first {
                out.push(',');
            }
            first = false;
            if let Some(&x) = v.get(i) {
                push_f64(&mut out, x);
            }
        }
        out.push('\n');
    }
    out
}

/// A run's profile values per field: its cells (or nodes) summed over the profile times, the
/// rows of its `profiles_<label>.csv` and the cells of its `.vtu` snapshots.
pub(crate) fn profile_rows(rec: &RunRecord) -> usize {
    rec.profiles.iter().map(|p| p.x_ref.len()).sum()
}

/// What the size limits kept out of the text and snapshot files, one sentence per run that
/// lost any (its profiles are in its `.npz` all the same).
///
/// ```
/// use celltissue::observe::{ModelKind, Profile, RunRecord, Summary};
/// let run = |label: &str, cells: usize| RunRecord {
///     label: label.into(), model: ModelKind::Discrete, parameters: serde_json::Value::Null,
///     series: Default::default(),
///     profiles: vec![Profile { t: 1.0, x_ref: vec![0.0; cells], ..Default::default() }; 3],
///     stats: Default::default(), divisions: vec![], error: None, notes: vec![], reference: None, accuracy_check: None,
/// };
/// let s = Summary { scenario: "demo".into(), runs: vec![run("small", 100), run("big", 100_000)] };
/// let out = celltissue::output::files::left_out(&s);
/// assert_eq!(out, ["big: 300000 profile values per field; the profile CSV (over 200000 rows) \
///                   left out, the profiles are in run_big.npz"]);
/// ```
pub fn left_out(summary: &Summary) -> Vec<String> {
    let names = npz_names(summary);
    summary
        .runs
        .iter()
        .zip(names)
        .filter_map(|(rec, npz)| {
            let rows = profile_rows(rec);
            let mut what = Vec::new();
            if rows > PROFILE_CSV_MAX_ROWS {
                what.push(format!(
                    "the profile CSV (over {PROFILE_CSV_MAX_ROWS} rows)"
                ));
            }
            if rows > super::vtu::VTU_MAX_CELLS {
                what.push(format!(
                    "the VTU snapshots (over {} cells)",
                    super::vtu::VTU_MAX_CELLS
                ));
            }
            (!what.is_empty()).then(|| {
                format!(
                    "{}: {rows} profile values per field; {} left out, the profiles are in {npz}",
                    rec.label,
                    what.join(" and ")
                )
            })
        })
        .collect()
}

/// Writes the CSV files of every run; returns their paths.
pub(crate) fn write_csvs(dir: &Path, summary: &Summary) -> Result<Vec<PathBuf>, OutputError> {
    let slugs = unique_slugs(summary.runs.iter().map(|r| r.label.as_str()));
    let mut files = Vec::new();
    for (rec, s) in summary.runs.iter().zip(&slugs) {
        files.push(write(
            &dir.join(format!("series_{s}.csv")),
            &series_csv(rec),
        )?);
        if !rec.profiles.is_empty() && profile_rows(rec) <= PROFILE_CSV_MAX_ROWS {
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
///
/// ```
/// let dir = std::env::temp_dir().join(format!("celltissue_doc_scenario_{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let table: toml::Table = toml::from_str("name = \"demo\"")?;
/// let path = celltissue::output::files::write_scenario(&dir, &table)?;
/// assert!(std::fs::read_to_string(&path)?.contains("name = \"demo\""));
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_scenario(dir: &Path, table: &toml::Table) -> Result<PathBuf, OutputError> {
    let text = toml::to_string_pretty(table).map_err(|e| OutputError::Serialize(e.to_string()))?;
    write(
        &dir.join("scenario.toml"),
        &format!("# the scenario as run (after --set overrides)\n{text}"),
    )
}
