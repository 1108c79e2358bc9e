//! The BDF method's vector kernels: the interpolation coefficients of its history, the blocked
//! passes that evaluate the predictor and the error norms (split in two halves when the
//! solve runs in parallel), the Newton update's fused solution map and the norm accumulators.

use super::*;

/// Newton-form interpolation through the nodes `z` (newest first; two equal adjacent nodes mean
/// the second carries the derivative item, index `z.len()`): coefficients over the items of
/// `p(t)` and `p'(t)`.
///
/// Time is measured in a power of two `H` near the nodes' spread, so the divided differences
/// stay of order one however short the steps: in seconds, a step of 1e-80 made the order-5
/// table entries 1/h⁵ overflow while the products `Π (t − z)` underflowed (a shear column at
/// K = 1e-80 took 4× the steps and erred by 280·rtol). Scaling by a power of two is exact,
/// so wherever nothing over- or underflowed every coefficient is bitwise the unscaled one.
pub(super) fn interp_coeffs(z: &[f64], t: f64, p: &mut [f64; NC], dp: &mut [f64; NC]) {
    let m = z.len();
    debug_assert!((1..NC).contains(&m));
    let (unit, inv_unit) = time_unit(z, t);
    let mut table = [[0.0; NC]; NC];
    for (i, row) in table.iter_mut().enumerate().take(m) {
        row[i] = 1.0;
    }
    *p = [0.0; NC];
    *dp = [0.0; NC];
    let mut w = 1.0;
    let mut dw = 0.0;
    for level in 0..m {
        for q in 0..=m {
            p[q] += table[0][q] * w;
            dp[q] += table[0][q] * dw;
        }
        if level + 1 == m {
            break;
        }
        let d = (t - z[level]) * inv_unit;
        dw = dw * d + w;
        w *= d;
        for i in 0..m - level - 1 {
            let den = (z[i + level + 1] - z[i]) * inv_unit;
            if den == 0.0 {
                // the derivative item, in units of H: dy/d(t/H) = H·ẏ
                let mut e = [0.0; NC];
                e[m] = unit;
                table[i] = e;
            } else {
                let next = table[i + 1];
                for (cur, nxt) in table[i].iter_mut().zip(next).take(m + 1) {
                    *cur = (nxt - *cur) / den;
                }
            }
        }
    }
    // p' in units of H back to units of t
    for d in dp.iter_mut() {
        *d *= inv_unit;
    }
}

/// The time unit `H` of [`interp_coeffs`] and `1/H`: the power of two nearest the larger of
/// `|t − z₀|` and the nodes' spread (1 when both vanish), its exponent kept within ±1000 so
/// both are normal numbers.
fn time_unit(z: &[f64], t: f64) -> (f64, f64) {
    let spread = z
        .iter()
        .fold((t - z[0]).abs(), |m, &zi| m.max((zi - z[0]).abs()));
    if spread == 0.0 || !spread.is_finite() {
        return (1.0, 1.0);
    }
    let e = (spread.log2().round() as i64).clamp(-1000, 1000);
    let pow2 = |k: i64| f64::from_bits(((1023 + k) as u64) << 52);
    (pow2(e), pow2(-e))
}

/// Where a vector pass of length `n` is split in two halves (run by [`rayon::join`]): a
/// block boundary near the middle, or 0 (no split) when `parallel` does not split `n`.
pub(super) fn split_point(n: usize, parallel: crate::Parallelism) -> usize {
    if !parallel.splits(n) || n < 2 * BLK {
        return 0;
    }
    (n / 2) / BLK * BLK
}

/// The predictor (and optionally the weights) for components `lo..lo + y.len()`: `y`, `yp`
/// and the weights' outputs are that range's slices, the history vectors, `y0` (the newest,
/// for the weights) and the weights' inputs are whole vectors.
pub(super) fn poly_blocks(
    items: &Items<'_>,
    y0: &[f64],
    lo: usize,
    y: &mut [f64],
    yp: &mut [f64],
    mut weights: Option<Weights<'_>>,
) {
    let n = y.len();
    let mut s = 0;
    while s < n {
        let e = (s + BLK).min(n);
        let (yb, ypb) = (&mut y[s..e], &mut yp[s..e]);
        if items.len == 0 {
            yb.fill(0.0);
            ypb.fill(0.0);
        } else {
            for_each_sum(
                items.as_slice(),
                items.base,
                items.deriv,
                lo + s,
                e - s,
                |i, a, b| {
                    yb[i] = a;
                    ypb[i] = b;
                },
            );
        }
        if let Some(w) = weights.as_mut() {
            w.pred[s..e].copy_from_slice(yb);
            // the Newton weights are the error weights without the suppression of algebraic
            // components, as in `System::error_weights`
            let rtol = w.rtol;
            if w.map.is_empty() {
                let (yb0, atol) = (&y0[lo + s..lo + e], &w.atol[lo + s..lo + e]);
                for ((nw, yi), a) in w.nwt[s..e].iter_mut().zip(yb0).zip(atol) {
                    *nw = 1.0 / (rtol * yi.abs() + a);
                }
            } else {
                // cell-level weights (differences with the partner, read from the whole y0)
                w.map.weights(y0, w.atol, rtol, lo + s, &mut w.nwt[s..e]);
            }
            if let Some(ew) = w.ewt.as_mut() {
                let alg = &w.algebraic[lo + s..lo + e];
                for ((ewi, &nw), &is_alg) in ew[s..e].iter_mut().zip(&w.nwt[s..e]).zip(alg) {
                    *ewi = if is_alg { 0.0 } else { nw };
                }
            }
        }
        s = e;
    }
}

/// The error-norm sweep of [`Bdf::error_norms`] over components `lo..hi`: one accumulator
/// per order in `items` (the norm of `y_new − predictor_m`).
pub(super) fn norm_blocks(
    items: &[Items<'_>],
    ycur: &[f64],
    ewt: &[f64],
    norm: ErrorNorm,
    map: &ErrorMap,
    lo: usize,
    hi: usize,
) -> [NormAcc; MAX_NORMS] {
    let mut acc = [NormAcc::new(norm); MAX_NORMS];
    if !map.is_empty() {
        return map_norm_blocks(items, ycur, ewt, map, lo, hi, acc);
    }
    let mut buf = [0.0; BLK];
    let mut s = lo;
    while s < hi {
        let e = (s + BLK).min(hi);
        let wb = &ewt[s..e];
        for (it, a) in items.iter().zip(acc.iter_mut()) {
            let b = &mut buf[..e - s];
            error_block(it, ycur, s, b);
            for (bi, wi) in b.iter().zip(wb) {
                a.push(bi * wi);
            }
        }
        s = e;
    }
    acc
}

/// Rows before a block whose errors [`map_norm_blocks`] keeps in its buffers, so that a
/// partner up to this many rows back is read, not recomputed (a line's boundaries partner the
/// previous one, 1–3 rows back with growth and Maxwell unknowns in between).
pub(super) const HALO: usize = 16;

/// [`norm_blocks`] through a non-empty error map: per block, the error of every order over the
/// block and up to [`HALO`] rows before it (as far back as the map's partners reach), then one
/// pass over the rows that reads each row's marker once for all orders. The products reach
/// each accumulator in the same order as a per-order pass, so the norms are bitwise those of
/// [`ErrorMap::norm`] on the error vectors.
fn map_norm_blocks(
    items: &[Items<'_>],
    ycur: &[f64],
    ewt: &[f64],
    map: &ErrorMap,
    lo: usize,
    hi: usize,
    mut acc: [NormAcc; MAX_NORMS],
) -> [NormAcc; MAX_NORMS] {
    let mut bufs = [[0.0; HALO + BLK]; MAX_NORMS];
    let mut qs = [[0.0; BLK]; MAX_NORMS];
    let nord = items.len();
    let h = map.max_back().min(HALO);
    let markers = map.markers();
    let mut s = lo;
    while s < hi {
        let e = (s + BLK).min(hi);
        let len = e - s;
        // the buffers hold rows b0..e: the errors y − predictor_m
        let b0 = s.saturating_sub(h);
        for (it, buf) in items.iter().zip(bufs.iter_mut()) {
            error_block(it, ycur, b0, &mut buf[..e - b0]);
        }
        // a block whose rows all difference with the row `d` back (a line's boundaries)
        let d = ErrorMap::offset(markers[s]);
        // (a fold, not `all`: without the early exit the comparison runs in vector lanes)
        let m0 = markers[s];
        let uniform = d > 0
            && d as usize <= s - b0
            && markers[s..e].iter().fold(true, |same, &m| same & (m == m0));
        if uniform {
            let (k0, kp) = (s - b0, s - b0 - d as usize);
            for ((q, buf), a) in qs.iter_mut().zip(&bufs).zip(acc.iter_mut()).take(nord) {
                let q = &mut q[..len];
                for (((qi, &bi), &bp), &w) in
                    q.iter_mut().zip(&buf[k0..]).zip(&buf[kp..]).zip(&ewt[s..e])
                {
                    *qi = (bi - bp) * w;
                }
                a.push_slice(q);
            }
        } else {
            for (i, (&marker, &w)) in (s..e).zip(markers[s..e].iter().zip(&ewt[s..e])) {
                let k = i - b0;
                let off = ErrorMap::offset(marker);
                for ((q, buf), it) in qs.iter_mut().zip(&bufs).zip(items) {
                    let partner = if off == 0 {
                        0.0
                    } else if off > 0 && off as usize <= k {
                        buf[k - off as usize]
                    } else {
                        // a partner outside the buffers: its error recomputed from the history
                        let p = (i as i64 - off) as usize;
                        ycur[p] - it.at(p).0
                    };
                    q[i - s] = (buf[k] - partner) * w;
                }
            }
            for (q, a) in qs.iter().zip(acc.iter_mut()).take(nord) {
                a.push_slice(&q[..len]);
            }
        }
        map.for_each_end(s, e, ewt, |i, p, we| {
            for ((a, buf), it) in acc.iter_mut().zip(&bufs).zip(items).take(nord) {
                // a seam's partner: read from the buffer, or recomputed from the history
                let partner = match p {
                    None => 0.0,
                    Some(p) if (b0..e).contains(&p) => buf[p - b0],
                    Some(p) => ycur[p] - it.at(p).0,
                };
                a.push((buf[i - b0] - partner) * we);
            }
        });
        s = e;
    }
    acc
}

/// The error `y − Σ c·v` of one order's predictor over rows `b0..b0 + out.len()`.
#[inline(always)]
fn error_block(it: &Items<'_>, ycur: &[f64], b0: usize, out: &mut [f64]) {
    let e = b0 + out.len();
    let list = it.as_slice();
    if list.is_empty() {
        out.copy_from_slice(&ycur[b0..e]);
        return;
    }
    let y = &ycur[b0..e];
    for_each_sum(list, it.base, it.deriv, b0, out.len(), |i, sum, _| {
        out[i] = y[i] - sum
    });
}

/// Calls `emit(i, Σ a·v[lo + i], Σ b·v[lo + i])` for `i in 0..len` over the items `(v, a, b)`
/// of a non-empty `list` (at most `NC`), each sum taken in list order (the first product,
/// then each further one added), so the values are bitwise those of one pass per item
/// through a buffer. One pass with every coefficient in a register instead: the buffer's
/// loads and stores per item were most of the predictor's and the error norms' cost
/// (measured on the raw Chapter 2 line at N = 1000). An unused second sum is not computed.
///
/// With a `base` `r` (whole vector) the sums are `r + Σ a·(v − r)` and `Σ b·(v − r)` over
/// the values (see [`Items`]), plus `a·v`, `b·v` of a last derivative item if `deriv`: equal
/// to the plain sums when the values' coefficients sum to 1 and 0, as an interpolant's do.
#[inline(always)]
fn for_each_sum(
    list: &[(&[f64], f64, f64)],
    base: Option<&[f64]>,
    deriv: bool,
    lo: usize,
    len: usize,
    emit: impl FnMut(usize, f64, f64),
) {
    // the kind of sum as a constant, so each inner loop is branch-free: 0 plain, 1 every item
    // from the base, 2 the values from the base and the last item (a derivative) as is
    macro_rules! dispatch {
        ($kind:literal) => {
            match list.len() {
                1 => sums::<1, $kind>(list, base, lo, len, emit),
                2 => sums::<2, $kind>(list, base, lo, len, emit),
                3 => sums::<3, $kind>(list, base, lo, len, emit),
                4 => sums::<4, $kind>(list, base, lo, len, emit),
                5 => sums::<5, $kind>(list, base, lo, len, emit),
                6 => sums::<6, $kind>(list, base, lo, len, emit),
                7 => sums::<7, $kind>(list, base, lo, len, emit),
                8 => sums::<8, $kind>(list, base, lo, len, emit),
                m => unreachable!("{m} history items (at most {NC})"),
            }
        };
    }
    match (base, deriv) {
        (None, _) => dispatch!(0),
        (Some(_), false) => dispatch!(1),
        (Some(_), true) => dispatch!(2),
    }
}

/// [`for_each_sum`] with the number of items `M` and the kind of sum `KIND` (0 plain, 1 from
/// the base, 2 from the base but for the last item) known at compile time (the index runs over
/// `M` slices at once, hence the indexed loop).
#[inline(always)]
#[allow(clippy::needless_range_loop)]
fn sums<const M: usize, const KIND: u8>(
    list: &[(&[f64], f64, f64)],
    base: Option<&[f64]>,
    lo: usize,
    len: usize,
    mut emit: impl FnMut(usize, f64, f64),
) {
    let vs: [&[f64]; M] = std::array::from_fn(|j| &list[j].0[lo..lo + len]);
    let a: [f64; M] = std::array::from_fn(|j| list[j].1);
    let b: [f64; M] = std::array::from_fn(|j| list[j].2);
    if KIND == 0 {
        for i in 0..len {
            let x0 = vs[0][i];
            let (mut sa, mut sb) = (a[0] * x0, b[0] * x0);
            for j in 1..M {
                let x = vs[j][i];
                sa += a[j] * x;
                sb += b[j] * x;
            }
            emit(i, sa, sb);
        }
        return;
    }
    let r = &base.expect("a base for this kind of sum")[lo..lo + len];
    // the items taken from the base: all, or all but the last
    let nv = if KIND == 2 { M - 1 } else { M };
    for i in 0..len {
        let ri = r[i];
        let x0 = if nv > 0 { vs[0][i] - ri } else { vs[0][i] };
        let (mut sa, mut sb) = (a[0] * x0, b[0] * x0);
        for j in 1..nv {
            let x = vs[j][i] - ri;
            sa += a[j] * x;
            sb += b[j] * x;
        }
        if KIND == 2 && M > 1 {
            let x = vs[M - 1][i];
            sa += a[M - 1] * x;
            sb += b[M - 1] * x;
        }
        emit(i, ri + sa, sb);
    }
}

/// The Newton norm of `v` (weights `w`) through a non-empty error map, on two threads for a
/// large state (the halves' partial norms are merged, as [`Bdf::error_norms`] does). The end
/// rows ([`ErrorMap::with_end`]) are tested as in the error test: without them a Newton
/// correction that moves the boundary next to a driven end together with its neighbours (a
/// smooth profile, small in every difference) passes while the end cell's stretch is far from
/// converged — measured on fig2_6's continuum (n = 2000, K = 1e-5, rtol 1e-6), an accepted
/// first step left that cell at λ = 0.48 against 0.999.
pub(super) fn map_norm(
    map: &ErrorMap,
    v: &[f64],
    w: &[f64],
    norm: ErrorNorm,
    parallel: crate::Parallelism,
) -> f64 {
    let n = v.len();
    let mid = split_point(n, parallel);
    let sum = if mid == 0 {
        map.norm_range(v, w, norm, 0, n)
    } else {
        let (mut first, second): (NormSum, NormSum) = rayon::join(
            || map.norm_range(v, w, norm, 0, mid),
            || map.norm_range(v, w, norm, mid, n),
        );
        first.merge(&second);
        first
    };
    sum.finish(norm, n)
}

/// Index of the largest `|v_i w_i|`.
pub(super) fn worst(v: &[f64], w: &[f64]) -> Option<usize> {
    worst_of(v.iter().zip(w).map(|(a, b)| a * b))
}

/// Index of the largest `|x_i|`, or of the first NaN.
pub(super) fn worst_of(xs: impl Iterator<Item = f64>) -> Option<usize> {
    let mut best = None;
    let mut bv = -1.0;
    for (i, x) in xs.enumerate() {
        let x = x.abs();
        if x > bv || x.is_nan() {
            bv = x;
            best = Some(i);
            if x.is_nan() {
                break;
            }
        }
    }
    best
}

/// The per-component Newton update, applied by the linear solve as each component of
/// `J⁻¹F` is found ([`System::solve_map`]). With `OWN_NORM` it also accumulates the weighted
/// norm of `δ`; without it (a problem with an error map, whose Newton norm is taken over
/// cell-level quantities in a pass of its own) the accumulation is compiled out rather than
/// computed and discarded.
pub(super) struct NewtonUpdate<'a, const OWN_NORM: bool> {
    /// Global index of `y[0]` (non-zero for the second half of a split).
    pub(super) off: usize,
    pub(super) y: &'a mut [f64],
    pub(super) yp: &'a mut [f64],
    pub(super) w: &'a [f64],
    pub(super) scale: f64,
    pub(super) alpha: f64,
    pub(super) acc: NormAcc,
}

impl<'a, const OWN_NORM: bool> NewtonUpdate<'a, OWN_NORM> {
    /// The update of the whole state (`off = 0`) with step scale `scale`, `∂ẏ/∂y = alpha` and
    /// weights `w`, accumulating the `norm` of `δ` if `OWN_NORM`.
    pub(super) fn new(
        y: &'a mut [f64],
        yp: &'a mut [f64],
        w: &'a [f64],
        scale: f64,
        alpha: f64,
        norm: ErrorNorm,
    ) -> Self {
        Self {
            off: 0,
            y,
            yp,
            w,
            scale,
            alpha,
            acc: NormAcc::new(norm),
        }
    }
}

impl<const OWN_NORM: bool> SolutionMap for NewtonUpdate<'_, OWN_NORM> {
    /// `δ_i = −scale·d_i`; updates `y`, `ẏ` (and the norm, with `OWN_NORM`); returns `δ_i`.
    #[inline(always)]
    fn map(&mut self, i: usize, d: f64) -> f64 {
        let i = i - self.off;
        let di = if self.scale != 1.0 {
            -(d * self.scale)
        } else {
            -d
        };
        self.y[i] += di;
        self.yp[i] += self.alpha * di;
        if OWN_NORM {
            self.acc.push(di * self.w[i]);
        }
        di
    }

    fn split(self, mid: usize) -> Result<(Self, Self), Self> {
        let at = mid - self.off;
        let (y1, y2) = self.y.split_at_mut(at);
        let (yp1, yp2) = self.yp.split_at_mut(at);
        let (w1, w2) = self.w.split_at(at);
        // the first half carries what the accumulator has seen, the second starts empty
        let half = |off, y, yp, w, acc| NewtonUpdate {
            off,
            y,
            yp,
            w,
            scale: self.scale,
            alpha: self.alpha,
            acc,
        };
        Ok((
            half(self.off, y1, yp1, w1, self.acc),
            half(mid, y2, yp2, w2, self.acc.emptied()),
        ))
    }

    fn merge(&mut self, other: Self) {
        self.acc.merge(&other.acc);
    }
}

/// Outputs and inputs of the weights pass fused into the predictor ([`Bdf::predict`]), and
/// the copy of the predictor it keeps for the step's error test.
pub(super) struct Weights<'a> {
    /// A copy of the predictor (the error test's order-`k` difference is `y − pred`).
    pub(super) pred: &'a mut [f64],
    pub(super) nwt: &'a mut [f64],
    /// Separate error weights (suppressed algebraic components), if any.
    pub(super) ewt: Option<&'a mut [f64]>,
    /// [`System::weight_atol`].
    pub(super) atol: &'a [f64],
    pub(super) algebraic: &'a [bool],
    pub(super) rtol: f64,
    /// The problem's error map (empty: the identity).
    pub(super) map: &'a ErrorMap,
}

/// Up to `NC` history vectors with their coefficients (see `Bdf::items`), and the base the
/// sums are taken from.
///
/// With a `base` (the newest history value `y₀`; `Bdf::items` always sets it, the error test's
/// stored-predictor list has none) the sums over the history values are `y₀ + Σ a·(v − y₀)`
/// and `Σ b·(v − y₀)`, a last derivative item (`deriv`) added as is: an interpolant's value coefficients sum
/// to 1 and its derivative coefficients to 0, so this is `Σ a·v`, `Σ b·v`, with the rounding
/// of the increments `v − y₀` instead of the values. Taken from the values, an order-5
/// predictor's `Σ|b|` ≈ 10²/h multiplied the rounding of positions far from the origin
/// into its `ẏ`, i.e. into the equation every step solves (`ẏ = ẏ_pred + α(y − y_pred)`):
/// on a ring of 56 Maxwell cells under active stress at K = 10⁻³ that noise, of order
/// ε·|x| per step and independent of the tolerance, seeded a cell-to-cell zigzag that BDF
/// orders 3–5 carried to 10⁻⁸ at r_tol 10⁻¹² (`tests/methods_on_sweep_finds.rs`).
#[derive(Clone, Copy)]
pub(super) struct Items<'s> {
    pub(super) list: [(&'s [f64], f64, f64); NC],
    pub(super) len: usize,
    pub(super) base: Option<&'s [f64]>,
    /// Whether the last item is the derivative item `ẏ₀` (summed as is, not from the base).
    pub(super) deriv: bool,
}

impl<'s> Items<'s> {
    pub(super) fn as_slice(&self) -> &[(&'s [f64], f64, f64)] {
        &self.list[..self.len]
    }

    /// `(Σ a·v[i], Σ b·v[i])` at one component, as [`for_each_sum`] takes them.
    pub(super) fn at(&self, i: usize) -> (f64, f64) {
        let mut out = (0.0, 0.0);
        for_each_sum(self.as_slice(), self.base, self.deriv, i, 1, |_, a, b| {
            out = (a, b)
        });
        out
    }
}

/// Running weighted norm of one kind: a [`NormSum`] that carries its [`ErrorNorm`], bitwise
/// equal to [`ErrorNorm::of`] over the same products.
#[derive(Clone, Copy)]
pub(super) struct NormAcc {
    norm: ErrorNorm,
    sum: NormSum,
}

impl NormAcc {
    pub(super) fn new(norm: ErrorNorm) -> Self {
        Self {
            norm,
            sum: NormSum::default(),
        }
    }

    /// An empty accumulator of the same kind.
    pub(super) fn emptied(&self) -> Self {
        Self::new(self.norm)
    }

    #[inline(always)]
    pub(super) fn push(&mut self, x: f64) {
        self.sum.push(self.norm, x);
    }

    /// [`push`](Self::push) of every entry of `xs`, in order (see [`NormSum::push_slice`]).
    #[inline(always)]
    pub(super) fn push_slice(&mut self, xs: &[f64]) {
        self.sum.push_slice(self.norm, xs);
    }

    /// Adds the products another accumulator (of the same kind) has seen.
    pub(super) fn merge(&mut self, other: &NormAcc) {
        self.sum.merge(&other.sum);
    }

    pub(super) fn finish(&self, n: usize) -> f64 {
        self.sum.finish(self.norm, n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_pass_sums_are_the_per_item_sums_bitwise() {
        // every list length, an offset window, coefficients and values of mixed sign and scale
        let n = 300;
        let vecs: Vec<Vec<f64>> = (0..NC)
            .map(|j| {
                (0..n)
                    .map(|i| ((i * 7 + j * 13) as f64 * 0.37).sin() * 10f64.powi(j as i32 - 3))
                    .collect()
            })
            .collect();
        let (lo, len) = (17, 250);
        for m in 1..=NC {
            let list: Vec<(&[f64], f64, f64)> = (0..m)
                .map(|j| {
                    (
                        &vecs[j][..],
                        1.0 / (j as f64 + 0.3) - 0.9,
                        (j as f64 * 1.7).cos(),
                    )
                })
                .collect();
            // one pass per item through buffers, the first product written; with a base,
            // over the increments from it, the base added to the first sum at the end
            let base = &vecs[NC - 1];
            for (with_base, deriv) in [(false, false), (true, false), (true, true)] {
                let r = |i: usize| if with_base { base[lo + i] } else { 0.0 };
                let mut want_a = vec![0.0; len];
                let mut want_b = vec![0.0; len];
                for (j, &(v, a, b)) in list.iter().enumerate() {
                    for i in 0..len {
                        let value = !(deriv && j == m - 1);
                        let d = if with_base && value {
                            v[lo + i] - r(i)
                        } else {
                            v[lo + i]
                        };
                        let (pa, pb) = (a * d, b * d);
                        if j == 0 {
                            (want_a[i], want_b[i]) = (pa, pb);
                        } else {
                            want_a[i] += pa;
                            want_b[i] += pb;
                        }
                    }
                }
                if with_base {
                    for (i, w) in want_a.iter_mut().enumerate() {
                        *w += r(i);
                    }
                }
                let mut got = vec![(f64::NAN, f64::NAN); len];
                let b = with_base.then_some(&base[..]);
                for_each_sum(&list, b, deriv, lo, len, |i, a, b| got[i] = (a, b));
                for i in 0..len {
                    assert_eq!(got[i].0.to_bits(), want_a[i].to_bits(), "m={m} i={i}");
                    assert_eq!(got[i].1.to_bits(), want_b[i].to_bits(), "m={m} i={i}");
                }
            }
        }
    }
}
