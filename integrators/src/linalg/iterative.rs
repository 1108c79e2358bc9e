//! Iterative sparse solver: an ILU(0) preconditioner built by "factor" and left-preconditioned
//! BiCGStab run by "solve", for large sparse iteration matrices where a sparse direct LU costs
//! superlinearly in `n` (fill-in).
//!
//! The ILU(0) factorisation comes from a crate (`faer_precond::Ilu0`: symbolic structure built
//! once per pattern, numeric refactorisation without allocation). The Krylov iteration and the
//! kernels it runs on are written here, on purpose (the first version used
//! `faer::matrix_free::bicgstab`; a 500 × 500 sheet spent ≈ 70 % of its time in it):
//!
//! * **stopping rule** — faer's BiCGStab only stops on `‖b − A x‖₂ ≤ rtol·‖b‖₂`. A Newton
//!   iteration needs the linear error in *its* weighted norm only a little below *its*
//!   tolerance, as in SUNDIALS IDA/CVODE (inexact Newton): with a [`LinearTolerance`]
//!   (error weights, norm, Newton tolerance ε) the solve stops as soon as the weighted norm of
//!   the preconditioned residual `M⁻¹(b − A x)` (an estimate of the error of `x`, in the units
//!   of `x`) is ≤ [`IterativeSettings::newton_factor`]`·ε` (SUNDIALS' `eplifac`; default 0.01).
//!   Left preconditioning makes that residual the one BiCGStab updates anyway (no extra
//!   preconditioner application per iteration).
//! * **no copies** — faer's version copies vectors each iteration (`Mat::copy_from` was 8.7 % of
//!   the profile) and runs the one-column updates through its general matmul kernels; here each
//!   iteration is two fused sweeps per `M⁻¹A·v` and two fused vector passes.
//! * **CSR gather kernels** — `A` and the ILU factors `L`, `U` share A's pattern (ILU(0) has no
//!   fill), so one CSR structure with `u32` column indices, built once per pattern, serves all
//!   three. `M⁻¹A·v` is one forward sweep (row `i` of `A·v` and of the `L` solve use the same
//!   column indices) and one backward sweep (the `U` solve, multiplying by stored inverse
//!   pivots). The values are scattered into CSR order once per factorisation (O(nnz)).
//! * **single-precision factors** — the sweeps are memory-bound, so the off-diagonal factor
//!   entries are stored as `f32`: `L` and the row-scaled `D⁻¹U` (unit diagonal), both
//!   scale-free ratios, with the inverse pivots `D⁻¹` in `f64`. This perturbs only the
//!   preconditioner `M` (by ~1e-7 relative), i.e. the speed of convergence, never what the
//!   iteration converges to: `A` itself is kept in `f64`.
//!
//! Contract with [`super::LinearSolver`]:
//!
//! * `factor` refactorises ILU(0) and stores `A`'s and the factors' values in CSR order; a zero
//!   pivot (or a pattern without its diagonal, which [`crate::SparsityPattern::from_entries`]
//!   never builds) or a non-finite entry is `Err(column)`, like a direct LU;
//! * `solve` starts from `x = 0` and stops at the first of: the Newton-aware test above (when
//!   the caller passes a [`LinearTolerance`] and `newton_factor > 0`), or the relative
//!   preconditioned residual `‖M⁻¹(b − A x)‖₂ ≤ rtol·‖M⁻¹b‖₂` ([`IterativeSettings::rtol`], the
//!   only rule for callers without a Newton tolerance, and a floor that bounds the work of any
//!   solve). If neither is reached within `max_iters` (or a non-finite value or a breakdown
//!   appears), the right-hand side is overwritten with NaN. Every method treats a non-finite
//!   Newton update as a failed Newton iteration, i.e. a recoverable step failure: the step is
//!   retried smaller (where the iteration matrix is better conditioned). No panic, and no
//!   silently inaccurate solution.
//!
//! Work vectors are allocated once per pattern and kept in a `RefCell` because
//! `LinearSolver::solve_in_place` takes `&self`.

use std::cell::{Cell, RefCell};
use std::sync::Arc;

use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer_precond::ilu0::{Ilu0Error, SymbolicIlu0};
use faer_precond::Ilu0;

use super::first_non_finite;
use crate::options::{ErrorNorm, IterativeSettings};
use crate::pattern::SparsityPattern;

/// What a Newton iteration needs from a linear solve: the solution error measured in its own
/// weighted norm, `‖(e_i·w_i)‖ ≤ target` (only the iterative solver uses it; direct solvers are
/// exact to rounding).
///
/// The BDF method passes its Newton weights, its norm and its Newton convergence tolerance;
/// the iterative solver stops when the weighted norm of the preconditioned residual is below
/// [`IterativeSettings::newton_factor`]` · target`.
///
/// ```
/// use integrators::linalg::LinearTolerance;
/// use integrators::ErrorNorm;
/// let w = vec![1e6; 4];
/// let tol = LinearTolerance { weights: &w, norm: ErrorNorm::Max, target: 0.33 };
/// assert_eq!(tol.weights.len(), 4);
/// ```
#[derive(Clone, Copy, Debug)]
pub struct LinearTolerance<'a> {
    /// Error weights `w_i` (one per unknown, ≥ 0), typically `1/(rtol·|y_i| + atol_i)`.
    pub weights: &'a [f64],
    /// Norm of the weighted error vector.
    pub norm: ErrorNorm,
    /// Tolerance of the caller's (Newton) convergence test in that norm (> 0).
    pub target: f64,
}

/// Counters of the Krylov iterations made by one [`super::LinearSolver`] (for statistics and
/// performance reports).
///
/// ```
/// use integrators::linalg::LinearSolver;
/// use integrators::Pattern;
/// // a direct solver makes no Krylov iterations
/// let lu = LinearSolver::new(3, &Pattern::Dense);
/// let k = lu.krylov_counters();
/// assert_eq!((k.solves, k.iterations, k.failures), (0, 0, 0));
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct KrylovCounters {
    /// Solves attempted.
    pub solves: usize,
    /// BiCGStab iterations summed over all solves.
    pub iterations: usize,
    /// Solves that did not reach the tolerance (answered with NaN).
    pub failures: usize,
    /// Most iterations taken by one converged solve.
    pub max_iterations: usize,
}

/// CSR structure of the pattern (built once): `A`, `L` (strictly lower part) and `U` (diagonal
/// and upper part) of ILU(0) all live on it.
struct Csr {
    row_ptr: Vec<usize>,
    /// Column indices, sorted within each row (`u32`: the sweeps are memory-bound).
    col: Vec<u32>,
    /// Slot of the diagonal entry of each row.
    diag: Vec<usize>,
}

impl Csr {
    /// Transposes the CSC pattern. `None` if `n` does not fit in `u32` or a diagonal entry is
    /// missing.
    fn new(p: &SparsityPattern) -> Option<Self> {
        let n = p.n();
        u32::try_from(n).ok()?;
        let (cp, ri) = (p.col_ptr(), p.row_idx());
        let mut row_ptr = vec![0usize; n + 1];
        for &i in ri {
            row_ptr[i + 1] += 1;
        }
        for i in 0..n {
            row_ptr[i + 1] += row_ptr[i];
        }
        let mut next = row_ptr[..n].to_vec();
        let mut col = vec![0u32; ri.len()];
        let mut diag = vec![usize::MAX; n];
        for j in 0..n {
            for &i in &ri[cp[j]..cp[j + 1]] {
                let k = next[i];
                next[i] += 1;
                col[k] = j as u32;
                if i == j {
                    diag[i] = k;
                }
            }
        }
        if diag.contains(&usize::MAX) {
            return None;
        }
        Some(Self { row_ptr, col, diag })
    }

    /// Scatters CSC values (`A`'s, aligned with the pattern) into CSR order.
    fn scatter(&self, p: &SparsityPattern, values: &[f64], next: &mut [usize], out: &mut [f64]) {
        let (cp, ri) = (p.col_ptr(), p.row_idx());
        next.copy_from_slice(&self.row_ptr[..p.n()]);
        for j in 0..p.n() {
            for (&i, &v) in ri[cp[j]..cp[j + 1]].iter().zip(&values[cp[j]..cp[j + 1]]) {
                out[next[i]] = v;
                next[i] += 1;
            }
        }
    }

    /// Scatters the ILU(0) factors into CSR order: `L`'s strictly lower entries, then the
    /// strictly upper entries of `D⁻¹U` (`D` = diag `U`, whose inverse goes to `dinv`; the
    /// diagonal slot of `out` is unused). Checks on the way that the factors have exactly A's
    /// pattern (ILU(0) has no fill); `false` if not.
    fn scatter_lu(
        &self,
        ilu: &Ilu0<usize, f64>,
        next: &mut [usize],
        out: &mut [f32],
        dinv: &mut [f64],
    ) -> bool {
        let n = self.diag.len();
        next.copy_from_slice(&self.row_ptr[..n]);
        let l = ilu.l_view();
        let (lcp, lri, lv) = (l.symbolic().col_ptr(), l.symbolic().row_idx(), l.val());
        for j in 0..n {
            for (&i, &v) in lri[lcp[j]..lcp[j + 1]].iter().zip(&lv[lcp[j]..lcp[j + 1]]) {
                if i > j {
                    let k = next[i];
                    if k >= self.diag[i] || self.col[k] as usize != j {
                        return false;
                    }
                    out[k] = v as f32;
                    next[i] += 1;
                }
            }
        }
        if next.iter().zip(&self.diag).any(|(a, b)| a != b) {
            return false;
        }
        // U's diagonal is the last entry of each of its columns: collect the inverse pivots
        // first, then scale the rows
        {
            let u = ilu.u_view();
            let (ucp, uv) = (u.symbolic().col_ptr(), u.val());
            for (j, d) in dinv.iter_mut().enumerate() {
                *d = if ucp[j + 1] > ucp[j] {
                    1.0 / uv[ucp[j + 1] - 1]
                } else {
                    f64::NAN
                };
            }
        }
        let u = ilu.u_view();
        let (ucp, uri, uv) = (u.symbolic().col_ptr(), u.symbolic().row_idx(), u.val());
        for j in 0..n {
            for (&i, &v) in uri[ucp[j]..ucp[j + 1]].iter().zip(&uv[ucp[j]..ucp[j + 1]]) {
                let k = next[i];
                if k >= self.row_ptr[i + 1] || self.col[k] as usize != j {
                    return false;
                }
                out[k] = if i == j { 0.0 } else { (v * dinv[i]) as f32 };
                next[i] += 1;
            }
        }
        next.iter().zip(&self.row_ptr[1..]).all(|(a, b)| a == b)
    }
}

/// Work vectors of one solve (allocated on the first solve, reused).
#[derive(Default)]
struct Work {
    x: Vec<f64>,
    r: Vec<f64>,
    r_hat: Vec<f64>,
    p: Vec<f64>,
    v: Vec<f64>,
    t: Vec<f64>,
}

/// ILU(0)-preconditioned BiCGStab over a fixed sparsity pattern.
pub(crate) struct IterativeSolver {
    pattern: Arc<SparsityPattern>,
    settings: IterativeSettings,
    /// `None` when the pattern cannot be handled (no diagonal entry in some row, or more than
    /// `u32::MAX` unknowns): `factor` then reports an error.
    csr: Option<Csr>,
    /// `A`'s values in CSR order.
    a: Vec<f64>,
    /// ILU(0) factors in CSR order (`L` strictly lower, `D⁻¹U` strictly upper; `f32`, see the
    /// module docs).
    lu: Vec<f32>,
    /// Inverse pivots `1/U_ii`.
    dinv: Vec<f64>,
    /// Per-row insertion cursors for the scatters.
    next: Vec<usize>,
    ilu: Option<Ilu0<usize, f64>>,
    work: RefCell<Work>,
    factored: bool,
    pub(crate) last_symbolic: bool,
    counters: Cell<KrylovCounters>,
}

impl IterativeSolver {
    pub(crate) fn new(pattern: Arc<SparsityPattern>, settings: IterativeSettings) -> Self {
        // Validate the CSC structure once (sorted, in-range row indices); every later view is
        // built unchecked (see `structure`).
        let _ = SymbolicSparseColMatRef::new_checked(
            pattern.n(),
            pattern.n(),
            pattern.col_ptr(),
            None,
            pattern.row_idx(),
        );
        let csr = Csr::new(&pattern);
        Self {
            pattern,
            settings,
            csr,
            a: Vec::new(),
            lu: Vec::new(),
            dinv: Vec::new(),
            next: Vec::new(),
            ilu: None,
            work: RefCell::new(Work::default()),
            factored: false,
            last_symbolic: false,
            counters: Cell::new(KrylovCounters::default()),
        }
    }

    pub(crate) fn counters(&self) -> KrylovCounters {
        self.counters.get()
    }

    /// Builds the ILU(0) preconditioner and stores `A` and the factors in CSR order.
    pub(crate) fn factor(
        &mut self,
        pattern: &Arc<SparsityPattern>,
        values: &[f64],
    ) -> Result<(), usize> {
        self.factored = false;
        self.last_symbolic = false;
        super::check_sparse_values(&self.pattern, pattern, values)?;
        let n = self.pattern.n();
        if n == 0 {
            self.factored = true;
            return Ok(());
        }
        let structure = structure(&self.pattern);
        if self.ilu.is_none() {
            let sym = SymbolicIlu0::try_new(structure).map_err(|e| ilu_column(&e))?;
            self.ilu = Some(Ilu0::new_with_symbolic(sym));
            self.last_symbolic = true;
            let nnz = self.pattern.nnz();
            self.a = vec![0.0; nnz];
            self.lu = vec![0.0; nnz];
            self.dinv = vec![0.0; n];
            self.next = vec![0; n];
        }
        let ilu = self.ilu.as_mut().expect("ILU allocated");
        ilu.refactorize(SparseColMatRef::new(structure, values))
            .map_err(|e| ilu_column(&e))?;
        // a pattern the CSR kernels cannot take (no diagonal in some row, which ILU(0) has
        // already rejected above, or > u32::MAX unknowns) is reported at column 0
        let csr = self.csr.as_ref().ok_or(0usize)?;
        csr.scatter(&self.pattern, values, &mut self.next, &mut self.a);
        if !csr.scatter_lu(ilu, &mut self.next, &mut self.lu, &mut self.dinv) {
            // ILU(0) factors always have A's pattern; anything else is a broken invariant of
            // the factorisation crate, reported (not panicked on) as a failed factorisation
            return Err(0);
        }
        // a pivot so small that its inverse overflows is as good as zero; a factor ratio
        // beyond f32's range (≈ 3e38) is reported the same way
        if let Some(i) = first_non_finite(&self.dinv) {
            return Err(i);
        }
        if let Some(k) = self.lu.iter().position(|v| !v.is_finite()) {
            return Err(csr.col[k] as usize);
        }
        self.factored = true;
        Ok(())
    }

    /// Solves `A x = b` in place (NaN on non-convergence; see the module docs).
    pub(crate) fn solve(&self, b: &mut [f64], tol: Option<&LinearTolerance<'_>>) {
        assert!(
            self.factored,
            "LinearSolver::solve_in_place before a successful factor"
        );
        let n = self.pattern.n();
        assert_eq!(b.len(), n, "right-hand side length mismatch");
        if n == 0 {
            return;
        }
        if let Some(t) = tol {
            assert_eq!(
                t.weights.len(),
                n,
                "LinearTolerance weights length mismatch"
            );
        }
        let mut work = self.work.borrow_mut();
        let res = self.bicgstab(b, tol, &mut work);
        let mut c = self.counters.get();
        c.solves += 1;
        match res {
            Ok(iters) => {
                c.iterations += iters;
                c.max_iterations = c.max_iterations.max(iters);
                b.copy_from_slice(&work.x);
            }
            Err(iters) => {
                c.iterations += iters;
                c.failures += 1;
                b.fill(f64::NAN);
            }
        }
        self.counters.set(c);
    }

    /// Left-preconditioned BiCGStab (van der Vorst 1992) on `M⁻¹A x = M⁻¹b` from `x = 0`, the
    /// solution left in `work.x`. `Ok(iterations)` when a stopping test is met,
    /// `Err(iterations)` on `max_iters`, breakdown or a non-finite value.
    fn bicgstab(
        &self,
        b: &[f64],
        tol: Option<&LinearTolerance<'_>>,
        w: &mut Work,
    ) -> Result<usize, usize> {
        let n = b.len();
        for v in [
            &mut w.x,
            &mut w.r,
            &mut w.r_hat,
            &mut w.p,
            &mut w.v,
            &mut w.t,
        ] {
            // every vector but `x` is fully overwritten before it is read
            v.resize(n, 0.0);
        }
        w.x.fill(0.0);
        let Work {
            x,
            r,
            r_hat,
            p,
            v,
            t,
        } = w;
        // r₀ = M⁻¹b
        r.copy_from_slice(b);
        self.precondition_in_place(r);
        let weighted = tol.filter(|_| self.settings.newton_factor > 0.0);
        let r0 = measure(r, weighted);
        if !(r0.l2sq.is_finite() && r0.weighted.is_finite()) {
            return Err(0);
        }
        if r0.l2sq == 0.0 {
            return Ok(0); // x = 0 exactly
        }
        let l2_threshold = self.settings.rtol * self.settings.rtol * r0.l2sq;
        let w_threshold = weighted.map_or(-1.0, |t| self.settings.newton_factor * t.target);
        let done = |m: &Measure| m.l2sq <= l2_threshold || m.weighted <= w_threshold;
        // No early exit on `r₀` even when it already passes the weighted test: `x = 0` would be
        // a zero Newton correction, which BDF takes as converged at once (bypassing its
        // contraction checks); at least one iteration gives a correction accurate to the target.
        r_hat.copy_from_slice(r);
        let mut rho = r0.l2sq; // (r̂, r)
        let (mut omega, mut beta) = (0.0f64, 0.0f64);
        for iter in 1..=self.settings.max_iters {
            if iter == 1 {
                p.copy_from_slice(r);
            } else {
                for ((pi, &ri), &vi) in p.iter_mut().zip(r.iter()).zip(v.iter()) {
                    *pi = ri + beta * (*pi - omega * vi);
                }
            }
            let (rv, _) = self.apply_prec_a(p, v, r_hat);
            if rv == 0.0 || !rv.is_finite() {
                return Err(iter);
            }
            let alpha = rho / rv;
            // s = r − α v (kept in r)
            let s = axpy_measure(r, -alpha, v, weighted);
            if !(s.l2sq.is_finite() && s.weighted.is_finite()) {
                return Err(iter);
            }
            if done(&s) {
                for (xi, &pi) in x.iter_mut().zip(p.iter()) {
                    *xi += alpha * pi;
                }
                return Ok(iter);
            }
            let (ts, tt) = self.apply_prec_a(r, t, r);
            if tt == 0.0 || !(ts.is_finite() && tt.is_finite()) {
                return Err(iter);
            }
            omega = ts / tt;
            // x += α p + ω s; r = s − ω t; ρ_new = (r̂, r)
            let (m, rho_new) = update(x, p, r, t, r_hat, alpha, omega, weighted);
            if !(m.l2sq.is_finite() && m.weighted.is_finite()) {
                return Err(iter);
            }
            if done(&m) {
                return Ok(iter);
            }
            if omega == 0.0 || rho_new == 0.0 || !rho_new.is_finite() {
                return Err(iter); // breakdown
            }
            beta = (rho_new / rho) * (alpha / omega);
            rho = rho_new;
        }
        Err(self.settings.max_iters)
    }

    /// `dst = M⁻¹ A src`, returning `((with, dst), (dst, dst))` (see [`Self::backward`]): one
    /// forward sweep (row `i` of `A·src`, minus the `L` part already
    /// solved, over the same column indices) and one backward sweep (`U`).
    fn apply_prec_a(&self, src: &[f64], dst: &mut [f64], with: &[f64]) -> (f64, f64) {
        let csr = self.csr.as_ref().expect("factored");
        let (rp, col, diag) = (&csr.row_ptr, &csr.col, &csr.diag);
        let (a, lu) = (&self.a[..], &self.lu[..]);
        for i in 0..dst.len() {
            let (s, d, e) = (rp[i], diag[i], rp[i + 1]);
            let mut acc = 0.0;
            for (&c, &av) in col[s..e].iter().zip(&a[s..e]) {
                acc += av * src[c as usize];
            }
            for (&c, &l) in col[s..d].iter().zip(&lu[s..d]) {
                acc -= f64::from(l) * dst[c as usize];
            }
            dst[i] = acc;
        }
        self.backward(dst, with)
    }

    /// `v = M⁻¹ v = U⁻¹ L⁻¹ v`.
    fn precondition_in_place(&self, v: &mut [f64]) {
        let csr = self.csr.as_ref().expect("factored");
        let (rp, col, diag) = (&csr.row_ptr, &csr.col, &csr.diag);
        let lu = &self.lu[..];
        for i in 0..v.len() {
            let (s, d) = (rp[i], diag[i]);
            let mut acc = v[i];
            for (&c, &l) in col[s..d].iter().zip(&lu[s..d]) {
                acc -= f64::from(l) * v[c as usize];
            }
            v[i] = acc;
        }
        self.backward(v, &[]);
    }

    /// `v = U⁻¹ v = (D⁻¹U)⁻¹ D⁻¹ v`, returning `((with, v), (v, v))` of the result when
    /// `with` is non-empty (the BiCGStab dot products, without another pass over `v`).
    fn backward(&self, v: &mut [f64], with: &[f64]) -> (f64, f64) {
        let csr = self.csr.as_ref().expect("factored");
        let (rp, col, diag) = (&csr.row_ptr, &csr.col, &csr.diag);
        let lu = &self.lu[..];
        let (mut wv, mut vv) = (0.0, 0.0);
        for i in (0..v.len()).rev() {
            let (d, e) = (diag[i], rp[i + 1]);
            let mut acc = v[i] * self.dinv[i];
            for (&c, &u) in col[d + 1..e].iter().zip(&lu[d + 1..e]) {
                acc -= f64::from(u) * v[c as usize];
            }
            v[i] = acc;
            if let Some(&w) = with.get(i) {
                wv += w * acc;
                vv += acc * acc;
            }
        }
        (wv, vv)
    }
}

/// Squared 2-norm of a residual and its weighted norm (0 when there is no weighted test).
struct Measure {
    l2sq: f64,
    weighted: f64,
}

/// Running sums for [`Measure`].
#[derive(Default)]
struct Acc {
    l2sq: f64,
    wsq: f64,
    wmax: f64,
}

impl Acc {
    #[inline]
    fn push(&mut self, r: f64, w: f64) {
        self.l2sq += r * r;
        let rw = r * w;
        self.wsq += rw * rw;
        self.wmax = self.wmax.max(rw.abs());
    }
    fn finish(self, n: usize, tol: Option<&LinearTolerance<'_>>) -> Measure {
        let weighted = match tol.map(|t| t.norm) {
            None => 0.0,
            // NaN in the vector already shows in `l2sq`
            Some(ErrorNorm::Rms) => (self.wsq / n as f64).sqrt(),
            Some(ErrorNorm::Max) => self.wmax,
        };
        Measure {
            l2sq: self.l2sq,
            weighted,
        }
    }
}

/// The weight of component `i` (0 without a weighted test: the weighted sums are then unused).
#[inline]
fn weight(tol: Option<&LinearTolerance<'_>>, i: usize) -> f64 {
    tol.map_or(0.0, |t| t.weights[i])
}

fn measure(r: &[f64], tol: Option<&LinearTolerance<'_>>) -> Measure {
    let mut acc = Acc::default();
    for (i, &ri) in r.iter().enumerate() {
        acc.push(ri, weight(tol, i));
    }
    acc.finish(r.len(), tol)
}

/// `r += a·v`, measuring the new `r`.
fn axpy_measure(r: &mut [f64], a: f64, v: &[f64], tol: Option<&LinearTolerance<'_>>) -> Measure {
    let mut acc = Acc::default();
    for (i, (ri, &vi)) in r.iter_mut().zip(v).enumerate() {
        *ri += a * vi;
        acc.push(*ri, weight(tol, i));
    }
    acc.finish(r.len(), tol)
}

/// The end of a BiCGStab iteration in one pass: `x += α p + ω s`, `r = s − ω t` (`s` is in
/// `r`), returning the measure of the new `r` and `(r̂, r)`.
#[allow(clippy::too_many_arguments)]
fn update(
    x: &mut [f64],
    p: &[f64],
    r: &mut [f64],
    t: &[f64],
    r_hat: &[f64],
    alpha: f64,
    omega: f64,
    tol: Option<&LinearTolerance<'_>>,
) -> (Measure, f64) {
    let mut acc = Acc::default();
    let mut rho = 0.0;
    for (i, ((((xi, &pi), ri), &ti), &rh)) in x
        .iter_mut()
        .zip(p)
        .zip(r.iter_mut())
        .zip(t)
        .zip(r_hat)
        .enumerate()
    {
        *xi += alpha * pi + omega * *ri;
        *ri -= omega * ti;
        acc.push(*ri, weight(tol, i));
        rho += rh * *ri;
    }
    (acc.finish(x.len(), tol), rho)
}

/// Column named by an ILU(0) error (0 when the error names none).
fn ilu_column(e: &Ilu0Error) -> usize {
    match e {
        Ilu0Error::MissingDiagonal { col }
        | Ilu0Error::UnsortedRowIndices { col }
        | Ilu0Error::ZeroPivot { col } => *col,
        _ => 0,
    }
}

/// faer's view of a pattern, without faer's O(nnz) structure check on every call.
fn structure(p: &SparsityPattern) -> SymbolicSparseColMatRef<'_, usize> {
    // SAFETY: `SparsityPattern` is built only by `from_entries`, whose output has
    // `col_ptr` non-decreasing from 0 to `row_idx.len()` and strictly increasing,
    // in-range row indices per column — faer's invariants; `IterativeSolver::new` also checks
    // them once with `new_checked` (which panics on violation).
    unsafe { SymbolicSparseColMatRef::new_unchecked(p.n(), p.n(), p.col_ptr(), None, p.row_idx()) }
}

#[cfg(test)]
mod tests;
