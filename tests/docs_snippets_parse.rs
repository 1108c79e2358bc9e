//! Every TOML snippet in the documentation is accepted by the loader as written: fenced
//! ```` ```toml ```` blocks are complete scenarios and must validate; inline `key = { … }`
//! assignments (the law, field, division forms of `models/README.md`) must validate in at least
//! one model context. Documentation and parser cannot drift apart (once the documented line-law
//! syntax `{ type = … }` was rejected by the parser).

use celltissue::scenario::load_str;
use std::path::{Path, PathBuf};

fn docs() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = vec![root.join("README.md"), root.join("models/README.md")];
    if let Ok(dir) = std::fs::read_dir(root.join("docs")) {
        let mut more: Vec<PathBuf> = dir
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "md"))
            .collect();
        more.sort();
        files.extend(more);
    }
    files
}

/// The bodies of the ```` ```toml ```` blocks of a markdown text.
fn toml_blocks(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut current: Option<Vec<&str>> = None;
    for line in text.lines() {
        let fence = line.trim_start();
        match &mut current {
            None if fence.starts_with("```toml") => current = Some(Vec::new()),
            Some(body) if fence.starts_with("```") => {
                out.push(body.join("\n"));
                current = None;
            }
            Some(body) => body.push(line),
            None => {}
        }
    }
    out
}

/// Inline code spans of the form `key = { … }` (complete: no `…` placeholder).
fn inline_assignments(text: &str) -> Vec<String> {
    text.split('`')
        .skip(1)
        .step_by(2)
        .filter(|s| {
            let Some((k, v)) = s.split_once(" = ") else {
                return false;
            };
            !k.is_empty()
                && k.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
                && v.starts_with('{')
                && v.ends_with('}')
                && !s.contains('…')
        })
        .map(str::to_string)
        .collect()
}

/// Model contexts an inline assignment may belong to.
const CONTEXTS: [&str; 4] = [
    "kind = \"line\"\ncells = 10",
    "kind = \"line\"\ncells = 10\nright_end = \"free\"\ngrowth = { sigma0 = 0.1 }\nmodels = [\"discrete\"]",
    "kind = \"sheet\"\ncells_x = 3\ncells_y = 2",
    "kind = \"shear\"\ncells = 3",
];

#[test]
fn fenced_toml_blocks_are_valid_scenarios() {
    let mut checked = 0;
    for file in docs() {
        let text = std::fs::read_to_string(&file).unwrap();
        for (i, block) in toml_blocks(&text).into_iter().enumerate() {
            let r = load_str(&block, &file, &[]);
            assert!(
                r.is_ok(),
                "{} block {i} does not validate: {}\n{block}",
                file.display(),
                r.unwrap_err()
            );
            checked += 1;
        }
    }
    // models/README.md has a line, a sheet, a grid and a zip example
    assert!(checked >= 4, "only {checked} blocks found");
}

#[test]
fn inline_key_tables_are_accepted_as_documented() {
    let mut checked = Vec::new();
    for file in docs() {
        let text = std::fs::read_to_string(&file).unwrap();
        for snippet in inline_assignments(&text) {
            let errors: Vec<String> = CONTEXTS
                .iter()
                .filter_map(|ctx| {
                    let scenario = format!(
                        "name = \"snippet\"\n[output]\nseries = [0, 1]\n[model]\n{ctx}\n{snippet}\n"
                    );
                    load_str(&scenario, &file, &[]).err().map(|e| e.to_string())
                })
                .collect();
            assert!(
                errors.len() < CONTEXTS.len(),
                "{}: `{snippet}` is rejected in every model context: {errors:#?}",
                file.display()
            );
            checked.push(snippet);
        }
    }
    for must in [
        "law = { law = \"neo_hookean\", mu = 1 }",
        "division = {",
        "mu = { type = \"gaussian\"",
    ] {
        assert!(
            checked.iter().any(|s| s.starts_with(must)),
            "no documented `{must}` snippet was found: {checked:#?}"
        );
    }
    // every built-in strain energy has a documented, accepted example
    for name in celltissue::energy::registry::names() {
        let must = format!("law = {{ law = \"{name}\"");
        assert!(
            checked.iter().any(|s| s.starts_with(&must)),
            "the law `{name}` has no example in the docs ({must} …)"
        );
    }
}

#[test]
fn the_old_line_law_syntax_is_rejected_naming_the_key() {
    // `{ type = … }` was documented for the law but never parsed: the docs now say `law = …`
    let s = "name = \"x\"\n[output]\nseries = [0, 1]\n[model]\nkind = \"line\"\nlaw = { type = \"neo_hookean\", mu = 1 }\n";
    let e = load_str(s, Path::new("x.toml"), &[]).unwrap_err();
    assert_eq!(e.key_name(), Some("model.law"), "{e}");
}
