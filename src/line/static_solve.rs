//! Static equilibrium of a line with fixed or prescribed ends (docs/model.md §5.2).
//!
//! * [`static_equilibrium`] — at rest every cell carries the same stress `S`
//!   (`μ_j σ_el(λ_j) = S`) and the stretches add up to the length (`Σ L₀,j λ_j = l`). Each cell is
//!   inverted for `λ_j(S)` (closed form for neo-Hookean: [`neo_hookean_stretch`]; safeguarded
//!   Newton for any other law: [`invert_stretch`]), and `S` is found by a bracketing solve, since
//!   `Σ L₀λ(S)` increases with `S`. O(N) per iteration.
//! * [`static_newton`] — Newton on the static residual `F(t, y, ẏ = 0) = 0` of any line without
//!   growth, with the banded Jacobian from AD and a banded LU (active stress at a frozen time,
//!   width rules, …).

use super::array::Line;
use super::LineError;
use crate::array::CellArray;
use crate::energy::StrainEnergy;
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
    let inside = |l: f64| energy.admissible([l, 1.0 / l, 1.0]).is_ok();
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
    /// Cell pressures `μ_j p_el(λ_j)`.
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

/// Static equilibrium of `line` (elastic cells, no growth or active stress) held at length `l`.
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
    if !(l > 0.0 && l.is_finite()) {
        return Err(LineError::invalid("length", l, "finite and > 0"));
    }
    let c = &line.cells;
    let n = c.len();
    // cells with the same μ carry the same stretch: the runs of bitwise equal μ, with the
    // reference length of each, are inverted once per run (measured: at 10⁶ uniform cells,
    // one law inversion per cell per iteration was 44 s of a 50 s run, against a 6 s solve)
    let mut runs: Vec<(f64, f64)> = Vec::new();
    for (&mu, &l0) in c.mu.iter().zip(&c.l0) {
        match runs.last_mut() {
            Some((m, sum)) if m.to_bits() == mu.to_bits() => *sum += l0,
            _ => runs.push((mu, l0)),
        }
    }
    let stretches = |s: f64| -> Result<Vec<f64>, LineError> {
        let mut lam = Vec::with_capacity(n);
        let mut last: Option<(u64, f64)> = None;
        for &mu in &c.mu {
            let l = match last {
                Some((bits, l)) if bits == mu.to_bits() => l,
                _ => invert_stretch(&line.energy, mu, s)?,
            };
            last = Some((mu.to_bits(), l));
            lam.push(l);
        }
        Ok(lam)
    };
    let excess = |s: f64| -> Result<f64, LineError> {
        let mut sum = 0.0;
        for &(mu, l0) in &runs {
            sum += invert_stretch(&line.energy, mu, s)? * l0;
        }
        Ok(sum - l)
    };
    // bracket S
    let (mut a, mut b) = (-1.0, 1.0);
    let (mut fa, mut fb) = (excess(a)?, excess(b)?);
    let mut k = 0;
    while fa > 0.0 {
        a *= 2.0;
        fa = excess(a)?;
        k += 1;
        if k > 200 {
            return Err(LineError::Combination(
                "no static equilibrium bracket".into(),
            ));
        }
    }
    while fb < 0.0 {
        b *= 2.0;
        fb = excess(b)?;
        k += 1;
        if k > 400 {
            return Err(LineError::Combination(
                "no static equilibrium bracket".into(),
            ));
        }
    }
    // Illinois regula falsi
    let mut side = 0;
    let mut s = 0.5 * (a + b);
    for _ in 0..300 {
        s = (a * fb - b * fa) / (fb - fa);
        let fs = excess(s)?;
        if fs.abs() <= 1e-14 * l || (b - a).abs() <= 1e-16 * (1.0 + s.abs()) {
            break;
        }
        if fs * fb > 0.0 {
            b = s;
            fb = fs;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        } else {
            a = s;
            fa = fs;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        }
    }
    let lambda = stretches(s)?;
    let pressure = (0..n)
        .map(|i| c.mu[i] * line.energy.line(lambda[i]).pressure)
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
