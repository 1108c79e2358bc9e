//! The bundled scenario catalogue: `models/*.toml` beside the crate's manifest and in the
//! current directory, and — so that `celltissue list` and `celltissue run fig2_5` work wherever
//! the binary is, with no checkout — the same files as they were when the binary was built,
//! embedded by `build.rs` ([`crate::scenario::bundled`]). A file on disk of the same name
//! wins over the embedded copy.

use std::path::{Path, PathBuf};

use crate::scenario::bundled::BUNDLED as EMBEDDED;

/// Where a scenario's text comes from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Source {
    /// A file (as given, or found in a catalogue directory).
    File(PathBuf),
    /// A scenario embedded in the binary: its name and text.
    Embedded {
        /// The name (`fig2_5`).
        name: &'static str,
        /// The file's text at build time.
        text: &'static str,
    },
}

impl Source {
    /// How messages and listings name it: the path, or `<embedded>/NAME.toml`.
    pub fn display_path(&self) -> PathBuf {
        match self {
            Source::File(p) => p.clone(),
            Source::Embedded { name, .. } => Path::new("<embedded>").join(format!("{name}.toml")),
        }
    }
}

/// Directories searched for bundled scenarios, in order.
pub fn dirs() -> Vec<PathBuf> {
    let mut d = vec![Path::new(env!("CARGO_MANIFEST_DIR")).join("models")];
    if let Ok(cwd) = std::env::current_dir() {
        d.push(cwd.join("models"));
    }
    d
}

/// Every scenario file in the catalogue directories, de-duplicated, in natural order (fig2_9
/// before fig2_10).
pub fn files() -> Vec<PathBuf> {
    let mut seen = Vec::new();
    let mut out = Vec::new();
    for dir in dirs() {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        let mut here: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "toml"))
            .collect();
        here.sort_by_key(|p| natural_key(&p.file_name().unwrap_or_default().to_string_lossy()));
        for p in here {
            let canon = p.canonicalize().unwrap_or_else(|_| p.clone());
            if !seen.contains(&canon) {
                seen.push(canon);
                out.push(p);
            }
        }
    }
    out
}

/// The whole catalogue: the files of [`files`], then every embedded scenario no file of the
/// same name shadows, in natural order of name.
pub fn sources() -> Vec<Source> {
    let files = files();
    let on_disk = |name: &str| {
        files
            .iter()
            .any(|p| p.file_stem().is_some_and(|s| s == name))
    };
    let mut out: Vec<Source> = files.iter().cloned().map(Source::File).collect();
    let mut embedded: Vec<Source> = EMBEDDED
        .iter()
        .filter(|(name, _)| !on_disk(name))
        .map(|&(name, text)| Source::Embedded { name, text })
        .collect();
    embedded.sort_by_key(|s| match s {
        Source::Embedded { name, .. } => natural_key(name),
        Source::File(_) => Vec::new(),
    });
    out.extend(embedded);
    out
}

/// A path as given if it exists (or has an extension: a file the user means); otherwise a
/// catalogue scenario of that name, on disk first, then embedded; otherwise the path as given
/// (reading it then reports that it does not exist).
pub fn resolve(arg: &Path) -> Source {
    resolve_in(arg, dirs())
}

/// [`resolve`] with the catalogue directories given.
fn resolve_in(arg: &Path, dirs: Vec<PathBuf>) -> Source {
    if arg.exists() || arg.extension().is_some() {
        return Source::File(arg.to_path_buf());
    }
    let name = format!("{}.toml", arg.display());
    if let Some(p) = dirs.into_iter().map(|d| d.join(&name)).find(|p| p.exists()) {
        return Source::File(p);
    }
    let stem = arg.to_string_lossy();
    EMBEDDED
        .iter()
        .find(|(n, _)| *n == stem)
        .map(|&(name, text)| Source::Embedded { name, text })
        .unwrap_or_else(|| Source::File(arg.to_path_buf()))
}

/// Sort key that orders digit runs numerically.
fn natural_key(s: &str) -> Vec<(String, u64)> {
    let mut out = Vec::new();
    let mut text = String::new();
    let mut chars = s.chars().peekable();
    while let Some(c) = chars.next() {
        if c.is_ascii_digit() {
            let mut n = c.to_digit(10).unwrap_or(0) as u64;
            while let Some(d) = chars.peek().and_then(|d| d.to_digit(10)) {
                n = n.saturating_mul(10).saturating_add(d as u64);
                chars.next();
            }
            out.push((std::mem::take(&mut text), n));
        } else {
            text.push(c);
        }
    }
    out.push((text, u64::MAX));
    out
}

#[cfg(test)]
mod tests {
    use super::{natural_key, resolve, resolve_in, Source, EMBEDDED};
    use std::path::Path;

    #[test]
    fn a_name_found_on_disk_is_the_file_else_the_embedded_copy() {
        let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("models");
        assert_eq!(
            resolve_in(Path::new("fig2_5"), vec![models.clone()]),
            Source::File(models.join("fig2_5.toml"))
        );
        // no catalogue directory (a binary away from any checkout): the embedded text
        match resolve_in(Path::new("fig2_5"), vec![]) {
            Source::Embedded { name, text } => {
                assert_eq!(name, "fig2_5");
                let on_disk = std::fs::read_to_string(models.join("fig2_5.toml")).unwrap();
                assert_eq!(text, on_disk);
            }
            other => panic!("expected the embedded fig2_5, got {other:?}"),
        }
        assert!(EMBEDDED.iter().any(|(n, _)| *n == "fig2_5"));
    }

    #[test]
    fn unknown_names_stay_paths() {
        assert_eq!(
            resolve(Path::new("no_such_scenario")),
            Source::File("no_such_scenario".into())
        );
    }

    #[test]
    fn natural_order() {
        let mut v = vec!["fig2_10.toml", "fig2_9.toml", "fig2_5.toml", "fig3_1.toml"];
        v.sort_by_key(|s| natural_key(s));
        assert_eq!(
            v,
            ["fig2_5.toml", "fig2_9.toml", "fig2_10.toml", "fig3_1.toml"]
        );
    }
}
