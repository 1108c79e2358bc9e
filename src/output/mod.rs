//! Writers: from a [`Summary`] to files in an output directory — `summary.json`, CSV series and
//! profiles per run, the resolved `scenario.toml`, and PNG plots laid out like the thesis
//! figures ([`figures`], built on the reusable [`plot`] module). Nothing here runs a model.

pub mod atomic;
pub mod figures;
pub mod files;
pub mod finite;
pub mod fonts;
pub mod plot;

use crate::observe::Summary;
use crate::scenario::Scenario;
use std::path::{Path, PathBuf};

/// Why outputs could not be written.
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
    NonFinite(String),
    /// Serialisation failed.
    #[error("serialisation failed: {0}")]
    Serialize(String),
}

/// What [`write_all`] wrote.
#[derive(Debug, Default)]
pub struct Written {
    /// Data files (JSON, CSV, TOML).
    pub data: Vec<PathBuf>,
    /// PNG plots.
    pub plots: Vec<PathBuf>,
    /// Plots that could not be drawn, with the reason (data files are unaffected).
    pub plot_errors: Vec<String>,
}

/// Creates `dir` and writes every output of a scenario run: data first (JSON, CSV, TOML),
/// then plots. The summary is checked for non-finite numbers before anything is written.
pub fn write_all(
    dir: &Path,
    scenario: &Scenario,
    summary: &Summary,
) -> Result<Written, OutputError> {
    finite::check_summary(summary).map_err(OutputError::NonFinite)?;
    std::fs::create_dir_all(dir).map_err(|source| OutputError::Write {
        path: dir.to_path_buf(),
        source,
    })?;
    let mut w = Written::default();
    w.data.push(files::write_summary(dir, summary)?);
    w.data.extend(files::write_csvs(dir, summary)?);
    w.data.push(files::write_scenario(dir, &scenario.table)?);
    for (path, result) in figures::write_figures(dir, scenario, summary) {
        match result {
            Ok(()) => w.plots.push(path),
            Err(plot::PlotError::NoData) => {}
            Err(e) => w.plot_errors.push(format!("{}: {e}", path.display())),
        }
    }
    Ok(w)
}
