use super::*;

/// The first `len` items of `list`, summed as they are (no base, no derivative item).
fn plain(list: [(&[f64], f64, f64); NC], len: usize) -> Items<'_> {
    Items {
        list,
        len,
        base: None,
        deriv: false,
    }
}

#[test]
fn interpolation_reproduces_polynomials() {
    // cubic through 4 nodes: exact value and derivative
    let f = |t: f64| 1.0 + 2.0 * t - t * t + 0.5 * t * t * t;
    let df = |t: f64| 2.0 - 2.0 * t + 1.5 * t * t;
    let z = [1.0, 0.7, 0.2, -0.4];
    let mut p = [0.0; NC];
    let mut dp = [0.0; NC];
    interp_coeffs(&z, 1.3, &mut p, &mut dp);
    let v: f64 = (0..4).map(|i| p[i] * f(z[i])).sum();
    let d: f64 = (0..4).map(|i| dp[i] * f(z[i])).sum();
    assert!((v - f(1.3)).abs() < 1e-12);
    assert!((d - df(1.3)).abs() < 1e-12);
}

#[test]
fn interpolation_coefficients_do_not_depend_on_the_time_scale() {
    // order-5 nodes with a double (derivative) node, as after a start: at steps of 1e-80
    // the unscaled divided differences (1/h⁵ ≈ 1e400) overflowed; in time units of a power
    // of two the coefficients are the unit-scale ones, the derivative's scaled by 1/s and
    // the derivative item's value coefficient by s, exactly (s a power of two) or to
    // rounding (s = 10^-k)
    let z = [1.0, 0.7, 0.45, 0.2, 0.0, 0.0];
    let t = 1.3;
    let (mut p, mut dp) = ([0.0; NC], [0.0; NC]);
    interp_coeffs(&z, t, &mut p, &mut dp);
    let m = z.len();
    for (s, exact) in [
        (2f64.powi(-300), true),
        (1e-80, false),
        (1e-250, false),
        (1e250, false),
    ] {
        let zs = z.map(|x| x * s);
        let (mut ps, mut dps) = ([0.0; NC], [0.0; NC]);
        interp_coeffs(&zs, t * s, &mut ps, &mut dps);
        for q in 0..=m {
            // the derivative item's coefficients carry one power of time more
            let unit = if q == m { s } else { 1.0 };
            let (want, dwant) = (p[q] * unit, dp[q] * unit / s);
            for (got, want) in [(ps[q], want), (dps[q], dwant)] {
                assert!(got.is_finite(), "s = {s:e}, item {q}: {got}");
                if exact {
                    assert_eq!(got, want, "s = {s:e}, item {q}");
                } else {
                    assert!(
                        (got - want).abs() <= 1e-12 * want.abs().max(unit),
                        "s = {s:e}, item {q}: {got:e} against {want:e}"
                    );
                }
            }
        }
    }
}

#[test]
fn split_vector_passes_match_the_whole_pass() {
    // the two-thread split of the predictor/weights pass and of the error-norm sweep, run
    // here on one thread at a block boundary: predictor and weights bitwise, norms merged
    let n = 3 * BLK + 17;
    let vec_of = |k: f64| -> Vec<f64> { (0..n).map(|i| (i as f64 * k).sin() + 1.5).collect() };
    let (h0, h1, h2) = (vec_of(0.3), vec_of(0.7), vec_of(1.1));
    let mut list = [(&[][..], 0.0, 0.0); NC];
    list[0] = (&h0[..], 1.7, 0.4);
    list[1] = (&h1[..], -0.9, -1.3);
    list[2] = (&h2[..], 0.2, 0.9);
    let items = plain(list, 3);
    let atol = vec![1e-6; n];
    let alg: Vec<bool> = (0..n).map(|i| i % 5 == 0).collect();
    // the identity and a line's cell map (anchor + differences with the previous
    // component, so the sweep's partners cross the block and split boundaries)
    let mut rows = vec![crate::Row::Anchor { size: 2.0 }];
    rows.extend((1..n).map(|i| crate::Row::Difference { partner: i - 1 }));
    let line = ErrorMap::from_rows(rows).expect("valid rows");
    for mut map in [ErrorMap::default(), line] {
        let eatol = if map.is_empty() {
            atol.clone()
        } else {
            map.effective_atol(&atol, 1e-3)
        };
        let run = |mid: usize| {
            let (mut y, mut yp, mut nw, mut ew, mut pred) = (
                vec![0.0; n],
                vec![0.0; n],
                vec![0.0; n],
                vec![0.0; n],
                vec![0.0; n],
            );
            let (y1, y2) = y.split_at_mut(mid);
            let (yp1, yp2) = yp.split_at_mut(mid);
            let (n1, n2) = nw.split_at_mut(mid);
            let (e1, e2) = ew.split_at_mut(mid);
            let (p1, p2) = pred.split_at_mut(mid);
            let w = |pred, nwt, ewt| Weights {
                pred,
                nwt,
                ewt: Some(ewt),
                atol: &eatol,
                algebraic: &alg,
                rtol: 1e-3,
                map: &map,
            };
            poly_blocks(&items, &h0, 0, y1, yp1, Some(w(p1, n1, e1)));
            poly_blocks(&items, &h0, mid, y2, yp2, Some(w(p2, n2, e2)));
            // the stored predictor is the predictor
            assert_eq!(pred, y);
            (y, yp, nw, ew)
        };
        let whole = run(n);
        let split = run(BLK);
        assert_eq!(whole, split);
        let ycur = vec_of(0.5);
        let norm_items = [plain(list, 3), plain(list, 2)];
        for norm in [ErrorNorm::Max, ErrorNorm::Rms] {
            let a = norm_blocks(&norm_items, &ycur, &whole.3, norm, &map, 0, n);
            let mut a1 = norm_blocks(&norm_items, &ycur, &whole.3, norm, &map, 0, BLK);
            let a2 = norm_blocks(&norm_items, &ycur, &whole.3, norm, &map, BLK, n);
            for (x, y) in a1.iter_mut().zip(&a2) {
                x.merge(y);
            }
            let close = |x: f64, y: f64| (x - y).abs() <= 1e-14 * x.abs().max(1e-300);
            // (two orders in the sweep: the other accumulators stay empty)
            for ((x, y), it) in a.iter().zip(&a1).zip(&norm_items) {
                assert!(
                    x.finish(n) > 0.0 && close(x.finish(n), y.finish(n)),
                    "{norm:?}"
                );
                // against the materialised error vector through `ErrorMap::norm`
                let err: Vec<f64> = (0..n)
                    .map(|i| ycur[i] - it.as_slice().iter().map(|&(v, c, _)| c * v[i]).sum::<f64>())
                    .collect();
                let direct = map.norm(&err, &whole.3, norm);
                assert!(
                    close(x.finish(n), direct),
                    "{norm:?}: {} vs {direct}",
                    x.finish(n)
                );
            }
        }
    }
}

#[test]
fn confluent_node_uses_the_derivative() {
    // quadratic through (1, f(1)), and the double node (0, f(0), f'(0))
    let f = |t: f64| 3.0 - t + 2.0 * t * t;
    let df = |t: f64| -1.0 + 4.0 * t;
    let z = [1.0, 0.0, 0.0];
    let mut p = [0.0; NC];
    let mut dp = [0.0; NC];
    interp_coeffs(&z, 0.6, &mut p, &mut dp);
    let v = p[0] * f(1.0) + p[1] * f(0.0) + p[2] * f(0.0) + p[3] * df(0.0);
    let d = dp[0] * f(1.0) + dp[1] * f(0.0) + dp[2] * f(0.0) + dp[3] * df(0.0);
    assert!((v - f(0.6)).abs() < 1e-12);
    assert!((d - df(0.6)).abs() < 1e-12);
}

#[test]
fn map_sweeps_match_the_row_definition() {
    // rows of every kind over several blocks: a growing line's interleaved layout (each
    // boundary differenced two rows back, growth stretches on their own), a stretch of plain
    // line (the vectorised path), partners beyond the halo and ahead of their row, an anchor
    // and an end row; the fused sweeps against each row's definition
    use crate::Row;
    let n = 4 * BLK + 37;
    let rows: Vec<Row> = (0..n)
        .map(|i| match i {
            0 => Row::Anchor { size: 2.0 },
            i if i < BLK => {
                if i % 2 == 0 {
                    Row::Difference { partner: i - 2 }
                } else {
                    Row::Own
                }
            }
            i if i == BLK + 5 => Row::Difference {
                partner: i - (HALO + 9),
            },
            i if i == BLK + 6 => Row::Difference { partner: i + 3 },
            i if i == 3 * BLK + 1 => Row::Anchor { size: 0.5 },
            i => Row::Difference { partner: i - 1 },
        })
        .collect();
    let mut map = ErrorMap::from_rows(rows.clone())
        .expect("valid rows")
        .with_end(n - 1, 1.5)
        .expect("valid end")
        // a seam from row 0 (far outside the last block: its error recomputed) to row n − 1
        .with_seam(n - 1, 0, 1.5, -0.25)
        .expect("valid seam");
    let vec_of = |k: f64| -> Vec<f64> {
        (0..n)
            .map(|i| (i as f64 * k).sin() + 1.5 * i as f64)
            .collect()
    };
    let (h0, h1, h2) = (vec_of(0.3), vec_of(0.7), vec_of(1.1));
    let ycur: Vec<f64> = (0..n)
        .map(|i| 1.5 * i as f64 + 1e-3 * (i as f64).cos())
        .collect();
    let mut list = [(&[][..], 0.0, 0.0); NC];
    list[0] = (&h0[..], 1.7, 0.4);
    list[1] = (&h1[..], -0.9, -1.3);
    list[2] = (&h2[..], 0.2, 0.9);
    let items = [plain(list, 3), plain(list, 2)];
    let (rtol, atol) = (1e-3, vec![1e-6; n]);
    let eatol = map.effective_atol(&atol, rtol);
    map.refresh_ends(0.0, &ycur, rtol);
    let seam_w = 1.0 / (rtol * (ycur[n - 1] - 0.25 - ycur[0]).abs() + atol[n - 1]);
    // weights: rtol·|y_i − y_p| + atol, rtol·size + atol, rtol·|y_i| + atol
    let mut w = vec![0.0; n];
    map.weights(&ycur, &eatol, rtol, 0, &mut w);
    for (i, (r, &wi)) in rows.iter().zip(&w).enumerate() {
        let want = match *r {
            Row::Own => 1.0 / (rtol * ycur[i].abs() + atol[i]),
            Row::Anchor { size } => 1.0 / (rtol * size + atol[i]),
            Row::Difference { partner } => 1.0 / (rtol * (ycur[i] - ycur[partner]).abs() + atol[i]),
        };
        assert_eq!(wi, want, "weight of row {i}");
    }
    for (it, norm) in items.iter().zip([ErrorNorm::Max, ErrorNorm::Rms]) {
        let err: Vec<f64> = (0..n)
            .map(|i| ycur[i] - it.as_slice().iter().map(|&(v, c, _)| c * v[i]).sum::<f64>())
            .collect();
        let mut prods: Vec<f64> = rows
            .iter()
            .enumerate()
            .map(|(i, r)| match *r {
                Row::Difference { partner } => (err[i] - err[partner]) * w[i],
                _ => err[i] * w[i],
            })
            .collect();
        prods.push(err[n - 1] / (rtol * 1.5 + atol[n - 1]));
        prods.push((err[n - 1] - err[0]) * seam_w);
        let want = match norm {
            ErrorNorm::Max => prods.iter().fold(0.0f64, |m, x| m.max(x.abs())),
            ErrorNorm::Rms => (prods.iter().map(|x| x * x).sum::<f64>() / n as f64).sqrt(),
        };
        let swept = norm_blocks(std::slice::from_ref(it), &ycur, &w, norm, &map, 0, n)[0].finish(n);
        let direct = map.norm(&err, &w, norm);
        // the sweeps push the products in the definition's order (the end row is last here)
        assert_eq!((swept, direct), (want, want), "{norm:?}");
    }
}

#[test]
fn the_stored_predictor_gives_the_history_predictor_error_norm_bitwise() {
    // `predict` lists an item whose value coefficient is zero when its derivative coefficient
    // is not; the error test's own list leaves it out. The stored predictor's error norm is
    // still bitwise the one re-evaluated from the history, with and without a line's map.
    let n = 2 * BLK + 37;
    let vec_of = |f: f64| -> Vec<f64> {
        (0..n)
            .map(|i| ((i as f64) * f).sin() * (1.0 + i as f64))
            .collect()
    };
    let (h0, h1, h2, ycur) = (vec_of(0.3), vec_of(0.7), vec_of(1.1), vec_of(0.31));
    let mut with_zero = [(&[][..], 0.0, 0.0); NC];
    with_zero[0] = (&h0[..], 1.7, 0.4);
    with_zero[1] = (&h1[..], 0.0, -1.3);
    with_zero[2] = (&h2[..], 0.2, 0.9);
    // (both lists' sums over increments from the newest value, as `Bdf::items` builds them)
    let predict_items = Items {
        list: with_zero,
        len: 3,
        base: Some(&h0[..]),
        deriv: false,
    };
    let mut own = [(&[][..], 0.0, 0.0); NC];
    own[0] = (&h0[..], 1.7, 0.0);
    own[1] = (&h2[..], 0.2, 0.0);
    let error_items = Items {
        list: own,
        len: 2,
        base: Some(&h0[..]),
        deriv: false,
    };
    let (mut y, mut yp) = (vec![0.0; n], vec![0.0; n]);
    poly_blocks(&predict_items, &h0, 0, &mut y, &mut yp, None);
    let mut stored = [(&[][..], 0.0, 0.0); NC];
    stored[0] = (&y[..], 1.0, 0.0);
    let stored_items = plain(stored, 1);
    let w: Vec<f64> = (0..n).map(|i| 1.0 + 0.01 * i as f64).collect();
    let mut rows = vec![crate::Row::Anchor { size: 2.0 }];
    rows.extend((1..n).map(|i| crate::Row::Difference { partner: i - 1 }));
    let line = ErrorMap::from_rows(rows).expect("valid rows");
    for map in [ErrorMap::default(), line] {
        for norm in [ErrorNorm::Max, ErrorNorm::Rms] {
            let from_history = norm_blocks(&[error_items], &ycur, &w, norm, &map, 0, n)[0];
            let from_stored = norm_blocks(&[stored_items], &ycur, &w, norm, &map, 0, n)[0];
            let (a, b) = (from_history.finish(n), from_stored.finish(n));
            assert!(a > 0.0);
            assert_eq!(a.to_bits(), b.to_bits(), "{norm:?}");
        }
    }
}
