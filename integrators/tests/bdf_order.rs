//! Observed order of accuracy of the BDF at each fixed order k = 1..5, by a **tolerance sweep**
//! (the BDF is a multistep method: a fixed-step study would be dominated by its low-order
//! start). With `BdfOptions::fixed_order = Some(k)` the step-size control stays on; the global error then
//! behaves like `C·N^{−k}` in the number of steps N, so the slope of log(err) against log(N),
//! fitted by least squares over the sweep, must be −k ± 0.3.
//!
//! Problem: harmonic oscillator y1' = y2, y2' = −y1 on [0, 40], exact (cos t, −sin t) — smooth,
//! non-stiff, with a long enough interval that the start-up phase is a negligible part of N.

mod common;

use common::residual_fn;
use integrators::{MethodKind, Options, Problem, Solver};

/// `ẏ1 = y2`, `ẏ2 = −y1`.
fn oscillator() -> impl Problem {
    residual_fn(2, |_t, y, yp, r| {
        r[0] = yp[0] - y[1];
        r[1] = yp[1] + y[0];
        Ok(())
    })
}

fn slope(xs: &[f64], ys: &[f64]) -> f64 {
    let n = xs.len() as f64;
    let mx = xs.iter().sum::<f64>() / n;
    let my = ys.iter().sum::<f64>() / n;
    let sxy: f64 = xs.iter().zip(ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

#[test]
fn bdf_fixed_order_tolerance_sweep_observed_order() {
    let t_end: f64 = 40.0;
    let exact = [t_end.cos(), -t_end.sin()];
    // tolerance ranges per order: errors well above round-off, steps well above start-up
    let ranges: [(f64, f64); 5] = [
        (1e-4, 1e-7),
        (1e-5, 1e-9),
        (1e-6, 1e-11),
        (1e-6, 1e-12),
        (1e-6, 1e-12),
    ];
    for k in 1..=5 {
        let (hi, lo) = ranges[k - 1];
        let mut ln_n = Vec::new();
        let mut ln_e = Vec::new();
        let mut tol = hi;
        while tol >= lo * 0.999 {
            let o = Options {
                rtol: tol,
                atol: tol,
                bdf: integrators::BdfOptions {
                    fixed_order: Some(k),
                    max_order: 5,
                    ..Default::default()
                },
                ..Default::default()
            };
            let sol = Solver::new(MethodKind::Bdf, o)
                .solve(&mut oscillator(), 0.0, &[1.0, 0.0], &[t_end])
                .unwrap();
            let y = &sol.y[0];
            let err = (y[0] - exact[0]).abs().max((y[1] - exact[1]).abs());
            ln_n.push((sol.stats.steps as f64).ln());
            ln_e.push(err.ln());
            eprintln!("k={k} tol={tol:e}: steps {} err {err:.3e}", sol.stats.steps);
            tol /= 10f64.sqrt();
        }
        let p = -slope(&ln_n, &ln_e);
        eprintln!("k={k}: observed order {p:.3}");
        assert!((p - k as f64).abs() <= 0.3, "order {k}: observed {p}");
    }
}
