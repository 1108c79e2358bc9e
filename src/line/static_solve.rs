//! Static equilibrium of a line with fixed or prescribed ends (docs/model.md §5.2).
//!
//! * [`static_equilibrium`] — at rest every cell carries the same stress `S`
//!   (`μ_j σ_el(λ_j) = S`) and the stretches add up to the length (`Σ L₀,j λ_j = l`). Each cell is
//!   inverted for `λ_j(S)` by safeguarded Newton ([`invert_stretch`]; [`neo_hookean_stretch`]
//!   is the neo-Hookean closed form, for checks), and `S` is found by Newton safeguarded by
//!   a bracket, since `Σ L₀λ(S)` increases with `S`; each inversion starts from the cell's
//!   stretch at the previous iterate. O(N) per iteration.
//! * [`static_newton`] — Newton on the static residual `F(t, y, ẏ = 0) = 0` of any line without
//!   growth, with the banded Jacobian from AD and a banded LU (active stress at a frozen time,
//!   width rules, …).

use super::array::Line;
use super::LineError;
use crate::array::CellArray;
use crate::energy::{LawVisitor, StrainEnergy};
use integrators::{Pattern, ResidualError};
use num_dual::Dual64;

/// `λ` with `σ_el(λ)/μ = s` for neo-Hookean: `λ² = ½(s + √(s² + 4))`.
///
/// ```
/// use celltissue::line::static_solve::neo_hookean_stretch;
/// let l = neo_hookean_stretch(0.9f64.powi(2) - 0.9f64.powi(-2));
/// assert!((l - 0.9).abs() < 1e-14);
/// ```
pub fn neo_hookean_stretch(s: f64) -> f64 {
    // stable form for s < 0: λ² = 2 / (√(s²+4) − s)
    let r = (s * s + 4.0).sqrt();
    let l2 = if s >= 0.0 {
        0.5 * (s + r)
    } else {
        2.0 / (r - s)
    };
    l2.sqrt()
}

/// Solves `scale·σ_el(λ) = s` for `λ > 0` (σ_el strictly increasing) by Newton with a bracket.
///
/// The bracket grows by doubling (halving) from `λ = 1`; a stretch outside the law's domain
/// ([`StrainEnergy::admissible`], e.g. past a locking [`crate::Gent`] law's limit) is never
/// evaluated: the bracket then closes in on the domain's edge by bisection, where a locking
/// law's stress diverges, so any finite `s` is found inside the domain.
///
/// ```
/// use celltissue::line::static_solve::invert_stretch;
/// use celltissue::{Gent, NeoHookean, StrainEnergy};
/// let l = invert_stretch(&NeoHookean::new(1.0).unwrap(), 2.0, -0.5).unwrap();
/// assert!((2.0 * (l * l - 1.0 / (l * l)) + 0.5).abs() < 1e-12);
/// // Gent with J_m = 0.5 locks at λ ≈ 1.414 and 0.707: large stresses stay inside
/// let gent = Gent::new(1.0, 0.5).unwrap();
/// let l = invert_stretch(&gent, 1.0, 50.0).unwrap();
/// assert!(l < 1.4143 && (gent.line(l).sigma - 50.0).abs() < 1e-9 * 50.0);
/// ```
pub fn invert_stretch<E: StrainEnergy>(energy: &E, scale: f64, s: f64) -> Result<f64, LineError> {
    let inside = |l: f64| crate::energy::in_domain(energy, [l, 1.0 / l, 1.0]);
    let f = |l: f64| {
        let r = energy.line(l);
        (scale * r.sigma - s, scale * r.dsigma)
    };
    let fail = || {
        LineError::Combination(format!(
            "cannot invert the cell law for stress {s} (no stretch in its domain carries it)"
        ))
    };
    // grows the bracket from λ = 1 by `step` (×2 or ×½) until `f` changes sign to `want_pos`;
    // an inadmissible candidate is replaced by the midpoint with the last admissible one
    let search = |step: f64, want_pos: bool| -> Result<f64, LineError> {
        let mut last = 1.0;
        let mut out: Option<f64> = None;
        for _ in 0..4000 {
            let cand = match out {
                None => last * step,
                Some(o) => 0.5 * (last + o),
            };
            if !(cand > 1e-300 && cand < 1e300) || (out.is_some() && cand == last) {
                return Err(fail());
            }
            if !inside(cand) {
                out = Some(cand);
                continue;
            }
            let v = f(cand).0;
            if v == 0.0 || (v > 0.0) == want_pos {
                return Ok(cand);
            }
            last = cand;
        }
        Err(fail())
    };
    // bracket [lo, hi] with f(lo) < 0 < f(hi)
    let (mut lo, mut hi) = (1.0, 1.0);
    let f1 = f(1.0).0;
    if f1 == 0.0 {
        return Ok(1.0);
    }
    if f1 > 0.0 {
        lo = search(0.5, false)?;
        if f(lo).0 == 0.0 {
            return Ok(lo);
        }
    } else {
        hi = search(2.0, true)?;
        if f(hi).0 == 0.0 {
            return Ok(hi);
        }
    }
    let mut l = 0.5 * (lo + hi);
    for _ in 0..200 {
        let (v, d) = f(l);
        if v == 0.0 {
            return Ok(l);
        }
        if v < 0.0 {
            lo = l;
        } else {
            hi = l;
        }
        let mut next = l - v / d;
        if !(next > lo && next < hi && next.is_finite()) {
            next = 0.5 * (lo + hi);
        }
        if (next - l).abs() <= 1e-15 * l {
            return Ok(next);
        }
        l = next;
    }
    Ok(l)
}

/// Iterates of the common stress before [`static_equilibrium`] gives up (a doubling from one
/// known end reaches any finite stress within a few hundred).
const MAX_STRESS_ITERS: usize = 400;

/// [`invert_stretch`] from a nearby stretch `guess` (the same cells' at the previous stress
/// iterate): plain Newton steps while they stay positive, in the law's domain and on a rising
/// slope, accepted once a step is below 1e-11 relative (quadratic convergence then leaves an
/// error near 1e-22); anything else goes to the bracketed solve from `λ = 1`. Returns `λ` and
/// `scale·σ′(λ)`.
fn invert_stretch_near<E: StrainEnergy>(
    energy: &E,
    scale: f64,
    s: f64,
    guess: f64,
) -> Result<(f64, f64), LineError> {
    let mut l = guess;
    for _ in 0..8 {
        if !(l > 0.0 && l.is_finite() && crate::energy::in_domain(energy, [l, 1.0 / l, 1.0])) {
            break;
        }
        let r = energy.line(l);
        let (v, d) = (scale * r.sigma - s, scale * r.dsigma);
        if !(d > 0.0 && d.is_finite() && v.is_finite()) {
            break;
        }
        let step = v / d;
        if step.abs() <= 1e-11 * l {
            return Ok((l - step, d));
        }
        l -= step;
    }
    let l = invert_stretch(energy, scale, s)?;
    Ok((l, scale * energy.line(l).dsigma))
}

/// Consecutive cells of equal `μ` and external pressure `p_e`: one stretch for all, from
/// `μσ_el(λ) = S + p_e` at the common stress `S`.
struct Run {
    mu: f64,
    p_ext: f64,
    /// `Σ L₀` of its cells.
    l0: f64,
}

/// One sweep of [`static_equilibrium`]'s stress solve at stress `s`: each [`Run`] inverted
/// from its stretch in `lam` (updated), giving `Σ L₀λ(s) − l` and its slope `Σ L₀/(μσ′(λ))`.
struct Excess<'a> {
    runs: &'a [Run],
    lam: &'a mut [f64],
    s: f64,
    l: f64,
}

impl LawVisitor for Excess<'_> {
    type Output = Result<(f64, f64), LineError>;

    fn visit<E: StrainEnergy>(self, law: &E) -> Self::Output {
        let (sum, slope) = excess_sums(law, self.runs, self.lam, self.s)?;
        Ok((sum - self.l, slope))
    }
}

/// Runs from which [`excess_sums`] splits its sweep in two halves run concurrently.
const PAR_MIN_RUNS: usize = 1 << 15;

/// `(Σ L₀λ, Σ L₀/(μσ′(λ)))` over `runs` at stress `s`, each run's inversion from its stretch in
/// `lam` (updated); in two halves on two threads from [`PAR_MIN_RUNS`] runs (the halves' sums
/// added, so a long line's totals differ from one thread's in the last bits only).
fn excess_sums<E: StrainEnergy>(
    law: &E,
    runs: &[Run],
    lam: &mut [f64],
    s: f64,
) -> Result<(f64, f64), LineError> {
    if runs.len() >= PAR_MIN_RUNS {
        let mid = runs.len() / 2;
        let (r1, r2) = runs.split_at(mid);
        let (l1, l2) = lam.split_at_mut(mid);
        let (a, b) = rayon::join(
            || excess_sums(law, r1, l1, s),
            || excess_sums(law, r2, l2, s),
        );
        let ((s1, d1), (s2, d2)) = (a?, b?);
        return Ok((s1 + s2, d1 + d2));
    }
    let (mut sum, mut slope) = (0.0, 0.0);
    for (run, guess) in runs.iter().zip(lam.iter_mut()) {
        let (x, d) = invert_stretch_near(law, run.mu, s + run.p_ext, *guess)?;
        *guess = x;
        sum += x * run.l0;
        slope += run.l0 / d;
    }
    Ok((sum, slope))
}

/// A static equilibrium.
///
/// ```
/// use celltissue::line::build::{discrete, LineParams};
/// use celltissue::line::static_solve::static_equilibrium;
/// use celltissue::NeoHookean;
/// let line = discrete(NeoHookean::new(1.0).unwrap(), &LineParams::unit_cells(10)).unwrap();
/// let s = static_equilibrium(&line, 9.0).unwrap(); // uniform cells, 10 % shorter
/// assert!(s.lambda.iter().all(|l| (l - 0.9).abs() < 1e-12));
/// assert!((s.x[10] - 9.0).abs() < 1e-12 && (s.min_stretch() - 0.9).abs() < 1e-12);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct StaticSolution {
    /// Uniform axial stress `S`.
    pub stress: f64,
    /// Cell stretches.
    pub lambda: Vec<f64>,
    /// Cell pressures `μ_j p_el(λ_j) + p_e,j`.
    pub pressure: Vec<f64>,
    /// Boundary positions `x₀ = 0 .. x_N = l`.
    pub x: Vec<f64>,
}

impl StaticSolution {
    /// Maximum pressure.
    ///
    /// ```
    /// use celltissue::line::static_solve::static_equilibrium;
    /// use celltissue::line::{discrete, LineParams};
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(10))?;
    /// let s = static_equilibrium(&line, 9.0)?; // uniform line held 10 % short
    /// assert!((s.max_pressure() - 1.0 / 0.81).abs() < 1e-9); // μ/λ²
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn max_pressure(&self) -> f64 {
        self.pressure
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max)
    }
    /// Minimum stretch.
    ///
    /// ```
    /// use celltissue::line::static_solve::static_equilibrium;
    /// use celltissue::line::{discrete, LineParams};
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(10))?;
    /// let s = static_equilibrium(&line, 9.0)?; // uniform line held 10 % short
    /// assert!((s.min_stretch() - 0.9).abs() < 1e-12);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn min_stretch(&self) -> f64 {
        self.lambda.iter().copied().fold(f64::INFINITY, f64::min)
    }
}

/// Static equilibrium of `line` (elastic cells, no growth or active stress) held at length `l`:
/// one axial stress `S` with `μ_jσ_el(λ_j) = S + p_e,j` in every cell (`p_e` its external
/// pressure).
///
/// ```
/// use celltissue::line::build::{LineParams, discrete};
/// use celltissue::line::static_solve::static_equilibrium;
/// use celltissue::NeoHookean;
/// let line = discrete(NeoHookean::new(1.0).unwrap(), &LineParams::unit_cells(100)).unwrap();
/// let s = static_equilibrium(&line, 90.0).unwrap();
/// assert!((s.stress + 0.424568).abs() < 1e-6);          // docs/model.md §5.2 uniform
/// assert!((s.max_pressure() - 1.234568).abs() < 1e-6);
/// ```
pub fn static_equilibrium<E: StrainEnergy>(
    line: &Line<E>,
    l: f64,
) -> Result<StaticSolution, LineError> {
    static_equilibrium_from(line, l, None)
}

/// [`static_equilibrium`] started from `near`, the same line's equilibrium at a nearby length
/// (its stress and stretches; ignored unless it has one stretch per cell): the overlays of a
/// run solve one equilibrium per output time.
pub(crate) fn static_equilibrium_from<E: StrainEnergy>(
    line: &Line<E>,
    l: f64,
    near: Option<&StaticSolution>,
) -> Result<StaticSolution, LineError> {
    if !(l > 0.0 && l.is_finite()) {
        return Err(LineError::invalid("length", l, "finite and > 0"));
    }
    let c = &line.cells;
    let n = c.len();
    // cells with the same μ and external pressure carry the same stretch: the runs of such
    // cells, with the reference length of each, are inverted once per run (measured: at 10⁶
    // uniform cells, one law inversion per cell per iteration was 44 s of a 50 s run, against a
    // 6 s solve)
    let new_run = |i: usize| {
        i == 0
            || c.mu[i].to_bits() != c.mu[i - 1].to_bits()
            || c.p_ext[i].to_bits() != c.p_ext[i - 1].to_bits()
    };
    let mut runs: Vec<Run> = Vec::new();
    for (i, &l0) in c.l0.iter().enumerate() {
        match runs.last_mut() {
            Some(run) if !new_run(i) => run.l0 += l0,
            _ => runs.push(Run {
                mu: c.mu[i],
                p_ext: c.p_ext[i],
                l0,
            }),
        }
    }
    // each run's stretch at the last iterate: the next inversion starts from it (the first
    // from `near`'s, taken at each run's first cell)
    let near = near.filter(|s| s.lambda.len() == n && s.stress.is_finite());
    let mut lam = match near {
        Some(s) => {
            let mut v = Vec::with_capacity(runs.len());
            for (i, &l) in s.lambda.iter().enumerate() {
                if new_run(i) {
                    v.push(l);
                }
            }
            v
        }
        None => vec![1.0; runs.len()],
    };
    // Σ L₀λ(S) − l and its slope Σ L₀/(μσ′(λ)), from the stretches at the last iterate
    // (the registry's law picked once per sweep, not at every evaluation)
    let excess = |s: f64, lam: &mut [f64]| {
        line.with_law(Excess {
            runs: &runs,
            lam,
            s,
            l,
        })
    };
    // Newton on S, safeguarded by the bracket the iterates' signs give (Σ L₀λ(S) increases
    // with S): a step that leaves it bisects it, or doubles away from its one known end.
    // From S = 0 a Gaussian-μ line (every cell its own μ) takes 5 iterates and about 16 law
    // evaluations per cell in all; regula falsi with each inversion from λ = 1 took 209 (at
    // 10⁶ cells 2.9 s against 0.23 s on one thread; `examples/static_equilibrium_large.rs`, pinned in
    // `the_static_equilibrium_costs_a_few_law_evaluations_per_cell`)
    let (mut a, mut b) = (f64::NEG_INFINITY, f64::INFINITY);
    let mut s = near.map_or(0.0, |s| s.stress);
    let mut converged = false;
    for _ in 0..MAX_STRESS_ITERS {
        let (e, slope) = excess(s, &mut lam)?;
        if e.abs() <= 1e-14 * l {
            converged = true;
            break;
        }
        if e < 0.0 {
            a = s;
        } else {
            b = s;
        }
        if (b - a).abs() <= 1e-16 * (1.0 + s.abs()) {
            converged = true;
            break;
        }
        let newton = s - e / slope;
        s = if newton > a && newton < b && newton.is_finite() {
            newton
        } else if a.is_finite() && b.is_finite() {
            0.5 * (a + b)
        } else if a.is_finite() {
            a + a.abs().max(1.0)
        } else {
            b - b.abs().max(1.0)
        };
    }
    if !converged {
        return Err(LineError::Combination(format!(
            "no static equilibrium: the common stress did not converge in {MAX_STRESS_ITERS} \
             iterations (last {s:e}, bracket [{a:e}, {b:e}])"
        )));
    }
    // each cell takes its run's stretch (runs break where μ or p_e changes, as built above)
    let mut lambda = Vec::with_capacity(n);
    let mut r = 0;
    for i in 0..n {
        if i > 0 && new_run(i) {
            r += 1;
        }
        lambda.push(lam[r]);
    }
    let pressure = (0..n)
        .map(|i| c.mu[i] * line.energy.line(lambda[i]).pressure + c.p_ext[i])
        .collect();
    let mut x = Vec::with_capacity(n + 1);
    x.push(0.0);
    let mut acc = 0.0;
    for (l0, l) in c.l0.iter().zip(&lambda) {
        acc += l0 * l;
        x.push(acc);
    }
    Ok(StaticSolution {
        stress: s,
        lambda,
        pressure,
        x,
    })
}

/// Newton solve of the static problem `F(t, y, 0) = 0` for a line without growth, from the
/// guess `y` (e.g. [`Line::initial_state`]); damped so every iterate keeps all cells positive.
/// Returns the converged unknowns: `max |F| ≤ tol`, or `max |F|` at its round-off floor
/// (`8ε·max_i Σ_j |∂F_i/∂y_j|·|y_j|`, above a tight `tol` on fine continuum grids), or a Newton
/// step at round-off level.
///
/// ```
/// use celltissue::boundary::{Ramp, RightEnd};
/// use celltissue::line::build::{discrete, LineParams};
/// use celltissue::line::static_solve::static_newton;
/// use celltissue::NeoHookean;
/// let mut p = LineParams::unit_cells(10);
/// p.right = RightEnd::Prescribed(Ramp::Constant(9.0));
/// let line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
/// let x = static_newton(&line, 0.0, None, 1e-12).unwrap();
/// assert!((x[0] - 0.9).abs() < 1e-10); // x₁ of the uniformly compressed line
/// ```
pub fn static_newton<E: StrainEnergy>(
    line: &Line<E>,
    t: f64,
    guess: Option<&[f64]>,
    tol: f64,
) -> Result<Vec<f64>, LineError> {
    if line.is_growing() {
        return Err(LineError::Combination(
            "static_newton: growing lines have no static state".into(),
        ));
    }
    let (lower, upper) = match line.pattern() {
        Pattern::Banded { lower, upper } => (lower, upper),
        _ => {
            return Err(LineError::Combination(
                "static_newton: ring (periodic) lines have a translation null mode; use static_equilibrium".into(),
            ))
        }
    };
    let mut y = match guess {
        Some(g) => g.to_vec(),
        None => {
            let y0 = line.initial_state();
            let z0 = vec![0.0; y0.len()];
            let nc = line.n_cells();
            let end = line.boundary(nc, t, &y0, &z0).0;
            let scale = if line.right.is_free() {
                1.0
            } else {
                end / line.l0_total
            };
            y0.iter().map(|v| v * scale).collect()
        }
    };
    let n = y.len();
    let zero = vec![0.0; n];
    let mut r = vec![0.0; n];
    let res =
        |y: &[f64], r: &mut [f64]| -> Result<(), ResidualError> { line.residual(t, y, &zero, r) };
    let to_err = |e: ResidualError| LineError::Combination(format!("static_newton: {e:?}"));
    res(&y, &mut r).map_err(to_err)?;
    let w = lower + upper + 1;
    let zd = vec![Dual64::new(0.0, 0.0); n];
    let mut yd = vec![Dual64::new(0.0, 0.0); n];
    let mut rd = vec![Dual64::new(0.0, 0.0); n];
    for _iter in 0..100 {
        let norm = r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if norm <= tol {
            return Ok(y);
        }
        // banded Jacobian by colouring: band[(i, j)] stored at i*(lower+upper+1) + (j + lower - i)
        let mut band = vec![0.0; n * w];
        let mut floor = 0.0f64;
        for colour in 0..w.min(n) {
            for j in 0..n {
                yd[j] = Dual64::new(y[j], if j % w == colour { 1.0 } else { 0.0 });
            }
            line.residual(t, &yd, &zd, &mut rd).map_err(to_err)?;
            for j in (colour..n).step_by(w) {
                for i in j.saturating_sub(upper)..(j + lower + 1).min(n) {
                    band[i * w + (j + lower - i)] = rd[i].eps;
                }
            }
        }
        // Round-off floor of the residual: row i is a difference of stresses of cells whose
        // lengths are differences of positions, so evaluating it at `y` carries an error of
        // about ε·Σ_j |J_ij|·|y_j| (e.g. 4e-12 for 2000 segments of length 0.05 at x ≈ 90).
        // Stop there if `tol` is below it: the Jacobian's O(n²) condition number turns
        // round-off residuals into Newton steps far above ε·|y|, so the step test below never
        // fires (the continuum grid with n = 2000 did not converge in 100 iterations).
        for i in 0..n {
            let lo = i.saturating_sub(lower);
            let hi = (i + upper + 1).min(n);
            let row: f64 = (lo..hi)
                .map(|j| (band[i * w + (j + lower - i)] * y[j]).abs())
                .sum();
            floor = floor.max(row);
        }
        let floor = 8.0 * f64::EPSILON * floor;
        let mut dy: Vec<f64> = r.iter().map(|v| -v).collect();
        band_solve(&mut band, n, lower, upper, &mut dy).ok_or_else(|| {
            LineError::Combination("static_newton: singular static Jacobian".into())
        })?;
        if norm <= floor {
            // at the floor: one last full step (it still removes the smooth error modes the
            // floor hides), kept only if it does not leave the floor
            let trial: Vec<f64> = y.iter().zip(&dy).map(|(a, b)| a + b).collect();
            let mut rt = vec![0.0; n];
            let ok = res(&trial, &mut rt).is_ok();
            let nt = rt.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            return Ok(if ok && nt <= floor { trial } else { y });
        }
        // converged to round-off: the Newton step is below the positions' resolution
        let ymax = y.iter().fold(1.0f64, |m, v| m.max(v.abs()));
        if dy.iter().all(|d| d.abs() <= 4.0 * f64::EPSILON * ymax) {
            return Ok(y);
        }
        // damping: keep residual evaluable and decreasing
        let mut step = 1.0;
        loop {
            let trial: Vec<f64> = y.iter().zip(&dy).map(|(a, b)| a + step * b).collect();
            let mut rt = vec![0.0; n];
            let ok = res(&trial, &mut rt).is_ok();
            let nt = rt.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            if ok && (nt < norm || step < 1e-3) {
                y = trial;
                r = rt;
                break;
            }
            step *= 0.5;
            if step < 1e-10 {
                return Err(LineError::Combination(
                    "static_newton: line search failed (cells would invert)".into(),
                ));
            }
        }
    }
    Err(LineError::Combination(
        "static_newton: no convergence in 100 iterations".into(),
    ))
}

/// Gaussian elimination without pivoting on a band matrix (row-major band storage, fill-free
/// because no rows are swapped). Returns `None` on a zero pivot.
fn band_solve(a: &mut [f64], n: usize, lower: usize, upper: usize, b: &mut [f64]) -> Option<()> {
    let w = lower + upper + 1;
    let idx = |i: usize, j: usize| i * w + (j + lower - i);
    for k in 0..n {
        let piv = a[idx(k, k)];
        if piv == 0.0 || !piv.is_finite() {
            return None;
        }
        for i in k + 1..(k + lower + 1).min(n) {
            let f = a[idx(i, k)] / piv;
            if f == 0.0 {
                continue;
            }
            for j in k..(k + upper + 1).min(n) {
                a[idx(i, j)] -= f * a[idx(k, j)];
            }
            b[i] -= f * b[k];
        }
    }
    for k in (0..n).rev() {
        let mut s = b[k];
        for j in k + 1..(k + upper + 1).min(n) {
            s -= a[idx(k, j)] * b[j];
        }
        b[k] = s / a[idx(k, k)];
    }
    Some(())
}
