//! `results.h5` (feature `hdf5`): every run of a scenario in one HDF5 file, for MATLAB, Julia,
//! h5py and ParaView users. The arrays are the `.npz` archives' ([`super::npz`]), one group per
//! run named by its label; what the `.npz` cannot hold rides along as attributes.
//!
//! * root attributes: `scenario` (name), `provenance` (JSON: version, git commit, rustc, date,
//!   host, command line, threads, seeds; see [`super::provenance`]), `format`;
//! * `/<label>` (a group per run, in run order, its `index` attribute the position) with
//!   attributes `label`, `model`, `parameters` and `stats` (JSON), `error` (only if the run
//!   failed), and datasets `series/<name>`, `profiles/<field>` (times × cells when every profile
//!   has the same size), `profiles/t`, `profiles/cells`, `divisions/…` — the `.npz` members.
//!
//! The file is written to a temporary name and renamed, so a `results.h5` is always whole.

use super::npz::{members, Member};
use super::provenance::Provenance;
use super::OutputError;
use crate::observe::Summary;
use hdf5::types::VarLenUnicode;
use std::path::{Path, PathBuf};

/// A string attribute.
fn text_attr(loc: &hdf5::Location, name: &str, value: &str) -> hdf5::Result<()> {
    let v: VarLenUnicode = value
        .parse()
        .map_err(|e| hdf5::Error::from(format!("attribute {name}: {e}")))?;
    loc.new_attr::<VarLenUnicode>()
        .create(name)?
        .write_scalar(&v)
}

/// A dataset of `shape` holding `data` in `group`.
fn dataset<T: hdf5::H5Type>(
    group: &hdf5::Group,
    name: &str,
    shape: &[u64],
    data: &[T],
) -> hdf5::Result<()> {
    let shape: Vec<usize> = shape.iter().map(|&d| d as usize).collect();
    group
        .new_dataset::<T>()
        .shape(shape)
        .create(name)?
        .write_raw(data)
}

/// Writes `summary`'s runs to `dir/results.h5`; returns its path.
pub(crate) fn write_results(
    dir: &Path,
    summary: &Summary,
    provenance: Option<&Provenance>,
) -> Result<PathBuf, OutputError> {
    let path = dir.join("results.h5");
    let io = |e: hdf5::Error| std::io::Error::other(e.to_string());
    super::atomic::with_temp_file(&path, |tmp| -> std::io::Result<()> {
        let file = hdf5::File::create(tmp).map_err(io)?;
        write_into(&file, summary, provenance).map_err(io)?;
        file.close().map_err(io)
    })
    .map_err(|source| OutputError::Write {
        path: path.clone(),
        source,
    })?;
    Ok(path)
}

fn write_into(
    file: &hdf5::File,
    summary: &Summary,
    provenance: Option<&Provenance>,
) -> hdf5::Result<()> {
    text_attr(
        file,
        "format",
        "celltissue results (groups per run: series, profiles, divisions)",
    )?;
    text_attr(file, "scenario", &summary.scenario)?;
    if let Some(p) = provenance {
        text_attr(
            file,
            "provenance",
            &serde_json::to_string(p).unwrap_or_default(),
        )?;
    }
    for (index, rec) in summary.runs.iter().enumerate() {
        // a label is a group name as long as it has no `/` (labels are unique in a scenario)
        let run = file.create_group(&rec.label.replace('/', "_"))?;
        run.new_attr::<u64>()
            .create("index")?
            .write_scalar(&(index as u64))?;
        text_attr(&run, "label", &rec.label)?;
        text_attr(&run, "model", crate::scenario::load::model_name(rec.model))?;
        let parameters = super::files::clean_parameters(&rec.parameters);
        text_attr(&run, "parameters", &parameters.to_string())?;
        text_attr(
            &run,
            "stats",
            &serde_json::to_string(&rec.stats).unwrap_or_default(),
        )?;
        if let Some(e) = &rec.error {
            text_attr(&run, "error", e)?;
        }
        for (name, member) in members(rec) {
            let (group, leaf) = name.split_once('/').unwrap_or(("", name.as_str()));
            let parent = match run.group(group) {
                Ok(g) => g,
                Err(_) => run.create_group(group)?,
            };
            match member {
                Member::F64(shape, v) => dataset(&parent, leaf, &shape, &v)?,
                Member::I64(shape, v) => dataset(&parent, leaf, &shape, &v)?,
            }
        }
    }
    Ok(())
}
