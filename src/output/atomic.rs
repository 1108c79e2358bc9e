//! Atomic file writes: every output is written to a hidden temporary file in the same directory
//! and renamed over its final name only once it is complete, so a full disk, a crash or an
//! interrupt never leaves a truncated `summary.json`, `.npz`, `.vtu` or `.png` behind (the
//! rename is atomic on POSIX file systems; a failed write removes its temporary file).

use std::io;
use std::path::{Path, PathBuf};

/// The temporary name used while `path` is written: `.<name>.<pid>.partial.<ext>` beside it
/// (the extension is kept last because some writers, e.g. the PNG encoder, pick the format
/// from it).
///
/// ```
/// let t = celltissue::output::atomic::temp_path("out/summary.json".as_ref());
/// assert!(t.starts_with("out") && t.to_string_lossy().ends_with(".partial.json"));
/// ```
pub fn temp_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "output".into());
    let ext = path
        .extension()
        .map(|e| format!(".{}", e.to_string_lossy()))
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.{}.partial{ext}", std::process::id()))
}

/// Whether a file name is one of [`temp_path`]'s temporary names.
///
/// ```
/// use celltissue::output::atomic::{is_temp_name, temp_path};
/// let tmp = temp_path(std::path::Path::new("out/summary.json"));
/// assert!(is_temp_name(tmp.file_name().unwrap().to_str().unwrap()));
/// assert!(!is_temp_name("summary.json"));
/// ```
pub fn is_temp_name(name: &str) -> bool {
    name.starts_with('.') && name.contains(".partial")
}

/// Runs `write` on a temporary path beside `path`, then renames the result to `path`. On any
/// error the temporary file is removed and `path` is left as it was.
///
/// ```
/// use celltissue::output::atomic::with_temp_file;
/// let dir = std::env::temp_dir().join(format!("ct_with_temp_doc_{}", std::process::id()));
/// std::fs::create_dir_all(&dir).unwrap();
/// let path = dir.join("a.txt");
/// std::fs::write(&path, "old").unwrap();
/// // a writer that fails half-way leaves the old file, and no temporary file
/// let r: std::io::Result<()> = with_temp_file(&path, |tmp| {
///     std::fs::write(tmp, "half")?;
///     Err(std::io::Error::other("disk full"))
/// });
/// assert!(r.is_err());
/// assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
/// assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
/// # std::fs::remove_dir_all(&dir).unwrap();
/// ```
pub fn with_temp_file<T, E: From<io::Error>>(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<T, E>,
) -> Result<T, E> {
    let tmp = temp_path(path);
    let out = write(&tmp).and_then(|v| {
        std::fs::rename(&tmp, path)?;
        Ok(v)
    });
    if out.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    out
}

/// Writes `bytes` to `path` atomically.
///
/// ```
/// let dir = std::env::temp_dir().join(format!("ct_atomic_doc_{}", std::process::id()));
/// std::fs::create_dir_all(&dir).unwrap();
/// celltissue::output::atomic::write(&dir.join("a.txt"), b"hello").unwrap();
/// assert_eq!(std::fs::read(dir.join("a.txt")).unwrap(), b"hello");
/// # std::fs::remove_dir_all(&dir).unwrap();
/// ```
pub fn write(path: &Path, bytes: &[u8]) -> io::Result<()> {
    with_temp_file(path, |tmp| std::fs::write(tmp, bytes))
}

/// Writes to `path` atomically through a buffered writer handed to `fill`.
///
/// ```
/// use std::io::Write;
/// let path = std::env::temp_dir().join(format!("ct_write_with_doc_{}.txt", std::process::id()));
/// celltissue::output::atomic::write_with(&path, |w| writeln!(w, "t,l")).unwrap();
/// assert_eq!(std::fs::read_to_string(&path).unwrap(), "t,l\n");
/// # std::fs::remove_file(&path).unwrap();
/// ```
pub fn write_with(
    path: &Path,
    fill: impl FnOnce(&mut io::BufWriter<std::fs::File>) -> io::Result<()>,
) -> io::Result<()> {
    use io::Write as _;
    with_temp_file(path, |tmp| {
        let mut w = io::BufWriter::new(std::fs::File::create(tmp)?);
        fill(&mut w)?;
        w.flush()?;
        w.into_inner().map_err(|e| e.into_error())?.sync_data()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_write_leaves_the_old_file_and_no_temporary() {
        let dir = std::env::temp_dir().join(format!("ct_atomic_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("x.json");
        write(&p, b"old").unwrap();
        let r: io::Result<()> = with_temp_file(&p, |tmp| {
            std::fs::write(tmp, b"half")?;
            Err(io::Error::other("disk full"))
        });
        assert!(r.is_err());
        assert_eq!(std::fs::read(&p).unwrap(), b"old");
        let names: Vec<_> = std::fs::read_dir(&dir).unwrap().flatten().collect();
        assert_eq!(names.len(), 1, "temporary file left behind");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
