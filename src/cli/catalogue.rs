//! The bundled scenario catalogue: `models/*.toml` beside the crate's manifest and in the
//! current directory.

use std::path::{Path, PathBuf};

/// Directories searched for bundled scenarios, in order.
pub fn dirs() -> Vec<PathBuf> {
    let mut d = vec![Path::new(env!("CARGO_MANIFEST_DIR")).join("models")];
    if let Ok(cwd) = std::env::current_dir() {
        d.push(cwd.join("models"));
    }
    d
}

/// Every bundled scenario file, de-duplicated, in natural order (fig2_9 before fig2_10).
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

/// A path as given if it exists; otherwise a bundled scenario of that name.
pub fn resolve(arg: &Path) -> PathBuf {
    if arg.exists() || arg.extension().is_some() {
        return arg.to_path_buf();
    }
    let name = format!("{}.toml", arg.display());
    dirs()
        .into_iter()
        .map(|d| d.join(&name))
        .find(|p| p.exists())
        .unwrap_or_else(|| arg.to_path_buf())
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
    use super::natural_key;

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
