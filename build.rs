//! Build-time provenance for `summary.json` (see `src/output/provenance.rs`): the git commit
//! of the source tree, if it is a git checkout, and the compiler's version. Missing tools or a
//! source tree outside git leave the variables unset; the build never fails because of them.
//!
//! Also the bundled scenario catalogue: every `models/*.toml` is embedded in the binary
//! (`$OUT_DIR/embedded_models.rs`, read by `src/cli/catalogue.rs`), so `celltissue list` and
//! `celltissue run fig2_5` work wherever the binary is. Generated here rather than with a crate
//! such as `include_dir` because it is one `include_str!` per file and needs no dependency.

use std::process::Command;

fn output(cmd: &str, args: &[&str]) -> Option<String> {
    let out = Command::new(cmd).args(args).output().ok()?;
    if !out.status.success() {
        return None;
    }
    let s = String::from_utf8(out.stdout).ok()?.trim().to_string();
    (!s.is_empty()).then_some(s)
}

/// Writes `$OUT_DIR/embedded_models.rs`: a sorted `&[(name, text)]` of `models/*.toml`.
fn embed_models() {
    let manifest = std::env::var("CARGO_MANIFEST_DIR").unwrap_or_else(|_| ".".into());
    let dir = std::path::Path::new(&manifest).join("models");
    println!("cargo:rerun-if-changed={}", dir.display());
    let mut entries: Vec<(String, std::path::PathBuf)> = std::fs::read_dir(&dir)
        .map(|rd| {
            rd.filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "toml"))
                .filter_map(|p| {
                    let stem = p.file_stem()?.to_str()?.to_string();
                    Some((stem, p))
                })
                .collect()
        })
        .unwrap_or_default();
    entries.sort();
    let mut code = String::from("&[\n");
    for (name, path) in &entries {
        println!("cargo:rerun-if-changed={}", path.display());
        code.push_str(&format!(
            "    ({name:?}, include_str!({:?})),\n",
            path.display().to_string()
        ));
    }
    code.push_str("]\n");
    let out = std::path::Path::new(&std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"))
        .join("embedded_models.rs");
    std::fs::write(out, code).expect("OUT_DIR is writable");
}

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    embed_models();
    if let Some(commit) = output("git", &["rev-parse", "HEAD"]) {
        let dirty = output("git", &["status", "--porcelain", "--untracked-files=no"]).is_some();
        let suffix = if dirty { "-modified" } else { "" };
        println!("cargo:rustc-env=CELLTISSUE_GIT_COMMIT={commit}{suffix}");
        // rebuild the stamp when HEAD moves
        for path in [
            output("git", &["rev-parse", "--git-path", "HEAD"]),
            output("git", &["rev-parse", "--symbolic-full-name", "HEAD"])
                .and_then(|r| output("git", &["rev-parse", "--git-path", &r])),
        ]
        .into_iter()
        .flatten()
        {
            println!("cargo:rerun-if-changed={path}");
        }
    }
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    if let Some(v) = output(&rustc, &["--version"]) {
        println!("cargo:rustc-env=CELLTISSUE_RUSTC_VERSION={v}");
    }
}
