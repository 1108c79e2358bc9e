//! Growth without division (docs/model.md §5.5): free end, N₀ = 100, σ₀ = 0.1, η = 0. Ref l(10),
//! min α(10) and l(100) for m = 0; l(100) for m = 1 in forms B and C; forms agree to round-off
//! for m = 0; the length is asymptotically linear for m = 0.

use celltissue::cell::TanhGrowth;
use celltissue::line::config::RightEndKind;
use celltissue::line::{run_line, LineConfig, OutputTimes, SolveSettings};
use celltissue::observe::{ModelKind, RunRecord};
use celltissue::substrate::DragForm;

fn run(k: f64, m: f64, form: DragForm, t: &[f64]) -> RunRecord {
    let cfg = LineConfig {
        k: k.into(),
        m,
        drag_form: form,
        right_end: RightEndKind::Free,
        growth: Some(celltissue::cell::growth_laws::tanh(TanhGrowth::default()).unwrap()),
        ..Default::default()
    };
    let times = OutputTimes {
        series: t.to_vec(),
        profiles: vec![],
    };
    let s = SolveSettings {
        rtol: 1e-8,
        atol: 1e-10,
        ..Default::default()
    };
    let rec = run_line(&cfg, ModelKind::Discrete, None, &s, &times);
    assert!(rec.error.is_none(), "K = {k}, m = {m}: {:?}", rec.error);
    rec
}

/// |a − ref| within half a unit of Ref's last printed digit (plus 1e-5 relative).
fn close(a: f64, r: f64, digit: f64) -> bool {
    (a - r).abs() <= 0.5 * digit + 1e-5 * r
}

#[test]
fn m0_length_and_min_alpha_match_ref() {
    let ks = [1e-5, 1e-3, 1e-2, 1e-1, 1.0];
    let l10 = [528.77, 178.96, 123.69, 106.22, 101.29];
    let amin = [0.9948, 0.9539, 0.9290, 0.9210, 0.9210];
    let l100 = [4390.3, 894.0, 339.2, 163.0, 113.1];
    for i in 0..5 {
        let rec = run(ks[i], 0.0, DragForm::Boundary, &[0.0, 10.0, 100.0]);
        let s = &rec.series;
        println!(
            "K = {:e}: l(10) = {:.3} (Ref {}), min α(10) = {:.5} (Ref {}), l(100) = {:.2} (Ref {})",
            ks[i], s.length[1], l10[i], s.min_stretch[1], amin[i], s.length[2], l100[i]
        );
        assert!(close(s.length[1], l10[i], 0.01), "l(10) K = {}", ks[i]);
        assert!(
            close(s.min_stretch[1], amin[i], 1e-4),
            "min α(10) K = {}",
            ks[i]
        );
        assert!(close(s.length[2], l100[i], 0.1), "l(100) K = {}", ks[i]);
    }
}

#[test]
fn m1_forms_b_and_c_match_ref() {
    let ks = [1e-5, 1e-3, 1e-2, 1e-1, 1.0];
    let b = [2065.5, 356.4, 178.4, 122.9, 106.3];
    let c = [2065.2, 354.3, 176.8, 122.0, 106.0];
    for i in 0..5 {
        let lb = run(ks[i], 1.0, DragForm::Boundary, &[0.0, 100.0])
            .series
            .length[1];
        let lc = run(ks[i], 1.0, DragForm::Centre, &[0.0, 100.0])
            .series
            .length[1];
        println!(
            "K = {:e}: B {lb:.2} (Ref {}), C {lc:.2} (Ref {})",
            ks[i], b[i], c[i]
        );
        assert!(close(lb, b[i], 0.1), "B K = {}", ks[i]);
        assert!(close(lc, c[i], 0.1), "C K = {}", ks[i]);
    }
}

#[test]
fn m0_forms_agree_and_growth_is_asymptotically_linear() {
    let t: Vec<f64> = (0..=10).map(|k| 10.0 * k as f64).collect();
    let b = run(1e-2, 0.0, DragForm::Boundary, &t);
    let c = run(1e-2, 0.0, DragForm::Centre, &t);
    for ((tk, &lb), &lc) in t.iter().zip(&b.series.length).zip(&c.series.length) {
        // same ODE solution; difference only from the integrators' different error paths
        assert!((lb - lc).abs() < 1e-5 * lb, "t = {tk}: {lb} vs {lc}");
    }
    // linear: the growth rate dl/dt over [50,100] is constant to 1 %
    let l = &b.series.length;
    let r1 = (l[7] - l[5]) / 20.0;
    let r2 = (l[10] - l[8]) / 20.0;
    assert!((r1 - r2).abs() < 0.01 * r2, "rates {r1} {r2}");
}
