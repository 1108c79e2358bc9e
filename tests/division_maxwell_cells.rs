//! Divisions of cells with a Maxwell branch (`viscosity` Maxwell or standard linear solid,
//! docs/viscoelasticity.md): each daughter takes its parent's viscous stretch `a_v`, which is
//! intensive like the elastic stretch `α`, so the branch's elastic stretch `α/a_v` and its
//! stress carry over unchanged, as the elastic stress does. Checked: the split itself (stress,
//! `a_v` and the carried rates of each daughter), a line that divides all at once against its
//! reduction to one cell (without drag its cells share one stress), and the carried history
//! against a consistent restart with drag.

use celltissue::boundary::{Ramp, RightEnd};
use celltissue::cell::{GrowthLaw, ViscousBranch};
use celltissue::cell::{MaxwellBranch, TanhGrowth};
use celltissue::events::{AreaDoubling, Dividing};
use celltissue::line::build::{discrete, LineParams};
use celltissue::line::run::{integrate, SolveSettings};
use celltissue::{ArrayProblem, CellArray, NeoHookean, StrainEnergy};
use integrators::EventAction;
use std::sync::Arc;

/// `cells` unit cells with a tanh growth law and a branch `(μ_m, η_m) = (1, 2)`: a standard
/// linear solid (`sls`) or a Maxwell fluid.
fn params(cells: usize, sls: bool) -> LineParams {
    let mut p = LineParams::unit_cells(cells);
    p.growth = Some(Arc::new(TanhGrowth::default()));
    p.maxwell = Some(if sls {
        MaxwellBranch::standard_linear_solid(1.0, 2.0).unwrap()
    } else {
        MaxwellBranch::maxwell(1.0, 2.0).unwrap()
    });
    p
}

fn dividing(p: &LineParams) -> Dividing<NeoHookean> {
    let line = discrete(NeoHookean::new(1.0).unwrap(), p).unwrap();
    Dividing::new(line, Box::new(AreaDoubling::default()), 0).unwrap()
}

/// On a moving, non-uniform state (every unknown and rate perturbed) the daughters of four
/// cells (two neighbours among them, and the last) carry their parent's stress, `a_v` and rate
/// `ȧ_v`, and the map places every other unknown where the split moved it, on a line with a
/// free end and on a ring (whose first unknown is `x₀`).
#[test]
fn a_split_keeps_each_daughters_stress_and_viscous_stretch() {
    let ends = [RightEnd::Free(None), RightEnd::Periodic { gauge: false }];
    for (sls, right) in [true, false]
        .into_iter()
        .flat_map(|s| ends.clone().map(|e| (s, e)))
    {
        let mut p = params(100, sls);
        p.right = right;
        p.k = 1e-3.into();
        let mut div = dividing(&p);
        let dim = div.dim();
        let mut y = div.line.initial_state();
        for (k, v) in y.iter_mut().enumerate() {
            *v += 0.05 * (0.3 * k as f64).cos();
        }
        let yp: Vec<f64> = (0..dim).map(|k| 0.2 + 0.1 * (k as f64).sin()).collect();
        let y_old = y.clone();
        let fired = [0, 41, 42, 99];
        let lay = div.line.layout().clone();
        let before: Vec<(f64, f64, f64)> = fired
            .iter()
            .map(|&i| {
                let s = div.line.eval_cell(i + 1, 0.5, &y, &yp).unwrap().sigma;
                (s, y[lay.vi[i]], yp[lay.vi[i]])
            })
            .collect();
        let action = div.handle_event(0.5, &fired, &mut y, &yp).unwrap();
        assert_eq!(action, EventAction::Resized);
        assert_eq!(div.line.n_cells(), 104);
        let mut yp_new = vec![f64::NAN; y.len()];
        assert!(div.map_history(0.5, &yp, true, &mut yp_new));
        let mut y_mapped = vec![f64::NAN; y.len()];
        assert!(div.map_history(0.5, &y_old, false, &mut y_mapped));
        assert_eq!(
            y_mapped, y,
            "sls {sls}: the mapped state is the split state"
        );
        let new = div.line.layout().clone();
        for (k, (&i, &(sigma, a, a_dot))) in fired.iter().zip(&before).enumerate() {
            for d in [i + k, i + k + 1] {
                let after = div.line.eval_cell(d + 1, 0.5, &y, &yp_new).unwrap().sigma;
                assert!(
                    // round-off: a daughter's length is a difference of positions up to
                    // l ≈ 100 (ulp 1.4e-14) over half a cell, times dσ/dα of a few
                    (after - sigma).abs() <= 1e-12,
                    "sls {sls}, cell {i}, daughter {d}: stress {sigma} before, {after} after"
                );
                assert_eq!(
                    (y[new.vi[d]], yp_new[new.vi[d]]),
                    (a, a_dot),
                    "daughter {d}"
                );
                assert_eq!(y[new.gi[d]], 1.0);
            }
        }
        // an undivided cell keeps its own a_v and rate at its new index
        for (old, now) in [(10, 11), (50, 53), (98, 101)] {
            assert_eq!(y[new.vi[now]], y_old[lay.vi[old]]);
            assert_eq!(yp_new[new.vi[now]], yp[lay.vi[old]]);
        }
        assert!(yp_new.iter().all(|v| v.is_finite()));
    }
}

/// `l(t) = 8 e^{0.3t}(1 + 0.1 sin 2t)` and its rate: an end pulled out at a rate that changes.
fn pulled(t: f64) -> (f64, f64) {
    let (e, s) = (8.0 * (0.3 * t).exp(), 1.0 + 0.1 * (2.0 * t).sin());
    (e * s, 0.3 * e * s + e * 0.2 * (2.0 * t).cos())
}

/// The uniform line of `n₀` unit cells held at `l(t)` without drag, reduced to one cell: every
/// cell has `α = l/(n g)` and the stress `σ = σ_el(α) + σ_b(α, a_v)` (`σ_el` dropped for a
/// Maxwell fluid), grows at `ġ = G(σ)` and flows at `ȧ_v = rate(a_v, σ_b)`; when `g` reaches 2
/// every cell divides (`n` doubles; the area rule keeps `L₀ = 1`; `g` restarts at 1, `a_v`
/// stays). Classical RK4 at `h = 10⁻⁴`, a division located by bisecting the step to 1e-13.
/// Returns `(σ, α, a_v, n)` at each of `times`.
fn reduced_line(branch: &MaxwellBranch, n0: f64, times: &[f64]) -> Vec<(f64, f64, f64, f64)> {
    let law = NeoHookean::new(1.0).unwrap();
    let growth = TanhGrowth::default();
    let stress = |t: f64, n: f64, g: f64, a: f64| {
        let alpha = pulled(t).0 / (n * g);
        let sb = branch.stress(&law, alpha, a);
        let el = if branch.keeps_elastic() {
            law.line(alpha).sigma
        } else {
            0.0
        };
        (el + sb, alpha, sb)
    };
    let f = |t: f64, n: f64, [g, a]: [f64; 2]| {
        let (sigma, _, sb) = stress(t, n, g, a);
        [growth.value(sigma), branch.rate(a, sb)]
    };
    let rk4 = |t: f64, n: f64, y: [f64; 2], h: f64| {
        let add = |y: [f64; 2], k: [f64; 2], c: f64| [y[0] + c * k[0], y[1] + c * k[1]];
        let k1 = f(t, n, y);
        let k2 = f(t + h / 2.0, n, add(y, k1, h / 2.0));
        let k3 = f(t + h / 2.0, n, add(y, k2, h / 2.0));
        let k4 = f(t + h, n, add(y, k3, h));
        [0, 1].map(|i| y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
    };
    let (mut t, mut n, mut y) = (0.0, n0, [1.0, branch.initial()]);
    let mut out = Vec::new();
    for &t_out in times {
        while t < t_out {
            let h = (t_out - t).min(1e-4);
            let next = rk4(t, n, y, h);
            if next[0] < 2.0 {
                (t, y) = (t + h, next);
                continue;
            }
            // the step crosses g = 2: find where, divide there, go on
            let (mut lo, mut hi) = (0.0, h);
            while hi - lo > 1e-13 {
                let mid = 0.5 * (lo + hi);
                if rk4(t, n, y, mid)[0] < 2.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let at = rk4(t, n, y, hi);
            (t, n, y) = (t + hi, 2.0 * n, [1.0, at[1]]);
        }
        let (sigma, alpha, _) = stress(t, n, y[0], y[1]);
        out.push((sigma, alpha, y[1], n));
    }
    out
}

/// Eight identical cells held between a wall and the end [`pulled`], without drag: every cell
/// carries the same stress, grows alike and reaches g = 2 at the same instant, so all divide
/// in one event and the line is [`reduced_line`], written here from the cell laws alone (not
/// from the line's residual, layout or division code). Stress, stretch and the viscous stretch
/// of every cell (the profiles' `viscous`) agree with it at
/// t = 1…8 over three rounds of division within the solver's tolerance, for a standard linear
/// solid and a Maxwell fluid.
#[test]
fn a_line_dividing_all_at_once_follows_its_one_cell_reduction() {
    for sls in [true, false] {
        let mut p = params(8, sls);
        p.right = RightEnd::Prescribed(Ramp::Custom(Arc::new(pulled)));
        p.k = 0.0.into();
        let settings = SolveSettings {
            rtol: 1e-9,
            atol: 1e-11,
            ..Default::default()
        };
        let times: Vec<f64> = (0..=8).map(f64::from).collect();
        let reference = reduced_line(p.maxwell.as_ref().unwrap(), 8.0, &times);
        let mut div = ArrayProblem::new(dividing(&p));
        let run = integrate(&mut div, &settings, &times);
        assert!(run.error.is_none(), "{:?}", run.error);
        assert_eq!(run.snapshots.len(), times.len());
        for (s, &(sigma, alpha, a, n)) in run.snapshots.iter().zip(&reference) {
            assert_eq!(s.sigma.len() as f64, n, "sls {sls}, t = {}", s.t);
            let gap = |v: &[f64], r: f64| v.iter().map(|v| (v - r).abs()).fold(0.0, f64::max);
            let (ds, da) = (gap(&s.sigma, sigma), gap(&s.alpha, alpha));
            let dv = gap(s.viscous.as_deref().expect("a branch's a_v"), a);
            eprintln!(
                "sls {sls}, t = {}: {n} cells, σ = {sigma:.6}, a_v = {a:.6}, gaps σ {ds:.1e} \
                 α {da:.1e} a_v {dv:.1e}",
                s.t
            );
            assert!(
                ds < 1e-7 && da < 1e-7 && dv < 1e-7,
                "sls {sls}, t = {}: {ds:e}, {da:e}, {dv:e}",
                s.t
            );
        }
        assert_eq!(reference.last().unwrap().3, 64.0, "sls {sls}: three rounds");
    }
}

/// A free line of 20 cells with drag (K = 1e-3) dividing to t = 10 (64 cells), each cell a
/// standard linear solid: the carried history (each daughter's `a_v` and rate mapped from its
/// parent) against a restart from a consistent state after every division, and both against
/// a run at rtol 1e-10 (measured: l within 1.8e-8 and 5.5e-9 relative). Divisions, steps,
/// rejected steps and Jacobian pairs of the carried run are pinned (deterministic), so a cost
/// regression fails: 2 151 steps, 88 rejected and 50 Jacobians for 44 divisions, against
/// 2 204, 99 and 49 for the same line of elastic cells (measured before the first cell was
/// tested against its own stretch, when the Maxwell line took 2 149, 87 and 50) (the Newton matrices are carried across
/// each division with the rows around the daughters, their `a_v` rows included, evaluated
/// afresh).
#[test]
fn carried_history_agrees_with_a_consistent_restart() {
    let run = |carry: bool, rtol: f64| {
        let mut p = params(20, true);
        p.right = RightEnd::Free(None);
        p.k = 1e-3.into();
        let mut div = dividing(&p);
        div.carry_history = carry;
        let settings = SolveSettings {
            rtol,
            atol: rtol / 100.0,
            ..Default::default()
        };
        let c = crate::common::division_cost(div, &settings, 10.0);
        eprintln!(
            "carry {carry}, rtol {rtol:e}: {} divisions, {} steps, {} rejected, {} Newton \
             failures, {} Jacobians, l = {}",
            c.divisions, c.steps, c.rejected, c.newton_failures, c.jacobians, c.length
        );
        c
    };
    let exact = run(true, 1e-10);
    let carried = run(true, 1e-6);
    let fresh = run(false, 1e-6);
    assert_eq!(exact.divisions, 44);
    for (c, name) in [(&carried, "carried"), (&fresh, "consistent")] {
        assert_eq!(c.divisions, exact.divisions, "{name}");
        let err = (c.length - exact.length).abs() / exact.length;
        assert!(
            err < 1e-6,
            "{name}: l = {} against {}: {err:e}",
            c.length,
            exact.length
        );
    }
    assert_eq!(
        (carried.steps, carried.rejected, carried.jacobians),
        (2151, 88, 50),
        "pinned counters"
    );
}

/// Both proliferating continua divide cells with a branch: a segment's viscous stretch is
/// intensive, so the density continuum's divisions (which change only the segment's reference
/// length per unit X, its density and drags) leave it, and the cell-number grid's halves copy
/// it as the discrete daughters do. 100 standard-linear-solid cells (μ_m = 1, η_m = 2), free
/// end, K = 1e-5, the area rule, t ≤ 10 (545 cells), each continuum with its free end keeping
/// the tip cell's drag. Measured at t = 0, 1, …, 10: the density continuum (200 segments) l
/// within 5.8e-5 and N within one cell; the cell-number grid (50 segments of two cells) l
/// within 2.1e-5 and N within one cell, in 0.63 of the discrete line's steps.
#[test]
fn the_proliferating_continua_divide_cells_with_a_branch_as_the_discrete_line_does() {
    use celltissue::events::{run_proliferation, ProliferationConfig};
    use celltissue::line::OutputTimes;
    use celltissue::observe::{ModelKind, RunRecord};
    let table = |grid: &str| -> toml::Table {
        toml::from_str(&format!(
            "cells = 100\nK = 1e-5\nright_end = \"free\"\nfree_end_drag = \"cells\"\n\
             growth = {{ sigma0 = 0.1 }}\n\
             viscosity = {{ model = \"standard_linear_solid\", mu_m = 1, eta_m = 2 }}\n\
             division = {{ rule = \"area\"{grid} }}"
        ))
        .unwrap()
    };
    let times = OutputTimes {
        series: (0..=10).map(f64::from).collect(),
        profiles: vec![10.0],
    };
    let settings = SolveSettings {
        jacobian_age: 100,
        ..Default::default()
    };
    let run = |grid: &str, model: ModelKind, nodes: Option<usize>| -> RunRecord {
        let cfg = ProliferationConfig::from_table(&table(grid)).unwrap();
        cfg.validate_continuum().unwrap();
        let rec = run_proliferation(&cfg, model, nodes, &settings, &times);
        assert!(rec.error.is_none(), "{:?}", rec.error);
        rec
    };
    let d = run("", ModelKind::Discrete, None);
    let n_final = d.series.extra["cells"][10];
    assert!(n_final > 500.0, "{n_final}");
    for (name, grid, nodes, bound) in [
        ("density continuum", "", 200, 2e-4),
        ("cell-number grid", ", cell_grid = {}", 50, 5e-5),
    ] {
        let c = run(grid, ModelKind::Continuum, Some(nodes));
        let mut worst = (0.0f64, 0.0f64);
        for i in 0..=10 {
            let gl = (c.series.length[i] / d.series.length[i] - 1.0).abs();
            let gn = (c.series.extra["cells"][i] - d.series.extra["cells"][i]).abs();
            worst = (worst.0.max(gl), worst.1.max(gn));
        }
        println!(
            "{name}: largest gaps to the discrete line: l {:.2e}, N {} cells; steps {} against {}",
            worst.0, worst.1, c.stats.steps, d.stats.steps
        );
        assert!(worst.0 < bound && worst.1 <= 1.0, "{name}: {worst:?}");
        // the branch has flowed: some segment's viscous stretch is below 1
        let a_v = &c.profiles[0].extra["viscous"];
        assert!(a_v.iter().any(|&a| a < 1.0), "{name}");
    }
}

/// The cell-number grid merges standard-linear-solid cells behind a proliferating rim: a
/// merged segment's viscous stretch is the mean of its cells' weighted by grown length, so
/// the branch's rest lengths add as the lengths do (`Line::merge_cells`). 100 cells
/// (μ_m = 1, η_m = 2), free end, K = 1e-2, the area rule, t ≤ 400 (714 cells), one cell per
/// segment where cells grow. Measured at t = 0, 50, …, 400, against the discrete line: merge
/// threshold θ = 1e-2: l within 9.8e-5, N exact, 72 segments; θ = 1e-3: l within 8.1e-7, N
/// exact, 223 segments. Setting a merged segment's `a_v` to 1 instead (the branch's stress
/// lost at each merge) puts θ = 1e-3 at 5.8e-5 in l and one cell in N.
#[test]
fn the_cell_grid_merges_cells_with_a_branch_behind_the_rim() {
    use celltissue::events::{run_proliferation, ProliferationConfig};
    use celltissue::line::OutputTimes;
    use celltissue::observe::{ModelKind, RunRecord};
    let times = OutputTimes {
        series: (0..=8).map(|i| 50.0 * f64::from(i)).collect(),
        profiles: vec![400.0],
    };
    let run = |grid: &str, model: ModelKind, nodes: Option<usize>| -> RunRecord {
        let table: toml::Table = toml::from_str(&format!(
            "cells = 100\nK = 1e-2\nright_end = \"free\"\ngrowth = {{ sigma0 = 0.1 }}\n\
             viscosity = {{ model = \"standard_linear_solid\", mu_m = 1, eta_m = 2 }}\n\
             division = {{ rule = \"area\"{grid} }}"
        ))
        .unwrap();
        let cfg = ProliferationConfig::from_table(&table).unwrap();
        cfg.validate_continuum().unwrap();
        let rec = run_proliferation(&cfg, model, nodes, &SolveSettings::default(), &times);
        assert!(rec.error.is_none(), "{:?}", rec.error);
        rec
    };
    let d = run("", ModelKind::Discrete, None);
    assert_eq!(d.series.extra["cells"][8], 714.0);
    let mut previous = f64::INFINITY;
    for (theta, bound, pinned) in [(1e-2, 2e-4, 72), (1e-3, 5e-6, 223)] {
        let grid = format!(", cell_grid = {{ merge_below = {theta:e} }}");
        let c = run(&grid, ModelKind::Continuum, Some(100));
        let mut worst = (0.0f64, 0.0f64);
        for i in 0..=8 {
            let gl = (c.series.length[i] / d.series.length[i] - 1.0).abs();
            let gn = (c.series.extra["cells"][i] - d.series.extra["cells"][i]).abs();
            worst = (worst.0.max(gl), worst.1.max(gn));
        }
        let segments = c.profiles[0].x.len();
        println!(
            "θ = {theta:e}: largest gaps to the discrete line: l {:.2e}, N {} cells; \
             {segments} segments for 714 cells; steps {} against {}",
            worst.0, worst.1, c.stats.steps, d.stats.steps
        );
        assert!(worst.0 < bound && worst.1 <= 1.0, "θ = {theta}: {worst:?}");
        // the error falls with the threshold
        assert!(worst.0 < previous / 10.0, "θ = {theta}: {worst:?}");
        previous = worst.0;
        // merged: the bulk behind the rim holds many cells per segment
        assert_eq!(segments, pinned, "θ = {theta}");
    }
}
