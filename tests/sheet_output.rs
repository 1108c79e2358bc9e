//! Output of the sheet runs: VTK (`.vtu` per snapshot + `.pvd`), PNG snapshots coloured by
//! pressure, profiles with the per-cell extra fields, config validation errors naming the key.

use celltissue::observe::ModelKind;
use celltissue::sheet::{run::Outputs, run_sheet, SheetConfig, SolverSettings, TopBoundary};

#[test]
fn sheet_run_writes_vtu_pvd_and_png_snapshots() {
    let dir = std::env::temp_dir().join(format!("celltissue_sheet_out_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let cfg = SheetConfig {
        cells_x: 4,
        cells_y: 3,
        ..Default::default()
    };
    let out = Outputs {
        times: vec![0.0, 1.0, 2.0],
        profile_times: vec![1.0, 2.0],
        dir: Some(dir.clone()),
        prefix: None,
    };
    let rec = run_sheet(
        &cfg,
        &cfg.law,
        ModelKind::Discrete,
        None,
        &SolverSettings::default(),
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
    ] {
        assert_eq!(rec.profiles[0].extra[key].len(), 12, "{key}");
    }
    let vtu = std::fs::read_to_string(dir.join("sheet_0000.vtu")).unwrap();
    assert!(vtu.contains("NumberOfCells=\"12\"") && vtu.contains("NumberOfPoints=\"96\""));
    for name in ["pressure", "lambda1", "lambda2", "lambda3"] {
        assert!(vtu.contains(&format!("Name=\"{name}\"")), "{name}");
    }
    let pvd = std::fs::read_to_string(dir.join("sheet.pvd")).unwrap();
    assert!(pvd.contains("sheet_0001.vtu"));
    let png = std::fs::read(dir.join("sheet_pressure_0001.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    let json = serde_json::to_string(&rec).unwrap();
    assert!(json.contains("\"mean_pressure\"") && json.contains("\"boundary_mismatch_mean\""));
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
