//! `results.h5` (feature `hdf5`): every run's arrays in one HDF5 file, read back with the HDF5
//! library and compared, array by array, with the same run's `.npz` read by npyz; parameters,
//! stats and provenance as attributes. (`python/tests/test_results_h5.py` reads the same kind of
//! file with h5py, whose HDF5 is its own build, when CI points it at one.)

use celltissue::output::{write_all_with, WriteOptions};
use celltissue::scenario::{execute::run_spec, load};
use std::io::Read;

/// The `.npy` members of an `.npz`, by name, as f64 (int64 members converted).
fn npz(path: &std::path::Path) -> Vec<(String, Vec<u64>, Vec<f64>)> {
    let mut zip = zip::ZipArchive::new(std::fs::File::open(path).unwrap()).unwrap();
    let mut out = Vec::new();
    for i in 0..zip.len() {
        let mut f = zip.by_index(i).unwrap();
        let name = f.name().trim_end_matches(".npy").to_string();
        let mut bytes = Vec::new();
        f.read_to_end(&mut bytes).unwrap();
        let npy = npyz::NpyFile::new(&bytes[..]).unwrap();
        let shape = npy.shape().to_vec();
        let data: Vec<f64> = match npy.dtype() {
            npyz::DType::Plain(t) if t.type_char() == npyz::TypeChar::Int => npy
                .into_vec::<i64>()
                .unwrap()
                .into_iter()
                .map(|v| v as f64)
                .collect(),
            _ => npy.into_vec::<f64>().unwrap(),
        };
        out.push((name, shape, data));
    }
    out
}

#[test]
fn results_h5_holds_every_runs_arrays_and_attributes() {
    // a proliferating scenario: series, stacked and concatenated profiles, divisions
    let path = format!("{}/models/fig3_3b.toml", env!("CARGO_MANIFEST_DIR"));
    let scenario = load(&path, &["output.profiles=[0, 100]".to_string()]).unwrap();
    let summary = celltissue::observe::Summary {
        scenario: scenario.name.clone(),
        runs: scenario.runs.iter().map(run_spec).collect(),
    };
    let dir = std::env::temp_dir().join(format!("celltissue_h5_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    write_all_with(&dir, &scenario, &summary, &WriteOptions::default()).unwrap();

    let file = hdf5::File::open(dir.join("results.h5")).unwrap();
    let text = |loc: &hdf5::Location, name: &str| -> String {
        let v: hdf5::types::VarLenUnicode = loc.attr(name).unwrap().read_scalar().unwrap();
        v.to_string()
    };
    assert_eq!(text(&file, "scenario"), "fig3_3b");
    assert_eq!(file.member_names().unwrap().len(), summary.runs.len());
    let npz_names = celltissue::output::files::npz_names(&summary);
    let mut compared = 0;
    for (index, (rec, npz_name)) in summary.runs.iter().zip(npz_names).enumerate() {
        let run = file.group(&rec.label).unwrap();
        let i: u64 = run.attr("index").unwrap().read_scalar().unwrap();
        assert_eq!(i as usize, index);
        assert_eq!(text(&run, "label"), rec.label);
        let parameters: serde_json::Value =
            serde_json::from_str(&text(&run, "parameters")).unwrap();
        assert_eq!(parameters["K"], 1e-2);
        let stats: serde_json::Value = serde_json::from_str(&text(&run, "stats")).unwrap();
        assert_eq!(stats["steps"], rec.stats.steps);
        for (name, shape, data) in npz(&dir.join(npz_name)) {
            let ds = run.dataset(&name).unwrap();
            let shape_h5: Vec<u64> = ds.shape().iter().map(|&d| d as u64).collect();
            assert_eq!(shape_h5, shape, "{} {name}", rec.label);
            let h5: Vec<f64> = match ds.dtype().unwrap().is::<i64>() {
                true => ds
                    .read_raw::<i64>()
                    .unwrap()
                    .into_iter()
                    .map(|v| v as f64)
                    .collect(),
                false => ds.read_raw::<f64>().unwrap(),
            };
            assert_eq!(h5, data, "{} {name}", rec.label);
            compared += 1;
        }
    }
    // 2 runs: series columns, profiles (t, cells, X, x, stretch, pressure, …) and divisions
    assert!(compared > 30, "{compared} arrays");
    let _ = std::fs::remove_dir_all(&dir);
}
