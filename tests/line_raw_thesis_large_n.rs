//! The thesis's raw Chapter 2 parameters at large N (issue #3): l₀ = N, K = 1, η = 0, unit-time
//! exponential ramp, t ∈ [0, 10], rtol 1e-6. The end cells are driven to extreme compression; a
//! reference SciPy BDF run at N = 10⁴ "succeeded" with negative cell lengths. Ours must either
//! keep every cell positive or stop with an error naming the cell.

use celltissue::line::{run_line, LineConfig, OutputTimes, SolveSettings};
use celltissue::observe::ModelKind;

#[test]
fn cells_stay_positive_or_the_error_names_the_cell() {
    for n in [1000usize, 4000] {
        let cfg = LineConfig {
            cells: n,
            k: 1.0.into(),
            ..Default::default()
        };
        let times = OutputTimes {
            series: (0..=100).map(|k| 0.1 * k as f64).collect(),
            profiles: vec![1.0, 10.0],
        };
        let rec = run_line(
            &cfg,
            ModelKind::Discrete,
            None,
            &SolveSettings::default(),
            &times,
        );
        let all_finite = rec
            .series
            .min_stretch
            .iter()
            .chain(&rec.series.max_pressure)
            .all(|v| v.is_finite());
        assert!(all_finite, "NaN in outputs");
        match &rec.error {
            None => {
                let lmin = rec
                    .series
                    .min_stretch
                    .iter()
                    .copied()
                    .fold(f64::INFINITY, f64::min);
                println!(
                    "N = {n}: solved, min λ over t = {lmin:.4e}, steps {}",
                    rec.stats.steps
                );
                assert!(lmin > 0.0);
                assert_eq!(rec.series.t.len(), 101);
                for p in &rec.profiles {
                    assert!(p.stretch.iter().all(|&a| a > 0.0));
                    assert!(p.x.windows(2).all(|w| w[1] > w[0]), "cells out of order");
                }
            }
            Some(msg) => {
                println!("N = {n}: stopped: {msg}");
                assert!(msg.contains("cell"), "error must name the cell: {msg}");
            }
        }
    }
}
