//! Build-time provenance for `summary.json` (see `src/output/provenance.rs`): the git commit
//! of the source tree, if it is a git checkout, and the compiler's version. Missing tools or a
//! source tree outside git leave the variables unset; the build never fails because of them.

use std::process::Command;

fn output(cmd: &str, args: &[&str]) -> Option<String> {
    let out = Command::new(cmd).args(args).output().ok()?;
    if !out.status.success() {
        return None;
    }
    let s = String::from_utf8(out.stdout).ok()?.trim().to_string();
    (!s.is_empty()).then_some(s)
}

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
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
