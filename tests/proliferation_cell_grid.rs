//! The proliferating continuum on a grid in the cell-number coordinate
//! ([`celltissue::proliferation::CellGrid`]) against the discrete line with division: N₀ = 100,
//! σ₀ = 0.1, free end, m = 0, area rule — the targets the density continuum misses
//! (docs/model.md §8.4, "A grid in the cell-number coordinate").

use crate::common::fig3_3_line;
use celltissue::events::{
    AgeRule, AreaDoubling, Dividing, DivisionRule, RandomThreshold, SurfaceToVolume,
};
use celltissue::line::build::{continuum, discrete};
use celltissue::line::run::{integrate, SolveSettings};
use celltissue::observe::DivisionRecord;
use celltissue::proliferation::{CellGrid, Coarsening};
use celltissue::{ArrayProblem, NeoHookean};

fn settings(rtol: f64) -> SolveSettings {
    SolveSettings {
        rtol,
        atol: rtol / 100.0,
        ..Default::default()
    }
}

/// `N` just after time `t` from a division log.
fn cells_at(log: &[DivisionRecord], t: f64) -> f64 {
    log.iter()
        .take_while(|r| r.t <= t)
        .last()
        .map_or(100.0, |r| r.cells_after as f64)
}

/// Fraction of the divisions after `t` that lie in the outer tenth of the line.
fn rim_fraction(log: &[DivisionRecord], t: f64) -> f64 {
    let late: Vec<_> = log.iter().filter(|r| r.t > t).collect();
    late.iter().filter(|r| r.x_over_length > 0.9).count() as f64 / late.len() as f64
}

struct Run {
    /// `(l, N)` at the output times.
    ln: Vec<(f64, f64)>,
    log: Vec<DivisionRecord>,
    steps: usize,
    segments: usize,
}

fn discrete_run(k: f64, times: &[f64], rtol: f64) -> Run {
    discrete_with(k, Box::new(AreaDoubling::default()), times, rtol)
}

/// The discrete line dividing by `rule` (its thresholds from the rule's seed).
fn discrete_with(k: f64, rule: Box<dyn DivisionRule>, times: &[f64], rtol: f64) -> Run {
    let line = discrete(NeoHookean::new(1.0).unwrap(), &fig3_3_line(k)).unwrap();
    let seed = rule.seed();
    let mut prob = ArrayProblem::new(Dividing::new(line, rule, seed).unwrap());
    let traj = integrate(&mut prob, &settings(rtol), times);
    assert!(traj.error.is_none(), "{:?}", traj.error);
    Run {
        ln: traj
            .snapshots
            .iter()
            .map(|s| (s.length(), s.alpha.len() as f64))
            .collect(),
        segments: prob.array.line.n_cells(),
        log: prob.array.log.records,
        steps: traj.stats.steps,
    }
}

fn grid_run(k: f64, c: usize, coarsen: Option<Coarsening>, times: &[f64], rtol: f64) -> Run {
    grid_with(
        k,
        c,
        coarsen,
        Box::new(AreaDoubling::default()),
        times,
        rtol,
    )
}

/// The grid of `c` cells per segment dividing by `rule`.
fn grid_with(
    k: f64,
    c: usize,
    coarsen: Option<Coarsening>,
    rule: Box<dyn DivisionRule>,
    times: &[f64],
    rtol: f64,
) -> Run {
    let line = continuum(NeoHookean::new(1.0).unwrap(), &fig3_3_line(k), 100 / c).unwrap();
    let mut grid = CellGrid::new(line, 100, rule).unwrap();
    grid.coarsen = coarsen;
    let mut prob = ArrayProblem::new(grid);
    let traj = integrate(&mut prob, &settings(rtol), times);
    assert!(traj.error.is_none(), "{:?}", traj.error);
    let log = prob.array.log().records.clone();
    Run {
        ln: traj
            .snapshots
            .iter()
            .map(|s| (s.length(), cells_at(&log, s.t)))
            .collect(),
        segments: prob.array.segments(),
        log,
        steps: traj.stats.steps,
    }
}

/// Fraction of the cells added by divisions in each tenth of the line (`x_d/l`), each record
/// weighted by the cells it added (a segment's division adds all its cells).
fn location_histogram(log: &[DivisionRecord]) -> [f64; 10] {
    let mut h = [0.0; 10];
    let mut before = 100;
    for r in log {
        let bin = ((r.x_over_length * 10.0) as usize).min(9);
        h[bin] += (r.cells_after - before) as f64;
        before = r.cells_after;
    }
    let total: f64 = h.iter().sum();
    h.map(|x| x / total)
}

/// Largest difference between two runs' [`location_histogram`]s (printed).
fn location_gap(grid: &Run, reference: &Run) -> f64 {
    let (hg, hd) = (
        location_histogram(&grid.log),
        location_histogram(&reference.log),
    );
    println!("  division locations by tenths: grid {hg:.4?}\n  discrete {hd:.4?}");
    hg.iter()
        .zip(&hd)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
}

/// Largest relative errors in `l` and `N` over the output times.
fn errors(grid: &Run, reference: &Run) -> (f64, f64) {
    assert_eq!(grid.ln.len(), reference.ln.len());
    grid.ln
        .iter()
        .zip(&reference.ln)
        .fold((0.0f64, 0.0f64), |(el, en), (g, d)| {
            (
                el.max((g.0 / d.0 - 1.0).abs()),
                en.max((g.1 / d.1 - 1.0).abs()),
            )
        })
}

/// Two cells per segment, t ≤ 18, at every drag of Fig 3.3: `l(t)` and `N(t)` within 2 %
/// (the density continuum at n = 200 is −5.1 % and −5.9 % at K = 1e-5, t = 18). Measured:
/// `l` 3.0e-5 / 1.3e-4 / 8.0e-4 / 3.4e-3, `N` 3.8e-3 / 1.1e-2 / 1.5e-2 / 1.9e-2 for
/// K = 1e-5 / 1e-4 / 1e-3 / 1e-2 (the `N` error is a segment's two cells dividing at once).
#[test]
fn two_cells_per_segment_hold_l_and_n_to_two_percent_up_to_t_18() {
    let times: Vec<f64> = (0..=20).map(|i| 0.9 * i as f64).collect();
    for k in [1e-5, 1e-4, 1e-3, 1e-2] {
        let d = discrete_run(k, &times, 1e-8);
        let g = grid_run(k, 2, None, &times, 1e-8);
        let (el, en) = errors(&g, &d);
        println!(
            "K = {k:e}: N(18) = {} / {}, l error {el:.2e}, N error {en:.2e}, steps {} / {}",
            g.ln[20].1, d.ln[20].1, g.steps, d.steps
        );
        assert!(el < 0.02 && en < 0.02, "K = {k}: {el} {en}");
        // where the divisions fall: the share of new cells in each tenth of the line
        let worst = location_gap(&g, &d);
        // within 2 % where hundreds of cells divide (K ≤ 1e-4; measured 0.010 and 0.005),
        // within two segments' divisions at K = 1e-3 (74 new cells, measured 0.035). At
        // K = 1e-2 the rim has begun: 22 new cells, 10 % of them put at x/l ≈ 0.75 by one
        // two-cell segment where the discrete line has none — the rim wants c = 1 (the test
        // below)
        let added = d.ln[20].1 - 100.0;
        if k < 1e-2 {
            assert!(worst < f64::max(0.02, 4.0 / added), "K = {k}: {worst}");
        }
        // half the unknowns, and about half the steps (divisions come in pairs)
        assert!(g.steps < d.steps * 6 / 10, "{} {}", g.steps, d.steps);
        if k == 1e-5 {
            // convergence in the cells per segment (c = 1 is the discrete line): measured
            // l 3.0e-5 / 1.3e-4 / 6.5e-4 and N 3.8e-3 / 9.6e-3 / 2.1e-2 for c = 2 / 4 / 10,
            // about second order in l and first in N (a segment's cells divide at once)
            let (l4, n4) = errors(&grid_run(k, 4, None, &times, 1e-8), &d);
            let (l10, n10) = errors(&grid_run(k, 10, None, &times, 1e-8), &d);
            let order = |a: f64, b: f64, ratio: f64| (b / a).ln() / ratio.ln();
            println!(
                "c = 2 / 4 / 10: l {el:.2e} / {l4:.2e} / {l10:.2e}, N {en:.2e} / {n4:.2e} / \
                 {n10:.2e}; orders l {:.2}, {:.2}, N {:.2}, {:.2}",
                order(el, l4, 2.0),
                order(l4, l10, 2.5),
                order(en, n4, 2.0),
                order(n4, n10, 2.5)
            );
            assert!(order(el, l4, 2.0) > 1.5 && order(l4, l10, 2.5) > 1.5);
            assert!(order(en, n4, 2.0) > 0.7 && order(n4, n10, 2.5) > 0.7);
        }
    }
}

/// The proliferating rim to t = 1000 (K = 1e-2), one cell per segment where cells grow and
/// merged segments behind the rim: `l(t)` and `N(t)` within 2 % (the density continuum ends
/// with 419 against 1 637 cells), the rim's share of divisions as in the discrete line, and
/// errors that fall with the merge threshold. Measured: θ = 1e-2: `l` 1.0e-4, `N` 4.0e-3
/// (1 639 cells), rim share 99.64 % against 99.86 %, 87 segments; θ = 1e-3: `l` 1.2e-6, `N`
/// exact at every output time, rim share 99.86 %, 236 segments (1 637 cells); the share of new
/// cells in each tenth of the line is the discrete line's to 1.3e-3 (θ = 1e-2) and exactly
/// (θ = 1e-3).
#[test]
fn merged_bulk_behind_the_rim_holds_l_and_n_to_t_1000() {
    let times: Vec<f64> = (0..=20).map(|i| 50.0 * i as f64).collect();
    let d = discrete_run(1e-2, &times, 1e-6);
    assert_eq!(d.segments, 1637);
    let rim = rim_fraction(&d.log, 100.0);
    let mut previous = (f64::INFINITY, f64::INFINITY);
    for (theta, segments) in [(1e-2, 87), (1e-3, 236)] {
        let coarsen = Coarsening {
            growth_below: theta,
            stress_within: None,
            max_cells: 64,
            batch: 8,
        };
        let g = grid_run(1e-2, 1, Some(coarsen), &times, 1e-6);
        let (el, en) = errors(&g, &d);
        let share = rim_fraction(&g.log, 100.0);
        println!(
            "θ = {theta:e}: N(1000) = {} / {}, l error {el:.2e}, N error {en:.2e}, \
             {} segments, rim share {share:.4} / {rim:.4}, steps {} / {}",
            g.ln[20].1, d.ln[20].1, g.segments, g.steps, d.steps
        );
        assert!(el < 0.02 && en < 0.02, "θ = {theta}: {el} {en}");
        // (merged cells share their segment's stress: at θ = 1e-2 three more divide in the
        // bulk)
        assert!((share - rim).abs() < 5e-3, "{share} {rim}");
        let worst = location_gap(&g, &d);
        assert!(worst < 5e-3, "{worst}");
        assert!(el < previous.0 && en < previous.1);
        previous = (el, en);
        // the cost counter: segments at t = 1000 (the discrete line has 1 637 cells)
        assert_eq!(g.segments, segments);
    }
}

/// The scenario path: `division.cell_grid` runs the grid for `models = ["continuum"]`, its
/// `N(t)` series counts cells (not segments) and matches the discrete run's on a short span;
/// bad values are rejected before a run, naming the innermost key.
#[test]
fn the_cell_grid_runs_from_a_scenario_and_bad_settings_name_their_key() {
    use celltissue::scenario::load_str;
    use std::path::Path;
    let text = |division: &str, nodes: usize| {
        format!(
            "name = \"t\"\n[output]\nseries = [0, 3, 6]\nprofiles = [6]\n[model]\nkind = \"line\"\n\
             models = [\"discrete\", \"continuum\"]\ncells = 20\nnodes = {nodes}\n\
             right_end = \"free\"\nK = 1e-2\ngrowth = {{ sigma0 = 0.1 }}\ndivision = {division}\n"
        )
    };
    let good = text(
        "{ rule = \"area\", cell_grid = { merge_below = 0.9, merge_max = 4, merge_batch = 1 } }",
        20,
    );
    let sc = load_str(&good, Path::new("t.toml"), &[]).unwrap();
    let d = celltissue::scenario::execute::run_spec(&sc.runs[0]);
    let c = celltissue::scenario::execute::run_spec(&sc.runs[1]);
    assert!(
        d.error.is_none() && c.error.is_none(),
        "{:?} {:?}",
        d.error,
        c.error
    );
    let cells = |r: &celltissue::observe::RunRecord| r.series.extra["cells"].clone();
    assert!(cells(&d)[2] > 20.0);
    assert_eq!(cells(&c), cells(&d));
    // the continuum's profile says how many cells each segment stands for (whole cells on
    // this grid), and they add up to N; a discrete line's cells are one each
    let held = &c.profiles[0].extra["segment_cells"];
    assert!(
        held.iter().all(|&m| m >= 1.0 && m.fract() == 0.0),
        "{held:?}"
    );
    assert!(held.iter().any(|&m| m > 1.0), "{held:?}");
    assert_eq!(held.iter().sum::<f64>(), cells(&c)[2]);
    assert!(!d.profiles[0].extra.contains_key("segment_cells"));
    // segments merged (a loose threshold, for the test), yet N and the means are per cell
    let last = |r: &celltissue::observe::RunRecord| r.profiles.last().unwrap().x.len();
    assert!(last(&c) < last(&d), "{} {}", last(&c), last(&d));
    // the mean growth stretch per cell: this loose threshold merges cells that still grow,
    // and their shared stress moves their growth (measured 1.5e-2 at t = 6)
    let mean_g = |r: &celltissue::observe::RunRecord| r.series.extra["mean_g"][2];
    assert!(
        (mean_g(&c) - mean_g(&d)).abs() < 2e-2,
        "{} {}",
        mean_g(&c),
        mean_g(&d)
    );
    // the cap counts cells, not segments: every run ends (24 cells at t = 6 without it)
    let capped = text(
        "{ rule = \"area\", max_cells = 22, cell_grid = { merge_below = 0.9, merge_batch = 1 } }",
        20,
    );
    let sc = load_str(&capped, Path::new("t.toml"), &[]).unwrap();
    let c = celltissue::scenario::execute::run_spec(&sc.runs[1]);
    assert!(c.error.is_none(), "{:?}", c.error);
    let n = cells(&c);
    println!("capped at 22: N = {n:?}, uncapped {:?}", cells(&d));
    // (one event may pass the cap by the cells of the segments it splits)
    assert!(n[2] >= 22.0 && n[2] <= 23.0 && n[2] < cells(&d)[2], "{n:?}");
    for (division, nodes, key) in [
        (
            "{ rule = \"area\", cell_grid = { merge_below = 1.5 } }",
            20,
            "model.division.cell_grid.merge_below",
        ),
        (
            "{ rule = \"area\", cell_grid = { merge_max = 3 } }",
            20,
            "model.division.cell_grid.merge_max",
        ),
        (
            "{ rule = \"area\", cell_grid = { merge_after = 3 } }",
            20,
            "model.division.cell_grid.merge_after",
        ),
        ("{ rule = \"area\", cell_grid = {} }", 8, "model.nodes"),
    ] {
        let e = load_str(&text(division, nodes), Path::new("t.toml"), &[]).unwrap_err();
        assert_eq!(e.key_name(), Some(key), "{e}");
    }
}

/// The `U[1.8, 2.2]` area-threshold rule of `models/fig3_3_ensemble.toml`, seeded.
fn random_rule(seed: u64) -> Box<dyn DivisionRule> {
    Box::new(RandomThreshold {
        mean: 2.0,
        spread: 0.2,
        seed,
    })
}

/// One cell per segment with random thresholds is the discrete line drawing the same
/// thresholds from the same seed: every step, length and cell count agree.
#[test]
fn one_cell_per_segment_with_random_thresholds_is_the_discrete_line() {
    let times: Vec<f64> = (0..=10).map(|i| 2.0 * i as f64).collect();
    let d = discrete_with(1e-2, random_rule(7), &times, 1e-6);
    let g = grid_with(1e-2, 1, None, random_rule(7), &times, 1e-6);
    assert!(d.log.len() > 20, "{} divisions", d.log.len());
    assert_eq!((g.steps, g.segments), (d.steps, d.segments));
    assert_eq!(g.ln, d.ln);
}

/// Mean ± standard error of each column over realisations.
fn ensemble(runs: &[Run]) -> Vec<[(f64, f64); 2]> {
    let r = runs.len() as f64;
    (0..runs[0].ln.len())
        .map(|i| {
            let stat = |f: &dyn Fn(&Run) -> f64| {
                let mean = runs.iter().map(f).sum::<f64>() / r;
                let var = runs.iter().map(|x| (f(x) - mean).powi(2)).sum::<f64>() / (r - 1.0);
                (mean, (var / r).sqrt())
            };
            [stat(&|x| x.ln[i].0), stat(&|x| x.ln[i].1)]
        })
        .collect()
}

/// Random thresholds (U[1.8, 2.2], K = 1e-5, t ≤ 8) on four-cell segments: the cells of a
/// segment divide one by one, each at its own threshold, sharing the segment's stress (the
/// mean-field closure), and a segment that has doubled its cells splits. Over 16 seeded
/// realisations of each model the ensemble means of `N(t)` agree within sampling error, `l(t)`
/// within 2e-3 (its spread between realisations is smaller than the closure's error, which is
/// systematic: it grows with the cells per segment), and where the cells are added by tenths
/// of the line within 0.01. Measured here: mean `l` within 4.9e-4, mean `N` within 1.33
/// standard errors, locations within 0.008, 0.68 of the discrete steps.
///
/// Measured with 64 realisations to t = 12 (`celltissue run models/fig3_3_ensemble.toml
/// --set sweep.ensemble.realisations=64 --set model.nodes=50`, and 25, 10), over the 49 output
/// times, for 2 / 4 / 10 cells per segment: mean `N` within 0.82 / 0.71 / 0.53 % (at most 2.4 /
/// 2.2 / 2.2 standard errors), mean `l` within 0.074 / 0.13 / 0.10 %, the division-location
/// fractions in 20 bins within 0.0023 / 0.0026 / 0.0030, on 0.87 / 0.68 / 0.46 of the discrete
/// steps.
#[test]
fn random_thresholds_on_four_cell_segments_hold_the_ensemble_means() {
    let times: Vec<f64> = (0..=8).map(f64::from).collect();
    let seeds = 0..16u64;
    let d: Vec<Run> = seeds
        .clone()
        .map(|s| discrete_with(1e-5, random_rule(s), &times, 1e-6))
        .collect();
    let g: Vec<Run> = seeds
        .map(|s| grid_with(1e-5, 4, None, random_rule(s), &times, 1e-6))
        .collect();
    let (ed, eg) = (ensemble(&d), ensemble(&g));
    for (t, (a, b)) in times.iter().zip(ed.iter().zip(&eg)) {
        let ([(ld, _), (nd, sd)], [(lg, _), (ng, sg)]) = (a, b);
        let se = (sd * sd + sg * sg).sqrt();
        println!(
            "t = {t}: mean l {ld:.3} / {lg:.3} ({:+.2e}); mean N {nd:.2} / {ng:.2} ({:+.2} SE)",
            lg / ld - 1.0,
            if se > 0.0 { (ng - nd) / se } else { 0.0 }
        );
        assert!((lg / ld - 1.0).abs() < 2e-3, "mean l at t = {t}");
        assert!(
            (ng - nd).abs() <= 3.0 * se,
            "mean N at t = {t}: {ng} against {nd} ± {se}"
        );
    }
    let pooled = |runs: &[Run]| Run {
        ln: Vec::new(),
        log: Vec::new(),
        steps: runs.iter().map(|r| r.steps).sum(),
        segments: 0,
    };
    let histogram = |runs: &[Run]| {
        let mut h = [0.0; 10];
        for r in runs {
            h.iter_mut()
                .zip(location_histogram(&r.log))
                .for_each(|(a, b)| *a += b / runs.len() as f64);
        }
        h
    };
    let (hd, hg) = (histogram(&d), histogram(&g));
    let gap = hd
        .iter()
        .zip(&hg)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    println!(
        "division locations by tenths: grid {hg:.4?}\n  discrete {hd:.4?}\n  steps {} / {}",
        pooled(&g).steps,
        pooled(&d).steps
    );
    assert!(gap < 0.01, "division locations differ by {gap}");
    // cells of a segment divided one by one: records of a single cell each
    assert!(g.iter().all(|r| {
        r.log
            .iter()
            .scan(100, |before, x| {
                let added = x.cells_after - *before;
                *before = x.cells_after;
                Some(added)
            })
            .all(|a| a == 1)
    }));
}

/// The age rule on two-cell segments: cells born together divide together, so `N(t)` is the
/// discrete line's at every output time (100 · 2^⌊t/T⌋) and `l(t)` differs only by the lumped
/// drag and shared stress (measured 4.0e-5 to t = 8 at K = 1e-5, 4.1e-3 at K = 1e-2).
#[test]
fn age_rule_on_two_cell_segments_keeps_n_and_l() {
    let times: Vec<f64> = (0..=16).map(|i| 0.5 * i as f64).collect();
    for (k, bound) in [(1e-5, 1e-4), (1e-2, 1e-2)] {
        let rule = || Box::new(AgeRule { period: 2.5 }) as Box<dyn DivisionRule>;
        let d = discrete_with(k, rule(), &times, 1e-6);
        let g = grid_with(k, 2, None, rule(), &times, 1e-6);
        let (el, en) = errors(&g, &d);
        println!(
            "K = {k}: l within {el:.2e}, N within {en:.2e}; N(8) = {}",
            d.ln[16].1
        );
        assert_eq!(d.ln[16].1, 800.0);
        assert_eq!(en, 0.0);
        assert!(el < bound, "l within {el}");
    }
}

/// A rule that reads the cell's shape (surface to volume, critical 3) on two-cell segments
/// sees one cell of a segment, its length and area halved: `N(t)` and `l(t)` follow the
/// discrete line (measured at K = 1e-5, t = 0, 1, …, 8: `N` equal but 376 against 377 at t = 7
/// and 464 against 463 at t = 8, within 2.7e-3; `l` within 1.8e-5). Seeing the whole segment,
/// it never divided.
#[test]
fn shape_rule_on_two_cell_segments_sees_single_cells() {
    let times: Vec<f64> = (0..=8).map(f64::from).collect();
    let rule = || Box::new(SurfaceToVolume { critical: 3.0 }) as Box<dyn DivisionRule>;
    let d = discrete_with(1e-5, rule(), &times, 1e-6);
    let g = grid_with(1e-5, 2, None, rule(), &times, 1e-6);
    let (el, en) = errors(&g, &d);
    println!(
        "N {:?} against {:?}; l within {el:.2e}, N within {en:.2e}",
        g.ln.iter().map(|x| x.1).collect::<Vec<_>>(),
        d.ln.iter().map(|x| x.1).collect::<Vec<_>>()
    );
    assert!(d.ln[8].1 > 400.0);
    assert!(en < 0.02 && el < 1e-4, "l within {el}, N within {en}");
}

/// In-phase merging ([`Coarsening::stress_within`]): under weak drag every cell grows, so
/// nothing stops growing to merge, but neighbours bearing nearly the same stress grow alike.
/// Merging those (and splitting a merged segment again once the stress across it exceeds four
/// tolerances) makes the grid follow the stress profile instead of the cell count. Against the
/// discrete line at every half time unit (rtol 1e-6). Measured:
/// - K = 1e-8 to t = 14 (6 400 cells), tolerance 1e-3 of the stress scale: `l` 3.0e-4, `N`
///   4.3e-4 (one output inside a division wave), 194 segments at the end, 5 518 steps against
///   the discrete line's 13 273. Which segments merge depends on the integration's path: at
///   rtol 7e-7, 1.4e-6 and 1e-7 (and at 1e-6 before the cell at the wall was tested against
///   its own stretch) the grid ends with 203 segments and `l` within 1.19e-4. So `l` is held
///   to half the merge tolerance, 5e-4, not to the one path's value;
/// - K = 1e-5 to t = 18 (971 cells), tolerance 1e-2: `l` 3.6e-4, `N` 1.2e-2, 92 segments,
///   10 905 steps against 31 569; at tolerance 1e-3 both errors fall (`l` 1.05e-5, `N` 1.1e-3).
#[test]
fn in_phase_merging_follows_the_stress_profile_not_the_cell_count() {
    let times = |t_end: f64| -> Vec<f64> {
        (0..=(2.0 * t_end) as usize)
            .map(|i| 0.5 * i as f64)
            .collect()
    };
    let run = |k: f64, d: &Run, within: f64| {
        let times: Vec<f64> = times(0.5 * (d.ln.len() - 1) as f64);
        let coarsen = Coarsening {
            growth_below: 0.0,
            stress_within: Some(within),
            max_cells: 1024,
            batch: 8,
        };
        let g = grid_run(k, 1, Some(coarsen), &times, 1e-6);
        let (el, en) = errors(&g, d);
        println!(
            "K = {k:e}, tolerance {within:e}: N = {} / {}, l error {el:.2e}, N error {en:.2e}, \
             {} segments, steps {} / {}",
            g.ln.last().unwrap().1,
            d.ln.last().unwrap().1,
            g.segments,
            g.steps,
            d.steps
        );
        (el, en, g.segments, g.steps)
    };
    let weak = discrete_run(1e-8, &times(14.0), 1e-6);
    let (el, en, segments, steps) = run(1e-8, &weak, 1e-3);
    assert!(el < 5e-4 && en < 1e-3, "{el} {en}");
    // the cost counters: segments for 6 400 cells, and steps
    assert_eq!((segments, steps), (194, 5518));
    let fig3_3 = discrete_run(1e-5, &times(18.0), 1e-6);
    let (el, en, segments, steps) = run(1e-5, &fig3_3, 1e-2);
    assert!(el < 5e-4 && en < 0.02, "{el} {en}");
    assert_eq!((segments, steps), (92, 10905));
    // a tighter tolerance converges on the discrete line
    let (el_tight, en_tight, _, _) = run(1e-5, &fig3_3, 1e-3);
    assert!(
        el_tight < el / 10.0 && en_tight < en / 2.0,
        "{el_tight} {en_tight}"
    );
}
