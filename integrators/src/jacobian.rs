//! Building the iteration matrix `J = ∂F/∂y + c·∂F/∂ẏ` from the declared pattern: coloured
//! exact directional derivatives (AD) or coloured finite differences — one evaluation per
//! colour (bandwidth+1 for banded), never one per column.
//!
//! The same machinery also builds the matrix of consistent initialisation, whose column `j` is
//! `∂F/∂ẏ_j` for a differential and `∂F/∂y_j` for an algebraic component (`Columns::Init`).
//!
//! Sources, in order of preference (unless [`crate::Options::force_fd_jacobian`]):
//! 1. [`Problem::jacobian`](crate::Problem::jacobian) if it returns `Ok(true)`;
//! 2. [`Problem::directional`](crate::Problem::directional) with the seed
//!    `v = Σ_{j in colour} e_j`, one call per colour;
//! 3. finite differences: every column of a colour is perturbed at once (IDA's increment
//!    `δ_j = max(√ε·max(|y_j|, |ẏ_j/c|), rtol·|y_j| + atol_j)`, signed like `ẏ_j/c`), one residual
//!    call per colour plus one for the base point unless the caller supplies it.

use crate::linalg::Matrix;
use crate::system::{StepFailure, System};

/// Which matrix to build.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Columns<'a> {
    /// The iteration matrix `∂F/∂y + c·∂F/∂ẏ`.
    Iteration {
        /// The coefficient `c`.
        c: f64,
    },
    /// Column `j` is `∂F/∂ẏ_j` (differential) or `∂F/∂y_j` (`algebraic[j]`).
    Init {
        /// Algebraic flags.
        algebraic: &'a [bool],
    },
}

/// Builds the matrix selected by `cols` at `(t, y, ẏ)` into `jac` (shaped by the system's
/// pattern). `r0`, if given, must be `F(t, y, ẏ)`; it saves one residual call for finite
/// differences. Does not touch `stats.jacobian_evals` (the caller counts).
pub(crate) fn assemble(
    sys: &mut System<'_>,
    t: f64,
    y: &[f64],
    yp: &[f64],
    cols: Columns<'_>,
    r0: Option<&[f64]>,
    jac: &mut Matrix,
) -> Result<(), StepFailure> {
    let n = sys.dim();
    assert!(
        y.len() == n && yp.len() == n && jac.n() == n,
        "jacobian: dimension mismatch (n = {n}, y {}, ẏ {}, matrix {})",
        y.len(),
        yp.len(),
        jac.n()
    );
    if n == 0 {
        return Ok(());
    }
    if !sys.opts.force_fd_jacobian {
        if user_jacobian(sys, t, y, yp, cols, jac)? {
            return Ok(());
        }
        if directional(sys, t, y, yp, cols, jac)? {
            return Ok(());
        }
    }
    finite_differences(sys, t, y, yp, cols, r0, jac)
}

/// Writes `value(i)` into every structural entry of column `j`.
fn write_column(jac: &mut Matrix, j: usize, mut value: impl FnMut(usize) -> f64) {
    match jac {
        Matrix::Sparse(m) => {
            let (cp, ri) = (m.pattern.col_ptr(), m.pattern.row_idx());
            let range = cp[j]..cp[j + 1];
            for (v, &i) in m.values[range.clone()].iter_mut().zip(&ri[range]) {
                *v = value(i);
            }
        }
        Matrix::Banded(_) | Matrix::Dense(_) => {
            // contiguous rows from the column's first structural one (no per-column row list)
            let r0 = match jac {
                Matrix::Banded(b) => b.col_range(j).0,
                _ => 0,
            };
            for (k, v) in column_slots_mut(jac, j).iter_mut().enumerate() {
                *v = value(r0 + k);
            }
        }
    }
}

fn user_jacobian(
    sys: &mut System<'_>,
    t: f64,
    y: &[f64],
    yp: &[f64],
    cols: Columns<'_>,
    jac: &mut Matrix,
) -> Result<bool, StepFailure> {
    if sys.cache.no_user_jacobian {
        return Ok(false);
    }
    let provided = user_jacobian_columns(sys, t, y, yp, cols, jac)?;
    sys.cache.no_user_jacobian = !provided;
    Ok(provided)
}

fn user_jacobian_columns(
    sys: &mut System<'_>,
    t: f64,
    y: &[f64],
    yp: &[f64],
    cols: Columns<'_>,
    jac: &mut Matrix,
) -> Result<bool, StepFailure> {
    match cols {
        Columns::Iteration { c } => {
            jac.set_zero();
            sys.problem
                .jacobian(t, y, yp, c, jac)
                .map_err(|e| sys.residual_failure(e, t))
        }
        Columns::Init { algebraic } => {
            // J(0) = ∂F/∂y, J(1) − J(0) = ∂F/∂ẏ
            jac.set_zero();
            let provided = sys
                .problem
                .jacobian(t, y, yp, 0.0, jac)
                .map_err(|e| sys.residual_failure(e, t))?;
            if !provided {
                return Ok(false);
            }
            // J(1) in a spare of the same pattern (the same storage layout), then each
            // differential column becomes J(1) − J(0) slot by slot
            let mut j1 = sys.take_matrix();
            j1.set_zero();
            let provided = sys
                .problem
                .jacobian(t, y, yp, 1.0, &mut j1)
                .map_err(|e| sys.residual_failure(e, t));
            if provided.is_err() {
                sys.give_matrix(j1);
                return provided.map(|_| true);
            }
            // J(1) − J(0) loses a column's ∂F/∂ẏ to rounding where it is below about
            // ε·|∂F/∂y| (a line of unit stiffness at K = 1e-16 got exact zeros, "singular"):
            // those columns come from (J(C) − J(0))/C instead, C a power of two raised until
            // the column's change shows (a column that never changes stays zero: a true index
            // problem is still reported)
            let mut lost: Vec<usize> = (0..algebraic.len())
                .filter(|&j| !algebraic[j] && cancelled(column_slots(jac, j), column_slots(&j1, j)))
                .collect();
            for (j, &alg) in algebraic.iter().enumerate() {
                if !alg && lost.binary_search(&j).is_err() {
                    let (dst, src) = (column_slots_mut(jac, j), column_slots(&j1, j));
                    for (a, b) in dst.iter_mut().zip(src) {
                        *a = b - *a;
                    }
                }
            }
            for &scale in &INIT_SCALES {
                if lost.is_empty() {
                    break;
                }
                j1.set_zero();
                if let Err(e) = sys.problem.jacobian(t, y, yp, scale, &mut j1) {
                    sys.give_matrix(j1);
                    return Err(sys.residual_failure(e, t));
                }
                // `jac`'s lost columns still hold J(0)
                restore_columns(&mut lost, None, jac, &j1, scale);
            }
            for &j in &lost {
                column_slots_mut(jac, j).iter_mut().for_each(|a| *a = 0.0);
            }
            sys.give_matrix(j1);
            Ok(true)
        }
    }
}

/// `J(0) = ∂F/∂y` into `jy` and `∂F/∂ẏ` into `jyp`, for a method that combines them as
/// `∂F/∂y + α·∂F/∂ẏ` for any `α` (BDF). `∂F/∂ẏ` is `J(1) − J(0)`, except in the differential
/// columns where that difference cancelled (a drag far below the stiffness: the shear column
/// at `k_th = 1e-16` lost its drag entirely, and Newton then ran on `∂F/∂y` alone inside the
/// impulsive start, where `α·∂F/∂ẏ` dominates): those are read from `(J(C) − J(0))/C` as the
/// consistent initialisation does. Only for a coefficient `alpha` above [`PAIR_RESCUE_ALPHA`]:
/// a lost column's `∂F/∂ẏ` is below 2⁻⁴⁰ of its `∂F/∂y`, so below that `α` it changes the
/// Newton matrix by less than 2⁻¹⁰, and the pass over every column is skipped. A step that later shrinks past it with the same matrices is caught by
/// the Newton failure that refreshes them. Each matrix evaluation is counted in
/// `jacobian_evals` (two, or more when columns were restored).
#[allow(clippy::too_many_arguments)]
pub(crate) fn pair(
    sys: &mut System<'_>,
    t: f64,
    y: &[f64],
    yp: &[f64],
    alpha: f64,
    jy: &mut Matrix,
    jyp: &mut Matrix,
) -> Result<(), StepFailure> {
    sys.stats.jacobian_evals += 1;
    assemble(sys, t, y, yp, Columns::Iteration { c: 0.0 }, None, jy)?;
    sys.stats.jacobian_evals += 1;
    assemble(sys, t, y, yp, Columns::Iteration { c: 1.0 }, None, jyp)?;
    jyp.axpby(1.0, -1.0, jy);
    if alpha.abs() <= PAIR_RESCUE_ALPHA {
        return Ok(());
    }
    let mut lost: Vec<usize> = (0..jy.n())
        .filter(|&j| {
            let (j0, change) = (column_slots(jy, j), column_slots(jyp, j));
            !sys.algebraic()[j] && lost_to_rounding(j0, change.iter().copied())
        })
        .collect();
    if lost.is_empty() {
        return Ok(());
    }
    let mut jc = sys.take_matrix();
    for &scale in &INIT_SCALES {
        if lost.is_empty() {
            break;
        }
        jc.set_zero();
        sys.stats.jacobian_evals += 1;
        if let Err(e) = assemble(
            sys,
            t,
            y,
            yp,
            Columns::Iteration { c: scale },
            None,
            &mut jc,
        ) {
            sys.give_matrix(jc);
            return Err(e);
        }
        restore_columns(&mut lost, Some(jy), jyp, &jc, scale);
    }
    sys.give_matrix(jc);
    Ok(())
}

/// One rung of the `(J(C) − J(0))/C` ladder shared by the consistent initialisation and
/// [`pair`]: each column in `lost` whose change shows in `jc = J(C)` gets `(J(C) − J(0))/C` in
/// `dst` and leaves the list. `J(0)` is read from `j0`, or (`None`) from `dst` itself, whose
/// lost columns still hold it.
fn restore_columns(
    lost: &mut Vec<usize>,
    j0: Option<&Matrix>,
    dst: &mut Matrix,
    jc: &Matrix,
    scale: f64,
) {
    lost.retain(|&j| {
        let c = column_slots(jc, j);
        match j0 {
            Some(m) => {
                let a = column_slots(m, j);
                if cancelled(a, c) {
                    return true;
                }
                for ((d, a), b) in column_slots_mut(dst, j).iter_mut().zip(a).zip(c) {
                    *d = (b - a) / scale;
                }
            }
            None => {
                if cancelled(column_slots(dst, j), c) {
                    return true;
                }
                for (d, b) in column_slots_mut(dst, j).iter_mut().zip(c) {
                    *d = (b - *d) / scale;
                }
            }
        }
        false
    });
}

/// The coefficient `α` of `∂F/∂y + α·∂F/∂ẏ` above which [`pair`] restores the columns of
/// `∂F/∂ẏ` lost to rounding: 2³⁰ (steps below about 1e-9).
const PAIR_RESCUE_ALPHA: f64 = (1u64 << 30) as f64;

/// The `C`s of the consistent initialisation's `(J(C) − J(0))/C`, tried in turn for columns
/// whose `∂F/∂ẏ` is lost in `J(1) − J(0)`: powers of two (the division is exact), each
/// reaching a `∂F/∂ẏ` smaller than `|∂F/∂y|` by about 10⁶ less than the power (2⁶⁰ ≈ 10¹⁸
/// recovers 10⁻³⁰, 2⁹⁰⁰ ≈ 10²⁷¹ recovers 10⁻²⁶⁰, the largest power 2¹⁰²³ ≈ 9·10³⁰⁷ a drag of
/// 2.3e-308 on a line of unit stiffness, the smallest normal double); only the lost columns
/// read `J(C)`, so an entry that overflows elsewhere does no harm.
const INIT_SCALES: [f64; 5] = [pow2(60), pow2(200), pow2(500), pow2(900), pow2(1023)];

/// `2ᵏ` exactly (`k` in −1022..=1023), from its bits.
const fn pow2(k: i64) -> f64 {
    f64::from_bits(((1023 + k) as u64) << 52)
}

/// Whether a column's `J(1) − J(0)` (`j1 − j0`, slot by slot) kept fewer than about 12
/// significant bits of `∂F/∂ẏ` to cancellation against `∂F/∂y`: its largest change is below
/// 2⁻⁴⁰ of its largest `|∂F/∂y|` entry. Columns with a change of that size or more keep the
/// cheaper difference (and the bits they always had).
fn cancelled(j0: &[f64], j1: &[f64]) -> bool {
    lost_to_rounding(j0, j0.iter().zip(j1).map(|(a, b)| b - a))
}

/// [`cancelled`], given the column's `J(0)` and its change.
fn lost_to_rounding(j0: &[f64], change: impl Iterator<Item = f64>) -> bool {
    let scale = j0.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let change = change.fold(0.0f64, |m, x| m.max(x.abs()));
    change < scale * (2.0f64).powi(-40)
}

fn directional(
    sys: &mut System<'_>,
    t: f64,
    y: &[f64],
    yp: &[f64],
    cols: Columns<'_>,
    jac: &mut Matrix,
) -> Result<bool, StepFailure> {
    let n = y.len();
    // borrow the cached colour groups and work vectors for the duration of the call
    let groups = std::mem::take(&mut sys.cache.colour_cols);
    let mut work = std::mem::take(&mut sys.cache.jac_work);
    for w in work.iter_mut() {
        w.clear();
        w.resize(n, 0.0);
    }
    let res = directional_columns(sys, t, y, yp, cols, jac, &groups, &mut work);
    sys.cache.colour_cols = groups;
    sys.cache.jac_work = work;
    res
}

#[allow(clippy::too_many_arguments)]
fn directional_columns(
    sys: &mut System<'_>,
    t: f64,
    y: &[f64],
    yp: &[f64],
    cols: Columns<'_>,
    jac: &mut Matrix,
    groups: &[Vec<usize>],
    work: &mut [Vec<f64>; 4],
) -> Result<bool, StepFailure> {
    let [v, r, d1, d0] = work;
    let (v, r, d1, d0) = (&mut v[..], &mut r[..], &mut d1[..], &mut d0[..]);
    for group in groups.iter() {
        match cols {
            Columns::Iteration { c } => {
                for &j in group {
                    v[j] = 1.0;
                }
                let ok = call_directional(sys, t, y, yp, v, c, r, d1)?;
                if !ok {
                    return Ok(false);
                }
            }
            Columns::Init { algebraic } => {
                // d1 = J(1)·v_d, d0 = J(0)·(v_d − v_a); d1 − d0 = ∂F/∂ẏ·v_d + ∂F/∂y·v_a
                let has_diff = group.iter().any(|&j| !algebraic[j]);
                if has_diff {
                    for &j in group {
                        v[j] = if algebraic[j] { 0.0 } else { 1.0 };
                    }
                    if !call_directional(sys, t, y, yp, v, 1.0, r, d1)? {
                        return Ok(false);
                    }
                } else {
                    d1.iter_mut().for_each(|x| *x = 0.0);
                }
                for &j in group {
                    v[j] = if algebraic[j] { -1.0 } else { 1.0 };
                }
                if !call_directional(sys, t, y, yp, v, 0.0, r, d0)? {
                    return Ok(false);
                }
                // a group of differential columns whose ∂F/∂ẏ cancels in J(1)·v − J(0)·v (a
                // drag far below the stiffness) is read from (J(C)·v − J(0)·v)/C, as in
                // `user_jacobian_columns`
                let pure = has_diff && group.iter().all(|&j| !algebraic[j]);
                let mut scale = 1.0;
                if pure && cancelled(d0, d1) {
                    for &c in &INIT_SCALES {
                        if !call_directional(sys, t, y, yp, v, c, r, d1)? {
                            return Ok(false);
                        }
                        scale = c;
                        if !cancelled(d0, d1) {
                            break;
                        }
                    }
                }
                for (a, b) in d1.iter_mut().zip(&*d0) {
                    *a = (*a - b) / scale;
                }
            }
        }
        for &j in group {
            v[j] = 0.0;
            write_column(jac, j, |i| d1[i]);
        }
    }
    Ok(true)
}

#[allow(clippy::too_many_arguments)]
fn call_directional(
    sys: &mut System<'_>,
    t: f64,
    y: &[f64],
    yp: &[f64],
    v: &[f64],
    c: f64,
    r: &mut [f64],
    dr: &mut [f64],
) -> Result<bool, StepFailure> {
    let ok = sys
        .problem
        .directional(t, y, yp, v, c, r, dr)
        .map_err(|e| sys.residual_failure(e, t))?;
    if ok {
        sys.stats.directional_calls += 1;
    }
    Ok(ok)
}

fn finite_differences(
    sys: &mut System<'_>,
    t: f64,
    y: &[f64],
    yp: &[f64],
    cols: Columns<'_>,
    r0: Option<&[f64]>,
    jac: &mut Matrix,
) -> Result<(), StepFailure> {
    let n = y.len();
    let base: Vec<f64> = match r0 {
        Some(r) => {
            assert_eq!(r.len(), n, "base residual length mismatch");
            r.to_vec()
        }
        None => {
            let mut r = vec![0.0; n];
            sys.residual(t, y, yp, &mut r)?;
            r
        }
    };
    let srur = f64::EPSILON.sqrt();
    let rtol = sys.opts.rtol;
    let mut yq = y.to_vec();
    let mut ypq = yp.to_vec();
    let mut rq = vec![0.0; n];
    let mut inc = vec![0.0; n];
    let groups = sys.cache.colour_cols.clone();
    for group in groups.iter() {
        for &j in group {
            let tol = rtol * y[j].abs() + sys.cache.atol[j];
            // ẏ_j in "per unit of 1/c" (≈ h·ẏ_j for BDF), as in IDA
            let (scaled_yp, c) = match cols {
                Columns::Iteration { c } if c != 0.0 => (yp[j] / c, c),
                Columns::Iteration { c } => (0.0, c),
                Columns::Init { .. } => (yp[j], 1.0),
            };
            let mut d = (srur * y[j].abs().max(scaled_yp.abs())).max(tol);
            if scaled_yp < 0.0 {
                d = -d;
            }
            match cols {
                Columns::Iteration { .. } => {
                    yq[j] = y[j] + d;
                    d = yq[j] - y[j];
                    ypq[j] = yp[j] + c * d;
                }
                Columns::Init { algebraic } if algebraic[j] => {
                    yq[j] = y[j] + d;
                    d = yq[j] - y[j];
                }
                Columns::Init { .. } => {
                    ypq[j] = yp[j] + d;
                    d = ypq[j] - yp[j];
                }
            }
            inc[j] = d;
        }
        sys.residual(t, &yq, &ypq, &mut rq)?;
        for &j in group {
            let dj = inc[j];
            write_column(jac, j, |i| (rq[i] - base[i]) / dj);
            yq[j] = y[j];
            ypq[j] = yp[j];
        }
    }
    Ok(())
}

/// The storage slots of column `j`'s structural entries, in row order (a dense column, the
/// band rows of a banded one, the CSC values of a sparse one). Two matrices of one pattern
/// have the same slots.
fn column_slots(m: &Matrix, j: usize) -> &[f64] {
    match m {
        Matrix::Dense(d) => &d.data[j * d.n..(j + 1) * d.n],
        Matrix::Banded(b) => {
            let (r0, r1) = b.col_range(j);
            let base = j * b.ld() + b.lower + b.upper - j;
            &b.data[base + r0..base + r1]
        }
        Matrix::Sparse(sp) => {
            let cp = sp.pattern.col_ptr();
            &sp.values[cp[j]..cp[j + 1]]
        }
    }
}

/// [`column_slots`], mutable.
fn column_slots_mut(m: &mut Matrix, j: usize) -> &mut [f64] {
    match m {
        Matrix::Dense(d) => &mut d.data[j * d.n..(j + 1) * d.n],
        Matrix::Banded(b) => {
            let (r0, r1) = b.col_range(j);
            let base = j * b.ld() + b.lower + b.upper - j;
            &mut b.data[base + r0..base + r1]
        }
        Matrix::Sparse(sp) => {
            let cp = sp.pattern.col_ptr();
            let range = cp[j]..cp[j + 1];
            &mut sp.values[range]
        }
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use crate::linalg::Matrix;
    use crate::options::Options;
    use crate::pattern::{Pattern, SparsityPattern};
    use crate::problem::{JacobianSink, Problem, ResidualError};
    use crate::stats::Stats;
    use crate::system::{System, SystemCache};

    /// Which derivative sources a test problem offers.
    #[derive(Clone, Copy, PartialEq, Debug)]
    enum Source {
        Fd,
        Directional,
        User,
    }

    /// Discrete heat equation with a nonlinear source and a nonlinear mass term:
    /// `F_i = (1 + y_i²/4)·ẏ_i − (y_{i−1} − 2y_i + y_{i+1}) − sin(y_i)`, banded (1, 1); or, with
    /// `cyclic`, periodic neighbours and a sparse cyclic-tridiagonal pattern.
    struct Heat {
        n: usize,
        cyclic: bool,
        source: Source,
    }

    impl Heat {
        fn nb(&self, i: usize) -> (Option<usize>, Option<usize>) {
            let n = self.n;
            if self.cyclic {
                (Some((i + n - 1) % n), Some((i + 1) % n))
            } else {
                (i.checked_sub(1), (i + 1 < n).then_some(i + 1))
            }
        }
        /// Exact `∂F/∂y + c·∂F/∂ẏ` as (i, j, value) triples.
        fn exact(&self, y: &[f64], yp: &[f64], c: f64) -> Vec<(usize, usize, f64)> {
            let mut e = Vec::new();
            for i in 0..self.n {
                let d = 2.0 - y[i].cos() + y[i] / 2.0 * yp[i] + c * (1.0 + y[i] * y[i] / 4.0);
                e.push((i, i, d));
                let (l, r) = self.nb(i);
                for k in [l, r].into_iter().flatten() {
                    e.push((i, k, -1.0));
                }
            }
            e
        }
    }

    impl Problem for Heat {
        fn dim(&self) -> usize {
            self.n
        }
        fn residual(
            &mut self,
            _t: f64,
            y: &[f64],
            yp: &[f64],
            r: &mut [f64],
        ) -> Result<(), ResidualError> {
            for i in 0..self.n {
                let (l, rr) = self.nb(i);
                let lap = l.map_or(0.0, |k| y[k]) - 2.0 * y[i] + rr.map_or(0.0, |k| y[k]);
                r[i] = (1.0 + y[i] * y[i] / 4.0) * yp[i] - lap - y[i].sin();
            }
            Ok(())
        }
        fn pattern(&self) -> Pattern {
            if self.cyclic {
                let mut e = Vec::new();
                for i in 0..self.n {
                    let (l, r) = self.nb(i);
                    for k in [l, r].into_iter().flatten() {
                        e.push((i, k));
                    }
                }
                Pattern::Sparse(Arc::new(SparsityPattern::from_entries(self.n, &e)))
            } else {
                Pattern::Banded { lower: 1, upper: 1 }
            }
        }
        fn directional(
            &mut self,
            t: f64,
            y: &[f64],
            yp: &[f64],
            v: &[f64],
            c: f64,
            r: &mut [f64],
            dr: &mut [f64],
        ) -> Result<bool, ResidualError> {
            if self.source != Source::Directional {
                return Ok(false);
            }
            self.residual(t, y, yp, r)?;
            dr.iter_mut().for_each(|x| *x = 0.0);
            for (i, j, a) in self.exact(y, yp, c) {
                dr[i] += a * v[j];
            }
            Ok(true)
        }
        fn jacobian(
            &mut self,
            _t: f64,
            y: &[f64],
            yp: &[f64],
            c: f64,
            jac: &mut JacobianSink,
        ) -> Result<bool, ResidualError> {
            if self.source != Source::User {
                return Ok(false);
            }
            for (i, j, a) in self.exact(y, yp, c) {
                jac.add(i, j, a);
            }
            Ok(true)
        }
    }

    fn state(n: usize) -> (Vec<f64>, Vec<f64>) {
        let y = (0..n).map(|i| 0.3 + (i as f64 * 0.7).sin()).collect();
        let yp = (0..n).map(|i| (i as f64 * 1.3).cos() - 0.2).collect();
        (y, yp)
    }

    /// Builds J at c = 2.5 and returns (max abs error vs exact, stats of the build alone).
    fn check(p: &mut Heat, opts: &Options, with_r0: bool) -> (f64, Stats, usize) {
        let mut stats = Stats::default();
        let mut cache = SystemCache::default();
        cache.rebuild(&*p, opts).unwrap();
        let ncol = cache.colour_count();
        let (y, yp) = state(p.n);
        let exact = p.exact(&y, &yp, 2.5);
        let mut sys = System::new(p, opts, &mut stats, &mut cache);
        let mut jac = sys.new_matrix();
        if with_r0 {
            let mut r0 = vec![0.0; y.len()];
            sys.residual(0.0, &y, &yp, &mut r0).unwrap();
            sys.stats.residual_calls = 0;
            sys.jacobian_with_residual(0.0, &y, &yp, 2.5, &r0, &mut jac)
                .unwrap();
        } else {
            sys.jacobian(0.0, &y, &yp, 2.5, &mut jac).unwrap();
        }
        let mut dense = vec![0.0; y.len() * y.len()];
        for (i, j, a) in exact {
            dense[i * y.len() + j] += a;
        }
        let mut err = 0.0f64;
        for i in 0..y.len() {
            for j in 0..y.len() {
                err = err.max((jac.get(i, j) - dense[i * y.len() + j]).abs());
            }
        }
        (err, stats, ncol)
    }

    #[test]
    fn coloured_jacobians_match_analytic_banded_and_sparse() {
        let opts = Options::default();
        for cyclic in [false, true] {
            for n in [1, 2, 9, 40] {
                if cyclic && n < 3 {
                    continue;
                }
                // finite differences: one call per colour (+1 for the base point)
                let mut p = Heat {
                    n,
                    cyclic,
                    source: Source::Fd,
                };
                let (err, st, ncol) = check(&mut p, &opts, false);
                assert!(err < 1e-5, "fd cyclic={cyclic} n={n}: {err:e}");
                assert_eq!(st.residual_calls, ncol + 1);
                assert_eq!(st.jacobian_evals, 1);
                if !cyclic {
                    assert_eq!(ncol, 3.min(n), "banded (1,1): bandwidth + 1 colours");
                } else {
                    assert!(ncol <= 4, "{ncol}");
                }
                let (err, st, _) = check(&mut p, &opts, true);
                assert!(err < 1e-5, "fd+r0 cyclic={cyclic} n={n}: {err:e}");
                assert_eq!(
                    st.residual_calls, ncol,
                    "with r0: exactly one call per colour"
                );
                // exact directional derivatives: one call per colour, no residual calls
                p.source = Source::Directional;
                let (err, st, _) = check(&mut p, &opts, false);
                assert!(err < 1e-14, "ad cyclic={cyclic} n={n}: {err:e}");
                assert_eq!(st.directional_calls, ncol);
                assert_eq!(st.residual_calls, 0);
                // user Jacobian
                p.source = Source::User;
                let (err, st, _) = check(&mut p, &opts, false);
                assert!(err < 1e-14, "user: {err:e}");
                assert_eq!((st.residual_calls, st.directional_calls), (0, 0));
                // forced FD ignores both
                let forced = Options {
                    force_fd_jacobian: true,
                    ..Options::default()
                };
                let (err, st, _) = check(&mut p, &forced, false);
                assert!(err < 1e-5, "forced fd: {err:e}");
                assert_eq!(st.residual_calls, ncol + 1);
            }
        }
    }

    #[test]
    fn fd_jacobian_accuracy_tracks_tolerance() {
        // IDA's increment is ≈ rtol·|y| + atol: tighter tolerances, more accurate Jacobian
        let mut errs = Vec::new();
        for rtol in [1e-3, 1e-6, 1e-9] {
            let opts = Options {
                rtol,
                atol: rtol * 1e-2,
                ..Options::default()
            };
            let mut p = Heat {
                n: 12,
                cyclic: false,
                source: Source::Fd,
            };
            errs.push(check(&mut p, &opts, false).0);
        }
        assert!(
            errs[0] < 1e-2 && errs[1] < 1e-5 && errs[2] < 1e-6,
            "{errs:?}"
        );
        assert!(errs[1] < errs[0], "{errs:?}");
    }

    #[test]
    fn dense_fd_is_one_call_per_column() {
        struct D;
        impl Problem for D {
            fn dim(&self) -> usize {
                3
            }
            fn residual(
                &mut self,
                _t: f64,
                y: &[f64],
                yp: &[f64],
                r: &mut [f64],
            ) -> Result<(), ResidualError> {
                r[0] = yp[0] - y[1] * y[2];
                r[1] = yp[1] + y[0] * y[0];
                r[2] = y[2] - y[0] - 2.0 * y[1];
                Ok(())
            }
        }
        let opts = Options::default();
        let mut stats = Stats::default();
        let mut cache = SystemCache::default();
        let mut p = D;
        cache.rebuild(&p, &opts).unwrap();
        let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
        let mut jac = sys.new_matrix();
        assert!(matches!(jac, Matrix::Dense(_)));
        let (y, yp) = ([1.0, 2.0, 3.0], [0.0, 0.0, 0.0]);
        sys.jacobian(0.0, &y, &yp, 4.0, &mut jac).unwrap();
        let want = [[4.0, -3.0, -2.0], [2.0, 4.0, 0.0], [-1.0, -2.0, 1.0]];
        for (i, row) in want.iter().enumerate() {
            for (j, &w) in row.iter().enumerate() {
                assert!(
                    (jac.get(i, j) - w).abs() < 1e-5,
                    "({i},{j}) {}",
                    jac.get(i, j)
                );
            }
        }
        assert_eq!(stats.residual_calls, 4);
    }
}
