//! Output of the sheet runs: the runner returns profiles with the per-cell fields and extents
//! (and writes nothing); the writers draw VTK (`.vtu` per snapshot + `.pvd`) and PNG snapshots
//! coloured by pressure from them; config validation errors name the key.

use celltissue::observe::ModelKind;
use celltissue::output;
use celltissue::runner::OutputTimes;
use celltissue::scenario::{execute, load_str};
use celltissue::sheet::observe::sheet_cells;
use celltissue::sheet::{run_sheet, SheetConfig, TopBoundary};
use celltissue::SolveSettings;

#[test]
fn sheet_run_returns_profiles_and_writes_nothing() {
    let cfg = SheetConfig {
        cells_x: 4,
        cells_y: 3,
        ..Default::default()
    };
    let out = OutputTimes {
        series: vec![0.0, 1.0, 2.0],
        profiles: vec![1.0, 2.0],
    };
    let rec = run_sheet(
        &cfg,
        &cfg.law,
        ModelKind::Discrete,
        None,
        &SolveSettings::default(),
        &out,
    )
    .unwrap();
    assert!(rec.error.is_none());
    assert_eq!(rec.series.t, vec![0.0, 1.0, 2.0]);
    assert_eq!(rec.profiles.len(), 2);
    for key in [
        "Y",
        "y",
        "stretch_y",
        "stretch_z",
        "height",
        "sigma11",
        "sigma22",
        "kappa",
        "x_left",
        "x_right",
        "y_bottom",
        "y_top",
    ] {
        assert_eq!(rec.profiles[0].extra[key].len(), 12, "{key}");
    }
    // the cells rebuilt from the profile tile the sheet: each row spans [0, l(t)]
    let cells = sheet_cells(&rec.profiles[0]);
    for k in 1..=3 {
        let row: Vec<_> = cells.iter().filter(|c| c.k == k).collect();
        assert_eq!(row.len(), 4);
        assert_eq!(row[0].x[0], 0.0);
        for w in row.windows(2) {
            assert_eq!(w[0].x[1], w[1].x[0]);
        }
    }
    let json = serde_json::to_string(&rec).unwrap();
    assert!(json.contains("\"mean_pressure\"") && json.contains("\"boundary_mismatch_mean\""));
}

#[test]
fn the_writers_draw_vtu_pvd_and_png_snapshots_of_a_sheet_scenario() {
    let dir = std::env::temp_dir().join(format!("celltissue_sheet_out_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let text = "name = \"sheet_out\"\n[output]\nseries = [0, 1, 2]\nprofiles = [1, 2]\n\
                [model]\nkind = \"sheet\"\nmodels = [\"discrete\"]\ncells_x = 4\ncells_y = 3\n";
    let s = load_str(text, "sheet_out.toml".as_ref(), &[]).unwrap();
    let summary = execute::run_all(&s, execute::run_spec, |_| {});
    let w = output::write_all(&dir, &s, &summary).unwrap();
    assert!(w.plot_errors.is_empty(), "{:?}", w.plot_errors);
    let vtu = std::fs::read_to_string(dir.join("discrete_0000.vtu")).unwrap();
    assert!(vtu.contains("NumberOfCells=\"12\"") && vtu.contains("NumberOfPoints=\"96\""));
    for name in ["pressure", "lambda1", "lambda2", "lambda3"] {
        assert!(vtu.contains(&format!("Name=\"{name}\"")), "{name}");
    }
    let pvd = std::fs::read_to_string(dir.join("discrete.pvd")).unwrap();
    assert!(pvd.contains("discrete_0001.vtu"));
    let png = std::fs::read(dir.join("discrete_pressure_0001.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    // every file is the writers' (listed in what they report)
    assert!(w.data.iter().any(|p| p.ends_with("discrete_0001.vtu")));
    assert!(w
        .plots
        .iter()
        .any(|p| p.ends_with("discrete_pressure_0001.png")));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn invalid_configs_name_the_key() {
    let bad = SheetConfig {
        k1: 1.5,
        ..Default::default()
    };
    assert!(bad
        .validate()
        .unwrap_err()
        .to_string()
        .starts_with("k1 = 1.5"));
    let bad = SheetConfig {
        top: TopBoundary::Periodic,
        k_th: Some(0.0),
        ..Default::default()
    };
    assert!(bad.validate().unwrap_err().to_string().contains("k_th"));
    let err = toml::from_str::<SheetConfig>("cells_x = 3\nbogus = 1").unwrap_err();
    assert!(err.to_string().contains("bogus"));
    let cfg: SheetConfig =
        toml::from_str("law = { law = \"mooney_rivlin\", c1 = 0.3, c2 = 0.2 }\ntop = \"periodic\"")
            .unwrap();
    assert_eq!(cfg.law.name(), "mooney_rivlin");
}
