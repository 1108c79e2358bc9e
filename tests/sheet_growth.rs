//! Growth of the sheet's cells in both in-plane directions (docs/sheet_growth.md): growth
//! stretches `g₁, g₂` per cell with `ġᵢ = G(σᵢᵢ)`, the cell law at `λᵢ/gᵢ`, a free side `x = l`.
//!
//! * uniform unconstrained growth (no drag, free sides) is exact: `λᵢ = gᵢ = 1 + G(0) t`, no
//!   stress, the height unchanged — discrete and continuum;
//! * with a periodic side and growth along x only the rows decouple, and each row is the
//!   line of cells with a free end (the same plane-strain law, width and drag): the sheet's
//!   face positions equal the line's boundary positions;
//! * the sheet's outputs name what the line's do: its rows' profile `stretch` (the elastic
//!   stretch α = λ/g), `lambda` (the total stretch) and the series' stretch extremes equal
//!   the line's;
//! * discrete and continuum converge as the continuum grid is refined;
//! * keys that cannot act are refused by name.

use crate::common::sheet_solver;
use celltissue::array::ArrayProblem;
use celltissue::boundary::RightEnd;
use celltissue::cell::growth_laws::tanh;
use celltissue::cell::TanhGrowth;
use celltissue::drive::drive;
use celltissue::line::build::{discrete, LineParams};
use celltissue::line::run::{integrate as integrate_line, SolveSettings};
use celltissue::line::{run_line, LineConfig};
use celltissue::observe::{ModelKind, RunRecord};
use celltissue::runner::OutputTimes;
use celltissue::sheet::uniaxial::UniaxialSheet;
use celltissue::sheet::{run_sheet, GrowthDirections, RightEdge, SheetConfig, TopBoundary};
use celltissue::substrate::FreeEndDrag;
use celltissue::NeoHookean;
use std::sync::Arc;

fn nh() -> NeoHookean {
    NeoHookean::new(1.0).unwrap()
}

/// A growing sheet with a free side `x = l` and the thesis's tanh law (σ₀ = 0.1, G_m = 1).
fn growing(cells_x: usize, cells_y: usize, drag: f64, top: TopBoundary) -> SheetConfig {
    SheetConfig {
        cells_x,
        cells_y,
        drag: Some(drag),
        top,
        right: RightEdge::Free,
        growth: Some(tanh(TanhGrowth::default()).unwrap()),
        ..Default::default()
    }
}

fn run(cfg: &SheetConfig, model: ModelKind, grid: Option<(usize, usize)>, t: &[f64]) -> RunRecord {
    let out = OutputTimes {
        series: t.to_vec(),
        profiles: t.to_vec(),
    };
    let rec = run_sheet(cfg, &nh(), model, grid, &sheet_solver(1e-10, 1e-12), &out).unwrap();
    assert!(rec.error.is_none(), "{:?}", rec.error);
    rec
}

#[test]
fn uniform_unconstrained_growth_is_exact() {
    let cfg = growing(4, 3, 0.0, TopBoundary::Free);
    let times = [1.0, 4.0];
    for (model, grid) in [
        (ModelKind::Discrete, None),
        (ModelKind::Continuum, Some((8, 5))),
    ] {
        let rec = run(&cfg, model, grid, &times);
        let mut worst = 0.0f64;
        for (i, p) in rec.profiles.iter().enumerate() {
            let g = 1.0 + 0.5 * times[i]; // G(0) = G_m/2
            for c in 0..p.stretch.len() {
                // unstressed: the elastic stretches (`stretch`, `stretch_y`) stay 1, the
                // total ones (`lambda`, `lambda_y`) are the growth
                for v in [
                    p.stretch[c] - 1.0,
                    p.extra["stretch_y"][c] - 1.0,
                    p.extra["lambda"][c] - g,
                    p.extra["lambda_y"][c] - g,
                    p.extra["growth_x"][c] - g,
                    p.extra["growth_y"][c] - g,
                    p.extra["height"][c] - 1.0,
                    p.extra["sigma11"][c],
                    p.extra["sigma22"][c],
                ] {
                    worst = worst.max(v.abs());
                }
            }
            worst = worst
                .max((rec.series.length[i] - 4.0 * g).abs())
                .max((rec.series.extra["mean_width"][i] - 3.0 * g).abs());
        }
        println!("{model:?}: largest departure from g = 1 + t/2 at t = 1, 4: {worst:.2e}");
        assert!(worst < 1e-9, "{model:?}: {worst}");
    }
}

#[test]
fn rows_of_a_periodic_sheet_growing_along_x_are_lines_of_cells() {
    let (n, k_drag, t_end) = (20, 1e-2, 10.0);
    let mut cfg = growing(n, 3, k_drag, TopBoundary::Periodic);
    cfg.growth_directions = GrowthDirections::X;
    let sheet = UniaxialSheet::discrete(nh(), &cfg.params())
        .unwrap()
        .with_cell_atol(1e-12);
    let y0 = sheet.initial_state();
    let mut problem = ArrayProblem::new(sheet);
    let mut states = Vec::new();
    let driven = drive(
        &mut problem,
        &sheet_solver(1e-10, 1e-12),
        &y0,
        &[2.0, t_end],
        &[],
        |_, t, y, _| {
            states.push((t, y.to_vec()));
            Ok(())
        },
    );
    assert!(driven.error.is_none(), "{:?}", driven.error);
    let sheet = &problem.array;

    let mut p = LineParams::unit_cells(n);
    p.right = RightEnd::Free(None);
    p.k = k_drag.into();
    p.growth = Some(Arc::new(TanhGrowth::default()));
    p.atol_cell = 1e-12;
    let line = discrete(nh(), &p).unwrap();
    let settings = SolveSettings {
        rtol: 1e-10,
        atol: 1e-12,
        ..Default::default()
    };
    let traj = integrate_line(&mut ArrayProblem::new(line), &settings, &[2.0, t_end]);
    assert!(traj.error.is_none(), "{:?}", traj.error);

    let mut worst = 0.0f64;
    let mut y_motion = 0.0f64;
    for ((t, y), snap) in states.iter().zip(&traj.snapshots) {
        for k in 1..=3 {
            for j in 0..=n {
                worst = worst.max((sheet.xb(y, *t, j, k) - snap.x[j]).abs());
            }
        }
        for j in 1..=n {
            for k in 0..3 {
                y_motion = y_motion.max((sheet.yb(y, j, k) - k as f64).abs());
            }
        }
    }
    let l = traj.snapshots[1].x[n];
    println!(
        "periodic sheet, growth along x, K = {k_drag}: l({t_end}) = {l:.6} (line); \
         largest face-position difference {worst:.2e}, largest y motion {y_motion:.2e}"
    );
    assert!(l > 2.0 * n as f64, "the line grows: {l}");
    assert!(worst < 1e-7 * l, "{worst}");
    assert!(y_motion < 1e-10, "{y_motion}");
}

#[test]
fn the_rows_outputs_are_the_lines_outputs_under_the_same_names() {
    let (n, rows, k_drag) = (20, 3, 1e-2);
    let mut cfg = growing(n, rows, k_drag, TopBoundary::Periodic);
    cfg.growth_directions = GrowthDirections::X;
    let times = [2.0, 10.0];
    let sheet = run(&cfg, ModelKind::Discrete, None, &times);
    let line_cfg: LineConfig = toml::from_str(&format!(
        "cells = {n}\nK = {k_drag}\nright_end = \"free\"\ngrowth = {{ sigma0 = 0.1 }}"
    ))
    .unwrap();
    let out = OutputTimes {
        series: times.to_vec(),
        profiles: times.to_vec(),
    };
    let settings = SolveSettings {
        rtol: 1e-10,
        atol: 1e-12,
        ..Default::default()
    };
    let line = run_line(&line_cfg, ModelKind::Discrete, None, &settings, &out);
    assert!(line.error.is_none(), "{:?}", line.error);
    let mut worst = 0.0f64;
    let mut elastic_vs_total = 0.0f64;
    for (ps, pl) in sheet.profiles.iter().zip(&line.profiles) {
        // the sheet lists its cells column by column: cell (j, k) at (j − 1)·rows + (k − 1)
        for j in 0..n {
            for k in 0..rows {
                let c = j * rows + k;
                worst = worst
                    .max((ps.stretch[c] - pl.stretch[j]).abs())
                    .max((ps.extra["lambda"][c] - pl.extra["lambda"][j]).abs())
                    .max((ps.extra["growth_x"][c] - pl.extra["g"][j]).abs());
                elastic_vs_total =
                    elastic_vs_total.max((ps.extra["lambda"][c] - ps.stretch[c]).abs());
            }
        }
    }
    let (s, l) = (&sheet.series, &line.series);
    for (a, b) in s
        .min_stretch
        .iter()
        .chain(&s.max_stretch)
        .zip(l.min_stretch.iter().chain(&l.max_stretch))
    {
        worst = worst.max((a - b).abs());
    }
    println!(
        "periodic sheet rows against the line, K = {k_drag}: largest difference in `stretch`, \
         `lambda`, growth and the stretch extremes {worst:.2e}; total − elastic up to \
         {elastic_vs_total:.2}"
    );
    assert!(worst < 1e-7, "{worst}");
    // the two names hold different quantities here: the cells have grown
    assert!(elastic_vs_total > 1.0, "{elastic_vs_total}");
}

#[test]
fn continuum_converges_under_refinement() {
    let cfg = growing(6, 4, 0.05, TopBoundary::Free);
    let vals: Vec<[f64; 2]> = [(6, 4), (12, 8), (24, 16), (48, 32)]
        .into_iter()
        .map(|g| {
            let rec = run(&cfg, ModelKind::Continuum, Some(g), &[3.0]);
            [rec.series.length[0], rec.series.extra["mean_width"][0]]
        })
        .collect();
    let d: Vec<f64> = vals
        .windows(2)
        .map(|w| (w[1][0] - w[0][0]).abs().max((w[1][1] - w[0][1]).abs()))
        .collect();
    println!("growing sheet, (length, width) at t = 3 on 6x4 … 48x32: {vals:?}; differences {d:?}");
    // the sheet is not growing freely: drag holds it back from g = 1 + t/2 = 2.5
    assert!(vals[0][0] < 6.0 * 2.5 && vals[0][1] < 4.0 * 2.5);
    assert!(d[1] < 0.6 * d[0] && d[2] < 0.6 * d[1], "{d:?}");
}

/// The free edges' drag (docs/model.md §3.3a, "The free end's drag"): with
/// `free_end_drag = "cells"` a grid twice as fine as the cells approximates the discrete sheet
/// to second order in the cell size, with the default `"segment"` to first order (the edge
/// cells' half cell of drag, as at a line's free end). N × M = 6 × 4, 12 × 8, 24 × 16 cells
/// growing with free sides to t = 3, drag 0.05 (6/N)² (the macroscale held). Measured gaps in
/// (l/N, w/M) on grids twice as fine: "cells" (7.3e-3, 1.1e-2), (2.3e-3, 3.4e-3),
/// (6.3e-4, 9.3e-4) (order 1.85 over the last doubling); "segment" (5.5e-2, 7.3e-2),
/// (3.0e-2, 4.0e-2), (1.6e-2, 2.1e-2) (0.95).
#[test]
fn the_cells_free_edges_make_a_grid_approximate_the_cells_to_second_order() {
    let gaps = |drag: FreeEndDrag| -> Vec<f64> {
        [1usize, 2, 4]
            .into_iter()
            .map(|s| {
                let mut cfg = growing(6 * s, 4 * s, 0.05 / (s * s) as f64, TopBoundary::Free);
                cfg.free_end_drag = drag;
                let d = run(&cfg, ModelKind::Discrete, None, &[3.0]);
                let c = run(&cfg, ModelKind::Continuum, Some((12 * s, 8 * s)), &[3.0]);
                let gap_l = (c.series.length[0] - d.series.length[0]).abs() / (6 * s) as f64;
                let w = |r: &RunRecord| r.series.extra["mean_width"][0];
                let gap_w = (w(&c) - w(&d)).abs() / (4 * s) as f64;
                println!(
                    "{drag:?} {} x {}: gaps l/N {gap_l:.3e}, w/M {gap_w:.3e}",
                    6 * s,
                    4 * s
                );
                gap_l.max(gap_w)
            })
            .collect()
    };
    let (cells, segment) = (gaps(FreeEndDrag::Cells), gaps(FreeEndDrag::Segment));
    let order = |g: &[f64]| (g[1] / g[2]).log2();
    println!(
        "orders over the last doubling: cells {:.2}, segment {:.2}",
        order(&cells),
        order(&segment)
    );
    assert!(order(&cells) > 1.7, "{cells:?}");
    assert!((0.8..1.2).contains(&order(&segment)), "{segment:?}");
    assert!(cells[2] < segment[2] / 10.0, "{cells:?} vs {segment:?}");
}

#[test]
fn keys_that_cannot_act_are_refused_by_name() {
    let free_without_growth = SheetConfig {
        right: RightEdge::Free,
        ..Default::default()
    };
    assert_eq!(free_without_growth.validate().unwrap_err().key, "right");
    let directions_without_growth = SheetConfig {
        growth_directions: GrowthDirections::X,
        ..Default::default()
    };
    assert_eq!(
        directions_without_growth.validate().unwrap_err().key,
        "growth_directions"
    );
    let cfg: SheetConfig = toml::from_str(
        "right = \"free\"\ngrowth = { law = \"tanh\", sigma0 = 0.1 }\ngrowth_directions = \"x\"",
    )
    .unwrap();
    assert!(cfg.validate().is_ok());
    let both: SheetConfig =
        toml::from_str("right = \"free\"\ngrowth = { law = \"tanh\", sigma0 = 0.1 }").unwrap();
    assert!(both.validate().is_ok());
    assert_eq!(both.growth_directions, GrowthDirections::Both);
    assert!(toml::from_str::<SheetConfig>("growth_directions = \"z\"").is_err());
    // the free edges' drag needs a free edge: a periodic side and a prescribed one have none
    let no_free_edge: SheetConfig =
        toml::from_str("top = \"periodic\"\nfree_end_drag = \"cells\"").unwrap();
    assert_eq!(no_free_edge.validate().unwrap_err().key, "free_end_drag");
    let free_top: SheetConfig = toml::from_str("free_end_drag = \"cells\"").unwrap();
    assert!(free_top.validate().is_ok());
}
