//! Division on a ring (a periodic line of cells, `x_N = x₀ + P`): dividing splits cells inside
//! the same ring, so the circumference `P` stays.
//!
//! * **Uniform ring = one cell.** Identical cells stay identical: no boundary moves (up to a
//!   rigid rotation), every cell has `α = P/(N L₀ g)` and grows by `ġ = G(σ_el(α))`, and all
//!   of them divide together when `g = 2` (N doubles, the daughters start at `g = 1` with
//!   `L₀ g/2`). The ring must follow that scalar ODE, integrated here by RK4: division times,
//!   cell counts and every cell's `g`.
//! * **A heterogeneous ring** (random drag per cell) divides cell by cell: the circumference
//!   stays `P`, `Σ L₀ g` is continuous across each division, the cell count rises by one per
//!   division, and the division locations cover the ring.

use celltissue::boundary::RightEnd;
use celltissue::cell::{Field, GrowthLaw, TanhGrowth};
use celltissue::events::{AreaDoubling, Dividing};
use celltissue::line::build::{discrete, LineParams};
use celltissue::line::run::{integrate, SolveSettings};
use celltissue::{ArrayProblem, NeoHookean, StrainEnergy};
use std::sync::Arc;

/// Weakly stress-sensitive growth: with the thesis's σ₀ = 0.1 a ring of fixed circumference
/// stops growing long before any cell doubles (its cells are compressed).
fn law() -> TanhGrowth {
    TanhGrowth {
        sigma0: 10.0,
        gm: 1.0,
    }
}

fn ring(n: usize, k: Field) -> Dividing<NeoHookean> {
    let mut p = LineParams::unit_cells(n);
    p.right = RightEnd::Periodic { gauge: false };
    p.k = k;
    p.growth = Some(Arc::new(law()));
    p.atol_cell = 1e-12;
    let line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
    Dividing::new(line, Box::new(AreaDoubling::default()), 0).unwrap()
}

fn tight() -> SolveSettings {
    SolveSettings {
        rtol: 1e-10,
        atol: 1e-12,
        ..Default::default()
    }
}

/// The uniform ring's `g(t)` and division times to `t_end` by RK4 with step `h`: `α = P/(N g)`
/// (unit reference cells after every division), `ġ = G(σ_el(α))`, division at `g = 2`.
fn uniform_ring(n0: usize, t_end: f64, h: f64) -> (Vec<f64>, Vec<(f64, f64)>) {
    let law = law();
    let nh = NeoHookean::new(1.0).unwrap();
    let p = n0 as f64;
    let mut n = n0 as f64;
    let rate = |g: f64, n: f64| law.rate(nh.line(p / (n * g)).sigma).0;
    let (mut t, mut g) = (0.0, 1.0);
    let mut divisions = Vec::new();
    while t < t_end - 1e-12 {
        let step = h.min(t_end - t);
        let k1 = rate(g, n);
        let k2 = rate(g + 0.5 * step * k1, n);
        let k3 = rate(g + 0.5 * step * k2, n);
        let k4 = rate(g + step * k3, n);
        let g_new = g + step / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        if g_new >= 2.0 {
            // the crossing by bisection on the RK4 step
            let (mut lo, mut hi) = (0.0, step);
            for _ in 0..100 {
                let s = 0.5 * (lo + hi);
                let k1 = rate(g, n);
                let k2 = rate(g + 0.5 * s * k1, n);
                let k3 = rate(g + 0.5 * s * k2, n);
                let k4 = rate(g + s * k3, n);
                if g + s / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4) < 2.0 {
                    lo = s;
                } else {
                    hi = s;
                }
            }
            t += hi;
            divisions.push((t, 2.0 * n));
            n *= 2.0;
            g = 1.0;
            continue;
        }
        g = g_new;
        t += step;
    }
    (vec![g, n], divisions)
}

#[test]
fn a_uniform_ring_divides_as_one_cell_does() {
    let (n0, t_end) = (8, 12.0);
    let (end, reference) = uniform_ring(n0, t_end, 1e-3);
    let mut prob = ArrayProblem::new(ring(n0, Field::Constant(0.1)));
    let traj = integrate(&mut prob, &tight(), &[t_end]);
    assert!(traj.error.is_none(), "{:?}", traj.error);
    let div = &prob.array;
    let line = &div.line;
    println!(
        "uniform ring, N0 = {n0}: divisions (t, N after) by the scalar ODE {reference:?}; \
         the ring: {} divisions, first at t = {:.9}, last at t = {:.9}, N = {}",
        div.log.records.len(),
        div.log.records.first().map_or(f64::NAN, |r| r.t),
        div.log.records.last().map_or(f64::NAN, |r| r.t),
        line.n_cells()
    );
    assert!(!reference.is_empty(), "the reference divides");
    assert_eq!(line.n_cells() as f64, end[1]);
    // each generation: all cells divide within 1e-6 of the ODE's time
    let mut i = 0;
    for &(t_ref, n_after) in &reference {
        let cells_before = n_after as usize / 2;
        let gen = &div.log.records[i..i + cells_before];
        for r in gen {
            assert!((r.t - t_ref).abs() < 1e-6, "division at {} vs {t_ref}", r.t);
        }
        i += cells_before;
    }
    assert_eq!(i, div.log.records.len());
    // every cell's g at the end is the ODE's, and the ring keeps its circumference
    let last = traj.snapshots.last().unwrap();
    assert_eq!(last.g.len(), line.n_cells());
    let worst = last
        .g
        .iter()
        .map(|g| (g - end[0]).abs())
        .fold(0.0, f64::max);
    assert!((last.length() - n0 as f64).abs() < 1e-12);
    println!(
        "g(t_end) = {:.9} (ODE), largest cell difference {worst:.2e}",
        end[0]
    );
    assert!(worst < 1e-6, "{worst}");
}

#[test]
fn a_heterogeneous_ring_divides_cell_by_cell_keeping_its_invariants() {
    let n0 = 12;
    let mut p = LineParams::unit_cells(n0);
    p.right = RightEnd::Periodic { gauge: false };
    p.k = Field::Constant(0.1);
    p.mu = Field::Random {
        low: 0.5,
        high: 2.0,
        seed: 3,
    };
    p.growth = Some(Arc::new(law()));
    p.atol_cell = 1e-12;
    let line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
    let mut div = Dividing::new(line, Box::new(AreaDoubling::default()), 0).unwrap();
    div.check_invariants = Some(Default::default());
    let times: Vec<f64> = (1..=16).map(|i| i as f64 * 0.5).collect();
    let mut prob = ArrayProblem::new(div);
    let traj = integrate(&mut prob, &tight(), &times);
    assert!(traj.error.is_none(), "{:?}", traj.error);
    let div = &prob.array;
    let inv = div.check_invariants.unwrap();
    let records = &div.log.records;
    let distinct_times = {
        let mut t: Vec<f64> = records.iter().map(|r| r.t).collect();
        t.dedup();
        t.len()
    };
    println!(
        "heterogeneous ring, N0 = {n0}: {} divisions at {distinct_times} times, N = {}; \
         invariants over {} events: boundary shift {:.1e}, length change {:.1e}, Σ L₀g {:.1e}, \
         α jump {:.1e}, σ_el jump {:.1e}; steps {}",
        records.len(),
        div.line.n_cells(),
        inv.events,
        inv.boundary_shift,
        inv.length_change,
        inv.sum_l0g_rel,
        inv.alpha_jump,
        inv.sigma_el_jump,
        traj.stats.steps
    );
    // the stiffer cells are compressed less and divide first, one by one
    assert!(records.len() >= n0, "{}", records.len());
    assert!(distinct_times > n0 / 2, "{distinct_times}");
    assert_eq!(div.line.n_cells(), n0 + records.len());
    for (k, r) in records.iter().enumerate() {
        assert_eq!(r.cells_after, n0 + k + 1);
        assert!((0.0..=1.0).contains(&r.x_over_length), "{r:?}");
    }
    // continuity across every event (docs/model.md §2.8), the circumference unchanged
    assert!(inv.events >= distinct_times);
    assert!(inv.boundary_shift < 1e-12 && inv.length_change < 1e-12);
    assert!(inv.sum_l0g_rel < 1e-14 && inv.alpha_jump < 1e-12 && inv.sigma_el_jump < 1e-10);
    for s in &traj.snapshots {
        assert!((s.length() - n0 as f64).abs() < 1e-12, "t = {}", s.t);
        assert!(s.lambda.iter().all(|&l| l > 0.0));
    }
}
