//! One-shot timings of the line's per-step kernels at N cells (default 10⁶) on the
//! macroscale family's line (docs/model.md §5.4; `K = 1/N`, NeoHookean, prescribed end) at a
//! perturbed state: the `f64` residual, the line's own Jacobian (`Line::jacobian_into`, one
//! sweep), the coloured AD alternative it replaces (three `Dual64` directional sweeps through
//! `ArrayProblem::directional`, the tridiagonal colouring; the integrators' assembly not
//! included) and a snapshot. Each is the best of several calls.
//!
//! Run: `cargo run --release --example line_kernels [N]`; `THREADS=2` lets the residual sweep
//! two halves on two threads (from 2¹⁵ cells); `NONUNI=1` perturbs `L₀`, `μ` and `K` by 1e-12
//! so that the residual streams those vectors instead of using their uniform values.

use celltissue::cell::Field;
use celltissue::line::build::discrete;
use celltissue::line::LineConfig;
use celltissue::{ArrayProblem, CellArray, NeoHookean};
use integrators::linalg::Matrix;
use integrators::Problem;
use std::time::Instant;

/// Best wall time of `reps` calls of `f`, in ms.
fn best(reps: usize, mut f: impl FnMut()) -> f64 {
    (0..reps)
        .map(|_| {
            let s = Instant::now();
            f();
            s.elapsed().as_secs_f64() * 1e3
        })
        .fold(f64::INFINITY, f64::min)
}

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let env = |k: &str| std::env::var(k).ok();
    let threads = env("THREADS").and_then(|v| v.parse().ok()).unwrap_or(1);
    let nf = n as f64;
    let cfg = LineConfig {
        cells: n,
        k: (1.0 / nf).into(),
        t_ramp: nf,
        ..Default::default()
    };
    let mut p = cfg.params(1e-8);
    if env("NONUNI").is_some() {
        p.ref_lengths = (0..n).map(|i| 1.0 + 1e-12 * ((i % 7) as f64)).collect();
        p.mu = Field::gaussian_bump(1.0, 1e-12, 0.5, 0.2);
        p.k = Field::gaussian_bump(1.0 / nf, 1e-12 / nf, 0.5, 0.2);
    }
    let mut line = discrete(NeoHookean::new(1.0).expect("valid"), &p).expect("valid line");
    line.set_threads(threads);
    let mut y = line.initial_state();
    for (i, v) in y.iter_mut().enumerate() {
        *v += 0.05 * ((i as f64) * 0.1).sin();
    }
    let yp: Vec<f64> = (0..y.len())
        .map(|i| 0.01 * ((i as f64) * 0.3).cos())
        .collect();
    let mut r = vec![0.0; y.len()];
    let t_res = best(15, || {
        line.residual(1.0, &y, &yp, &mut r).expect("residual")
    });
    let mut jac = Matrix::zeros(line.dim(), &line.pattern());
    let t_jac = best(8, || {
        jac.set_zero();
        line.jacobian_into(1.0, &y, &yp, 0.5, &mut jac)
            .expect("jacobian");
    });
    let mut prob = ArrayProblem::new(line.clone());
    let (mut v, mut dr) = (vec![0.0; y.len()], vec![0.0; y.len()]);
    let t_dir = best(8, || {
        for colour in 0..3 {
            for (i, x) in v.iter_mut().enumerate() {
                *x = if i % 3 == colour { 1.0 } else { 0.0 };
            }
            prob.directional(1.0, &y, &yp, &v, 0.5, &mut r, &mut dr)
                .expect("directional");
        }
    });
    let t_snap = best(5, || {
        std::hint::black_box(line.snapshot(1.0, &y, &yp).expect("snapshot"));
    });
    println!(
        "N = {n}, threads = {threads}: residual {t_res:.2} ms, own Jacobian {t_jac:.2} ms \
         (with zeroing), 3 coloured dual sweeps {t_dir:.2} ms, snapshot {t_snap:.2} ms"
    );
}
