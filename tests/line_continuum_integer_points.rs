//! A continuum grid over cells that read their fields at integer points (`sampling =
//! "integer_points"`, the thesis code's grid: cell j reads μ at its left end X_{j−1}) reads the
//! cells' field, not one displaced by half a cell (docs/model.md §3.3a). Stiff cluster (2.82)
//! on 100 unit cells held at l = 90 without drag: the static equilibrium (one stress, each
//! stretch from its own μ) of the discrete line against grids coarser and finer than the cells,
//! at centre and integer-point sampling alike.

use celltissue::boundary::{Ramp, RightEnd};
use celltissue::cell::{Field, Sampling};
use celltissue::line::build::{continuum, discrete, LineParams};
use celltissue::line::static_solve::static_equilibrium;
use celltissue::NeoHookean;

fn nh() -> NeoHookean {
    NeoHookean::new(1.0).unwrap()
}

fn params(sampling: Sampling) -> LineParams {
    let mut p = LineParams::unit_cells(100);
    p.mu = Field::gaussian_bump(1.0, 1.0, 0.5, 0.1);
    p.sampling = sampling;
    p.right = RightEnd::Prescribed(Ramp::Constant(90.0));
    p
}

/// Linear interpolation of `(xs, ys)` (increasing `xs`) at `x` inside them.
fn interp(xs: &[f64], ys: &[f64], x: f64) -> f64 {
    let i = xs.partition_point(|&a| a <= x).clamp(1, xs.len() - 1);
    let w = (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
    ys[i - 1] + w * (ys[i] - ys[i - 1])
}

/// The largest gap between the static stretches of the discrete line and of the continuum on
/// `n` segments, each read where the other has its points (the finer one interpolated at the
/// coarser one's centres, inside the line).
fn stretch_gap(sampling: Sampling, n: usize) -> f64 {
    let p = params(sampling);
    let d = static_equilibrium(&discrete(nh(), &p).unwrap(), 90.0).unwrap();
    let c = static_equilibrium(&continuum(nh(), &p, n).unwrap(), 90.0).unwrap();
    let centres = |len: usize| -> Vec<f64> {
        let h = 100.0 / len as f64;
        (0..len).map(|i| (i as f64 + 0.5) * h).collect()
    };
    let (xd, xc) = (centres(100), centres(n));
    let (coarse_x, coarse, fine_x, fine) = if n < 100 {
        (&xc, &c.lambda, &xd, &d.lambda)
    } else {
        (&xd, &d.lambda, &xc, &c.lambda)
    };
    coarse_x
        .iter()
        .zip(coarse)
        .filter(|(&x, _)| x > fine_x[0] && x < fine_x[fine_x.len() - 1])
        .map(|(&x, &l)| (interp(fine_x, fine, x) - l).abs())
        .fold(0.0, f64::max)
}

/// On grids of 1/4, 1/16 and 4 cells per segment the continuum's stretches lie on the discrete
/// line's under either sampling, to the interpolation's own error, and a finer grid comes
/// closer: 2.3e-6 on 400 segments, 1.4e-7 on 1 600, 3.7e-5 on 25, alike for both. (Reading a
/// smooth field at each segment's left end, as the cells do, put a grid's field `h/2` instead of
/// half a cell to the left: under integer points the gap was 1.2e-3 on 400 segments, 1.5e-3 on
/// 1 600, converging to the wrong line, and 4.7e-3 on 25.)
#[test]
fn a_grid_reads_the_field_the_cells_read_at_integer_points() {
    for sampling in [Sampling::Centres, Sampling::IntegerPoints] {
        let fine = stretch_gap(sampling, 400);
        let finer = stretch_gap(sampling, 1600);
        let coarse = stretch_gap(sampling, 25);
        eprintln!("{sampling:?}: gap 400 {fine:.3e}, 1600 {finer:.3e}, 25 {coarse:.3e}");
        assert!(
            fine < 5e-5 && finer <= fine,
            "{sampling:?}: {fine:e}, {finer:e}"
        );
        assert!(coarse < 5e-4, "{sampling:?}: 25 segments {coarse:e}");
    }
}

/// On 100 segments of one cell each the continuum is the discrete line, bit for bit, under
/// either sampling (the grid reads a cell's field where the cell does).
#[test]
fn a_grid_of_the_cells_is_the_discrete_line_at_integer_points() {
    for sampling in [Sampling::Centres, Sampling::IntegerPoints] {
        let p = params(sampling);
        let d = discrete(nh(), &p).unwrap();
        let c = continuum(nh(), &p, 100).unwrap();
        assert_eq!(d.cells().mu, c.cells().mu, "{sampling:?}");
    }
}

/// A grid finer than the cells reads a field that jumps from cell to cell as the cell holding
/// each segment reads it, also a piecewise field whose break lies inside a cell: cell 51 of 100
/// reads 1 at its left end X = 50 under integer points and 3 at its centre, the break X = 50.5,
/// under centres, while two of its four segments lie on each side of the break (they read 1,
/// 1, 3, 3 before).
#[test]
fn a_finer_grid_reads_each_cells_jumping_field_as_the_cell_does() {
    for sampling in [Sampling::Centres, Sampling::IntegerPoints] {
        for mu in [
            Field::Piecewise {
                breaks: vec![0.505],
                values: vec![1.0, 3.0],
            },
            Field::PerCell {
                values: (0..100).map(|j| 1.0 + (j % 7) as f64).collect(),
            },
            Field::PerCell {
                values: vec![1.0, 2.0, 4.0],
            },
        ] {
            let mut p = params(sampling);
            p.mu = mu;
            let cells = discrete(nh(), &p).unwrap().cells().mu.clone();
            let grid = continuum(nh(), &p, 400).unwrap().cells().mu.clone();
            for (s, m) in grid.iter().enumerate() {
                assert_eq!(*m, cells[s / 4], "{sampling:?}, segment {s}");
            }
        }
    }
}
