//! Every bad input found by hand and by fuzzing is rejected by the loader (what `celltissue
//! validate` runs) before anything runs, with a message naming the innermost key in a researcher's words; the
//! one-key strain energy; `--set` against a sweep; multi-parameter sweeps.

use celltissue::cell::Field;
use celltissue::scenario::{load_str, ModelConfig, Scenario, ScenarioError};
use std::path::Path;

const LINE: &str = r#"
name = "t"
[output]
series = [0, 1]
profiles = [1]
[model]
kind = "line"
cells = 10
"#;

fn load(text: &str, sets: &[&str]) -> Result<Scenario, ScenarioError> {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    load_str(text, Path::new("t.toml"), &sets)
}

/// Loads `text` (+ `sets`), expects a key error naming `key`; returns the message.
fn rejects(text: &str, sets: &[&str], key: &str) -> String {
    let e = load(text, sets).expect_err(key);
    assert_eq!(e.key_name(), Some(key), "{e}");
    e.to_string()
}

fn line(extra: &str) -> String {
    format!("{LINE}{extra}\n")
}

#[test]
fn sizes_that_cannot_be_allocated_are_capped_with_the_memory_needed() {
    for cells in ["9223372036854775807", "1000000000000000000"] {
        let m = rejects(LINE, &[&format!("model.cells={cells}")], "model.cells");
        assert!(
            m.contains("limit is 100000000 cells") && m.contains("EB of memory"),
            "{m}"
        );
    }
    let sheet = "name = \"s\"\n[output]\nseries = [0, 1]\n[model]\nkind = \"sheet\"\n\
                 cells_x = 4294967296\ncells_y = 4294967296\n";
    let m = rejects(sheet, &[], "model.cells_x");
    assert!(m.contains("limit is 10000000 cells"), "{m}");
    // the continuum's grid counts too (n · m points)
    let sheet = sheet.replace("4294967296", "10") + "nodes = [100000, 1000]\n";
    let m = rejects(&sheet, &[], "model.nodes");
    assert!(
        m.contains("limit is 10000000 cells") && m.contains("800 GB of memory"),
        "{m}"
    );
    rejects(&line("nodes = 100000000000"), &[], "model.nodes");
    rejects(
        &line("right_end = \"free\"\ngrowth = { sigma0 = 0.1 }\ndivision = { rule = \"area\", max_cells = 1000000000000 }"),
        &[],
        "model.division.max_cells",
    );
}

/// Profiles are capped like cells: 10⁶ cells at 10⁵ profile times (10¹¹ values, 16 TB) used
/// to pass `validate` and then grow the run's records until the allocation aborted.
/// `output.profiles = []` records none, as the key left out does; `output.series` must
/// name a time.
#[test]
fn an_empty_profile_list_records_none() {
    let none = load(&LINE.replace("profiles = [1]", "profiles = []"), &[]).unwrap();
    let absent = load(&LINE.replace("profiles = [1]", ""), &[]).unwrap();
    assert!(none.runs[0].times.profiles.is_empty());
    assert_eq!(none.runs[0].times, absent.runs[0].times);
    assert!(load(LINE, &["output.profiles=[]"]).unwrap().runs[0]
        .times
        .profiles
        .is_empty());
    let m = rejects(LINE, &["output.series=[]"], "output.series");
    assert!(m.contains("at least one time"), "{m}");
}

#[test]
fn profiles_that_cannot_be_held_are_capped_with_the_memory_needed() {
    let big = "profiles = { start = 0, stop = 1, count = 100000, spacing = \"linear\" }";
    let m = rejects(
        &LINE.replace("profiles = [1]", big),
        &["model.cells=1000000"],
        "output.profiles",
    );
    assert!(
        m.contains("100000000000 cell values") && m.contains("17.5 TB") && m.contains("in run"),
        "{m}"
    );
    // the continuum's grid counts its nodes
    let m = rejects(
        &LINE.replace("profiles = [1]", big),
        &["model.nodes=10000000", "model.models=[\"continuum\"]"],
        "output.profiles",
    );
    assert!(m.contains("1000000000000 cell values"), "{m}");
    // a modest request passes
    assert!(load(&LINE.replace("profiles = [1]", big), &[]).is_ok());
}

#[test]
fn a_ten_thousand_part_set_key_is_an_error_not_a_stack_overflow() {
    let key = vec!["a"; 10_000].join(".");
    let e = load(LINE, &[&format!("{key}=1")]).unwrap_err();
    let m = e.to_string();
    assert!(matches!(e, ScenarioError::Set { .. }), "{m}");
    assert!(m.contains("at most 16 dotted parts"), "{m}");
    assert!(
        m.len() < 1000,
        "the key is not echoed whole: {} bytes",
        m.len()
    );
    // the same limit in a sweep parameter
    let m = rejects(
        &line(&format!("[sweep]\nparameter = \"{key}\"\nvalues = [1]")),
        &[],
        "sweep.parameter",
    );
    assert!(m.len() < 1000);
}

#[test]
fn gaussian_fields_need_a_finite_centre_and_a_resolvable_width() {
    let g = |centre: &str, width: &str| {
        line(&format!(
            "mu = {{ type = \"gaussian\", base = 1, amplitude = 1, centre = {centre}, width = {width} }}\nsampling = \"integer_points\""
        ))
    };
    for c in ["nan", "-inf", "inf"] {
        let m = rejects(&g(c, "0.1"), &[], "model.mu.centre");
        assert!(m.contains("must be finite"), "{m}");
    }
    // 1e-200 sampled at the bump's centre (an integer point) was 0/0 = NaN
    let m = rejects(&g("0.5", "1e-200"), &[], "model.mu.width");
    assert!(m.contains(">= 1e-10"), "{m}");
    assert!(load(&g("0.5", "1e-10"), &[]).is_ok());
    rejects(
        &line("mu = { type = \"gaussian\", base = 1, amplitude = nan, centre = 0.5, width = 0.1 }"),
        &[],
        "model.mu.amplitude",
    );
    rejects(
        &line("mu = { type = \"piecewise\", breaks = [nan], values = [1, 2] }"),
        &[],
        "model.mu.breaks",
    );
}

#[test]
fn subnormal_numbers_are_rejected_naming_their_key() {
    // 5e-324 is the smallest subnormal double: a sheet's k_th = 5e-324 halved to K = 0 and ran
    // as an undragged sheet; a line's K = 5e-324 stopped at t = 0 ("singular")
    let sheet = "name = \"t\"\n[output]\nseries = [0, 1]\n[model]\nkind = \"sheet\"\n\
                 cells_x = 4\ncells_y = 4\nk_th = 5e-324\n";
    let m = rejects(sheet, &[], "model.k_th");
    assert!(
        m.contains("subnormal") && m.contains("2.2250738585072014e-308"),
        "{m}"
    );
    rejects(LINE, &["model.K=5e-324"], "model.K");
    rejects(LINE, &["model.K=-1e-310"], "model.K");
    rejects(
        &line("mu = { type = \"gaussian\", base = 1, amplitude = 1, centre = 0.5, width = 0.1 }\nK = { type = \"piecewise\", breaks = [0.5], values = [1, 1e-310] }"),
        &[],
        "model.K.values[1]",
    );
    // the swept value is named where it is written
    let swept = line("[sweep]\nparameter = \"K\"\nvalues = [1, 1e-320]");
    rejects(&swept, &[], "sweep.values[1]");
    // the smallest normal double and 0 itself stay allowed
    assert!(load(LINE, &["model.K=2.2250738585072014e-308"]).is_ok());
    assert!(load(LINE, &["model.K=0"]).is_ok());
}

#[test]
fn type_errors_inside_a_field_name_the_innermost_key() {
    for (k, v) in [
        ("base", "\"one\""),
        ("amplitude", "[1]"),
        ("centre", "true"),
        ("width", "{ x = 1 }"),
    ] {
        let text = line(&format!(
            "mu = {{ type = \"gaussian\", base = 1, amplitude = 1, centre = 0.5, width = 0.1, {k} = {v} }}"
        ))
        .replace(&format!(" {k} = 1,"), " ")
        .replace(&format!(" {k} = 0.5,"), " ")
        .replace(&format!(" {k} = 0.1,"), " ");
        let m = rejects(&text, &[], &format!("model.mu.{k}"));
        assert!(m.contains("expected a number"), "{m}");
        assert!(!m.contains("f64"), "{m}");
    }
    rejects(
        &line("K = { type = \"random\", low = 0, high = 1, seed = -3 }"),
        &[],
        "model.K.seed",
    );
    rejects(
        &line("K = { type = \"random\", low = 0, high = 1, seed = 1, sead = 2 }"),
        &[],
        "model.K.sead",
    );
    // a list is one value per cell: an element that is not a number is named by its index
    let m = rejects(&line("mu = [1, \"stiff\", 1]"), &[], "model.mu[1]");
    assert!(m.contains("expected a number"), "{m}");
    rejects(&line("mu = [1, -2]"), &[], "model.mu");
    let ok = load(&line("mu = [1, 4, 1]"), &[]).expect("a per-cell list");
    assert!(format!("{:?}", ok.runs[0].config).contains("PerCell(3 values)"));
}

#[test]
fn messages_use_researchers_words_and_short_numbers() {
    let m = rejects(LINE, &["model.cells=1e300"], "model.cells");
    assert!(m.contains("expected a non-negative integer"), "{m}");
    assert!(!m.contains("usize"), "{m}");
    assert!(!m.contains("0000000000"), "no 300-digit integer: {m}");
    let m = rejects(LINE, &["model.cells=-3"], "model.cells");
    assert!(m.contains("non-negative integer"), "{m}");
    let m = rejects(LINE, &["model.cells=2.5"], "model.cells");
    assert!(m.contains("floating point `2.5`"), "{m}");
}

/// A whole number written as a float (`1e4`, `100.0`: TOML reads them as floats, and so do
/// Python's `1e4`) is taken where an integer is expected — at the top, inside a field's table,
/// in a range, in a sweep, a continuum grid, an ensemble; a fraction is still refused.
#[test]
fn whole_numbers_written_as_floats_count_as_integers() {
    let s = load(LINE, &["model.cells=1e4", "model.nodes=2e2"]).unwrap();
    let ModelConfig::Line(cfg) = &s.runs[0].config else {
        panic!("a line")
    };
    assert_eq!((cfg.cells, s.runs[1].nodes), (10_000, Some(200)));
    let s = load(
        LINE,
        &[
            "model.mu={ type = \"random\", low = 1, high = 2, seed = 3.0 }",
            "output.series={ start = 0, stop = 1, count = 1e1 }",
        ],
    )
    .unwrap();
    assert_eq!(s.runs[0].times.series.len(), 10);
    let ModelConfig::Line(cfg) = &s.runs[0].config else {
        panic!("a line")
    };
    assert!(
        matches!(cfg.mu, Field::Random { seed: 3, .. }),
        "{:?}",
        cfg.mu
    );
    let swept = load(
        LINE,
        &["sweep.parameter=\"cells\"", "sweep.values=[10.0, 2e1]"],
    )
    .unwrap();
    assert_eq!(swept.runs.len(), 4);
    let sheet = "name = \"s\"\n[output]\nseries = [0, 1]\n[model]\nkind = \"sheet\"\n\
                 cells_x = 4.0\ncells_y = 2\nnodes = [8.0, 4e0]\n";
    let s = load(sheet, &[]).unwrap();
    assert_eq!(s.runs[1].grid, Some((8, 4)));
    for bad in ["model.cells=2.5", "model.nodes=2.5", "model.cells=1e300"] {
        let key = bad.split('=').next().unwrap();
        rejects(LINE, &[bad], key);
    }
}

#[test]
fn a_huge_garbage_line_is_not_echoed_whole() {
    let garbage = format!("{LINE}\n{}\n", "é=@".repeat(2_000_000));
    let e = load(&garbage, &[]).unwrap_err();
    assert!(matches!(e, ScenarioError::Syntax { .. }));
    assert!(e.to_string().len() < 4000, "{} bytes", e.to_string().len());
    let long_value = line(&format!("sampling = \"{}\"", "x".repeat(10_000_000)));
    let m = rejects(&long_value, &[], "model.sampling");
    assert!(m.len() < 4000, "{} bytes", m.len());
}

#[test]
fn lengths_whose_sum_overflows_are_rejected_naming_the_length() {
    let m = rejects(&line("cell_length = 1e308"), &[], "model.cell_length");
    assert!(m.contains("[1e-100, 1e100]"), "{m}");
    assert!(!m.contains("NaN"), "{m}");
    rejects(&line("ref_lengths = [1, 1e300]"), &[], "model.ref_lengths");
    rejects(&line("cell_length = 1e-300"), &[], "model.cell_length");
}

#[test]
fn continuum_grids_too_small_for_their_scheme_name_nodes() {
    let m = rejects(&line("nodes = 1"), &[], "model.nodes");
    assert!(m.contains(">= 2") && m.contains("prescribed"), "{m}");
    let m = rejects(
        &line("nodes = 2\ncontinuum_scheme = \"thesis\""),
        &[],
        "model.nodes",
    );
    assert!(m.contains(">= 3"), "{m}");
    // the default grid is `cells`: named as such
    let m = rejects(
        &line("continuum_scheme = \"thesis\"").replace("cells = 10", "cells = 2"),
        &[],
        "model.nodes",
    );
    assert!(m.contains("default: `cells` = 2"), "{m}");
    // the discrete model alone needs no grid
    assert!(load(&line("nodes = 1\nmodels = [\"discrete\"]"), &[]).is_ok());
    assert!(load(&line("nodes = 3\ncontinuum_scheme = \"thesis\""), &[]).is_ok());
}

#[test]
fn a_ring_whose_drag_is_zero_everywhere_needs_a_gauge() {
    for k in [
        "0",
        "{ type = \"random\", low = 0, high = 0, seed = 1 }",
        "{ type = \"gaussian\", base = 0, amplitude = 0, centre = 0.5, width = 0.1 }",
        "{ type = \"piecewise\", breaks = [0.5], values = [0, 0] }",
        "{ type = \"per_cell\", values = [0, 0, 0] }",
    ] {
        let text = line(&format!("right_end = \"periodic\"\nK = {k}"));
        let m = rejects(&text, &[], "model.K");
        assert!(m.contains("gauge"), "{m}");
        assert!(load(&format!("{text}gauge = true\n"), &[]).is_ok(), "{k}");
    }
    // zero somewhere is fine
    assert!(load(
        &line("right_end = \"periodic\"\nK = { type = \"random\", low = 0, high = 1, seed = 1 }"),
        &[]
    )
    .is_ok());
}

#[test]
fn division_has_a_default_cap_and_a_continuum_only_for_the_area_rule() {
    let div = |d: &str| {
        line(&format!(
            "right_end = \"free\"\ngrowth = {{ sigma0 = 0.1 }}\ndivision = {d}\nmodels = [\"discrete\"]"
        ))
    };
    for d in [
        "{ rule = \"age\", period = 1e-300 }",
        "{ rule = \"area\", ratio = 1.0001 }",
    ] {
        let s = load(&div(d), &[]).unwrap();
        let ModelConfig::Proliferating(cfg) = &s.runs[0].config else {
            panic!("a proliferating line")
        };
        assert_eq!(
            cfg.division.max_cells,
            Some(celltissue::events::DEFAULT_MAX_CELLS),
            "{d}"
        );
    }
    let s = load(&div("{ rule = \"area\", max_cells = 50 }"), &[]).unwrap();
    let ModelConfig::Proliferating(cfg) = &s.runs[0].config else {
        panic!("a proliferating line")
    };
    assert_eq!(cfg.division.max_cells, Some(50));
    rejects(
        &div("{ rule = \"area\", ratoi = 2 }"),
        &[],
        "model.division.ratoi",
    );
    rejects(
        &div("{ rule = \"age\", period = 0 }"),
        &[],
        "model.division.period",
    );
    let m = rejects(
        &div("{ rule = \"age\", period = 2 }").replace("models = [\"discrete\"]", ""),
        &[],
        "model.division.rule",
    );
    assert!(m.contains("area") && m.contains("cell_grid"), "{m}");
    // the cell-number grid takes any rule
    assert!(load(
        &div("{ rule = \"age\", period = 2, cell_grid = {} }")
            .replace("models = [\"discrete\"]", ""),
        &[]
    )
    .is_ok());
}

#[test]
fn division_window_is_read_checked_and_refused_by_the_continuum() {
    let div = |d: &str, models: &str| {
        line(&format!(
            "right_end = \"free\"\ngrowth = {{ sigma0 = 0.1 }}\ndivision = {d}\nmodels = {models}"
        ))
    };
    let s = load(
        &div("{ rule = \"area\", batch_within = 1e-3 }", "[\"discrete\"]"),
        &[],
    )
    .unwrap();
    let ModelConfig::Proliferating(cfg) = &s.runs[0].config else {
        panic!("a proliferating line")
    };
    assert_eq!(cfg.division.batch_within, 1e-3);
    // echoed only when set
    assert_eq!(s.runs[0].config.to_json()["division"]["batch_within"], 1e-3);
    let plain = load(&div("{ rule = \"area\" }", "[\"discrete\"]"), &[]).unwrap();
    assert!(plain.runs[0].config.to_json()["division"]
        .get("batch_within")
        .is_none());
    for (bad, says) in [
        ("-1e-3", ">= 0"),
        ("inf", ">= 0"),
        ("\"soon\"", "expected a number"),
    ] {
        let m = rejects(
            &div(
                &format!("{{ rule = \"area\", batch_within = {bad} }}"),
                "[\"discrete\"]",
            ),
            &[],
            "model.division.batch_within",
        );
        assert!(m.contains(says), "{bad}: {m}");
    }
    for models in ["[\"continuum\"]", "[\"discrete\", \"continuum\"]"] {
        for grid in ["", ", cell_grid = {}"] {
            let m = rejects(
                &div(
                    &format!("{{ rule = \"area\", batch_within = 1e-3{grid} }}"),
                    models,
                ),
                &[],
                "model.division.batch_within",
            );
            assert!(m.contains("discrete line only"), "{m}");
        }
    }
}

#[test]
fn shear_cell_centre_form_with_the_continuum_is_rejected_before_the_run() {
    let shear = "name = \"s\"\n[output]\nseries = [0, 1]\n[model]\nkind = \"shear\"\nform = \"cell_centre\"\n";
    rejects(shear, &[], "model.form");
    assert!(load(shear, &["model.models=[\"discrete\"]"]).is_ok());
}

#[test]
fn sheet_and_shear_take_their_law_from_model_law_and_reject_energy() {
    for kind in [
        "kind = \"sheet\"\ncells_x = 3\ncells_y = 2",
        "kind = \"shear\"\ncells = 3",
    ] {
        let text = format!(
            "name = \"s\"\n[output]\nseries = [0, 1]\n[model]\n{kind}\nlaw = {{ law = \"neo_hookean\", mu = 5 }}\n"
        );
        let s = load(&text, &[]).unwrap();
        let run_law = match &s.runs[0].config {
            ModelConfig::Sheet(_, l) | ModelConfig::Shear(_, l) => l.clone(),
            _ => panic!("{kind}"),
        };
        assert_eq!(serde_json::to_value(&run_law).unwrap()["mu"], 5.0);
        let json = s.runs[0].config.to_json();
        assert_eq!(json["law"]["mu"], 5.0);
        assert!(json.get("energy").is_none());
        let m = rejects(&text.replace("law = {", "energy = {"), &[], "model.energy");
        assert!(m.contains("model.law"), "{m}");
    }
}

#[test]
fn set_of_a_swept_key_is_an_error_naming_the_conflict() {
    let swept = line("[sweep]\nparameter = \"K\"\nvalues = [0.1, 1]");
    for set in ["model.K=0.1", "K=0.1", "model.K.type=\"gaussian\""] {
        let e = load(&swept, &[set]).unwrap_err();
        let m = e.to_string();
        assert!(matches!(e, ScenarioError::Set { .. }), "{set}: {m}");
        assert!(
            m.contains("conflicts with the sweep") && m.contains("model.K"),
            "{m}"
        );
    }
    // changing the swept values is the documented way
    let s = load(&swept, &["sweep.values=[0.5]"]).unwrap();
    assert_eq!(s.runs.len(), 2);
    assert_eq!(s.runs[0].label, "discrete K=0.5");
    // other keys are fine
    assert!(load(&swept, &["model.k1=0.2"]).is_ok());
    // grid sweeps too
    let grid = line("[sweep]\ngrid = [{ parameter = \"k1\", values = [0.1, 0.2] }, { parameter = \"m\", values = [0, 1] }]");
    let m = load(&grid, &["model.m=2"]).unwrap_err().to_string();
    assert!(m.contains("`model.m` is swept"), "{m}");
}

#[test]
fn a_swept_value_is_validated_and_named_by_its_place_in_the_sweep() {
    let m = rejects(
        &line("[sweep]\nparameter = \"k1\"\nvalues = [0.1, 1.5]"),
        &[],
        "model.k1",
    );
    assert!(m.contains("sweep.values[1] = 1.5"), "{m}");
    let m = rejects(
        &line("[sweep]\nparameter = \"cells\"\nvalues = [10, 1e300]"),
        &[],
        "model.cells",
    );
    assert!(
        m.contains("sweep.values[1]") && m.contains("non-negative integer"),
        "{m}"
    );
    let m = rejects(
        &line("[sweep]\ngrid = [{ parameter = \"k1\", values = [0.1] }, { parameter = \"mu.width\", values = [0.1, 1e-300] }]\n")
            .replace("cells = 10", "cells = 10\nmu = { type = \"gaussian\", base = 1, amplitude = 1, centre = 0.5, width = 0.1 }"),
        &[],
        "model.mu.width",
    );
    assert!(m.contains("sweep.grid[1].values[1] = 1e-300"), "{m}");
    assert!(!m.contains("sweep.grid[0]"), "only the value at fault: {m}");
}

#[test]
fn grid_and_zip_sweeps_write_the_thesis_families() {
    // Figs 4.3b–d: k1 family × drag exponent m, as a grid
    let sheet = "name = \"s\"\n[output]\nseries = [0, 1]\n[model]\nkind = \"sheet\"\n\
                 [sweep]\ngrid = [{ parameter = \"k1\", values = [0.1, 0.3, 0.5] }, \
                 { parameter = \"drag_exponent\", values = [0, 1], labels = [\"m0\", \"m1\"] }]\n";
    let s = load(sheet, &[]).unwrap();
    assert_eq!(s.runs.len(), 12);
    assert_eq!(s.runs[0].label, "discrete k1=0.1 drag_exponent=m0");
    assert_eq!(s.runs[11].label, "continuum k1=0.5 drag_exponent=m1");
    let ModelConfig::Sheet(cfg, _) = &s.runs[7].config else {
        panic!("a sheet")
    };
    // run 7 = point 3 (k1 = 0.3, m = 1), continuum
    assert_eq!((cfg.k1, cfg.drag_exponent), (0.3, 1.0));
    let info = s.sweep.as_ref().unwrap();
    assert_eq!(info.parameters, ["model.k1", "model.drag_exponent"]);
    // Fig 3.3a–b: with / without a proliferation-like change, zipped with m
    let zipped = line(
        "right_end = \"free\"\ngrowth = { sigma0 = 0.1 }\n\
         [sweep]\nzip = [{ parameter = \"m\", values = [0, 1] }, \
         { parameter = \"growth.sigma0\", values = [0.1, 0.2] }]",
    );
    let s = load(&zipped, &[]).unwrap();
    let labels: Vec<&str> = s.runs.iter().map(|r| r.label.as_str()).collect();
    assert_eq!(
        labels,
        [
            "discrete m=0 growth.sigma0=0.1",
            "continuum m=0 growth.sigma0=0.1",
            "discrete m=1 growth.sigma0=0.2",
            "continuum m=1 growth.sigma0=0.2"
        ]
    );
    // labels are unique as file names
    let clash = line("[sweep]\nparameter = \"K\"\nvalues = [1, 2]\nlabels = [\"a+b\", \"a+b\"]");
    rejects(&clash, &[], "sweep.values[1]");
    let clash = line("[sweep]\nparameter = \"K\"\nvalues = [1, 2]\nlabels = [\"a,b\", \"a;b\"]");
    let m = rejects(&clash, &[], "sweep.labels");
    assert!(m.contains("same files"), "{m}");
}

#[test]
fn sweep_profiles_need_a_sweep_and_one_of_the_profile_times() {
    let m = rejects(
        &line("[plots]\nsweep_profiles = [1]"),
        &[],
        "plots.sweep_profiles",
    );
    assert!(m.contains("needs a [sweep]"), "{m}");
    let swept =
        line("[sweep]\nparameter = \"K\"\nvalues = [0.1, 1]\n[plots]\nsweep_profiles = [1, 0.5]");
    let m = rejects(&swept, &[], "plots.sweep_profiles.1");
    assert!(
        m.contains("time 0.5 is not one of the profile times") && m.contains("[1]"),
        "{m}"
    );
    let ok = load(&swept.replace("[1, 0.5]", "[1]"), &[]).unwrap();
    assert_eq!(ok.plots.sweep_profiles, [1.0]);
}

#[test]
fn the_jacobian_age_is_bdf_only_and_bounded() {
    let ok = load(&line(""), &["solver.jacobian_age=100"]).unwrap();
    assert_eq!(ok.runs[0].solver.jacobian_age, 100);
    rejects(&line(""), &["solver.jacobian_age=0"], "solver.jacobian_age");
    let m = rejects(
        &line(""),
        &["solver.method=\"radau\"", "solver.jacobian_age=10"],
        "solver.jacobian_age",
    );
    assert!(m.contains("bdf"), "{m}");
}

/// `solver.max_steps` caps a run's steps (default 10⁶): echoed only when set, bounded, and a
/// run that reaches it stops saying so, with the steps it took kept.
#[test]
fn the_step_cap_is_a_key_that_stops_a_run_by_name() {
    use celltissue::scenario::execute;
    let plain = load(&line(""), &[]).unwrap();
    assert_eq!(plain.runs[0].solver.max_steps, 1_000_000);
    assert!(serde_json::to_value(plain.runs[0].solver)
        .unwrap()
        .get("max_steps")
        .is_none());
    for bad in ["0", "-3", "1.5", "1000000000001"] {
        rejects(
            &line(""),
            &[&format!("solver.max_steps={bad}")],
            "solver.max_steps",
        );
    }
    let capped = load(&line(""), &["solver.max_steps=5"]).unwrap();
    assert_eq!(capped.runs[0].solver.options().unwrap().max_steps, 5);
    assert_eq!(
        serde_json::to_value(capped.runs[0].solver).unwrap()["max_steps"],
        5
    );
    let summary = execute::run_all(&capped, execute::run_spec, |_| {});
    let rec = &summary.runs[0];
    let err = rec
        .error
        .as_deref()
        .expect("five steps do not reach the end");
    assert!(err.contains("max_steps = 5"), "{err}");
    assert_eq!(rec.stats.steps, 5);
    assert!(
        !rec.series.t.is_empty(),
        "the outputs before the cap are kept"
    );
    let free = execute::run_all(&plain, execute::run_spec, |_| {});
    assert!(free.runs[0].error.is_none() && free.runs[0].stats.steps > 5);
}

#[test]
fn interpolated_rates_are_read_checked_and_echoed_only_when_asked_for() {
    let viscous = line("eta = 0.5");
    let set = load(&viscous, &["solver.interpolate_rates=true"]).unwrap();
    assert!(set.runs[0].solver.interpolate_rates);
    assert!(set.runs[0].solver.options().unwrap().interpolate_rates);
    let echo = serde_json::to_value(set.runs[0].solver).unwrap();
    assert_eq!(echo["interpolate_rates"], true);
    let plain = load(&viscous, &[]).unwrap();
    assert!(!plain.runs[0].solver.interpolate_rates);
    assert!(serde_json::to_value(plain.runs[0].solver)
        .unwrap()
        .get("interpolate_rates")
        .is_none());
    rejects(
        &viscous,
        &["solver.interpolate_rates=2"],
        "solver.interpolate_rates",
    );
    // on cells whose outputs read no rates it would change nothing: rejected, not ignored
    let m = rejects(
        &line(""),
        &["solver.interpolate_rates=true"],
        "solver.interpolate_rates",
    );
    assert!(m.contains("η > 0"), "{m}");
    assert!(load(&line(""), &["solver.interpolate_rates=false"]).is_ok());
}

#[test]
fn landing_on_outputs_is_read_and_echoed_only_when_set() {
    let set = load(&line(""), &["solver.land_on_outputs=false"]).unwrap();
    assert_eq!(set.runs[0].solver.land_on_outputs, Some(false));
    let echo = serde_json::to_value(set.runs[0].solver).unwrap();
    assert_eq!(echo["land_on_outputs"], false);
    let plain = load(&line(""), &[]).unwrap();
    assert_eq!(plain.runs[0].solver.land_on_outputs, None);
    assert!(serde_json::to_value(plain.runs[0].solver)
        .unwrap()
        .get("land_on_outputs")
        .is_none());
    rejects(
        &line(""),
        &["solver.land_on_outputs=2"],
        "solver.land_on_outputs",
    );
}

#[test]
fn end_keys_the_right_end_does_not_read_are_rejected_not_ignored() {
    // each key with an end that reads it loads; with one that does not, the error names it
    let cases = [
        ("k1 = 0.3", "prescribed", ["free", "periodic"]),
        ("t_ramp = 5", "prescribed", ["free", "periodic"]),
        ("ramp = \"polynomial\"", "prescribed", ["free", "periodic"]),
        ("force = 0.1", "free", ["prescribed", "periodic"]),
        ("gauge = true", "periodic", ["prescribed", "free"]),
    ];
    for (key_line, reads, others) in cases {
        let key = format!("model.{}", key_line.split(' ').next().unwrap());
        // (a free end needs a driver: K = 1)
        let body = |end: &str| line(&format!("K = 1\nright_end = \"{end}\"\n{key_line}"));
        assert!(load(&body(reads), &[]).is_ok(), "{key_line} with {reads}");
        for end in others {
            let m = rejects(&body(end), &[], &key);
            assert!(m.contains(&format!("right_end = \"{reads}\"")), "{m}");
        }
    }
    // in a sweep over the end, the run that would ignore the key is named
    let swept = format!(
        "{}[sweep]\nparameter = \"right_end\"\nvalues = [\"prescribed\", \"free\"]\n",
        line("K = 1\nk1 = 0.3")
    );
    let m = rejects(&swept, &[], "model.k1");
    assert!(m.contains("free"), "{m}");
    // a sheet's ramp keys with a free side x = l
    let sheet = |right: &str, key_line: &str| {
        format!(
            "name = \"s\"\n[output]\nseries = [0, 1]\n[model]\nkind = \"sheet\"\n\
             right = \"{right}\"\ngrowth = {{ sigma0 = 0.1 }}\n{key_line}\n"
        )
    };
    for (key_line, key) in [
        ("k1 = 0.3", "model.k1"),
        (
            "ramp = { kind = \"exponential\", t_ramp = 5 }",
            "model.ramp",
        ),
    ] {
        assert!(
            load(&sheet("prescribed", key_line), &[]).is_ok(),
            "{key_line}"
        );
        let m = rejects(&sheet("free", key_line), &[], key);
        assert!(m.contains("right = \"prescribed\""), "{m}");
    }
}

#[test]
fn an_error_unrelated_to_the_swept_key_names_the_run_but_no_swept_value() {
    let swept = line("[sweep]\nparameter = \"K\"\nvalues = [1, 2]\n[solver]\nrtol = -1");
    let m = rejects(&swept, &[], "solver.rtol");
    assert!(
        m.contains("in run `K=1`") && !m.contains("swept value"),
        "{m}"
    );
    // an error on the swept key itself still names the value it came from
    let swept = line("[sweep]\nparameter = \"K\"\nvalues = [1, -2]");
    let m = rejects(&swept, &[], "model.K");
    assert!(m.contains("swept value sweep.values[1] = -2"), "{m}");
}

#[test]
fn a_force_against_a_drag_too_small_to_step_is_rejected_and_the_bound_runs() {
    // F_A = 1 at atol = 1e-10 started the top edge at 2e300 cell widths per unit time at
    // k_th = 1e-298: the solver's first rate in tolerance units overflowed and the run stopped
    // at t = 0 ("non-finite Newton update") after `validate` had passed.
    use celltissue::scenario::execute::run_spec;
    let column = |extra: &str| {
        format!(
            "name = \"s\"\n[solver]\nrtol = 1e-8\natol = 1e-10\n[output]\nseries = [0, 0.5, 1]\n\
             [model]\nkind = \"shear\"\nmodels = [\"discrete\", \"continuum\"]\nnodes = 20\n\
             cells = 10\nforce = 1.0\n{extra}\n"
        )
    };
    for (k, least) in [
        ("k_th = 1e-298", "k_th ≥ 2e-290"),
        ("drag = 1e-300", "drag ≥ 1e-290"),
    ] {
        let key = format!("model.{}", k.split(' ').next().unwrap());
        let m = rejects(&column(k), &[], &key);
        assert!(m.contains(least) && m.contains("atol = 1e-10"), "{m}");
    }
    // at the bound both models run
    let s = load(&column("k_th = 2e-290"), &[]).unwrap();
    for spec in &s.runs {
        let rec = run_spec(spec);
        assert!(rec.error.is_none(), "{:?}", rec.error);
    }
    // Kelvin–Voigt cells bound the rate by their viscosity: any drag runs
    let viscous = column("k_th = 1e-305\nviscosity = { model = \"kelvin_voigt\", eta = 1 }");
    for spec in &load(&viscous, &[]).unwrap().runs {
        let rec = run_spec(spec);
        assert!(rec.error.is_none(), "{:?}", rec.error);
    }
    // a sheet's external pressure on its free top, the same
    let sheet = |extra: &str| {
        format!(
            "name = \"p\"\n[solver]\nrtol = 1e-8\natol = 1e-10\n[output]\nseries = [0, 1]\n\
             [model]\nkind = \"sheet\"\ncells_x = 4\ncells_y = 4\n{extra}\n"
        )
    };
    let m = rejects(
        &sheet("k_th = 1e-299\nexternal_pressure = 1.0"),
        &[],
        "model.k_th",
    );
    assert!(
        m.contains("external pressure") && m.contains("k_th ≥ 2e-290"),
        "{m}"
    );
    for ok in ["k_th = 1e-300", "k_th = 2e-290\nexternal_pressure = 1.0"] {
        for spec in &load(&sheet(ok), &[]).unwrap().runs {
            let rec = run_spec(spec);
            assert!(rec.error.is_none(), "{ok}: {:?}", rec.error);
        }
    }
}

/// Cells far stiffer than their growth law's stress scale (μ = 1e8 against σ₀ = 0.1, the
/// `fig3_1` line at K = 1e-2): at rtol 1e-6 a stretch tolerance leaves the stress that sets
/// growth free by 4μ·(rtol + atol) ≈ 400, and the run ended "ok" with l(1) 22 % too long after
/// 8.6·10⁵ steps. `validate` rejects it, naming `solver.rtol` and the tolerance that runs; at
/// that tolerance the length is within 10·rtol of an rtol 1e-11 run (measured 3.6e-11).
#[test]
fn cells_too_stiff_for_their_growth_law_at_the_tolerance_are_rejected() {
    use celltissue::scenario::execute;
    let growing = |mu: &str, rtol: &str, atol: &str| {
        format!(
            "name = \"stiff\"\n[solver]\nrtol = {rtol}\natol = {atol}\n[output]\n\
             series = [0, 1]\n[model]\nkind = \"line\"\nmodels = [\"discrete\"]\ncells = 100\n\
             right_end = \"free\"\nK = 1e-2\nmu = {mu}\ngrowth = {{ sigma0 = 0.1 }}\n"
        )
    };
    let m = rejects(&growing("1e8", "1e-6", "1e-8"), &[], "solver.rtol");
    assert!(
        m.contains("E·(rtol + atol) = 4.04e2") && m.contains("rtol + atol ≤ 2.50e-9"),
        "{m}"
    );
    // soft cells, the thesis's μ = 1, at the same tolerance
    assert!(load(&growing("1.0", "1e-6", "1e-8"), &[]).is_ok());
    // a gaussian μ is bounded by its peak; a growing sheet by its law's modulus
    let bump = growing(
        "{ type = \"gaussian\", base = 1.0, amplitude = 1e8, centre = 0.5, width = 0.1 }",
        "1e-6",
        "1e-8",
    );
    rejects(&bump, &[], "solver.rtol");
    let sheet = "name = \"s\"\n[output]\nseries = [0, 1]\n[model]\nkind = \"sheet\"\n\
                 cells_x = 4\ncells_y = 4\nright = \"free\"\nlaw = { law = \"neo_hookean\", mu = 1e8 }\n\
                 growth = { sigma0 = 0.1 }\n";
    assert!(rejects(sheet, &[], "solver.rtol").contains("model.law"));

    let length = |rtol: &str, atol: &str| {
        let s = load(&growing("1e8", rtol, atol), &[]).unwrap();
        let rec = execute::run_all(&s, execute::run_spec, |_| {})
            .runs
            .remove(0);
        assert!(rec.error.is_none(), "{:?}", rec.error);
        rec.series.length[1]
    };
    let (runs, tight) = (length("2.4e-9", "1e-11"), length("1e-11", "1e-13"));
    let err = (runs / tight - 1.0).abs();
    assert!(
        err < 10.0 * 2.4e-9,
        "l(1) = {runs} against {tight}: {err:e}"
    );
}

/// `plots.position` and `plots.rectangles` draw a line of cells. On a sheet the position plot
/// drew the rows end to end as one sawtooth, and the rectangles were skipped in silence; on a
/// shear column the position plot was x against x. They are rejected there, and the
/// rectangles without a discrete run.
#[test]
fn line_plots_are_rejected_for_sheets_and_shear_columns() {
    let sheet = "name = \"s\"\n[output]\nseries = [0, 1]\n[model]\nkind = \"sheet\"\n\
                 cells_x = 4\ncells_y = 4\n";
    let shear = "name = \"c\"\n[output]\nseries = [0, 1]\n[model]\nkind = \"shear\"\ncells = 4\n";
    for key in ["plots.position", "plots.rectangles"] {
        let set = format!("{key}=true");
        assert!(rejects(sheet, &[&set], key).contains("not a sheet"));
        assert!(rejects(shear, &[&set], key).contains("not a shear column"));
        assert!(load(&line(""), &[&set]).is_ok());
    }
    let m = rejects(
        &line(""),
        &["plots.rectangles=true", "model.models=[\"continuum\"]"],
        "plots.rectangles",
    );
    assert!(m.contains("discrete"), "{m}");
}

/// An external pressure given as a list or a piecewise field is checked before a run, for
/// either sign: an empty list (which failed mid-run, indexing no values) and a non-finite value
/// are named; negative values are allowed.
#[test]
fn an_external_pressure_list_is_checked_before_a_run() {
    for (value, words) in [
        ("[]", "must not be empty"),
        ("[0.1, inf]", "must be finite"),
        (
            "{ type = \"piecewise\", breaks = [0.5], values = [0.1, nan] }",
            "must be finite",
        ),
    ] {
        let m = rejects(
            &line(&format!("external_pressure = {value}")),
            &[],
            "model.external_pressure",
        );
        assert!(m.contains(words), "{value}: {m}");
    }
    load(&line("external_pressure = [0.1, -0.2, 0.3]"), &[]).unwrap();
}

/// Cells with a Maxwell branch divide on the discrete line and in both proliferating continua,
/// and the cell-number grid merges them (tests/division_maxwell_cells.rs checks the runs).
#[test]
fn a_maxwell_branch_divides_everywhere_and_merges_on_the_cell_grid() {
    let text = line(
        "right_end = \"free\"\ngrowth = { sigma0 = 0.1 }\ndivision = { rule = \"area\" }\n\
         viscosity = { model = \"standard_linear_solid\", mu_m = 1, eta_m = 2 }",
    );
    for models in [
        "[\"discrete\"]",
        "[\"continuum\"]",
        "[\"discrete\", \"continuum\"]",
    ] {
        load(&text, &[&format!("model.models={models}")]).unwrap();
    }
    load(&text, &["model.division.cell_grid={}"]).unwrap();
    load(&text, &["model.division.cell_grid={merge_below=1e-3}"]).unwrap();
}
