//! Writers: from a [`Summary`] to files in an output directory — `summary.json` (metadata,
//! provenance, series), a numpy `.npz` per run ([`npz`]), with the `hdf5` feature one
//! `results.h5` of every run (`h5`), CSV series and profiles, ensemble statistics
//! ([`ensemble`]), VTU/PVD
//! snapshots for ParaView ([`vtu`]), the resolved `scenario.toml`, and PNG plots laid out like
//! the thesis figures ([`figures`], built on the reusable [`plot`] module). Every file is
//! written atomically ([`atomic`]); the command line records each in the directory's manifest
//! (`manifest`, feature `cli`).
//! Nothing here runs a model.

pub mod atomic;
pub mod ensemble;
#[cfg(feature = "plots")]
pub mod figures;
pub mod files;
pub mod finite;
#[cfg(feature = "plots")]
pub mod fonts;
#[cfg(feature = "hdf5")]
pub(crate) mod h5;
#[cfg(feature = "cli")]
pub mod interrupt;
#[cfg(feature = "cli")]
pub mod manifest;
pub mod npz;
pub mod number;
#[cfg(feature = "plots")]
pub mod plot;
pub mod provenance;
pub mod vtr;
pub mod vtu;

use crate::observe::Summary;
use crate::scenario::Scenario;
use std::path::{Path, PathBuf};

/// Why outputs could not be written.
///
/// ```
/// use celltissue::observe::*;
/// use celltissue::output::{write_all, OutputError};
/// use celltissue::scenario::load_str;
/// let text = "name = \"n\"\n[output]\nseries = [1]\n[model]\nkind = \"line\"\nmodels = [\"discrete\"]\ncells = 4";
/// let s = load_str(text, "n.toml".as_ref(), &[])?;
/// let mut rec = RunRecord { label: "discrete".into(), model: ModelKind::Discrete,
///     parameters: serde_json::json!({}), series: Series::default(), profiles: vec![],
///     stats: RunStats::default(), divisions: vec![], error: None, notes: vec![], reference: None, accuracy_check: None };
/// rec.series.t = vec![f64::NAN];
/// let summary = Summary { scenario: "n".into(), runs: vec![rec] };
/// // a NaN is refused before anything is written
/// let dir = std::env::temp_dir().join(format!("ct_nan_doc_{}", std::process::id()));
/// assert!(matches!(write_all(&dir, &s, &summary), Err(OutputError::NonFinite(_))));
/// assert!(!dir.exists());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OutputError {
    /// A file or the directory could not be written.
    #[error("cannot write `{path}`: {source}")]
    Write {
        /// The path.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// A number is NaN or infinite (JSON cannot hold it; nothing is written).
    #[error("refusing to write a non-finite number: {0}")]
    NonFinite(#[from] finite::NonFiniteError),
    /// Serialisation failed.
    #[error("serialisation failed: {0}")]
    Serialize(String),
    /// The output directory holds files of another scenario or of unknown origin.
    #[error(
        "output directory `{dir}` holds {holds}; choose another --out, or pass --replace to \
         replace it (only files celltissue wrote there are removed)"
    )]
    DirectoryInUse {
        /// The directory.
        dir: PathBuf,
        /// What it holds.
        holds: String,
    },
}

/// What [`write_all`] wrote (see [`write_all`] and [`write_all_with`] for runs).
///
/// ```
/// let w = celltissue::output::Written::default();
/// assert!(w.data.is_empty() && w.plots.is_empty() && w.plot_errors.is_empty());
/// ```
#[derive(Debug, Default)]
pub struct Written {
    /// Data files (JSON, NPZ, CSV, VTU, TOML).
    pub data: Vec<PathBuf>,
    /// PNG plots.
    pub plots: Vec<PathBuf>,
    /// Plots that could not be drawn, with the reason (data files are unaffected).
    pub plot_errors: Vec<String>,
    /// Runs whose profile CSV or VTU snapshots the size limits left out
    /// ([`files::PROFILE_CSV_MAX_ROWS`], [`vtu::VTU_MAX_CELLS`]), one sentence each.
    pub left_out: Vec<String>,
}

/// Options of [`write_all_with`].
///
/// ```
/// use celltissue::output::{provenance::Provenance, WriteOptions};
/// let table: toml::Table = toml::from_str("[model]\ndivision = { seed = 7 }").unwrap();
/// let opts = WriteOptions {
///     provenance: Some(Provenance::collect(&table, 1)), // recorded in summary.json
///     interrupted: vec!["discrete K=1".into()],
///     ..Default::default()
/// };
/// assert!(!opts.no_plots);
/// ```
#[derive(Debug, Default)]
pub struct WriteOptions {
    /// Skip the PNG plots (`--no-plots`).
    pub no_plots: bool,
    /// Provenance for `summary.json`.
    pub provenance: Option<provenance::Provenance>,
    /// Labels of runs cut short by an interrupt (recorded in `summary.json`).
    pub interrupted: Vec<String>,
    /// Progress of the write phase (one tick per stage); hidden when not on a terminal.
    #[cfg(feature = "cli")]
    pub progress: Option<indicatif::ProgressBar>,
}

/// Creates `dir` and writes every output of a scenario run with default options (see
/// [`write_all_with`]).
///
/// ```
/// use celltissue::{output, scenario::{execute, load_str}};
/// let text = "name = \"demo\"\n[output]\nseries = [1, 2]\n[model]\nkind = \"line\"\nmodels = [\"discrete\"]\ncells = 10";
/// let s = load_str(text, "demo.toml".as_ref(), &[])?;
/// let summary = execute::run_all(&s, execute::run_spec, |_| {});
/// let dir = std::env::temp_dir().join(format!("celltissue_doc_write_all_{}", std::process::id()));
/// let w = output::write_all(&dir, &s, &summary)?;
/// assert!(dir.join("summary.json").exists() && dir.join("series_discrete.csv").exists());
/// assert!(w.data.iter().any(|p| p.ends_with("run_discrete.npz")));
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_all(
    dir: &Path,
    scenario: &Scenario,
    summary: &Summary,
) -> Result<Written, OutputError> {
    write_all_with(dir, scenario, summary, &WriteOptions::default())
}

/// Creates `dir` and writes every output of a scenario run: the data files (`summary.json`;
/// then the `.npz` beside the CSV and VTU files; then `scenario.toml`) and, alongside them on
/// the rayon pool, the plots. The summary is checked for non-finite numbers before anything
/// is written.
///
/// ```
/// use celltissue::output::{write_all_with, WriteOptions, Written};
/// use celltissue::scenario::{execute, load_str};
/// let text = "name = \"quiet\"\n[output]\nseries = [1]\n[model]\nkind = \"line\"\nmodels = [\"discrete\"]\ncells = 5";
/// let s = load_str(text, "quiet.toml".as_ref(), &[])?;
/// let summary = execute::run_all(&s, execute::run_spec, |_| {});
/// let dir = std::env::temp_dir().join(format!("celltissue_doc_no_plots_{}", std::process::id()));
/// let opts = WriteOptions { no_plots: true, ..Default::default() };
/// let w: Written = write_all_with(&dir, &s, &summary, &opts)?;
/// assert!(w.plots.is_empty() && !w.data.is_empty()); // `--no-plots`: data only
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_all_with(
    dir: &Path,
    scenario: &Scenario,
    summary: &Summary,
    opts: &WriteOptions,
) -> Result<Written, OutputError> {
    finite::check_summary(summary).map_err(OutputError::NonFinite)?;
    std::fs::create_dir_all(dir).map_err(|source| OutputError::Write {
        path: dir.to_path_buf(),
        source,
    })?;
    let stage = |what: &str| {
        #[cfg(feature = "cli")]
        if let Some(p) = &opts.progress {
            p.set_message(what.to_string());
            p.inc(1);
        }
        log::debug!("writing {what}");
    };
    let data = || -> Result<Vec<PathBuf>, OutputError> {
        let mut data = Vec::new();
        stage("summary.json");
        data.push(files::write_summary_with(
            dir,
            summary,
            opts.provenance.as_ref(),
            &opts.interrupted,
        )?);
        // the arrays (one thread: zip and its checksums) beside the text and the snapshots
        // (the VTU's compression on the pool)
        let arrays = || -> Result<Vec<PathBuf>, OutputError> {
            stage("arrays (.npz)");
            let arrays = files::write_arrays(dir, summary)?;
            #[cfg(feature = "hdf5")]
            let arrays = {
                stage("results.h5");
                let mut arrays = arrays;
                arrays.push(h5::write_results(dir, summary, opts.provenance.as_ref())?);
                arrays
            };
            Ok(arrays)
        };
        let text_and_snapshots = || -> Result<Vec<PathBuf>, OutputError> {
            stage("CSV");
            let mut written = files::write_csvs(dir, summary)?;
            written.extend(ensemble::write_ensemble(dir, scenario, summary)?);
            stage("VTU/PVD");
            written.extend(vtu::write_snapshots(dir, scenario, summary)?);
            Ok(written)
        };
        let (arrays, rest) = rayon::join(arrays, text_and_snapshots);
        data.extend(arrays?);
        data.extend(rest?);
        data.push(files::write_scenario(dir, &scenario.table)?);
        Ok(data)
    };
    let mut w = Written::default();
    #[cfg(feature = "plots")]
    {
        // the plots read only the summary, so they are drawn while the data files are
        // written (on one thread they were a third of the write phase at 10⁴ cells); a
        // failed data file still fails the whole write
        let plots = || {
            let mut drawn = (Vec::new(), Vec::new());
            if opts.no_plots {
                return drawn;
            }
            stage("plots");
            let figures = figures::write_figures(dir, scenario, summary);
            let ensemble = ensemble::ensemble_figures(dir, scenario, summary);
            for (path, result) in figures.into_iter().chain(ensemble) {
                match result {
                    Ok(()) => drawn.0.push(path),
                    Err(plot::PlotError::NoData) => {}
                    Err(e) => drawn.1.push(format!("{}: {e}", path.display())),
                }
            }
            drawn
        };
        let (data, (plots, plot_errors)) = rayon::join(data, plots);
        w.data = data?;
        w.plots = plots;
        w.plot_errors = plot_errors;
    }
    #[cfg(not(feature = "plots"))]
    {
        w.data = data()?;
    }
    w.left_out = files::left_out(summary);
    Ok(w)
}

/// Stages of [`write_all_with`] reported to its progress bar.
pub const WRITE_STAGES: u64 = 5 + cfg!(feature = "hdf5") as u64;
