use super::*;
use crate::boundary::RightEnd;
use crate::cell::{Field, TanhGrowth};
use crate::line::build::{discrete, LineParams};
use crate::NeoHookean;
use num_dual::Dual64;

fn line(n: usize, form: DragForm, growth: bool, free: bool) -> Line<NeoHookean> {
    let mut p = LineParams::unit_cells(n);
    p.k = Field::Constant(0.3);
    p.eta = Field::Constant(0.7);
    p.mu = Field::gaussian_bump(1.0, 1.0, 0.5, 0.2);
    p.form = form;
    if growth {
        p.growth = Some(Arc::new(TanhGrowth::default()));
    }
    if free {
        p.right = RightEnd::Free(None);
    }
    discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap()
}

fn state(line: &Line<NeoHookean>) -> (Vec<f64>, Vec<f64>) {
    let mut y = line.initial_state();
    for (i, v) in y.iter_mut().enumerate() {
        *v += 0.05 * ((i as f64) * 0.7).sin();
    }
    let yp = (0..y.len())
        .map(|i| 0.1 * ((i as f64) * 1.3).cos())
        .collect();
    (y, yp)
}

#[test]
fn two_thread_residual_is_the_serial_one() {
    // every split point of small lines (both drag forms, with and without growth, free
    // or prescribed end), in f64 and in dual numbers: bitwise the serial rows
    for form in [DragForm::Boundary, DragForm::Centre] {
        for (growth, free) in [(false, false), (true, true), (false, true)] {
            let l = line(9, form, growth, free);
            let (y, yp) = state(&l);
            let n = y.len();
            let mut serial = vec![0.0; n];
            l.residual_cells(0.3, &y, &yp, &mut serial, 0, 1, 9)
                .unwrap();
            let yd: Vec<Dual64> = y.iter().map(|&v| Dual64::new(v, 0.5)).collect();
            let ypd: Vec<Dual64> = yp.iter().map(|&v| Dual64::new(v, -0.25)).collect();
            let mut serial_d = vec![Dual64::new(0.0, 0.0); n];
            l.residual_cells(0.3, &yd, &ypd, &mut serial_d, 0, 1, 9)
                .unwrap();
            for c0 in 2..=9 {
                let mut r = vec![f64::NAN; n];
                l.residual_two_threads(0.3, &y, &yp, &mut r, c0)
                    .expect("splittable")
                    .unwrap();
                assert_eq!(r, serial, "{form:?} growth={growth} free={free} c0={c0}");
                let mut rd = vec![Dual64::new(f64::NAN, f64::NAN); n];
                l.residual_two_threads(0.3, &yd, &ypd, &mut rd, c0)
                    .expect("splittable")
                    .unwrap();
                for (a, b) in rd.iter().zip(&serial_d) {
                    assert_eq!((a.re, a.eps), (b.re, b.eps), "dual c0={c0}");
                }
            }
        }
    }
}

#[test]
fn two_thread_residual_reports_the_serial_error() {
    // a collapsed cell in either half: the same error as the serial sweep
    let l = line(12, DragForm::Centre, false, false);
    for bad in [2usize, 5, 6, 7, 11] {
        let (mut y, yp) = state(&l);
        // boundary `bad` moved onto boundary `bad − 1`: cell `bad` has zero stretch
        y[l.layout.xi[bad]] = y[l.layout.xi[bad - 1]];
        let mut r = vec![0.0; y.len()];
        let serial = l.residual_cells(0.0, &y, &yp, &mut r, 0, 1, 12);
        assert!(serial.is_err());
        for c0 in [3, 6, 7, 10] {
            let two = l.residual_two_threads(0.0, &y, &yp, &mut r, c0).unwrap();
            assert_eq!(two, serial, "bad={bad} c0={c0}");
        }
    }
}

#[test]
fn large_lines_take_the_two_thread_path_with_the_serial_result() {
    let n = PAR_MIN_CELLS + 5;
    let l = line(n, DragForm::Boundary, false, false);
    let (y, yp) = state(&l);
    let mut serial = vec![0.0; y.len()];
    l.residual_cells(0.1, &y, &yp, &mut serial, 0, 1, n)
        .unwrap();
    let mut r = vec![0.0; y.len()];
    l.residual(0.1, &y, &yp, &mut r).unwrap();
    assert_eq!(r, serial);
}

/// The residual of `l` with every layout and field read from the vectors (no contiguous
/// layout, no uniform fields): the reference the fast paths must reproduce bitwise.
fn reference_residual<S: Scalar>(l: &Line<NeoHookean>, y: &[S], yp: &[S]) -> Vec<S> {
    let mut slow = l.clone();
    slow.uniform = UniformFields::default();
    slow.uniform.extended = l.uniform.extended;
    let mut r = vec![S::from(f64::NAN); y.len()];
    slow.residual_cells_in::<S, _, true>(
        Indexed(&slow.layout),
        0.4,
        y,
        yp,
        &mut r,
        0,
        1,
        l.n_cells(),
    )
    .unwrap();
    r
}

#[test]
fn fast_paths_give_the_indexed_residual_bitwise() {
    // uniform fields (l0, mu, eta, K all uniform) and the contiguous layout, in f64 and
    // dual numbers, both forms, prescribed and free ends: bitwise the indexed sweep
    for form in [DragForm::Boundary, DragForm::Centre] {
        for free in [false, true] {
            let mut p = LineParams::unit_cells(7);
            p.k = Field::Constant(0.3);
            p.eta = Field::Constant(0.7);
            p.form = form;
            if free {
                p.right = RightEnd::Free(None);
            }
            let l = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
            assert!(l.contiguous().is_some());
            let u = l.uniform;
            assert!(u.inv_l0.is_some() && u.mu.is_some() && u.eta.is_some() && u.k_face.is_some());
            let (y, yp) = state(&l);
            let mut r = vec![0.0; y.len()];
            l.residual(0.4, &y, &yp, &mut r).unwrap();
            assert_eq!(r, reference_residual(&l, &y, &yp), "{form:?} free={free}");
            let yd: Vec<Dual64> = y.iter().map(|&v| Dual64::new(v, 0.5)).collect();
            let ypd: Vec<Dual64> = yp.iter().map(|&v| Dual64::new(v, -0.25)).collect();
            let mut rd = vec![Dual64::new(0.0, 0.0); y.len()];
            l.residual(0.4, &yd, &ypd, &mut rd).unwrap();
            for (a, b) in rd.iter().zip(reference_residual(&l, &yd, &ypd)) {
                assert_eq!((a.re, a.eps), (b.re, b.eps));
            }
        }
    }
}

#[test]
fn a_divided_line_reads_its_changed_fields() {
    // a growing line with uniform fields; cell 2 divides at g = 1.6, so its daughters have
    // L₀ = 0.8 and L₀ is no longer uniform: the residual must read the new lengths
    let mut p = LineParams::unit_cells(5);
    p.right = RightEnd::Free(None);
    p.k = Field::Constant(0.2);
    p.growth = Some(Arc::new(TanhGrowth::default()));
    let mut l = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
    assert!(l.uniform.inv_l0.is_some());
    let before = l.uniform;
    let mut y = l.initial_state();
    y[l.layout.gi[1]] = 1.6;
    y[l.layout.xi[2]] += 0.6;
    l.split_cell(2, 0.0, &mut y).unwrap();
    assert_eq!(l.n_cells(), 6);
    assert_eq!(l.uniform.inv_l0, None);
    let yp: Vec<f64> = (0..y.len()).map(|i| 0.01 * i as f64).collect();
    let mut r = vec![0.0; y.len()];
    l.residual(0.0, &y, &yp, &mut r).unwrap();
    assert_eq!(r, reference_residual(&l, &y, &yp));
    // and the check can fail: with the detection of before the split, cells 2 and 3
    // would be read with L₀ = 1
    let mut stale = l.clone();
    stale.uniform = before;
    let mut rs = vec![0.0; y.len()];
    stale.residual(0.0, &y, &yp, &mut rs).unwrap();
    assert_ne!(rs, r);
}

#[test]
fn density_divisions_refresh_the_uniform_fields() {
    use crate::proliferation::DensityContinuum;
    use integrators::{EventAction, Problem};
    let mut p = LineParams::unit_cells(6);
    p.right = RightEnd::Free(None);
    p.k = Field::Constant(0.2);
    p.growth = Some(Arc::new(TanhGrowth::default()));
    let l = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
    let mut d = crate::ArrayProblem::new(DensityContinuum::new(l, 6, 1.5).unwrap());
    let mut y = d.array.line.initial_state();
    let gk = d.array.line.layout.gi[2];
    y[gk] = 1.5;
    let yp = vec![0.0; y.len()];
    let act = d.handle_event(0.0, &[2], &mut y, &yp).unwrap();
    assert_eq!(act, EventAction::Modified);
    let line = &d.array.line;
    assert_eq!(line.uniform.inv_l0, None);
    assert_eq!(line.uniform.k_face, None);
    let mut r = vec![0.0; y.len()];
    line.residual(0.0, &y, &yp, &mut r).unwrap();
    assert_eq!(r, reference_residual(line, &y, &yp));
}

/// The band from the end windows (`Line::pattern`) is the band of the whole walk over every
/// Jacobian entry, for every combination of unknowns, ends and drag form, at every size from
/// 2 cells (a held line of one cell without growth has no unknowns) to past the windows.
#[test]
fn pattern_from_the_end_windows_is_the_full_band() {
    use crate::cell::MaxwellBranch;
    for n in 2..=16 {
        for form in [DragForm::Boundary, DragForm::Centre] {
            for (growth, free, maxwell) in (0..8).map(|b| (b & 1 != 0, b & 2 != 0, b & 4 != 0)) {
                let mut l = line(n, form, growth, free);
                if maxwell {
                    let mut p = LineParams::unit_cells(n);
                    p.form = form;
                    p.growth = l.growth.clone();
                    p.right = if free { RightEnd::Free(None) } else { p.right };
                    p.maxwell = Some(MaxwellBranch::standard_linear_solid(0.5, 2.0).unwrap());
                    l = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
                }
                let (mut lower, mut upper) = (0, 0);
                l.for_each_jacobian_entry(|i, j| {
                    lower = lower.max(i.saturating_sub(j));
                    upper = upper.max(j.saturating_sub(i));
                });
                let full = Pattern::Banded { lower, upper };
                assert_eq!(
                    l.pattern(),
                    full,
                    "n = {n}, {form:?}, growth {growth}, free {free}, maxwell {maxwell}"
                );
            }
        }
    }
}

#[test]
fn a_growing_line_gives_the_per_cell_growth_rows_bitwise() {
    // the interleaved layout: bitwise the indexed sweep; the growth rows handed to the law in
    // blocks (`GrowthLaw::values`): bitwise `ġ − G(σ)` with one law call per cell, σ from
    // `eval_cell`; on lines shorter and longer than a block, whole and in two-thread halves
    let law = TanhGrowth::default();
    for form in [DragForm::Boundary, DragForm::Centre] {
        for free in [false, true] {
            for n in [5, 64, 150] {
                let l = line(n, form, true, free);
                assert!(l.interleaved().is_some() && l.contiguous().is_none());
                let (y, yp) = state(&l);
                let mut r = vec![f64::NAN; y.len()];
                l.residual(0.4, &y, &yp, &mut r).unwrap();
                assert_eq!(
                    r,
                    reference_residual(&l, &y, &yp),
                    "{form:?} free={free} n={n}"
                );
                for c in 1..=n {
                    let gk = l.layout().gi[c - 1];
                    let sigma = l.eval_cell(c, 0.4, &y, &yp).unwrap().sigma;
                    assert_eq!(r[gk], yp[gk] - law.value(sigma), "cell {c}");
                }
                for c0 in [2, n / 2 + 1, n] {
                    let mut rh = vec![f64::NAN; y.len()];
                    l.residual_two_threads(0.4, &y, &yp, &mut rh, c0)
                        .expect("splittable")
                        .unwrap();
                    assert_eq!(rh, r, "{form:?} free={free} n={n} c0={c0}");
                }
            }
        }
    }
    // without growth the thesis's layout, not this one
    assert!(line(9, DragForm::Boundary, false, true)
        .interleaved()
        .is_none());
}
