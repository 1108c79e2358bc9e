//! A continuum's records count the tissue's cells, not its segments or nodes: its `cells`
//! series is N (whole for a grid over N cells), its per-cell averages weight each segment by
//! the cells it stands for, and its profiles say how many that is (`segment_cells`).

use celltissue::line::config::ContinuumScheme;
use celltissue::line::{run_line, LineConfig, OutputTimes, SolveSettings};
use celltissue::observe::{ModelKind, RunRecord};

fn run(cfg: &LineConfig, nodes: usize) -> RunRecord {
    let times = OutputTimes {
        series: vec![0.0, 0.5, 2.0],
        profiles: vec![2.0],
    };
    let rec = run_line(
        cfg,
        ModelKind::Continuum,
        Some(nodes),
        &SolveSettings::default(),
        &times,
    );
    assert!(rec.error.is_none(), "{:?}", rec.error);
    rec
}

#[test]
fn a_continuum_counts_the_tissues_cells_not_its_segments() {
    let cfg = LineConfig {
        cells: 100,
        k: 1.0.into(),
        ..Default::default()
    };
    for nodes in [10, 25, 100, 101, 333] {
        let rec = run(&cfg, nodes);
        assert_eq!(rec.series.extra["cells"], [100.0; 3], "n = {nodes}");
        assert_eq!(rec.series.extra["mean_alpha"][0], 1.0, "n = {nodes}");
        let counts = rec.profiles[0].extra.get("segment_cells");
        if nodes == 100 {
            assert!(counts.is_none()); // one cell per segment: the discrete line itself
        } else {
            let counts = counts.unwrap();
            assert_eq!(counts.len(), nodes);
            assert!(
                (counts.iter().sum::<f64>() - 100.0).abs() < 1e-11,
                "n = {nodes}"
            );
        }
    }
    // the thesis scheme's nodes stand for the cells within half a spacing: half at the ends
    let thesis = LineConfig {
        continuum_scheme: ContinuumScheme::Thesis,
        k: 0.01.into(), // K = 1 leaves a boundary layer thinner than 21 nodes resolve
        ..cfg.clone()
    };
    let rec = run(&thesis, 21);
    let n = rec.series.extra["cells"][0];
    assert!((n - 100.0).abs() < 1e-12, "{n}");
    let counts = &rec.profiles[0].extra["segment_cells"];
    assert_eq!((counts[0], counts[1], counts[20]), (2.5, 5.0, 2.5));
}

#[test]
fn unequal_cells_are_counted_and_averaged_per_cell() {
    // 40 cells alternately 0.5 and 1.5 long on 30 segments: each segment holds a different
    // number of cells, and every per-cell average weighs it by that number
    let cfg = LineConfig {
        ref_lengths: Some(
            (0..40)
                .map(|i| if i % 2 == 0 { 0.5 } else { 1.5 })
                .collect(),
        ),
        k: 0.0.into(),
        ..Default::default()
    };
    let rec = run(&cfg, 30);
    for n in &rec.series.extra["cells"] {
        assert!((n - 40.0).abs() < 1e-12, "{n}");
    }
    let counts = &rec.profiles[0].extra["segment_cells"];
    assert!(
        counts.iter().any(|c| (c - counts[0]).abs() > 0.1),
        "{counts:?}"
    );
    // without drag and with one modulus the stretch is uniform, so every average is it
    let length = rec.series.length[2];
    let mean = rec.series.extra["mean_alpha"][2];
    assert!(
        (mean - length / 40.0).abs() < 1e-6,
        "{mean} vs {}",
        length / 40.0
    );
}
