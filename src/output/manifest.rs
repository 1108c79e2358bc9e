//! Which files in an output directory this program wrote: `.celltissue-manifest.json` lists
//! them with the scenario's name. A directory holding anything else — another scenario's
//! outputs, or files of unknown origin — is refused unless the caller asks to replace it, and
//! then only the files a manifest lists are removed (a user's own files are never deleted).

use super::OutputError;
use serde::{Deserialize, Serialize};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// The manifest's file name.
pub const MANIFEST: &str = ".celltissue-manifest.json";

/// Contents of the manifest.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub(crate) struct Manifest {
    /// Scenario that wrote the directory.
    pub scenario: String,
    /// Files it wrote (names relative to the directory), sorted.
    pub files: Vec<String>,
}

/// What [`prepare`] found: files in the directory that this program did not write (kept).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Prepared {
    /// Names of files kept from before.
    pub foreign: BTreeSet<String>,
    /// Names of files removed (the previous run's).
    pub removed: Vec<String>,
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> OutputError + '_ {
    move |source| OutputError::Write {
        path: path.to_path_buf(),
        source,
    }
}

/// Names in `dir` other than the manifest and temporary files.
fn entries(dir: &Path) -> Result<BTreeSet<String>, OutputError> {
    let mut out = BTreeSet::new();
    for e in std::fs::read_dir(dir).map_err(io_err(dir))? {
        let e = e.map_err(io_err(dir))?;
        let name = e.file_name().to_string_lossy().into_owned();
        if name != MANIFEST && !super::atomic::is_temp_name(&name) {
            out.insert(name);
        }
    }
    Ok(out)
}

/// Reads the manifest of `dir`, if any.
pub(crate) fn read(dir: &Path) -> Option<Manifest> {
    let text = std::fs::read_to_string(dir.join(MANIFEST)).ok()?;
    serde_json::from_str(&text).ok()
}

/// Makes `dir` ready for the outputs of `scenario`: creates it, or accepts it when it is empty
/// or holds only this program's outputs of the same scenario (which are removed, so no stale
/// file of an earlier run survives). Anything else is [`OutputError::DirectoryInUse`] unless
/// `replace`; with `replace` the files of the previous manifest are removed and every other
/// file is kept. Leftover temporary files of an interrupted write are removed.
pub(crate) fn prepare(dir: &Path, scenario: &str, replace: bool) -> Result<Prepared, OutputError> {
    std::fs::create_dir_all(dir).map_err(io_err(dir))?;
    for e in std::fs::read_dir(dir).map_err(io_err(dir))?.flatten() {
        if super::atomic::is_temp_name(&e.file_name().to_string_lossy()) {
            let _ = std::fs::remove_file(e.path());
        }
    }
    let present = entries(dir)?;
    let old = read(dir);
    let ours: BTreeSet<String> = old
        .as_ref()
        .map(|m| m.files.iter().cloned().collect())
        .unwrap_or_default();
    let same = old.as_ref().is_some_and(|m| m.scenario == scenario);
    let foreign: BTreeSet<String> = present.difference(&ours).cloned().collect();
    let acceptable = present.is_empty() || replace || (same && foreign.is_empty());
    if !acceptable {
        return Err(OutputError::DirectoryInUse {
            dir: dir.to_path_buf(),
            holds: match &old {
                Some(m) if m.scenario != scenario => {
                    format!("the outputs of scenario `{}`", m.scenario)
                }
                Some(_) => format!("{} file(s) celltissue did not write", foreign.len()),
                None => format!("{} file(s) not written by celltissue", present.len()),
            },
        });
    }
    let mut removed = Vec::new();
    for name in present.intersection(&ours) {
        let p = dir.join(name);
        if p.is_file() {
            std::fs::remove_file(&p).map_err(io_err(&p))?;
            removed.push(name.clone());
        }
    }
    let _ = std::fs::remove_file(dir.join(MANIFEST));
    write(
        dir,
        &Manifest {
            scenario: scenario.into(),
            files: Vec::new(),
        },
    )?;
    Ok(Prepared { foreign, removed })
}

fn write(dir: &Path, m: &Manifest) -> Result<PathBuf, OutputError> {
    let path = dir.join(MANIFEST);
    let text =
        serde_json::to_string_pretty(m).map_err(|e| OutputError::Serialize(e.to_string()))?;
    super::atomic::write(&path, text.as_bytes()).map_err(io_err(&path))?;
    Ok(path)
}

/// Records every file now in `dir` except `prepared.foreign` as written by `scenario`.
pub(crate) fn finish(
    dir: &Path,
    scenario: &str,
    prepared: &Prepared,
) -> Result<Manifest, OutputError> {
    let files: Vec<String> = entries(dir)?
        .difference(&prepared.foreign)
        .cloned()
        .collect();
    let m = Manifest {
        scenario: scenario.into(),
        files,
    };
    write(dir, &m)?;
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmp(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("ct_manifest_{name}_{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        d
    }

    #[test]
    fn another_scenario_is_refused_and_replace_removes_only_ours() {
        let d = tmp("replace");
        let p = prepare(&d, "a", false).unwrap();
        std::fs::write(d.join("a.csv"), "1").unwrap();
        finish(&d, "a", &p).unwrap();
        std::fs::write(d.join("notes.txt"), "mine").unwrap();
        let e = prepare(&d, "b", false).unwrap_err().to_string();
        assert!(e.contains("scenario `a`") && e.contains("--replace"), "{e}");
        // the same scenario is refused too while a foreign file is there
        assert!(prepare(&d, "a", false).is_err());
        let p = prepare(&d, "b", true).unwrap();
        assert_eq!(p.removed, ["a.csv"]);
        assert!(d.join("notes.txt").exists() && !d.join("a.csv").exists());
        std::fs::write(d.join("b.csv"), "2").unwrap();
        let m = finish(&d, "b", &p).unwrap();
        assert_eq!(m.files, ["b.csv"]);
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn rerunning_a_scenario_clears_its_old_files() {
        let d = tmp("rerun");
        let p = prepare(&d, "a", false).unwrap();
        std::fs::write(d.join("series_K=1.csv"), "1").unwrap();
        finish(&d, "a", &p).unwrap();
        let p = prepare(&d, "a", false).unwrap();
        assert_eq!(p.removed, ["series_K=1.csv"]);
        assert!(!d.join("series_K=1.csv").exists());
        std::fs::remove_dir_all(&d).unwrap();
    }
}
