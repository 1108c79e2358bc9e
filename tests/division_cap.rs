//! A dividing line that reaches its `division.max_cells` cap divides no more, so its N(t) and
//! l(t) from then on are the cap's, not the model's: the record says so (`notes`, written to
//! `summary.json`), and a run below the cap carries no note.

use celltissue::observe::Summary;
use celltissue::output;
use celltissue::scenario::{execute, load_str};
use std::path::{Path, PathBuf};

/// Ten cells that divide every time unit (age rule) to t = 4: 160 cells without a cap.
fn scenario(max_cells: usize) -> String {
    format!(
        "name = \"cap\"\n[output]\nseries = [0, 1, 2, 3, 4]\n[model]\nkind = \"line\"\n\
         models = [\"discrete\"]\ncells = 10\nright_end = \"free\"\nK = 0.1\n\
         growth = {{ sigma0 = 10.0 }}\n\
         division = {{ rule = \"age\", period = 1.0, max_cells = {max_cells} }}\n"
    )
}

fn run(name: &str, max_cells: usize) -> (PathBuf, Summary) {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    let s = load_str(&scenario(max_cells), Path::new("cap.toml"), &[]).unwrap();
    let summary = execute::run_all(&s, execute::run_spec, |_| {});
    let opts = output::WriteOptions {
        no_plots: true,
        ..Default::default()
    };
    output::write_all_with(&dir, &s, &summary, &opts).unwrap();
    (dir, summary)
}

#[test]
fn a_run_that_reaches_its_cell_cap_says_so() {
    let (dir, summary) = run("division_cap_reached", 50);
    let rec = &summary.runs[0];
    assert!(rec.error.is_none(), "{:?}", rec.error);
    let cells = &rec.series.extra["cells"];
    // 10, 20, 40, then the cap
    assert_eq!(cells, &[10.0, 20.0, 40.0, 50.0, 50.0]);
    assert_eq!(rec.notes.len(), 1, "{:?}", rec.notes);
    let note = &rec.notes[0];
    assert!(
        note.contains("max_cells = 50") && note.contains("reached at t = 3"),
        "{note}"
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(v["runs"][0]["notes"][0], note.as_str());

    // below the cap: no note, and no `notes` key in summary.json
    let (dir, summary) = run("division_cap_not_reached", 1000);
    assert_eq!(summary.runs[0].series.extra["cells"][4], 160.0);
    assert!(summary.runs[0].notes.is_empty());
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert!(v["runs"][0].get("notes").is_none());
}
