//! Invariants of every line run (issue #3): Σ cell lengths = l(t), cells stay ordered (all
//! stretches positive), no NaN — for heterogeneous viscous lines, discrete and continuum, and
//! with a free end and growth.

use celltissue::cell::{Field, TanhGrowth};
use celltissue::line::config::RightEndKind;
use celltissue::line::{run_line, LineConfig, OutputTimes, SolveSettings};
use celltissue::observe::{ModelKind, RunRecord};

fn check(rec: &RunRecord, prescribed: bool) {
    assert!(rec.error.is_none(), "{:?}", rec.error);
    for v in [
        &rec.series.length,
        &rec.series.max_pressure,
        &rec.series.min_pressure,
        &rec.series.max_stretch,
        &rec.series.min_stretch,
    ] {
        assert!(v.iter().all(|x| x.is_finite()));
    }
    assert!(rec.series.min_stretch.iter().all(|&a| a > 0.0));
    for (k, &t) in rec.series.t.iter().enumerate() {
        if prescribed {
            let l = 50.0 * (0.9 + 0.1 * (-t).exp());
            assert!((rec.series.length[k] - l).abs() < 1e-10 * l, "t = {t}");
        }
    }
    for p in &rec.profiles {
        assert!(
            p.x.windows(2).all(|w| w[1] > w[0]),
            "centres out of order at t = {}",
            p.t
        );
        // Σ L₀ λ = l: with unit-length reference cells of the model, lengths add up
        let lambda = &p.extra["lambda"];
        let h = 50.0 / lambda.len() as f64;
        let g = p.extra.get("g");
        let sum: f64 = lambda.iter().map(|l| l * h).sum();
        let k = rec.series.t.iter().position(|&t| t == p.t).unwrap();
        assert!(
            (sum - rec.series.length[k]).abs() < 1e-9 * sum,
            "Σλh = {sum}"
        );
        if let Some(g) = g {
            assert!(g.iter().all(|&v| v >= 1.0));
        }
    }
}

fn cfg() -> LineConfig {
    LineConfig {
        cells: 50,
        k: 0.1.into(),
        eta: Field::Random {
            low: 0.0,
            high: 2.0,
            seed: 3,
        },
        mu: Field::gaussian_bump(1.0, 3.0, 0.3, 0.05),
        ..Default::default()
    }
}

fn times() -> OutputTimes {
    OutputTimes {
        series: (0..=20).map(|k| 0.5 * k as f64).collect(),
        profiles: vec![0.5, 2.0, 10.0],
    }
}

#[test]
fn heterogeneous_viscous_discrete_and_continuum() {
    let s = SolveSettings::default();
    check(
        &run_line(&cfg(), ModelKind::Discrete, None, &s, &times()),
        true,
    );
    check(
        &run_line(&cfg(), ModelKind::Continuum, Some(200), &s, &times()),
        true,
    );
}

#[test]
fn free_end_growth() {
    let c = LineConfig {
        right_end: RightEndKind::Free,
        growth: Some(TanhGrowth::default()),
        m: 1.0,
        ..cfg()
    };
    check(
        &run_line(
            &c,
            ModelKind::Discrete,
            None,
            &SolveSettings::default(),
            &times(),
        ),
        false,
    );
}

#[test]
fn invalid_config_gives_a_record_with_an_error_naming_the_key() {
    let c = LineConfig {
        cells: 0,
        ..Default::default()
    };
    let rec = run_line(
        &c,
        ModelKind::Discrete,
        None,
        &SolveSettings::default(),
        &times(),
    );
    assert!(rec.error.unwrap().contains("cells"));
    let c = LineConfig {
        k: (-1.0).into(),
        ..Default::default()
    };
    let rec = run_line(
        &c,
        ModelKind::Discrete,
        None,
        &SolveSettings::default(),
        &times(),
    );
    assert!(rec.error.unwrap().contains('K'));
}
