//! The bundled scenarios (`models/*.toml`), embedded in the library by `build.rs` when it is
//! compiled, so a binary or a Python wheel runs them by name wherever it is installed. The
//! command line's catalogue (`celltissue list`) and the Python module both read them here.

/// Every bundled scenario as `(name, TOML text)`, sorted by name (`fig2_10` before `fig2_4a`:
/// byte order; listings sort naturally).
///
/// ```
/// let (_, text) = celltissue::scenario::bundled::BUNDLED
///     .iter()
///     .find(|(name, _)| *name == "fig2_5")
///     .expect("fig2_5 is bundled");
/// let s = celltissue::scenario::load_str(text, "fig2_5.toml".as_ref(), &[]).unwrap();
/// assert_eq!(s.name, "fig2_5");
/// ```
pub const BUNDLED: &[(&str, &str)] = include!(concat!(env!("OUT_DIR"), "/embedded_models.rs"));

/// The text of the bundled scenario `name` (a file stem such as `fig2_5`).
///
/// ```
/// assert!(celltissue::scenario::bundled::text("fig2_5").is_some());
/// assert!(celltissue::scenario::bundled::text("no_such").is_none());
/// ```
pub fn text(name: &str) -> Option<&'static str> {
    BUNDLED.iter().find(|(n, _)| *n == name).map(|&(_, t)| t)
}

/// The bundled names, comma-separated (for messages that list what exists).
///
/// ```
/// let names = celltissue::scenario::bundled::names();
/// assert!(names.contains("fig2_5") && names.contains("fig3_3d"));
/// ```
pub fn names() -> String {
    BUNDLED
        .iter()
        .map(|(n, _)| *n)
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::BUNDLED;
    use std::path::Path;

    #[test]
    fn every_models_file_is_bundled_with_its_text() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("models");
        let mut n = 0;
        for e in std::fs::read_dir(&dir).expect("models/") {
            let p = e.expect("entry").path();
            if p.extension().is_some_and(|x| x == "toml") {
                let stem = p.file_stem().and_then(|s| s.to_str()).expect("utf-8 name");
                let text = std::fs::read_to_string(&p).expect("readable");
                assert_eq!(super::text(stem), Some(text.as_str()), "{stem}");
                n += 1;
            }
        }
        assert_eq!(n, BUNDLED.len());
    }

    #[test]
    fn every_bundled_scenario_loads() {
        for (name, text) in BUNDLED {
            let origin = Path::new(name).with_extension("toml");
            if let Err(e) = crate::scenario::load_str(text, &origin, &[]) {
                panic!("{name}: {e}");
            }
        }
    }
}
