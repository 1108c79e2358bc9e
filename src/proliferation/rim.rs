//! The travelling proliferating rim: how fast a free end under strong drag advances and adds
//! cells at long times, from a continuum in the **cell-number** coordinate (docs/model.md §8.4,
//! "The travelling rim in the cell-number coordinate").
//!
//! Under strong drag only the cells within a few stress decay lengths of the free end grow; the
//! rim they form advances at a constant speed `V` and the line lengthens linearly. Counted in
//! cells from the tip (depth `u`), the rim is steady: with `v(u)` the velocity of the boundary at
//! depth `u` and `α(u)` the cells' elastic stretch,
//!
//! ```text
//!   dσ/du = −K v α / w,                    (drag: one boundary per cell, width w/α)
//!   dv/du = −α G(σ) − (V − v) α_u / α,     (growth, and compression as cells sink)
//!   v(0) = V,   σ(0) = −K α V / (2w),      (the tip boundary's own drag: half a cell)
//!   v → 0 as u → ∞,
//! ```
//!
//! with `w = γ₀g₂` and `σ = σ_el(α)`. Only one `V` lets `v` decay to zero: slower and `v`
//! crosses zero, faster and `v` turns back up. [`travelling_rim`] finds it by bisection, each
//! trial an explicit integration in `u` ([`integrators`]' Dormand–Prince with two events).
//!
//! The model needs no closure for the cells' growth phases: the mean phase and the division
//! rate enter only through `v = V − α·(mean g)·(divisions ahead per unit time)`, and that
//! product is eliminated.
//!
//! It assumes what the derivation uses, and nothing checks it for you:
//! * `m = 0`: with `m ≠ 0` the drag depends on each cell's phase;
//! * the area rule with ratio 2 on cells of unit reference length, so every daughter again has
//!   `L₀ = 1` (other rules spread `L₀` and the growth of length per cell depends on it);
//! * elastic cells (`η = 0`; cells sinking into the compressed bulk have `α̇ ≠ 0`), no active
//!   stress and no force on the free end.
//!
//! Its error against the discrete line is second order in the per-cell stress drop at the tip
//! relative to the growth law's stress scale, [`RimSpeed::epsilon`]: +2.7 % at ε = 0.64
//! (K = 0.1), +31 % at ε = 4 (K = 100) for unit cells and the tanh law with σ₀ = 0.1. The rim is
//! found from K ≈ 3e-8 (below, its profile reaches over 10⁶ cells and [`RimError::NoRim`] says
//! the drag is too small) up to at least K = 1e8.
//!
//! The cell count does depend on the phases: `dN/dt` times the mean growth stretch of the cells
//! left behind is `∫G du`, and that mean is set by the phases at which cells stop growing. So
//! [`RimSpeed::cell_rate`] runs the phases cell by cell through the profile's growth rates: the
//! cell at depth `j` grows at `G(σ(j − ½))`, and the first to reach `g = 2` splits into two
//! cells of `g = 1` at depths `j` and `j + 1`, pushing every deeper cell one place in. Between
//! divisions the rates are constant, so this automaton jumps from one division to the next; it
//! skips 1 000 divisions and times the next 1 000, recording the depth of each
//! ([`RimSpeed::division_depths`]). It keeps the cells down to the rim's end,
//! where `v` has fallen to its least (the depth where the bisection's last fast trial turned
//! back up), or down to where `G` falls to 10⁻⁴ of `G(0)` if that comes first.

use crate::cell::GrowthLaw;
use crate::energy::StrainEnergy;
use integrators::{ErrorKind, MethodKind, Options, Problem, ResidualError, Solver};
use thiserror::Error;

/// A travelling-rim computation that cannot be done, with the parameter and its valid range.
///
/// ```
/// use celltissue::proliferation::{travelling_rim, RimError};
/// use celltissue::cell::TanhGrowth;
/// let err = travelling_rim(&celltissue::NeoHookean::new(1.0)?, &TanhGrowth::default(), 0.0, 1.0);
/// assert!(matches!(err, Err(RimError::Parameter { key: "K", .. })));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Error)]
pub enum RimError {
    /// A parameter outside its valid range.
    #[error("{key} = {value}: must be {range}")]
    Parameter {
        /// The parameter's name.
        key: &'static str,
        /// The value given.
        value: f64,
        /// The valid range.
        range: &'static str,
    },
    /// No speed separates "v crosses zero" from "v turns back up" within the bracket.
    #[error("no travelling rim: {0}")]
    NoRim(String),
    /// The integration in `u` failed.
    #[error("integrating the rim profile at V = {speed:e}: {source}")]
    Solve {
        /// The trial speed.
        speed: f64,
        /// The solver's failure.
        source: integrators::SolveFailure,
    },
}

/// The travelling rim (see the [module docs](self)).
///
/// ```
/// use celltissue::proliferation::travelling_rim;
/// use celltissue::cell::TanhGrowth;
/// let rim = travelling_rim(&celltissue::NeoHookean::new(1.0)?, &TanhGrowth::default(), 1e-2, 1.0)?;
/// // leading order, rigid cells: V² = (2w/K)∫G dσ = σ₀ ln 2 / K
/// let leading = (0.1 * 2f64.ln() / 1e-2).sqrt();
/// assert!(rim.speed < leading && rim.speed > 0.85 * leading);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct RimSpeed {
    /// Speed of the free end, `dl/dt` at long times.
    pub speed: f64,
    /// Stress at the tip boundary, `σ(0) = −KαV/(2w)`.
    pub tip_stress: f64,
    /// Depth in cells where the growth rate falls to 1 % of its unstressed value.
    pub width: f64,
    /// Cells the rim adds per unit time: the cells' phases run exactly, cell by cell, through
    /// the profile's growth rates (see the [module docs](self)). This is `dN/dt` at long times
    /// as long as the compressed cells behind the rim no longer divide. Soft cells still do, in
    /// proportion to their number: docs/model.md §8.4.
    pub cell_rate: f64,
    /// Where the rim's cells divide: `(depth, fraction)` pairs, the depth counted in cells from
    /// the tip (1 = the tip cell) and the fraction of the automaton's counted divisions there,
    /// by increasing depth.
    pub division_depths: Vec<(usize, f64)>,
    /// Per-cell stress drop at the tip over the growth law's stress scale `G(0)/G'(0)`:
    /// `ε = KαV/(w·G(0)/G'(0))`. The continuum holds for `ε ≪ 1`; its error is `O(ε²)`.
    pub epsilon: f64,
}

/// The rim's inputs: the cells' law, their growth law, the drag `K` and the width `w = γ₀g₂`.
struct Setup<'a, E: StrainEnergy> {
    energy: &'a E,
    growth: &'a dyn GrowthLaw,
    k: f64,
    width: f64,
}

// (references and numbers: copyable whatever `E` is, which `derive` would require)
impl<E: StrainEnergy> Clone for Setup<'_, E> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<E: StrainEnergy> Copy for Setup<'_, E> {}

/// What an integration in `u` stops at.
#[derive(Clone, Copy)]
enum Watch {
    /// `v` reaches zero (event 0: too slow) or `dv/du` turns positive (event 1: too fast).
    Separation,
    /// `G(σ)` falls to this rate.
    GrowthBelow(f64),
    /// Nothing: the integration runs to the last depth asked for.
    Nothing,
}

/// The rim profile as an explicit ODE in the depth `u`, state `(v, α)`, for a trial speed.
struct Profile<'a, E: StrainEnergy> {
    setup: Setup<'a, E>,
    speed: f64,
    watch: Watch,
}

impl<E: StrainEnergy> Profile<'_, E> {
    /// `(dv/du, dα/du)` at `(v, α)`.
    fn slope(&self, v: f64, a: f64) -> (f64, f64) {
        let Setup {
            energy,
            growth,
            k,
            width,
        } = self.setup;
        let r = energy.line(a);
        let ds = -k * v * a / width;
        let da = ds / r.dsigma;
        let dv = -a * growth.rate(r.sigma).0 - (self.speed - v) * da / a;
        (dv, da)
    }
}

impl<E: StrainEnergy> Problem for Profile<'_, E> {
    fn dim(&self) -> usize {
        2
    }
    fn residual(
        &mut self,
        _u: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        if y[1].is_nan() || y[1] <= 0.0 {
            return Err(ResidualError::Recoverable {
                reason: format!("elastic stretch {} is not positive", y[1]),
                component: Some(1),
            });
        }
        let (dv, da) = self.slope(y[0], y[1]);
        r[0] = yp[0] - dv;
        r[1] = yp[1] - da;
        Ok(())
    }
    fn num_events(&self) -> usize {
        match self.watch {
            Watch::Separation => 2,
            Watch::GrowthBelow(_) => 1,
            Watch::Nothing => 0,
        }
    }
    fn events(&mut self, _u: f64, y: &[f64], g: &mut [f64]) {
        match self.watch {
            Watch::Separation => {
                g[0] = y[0];
                g[1] = if y[1] > 0.0 {
                    self.slope(y[0], y[1]).0
                } else {
                    1.0
                };
            }
            Watch::GrowthBelow(rate) => {
                let s = self.setup;
                g[0] = s.growth.rate(s.energy.line(y[1]).sigma).0 - rate;
            }
            Watch::Nothing => {}
        }
    }
}

impl<'a, E: StrainEnergy> Setup<'a, E> {
    /// The tip cell's elastic stretch at speed `speed`: `σ_el(α) + cα = 0` with
    /// `c = KV/(2w)`, by Newton from `α = 1`.
    fn tip_stretch(&self, speed: f64) -> Result<f64, RimError> {
        let c = self.k * speed / (2.0 * self.width);
        let mut a = 1.0f64;
        for _ in 0..100 {
            let r = self.energy.line(a);
            let step = (r.sigma + c * a) / (r.dsigma + c);
            a = (a - step).max(0.5 * a);
            if step.abs() < 1e-15 * a {
                return Ok(a);
            }
        }
        Err(RimError::NoRim(format!(
            "no elastic stretch balances the tip drag (σ_el(α) = −{c}·α)"
        )))
    }

    /// Integrates the profile of speed `speed` from the tip, with output at `depths` (the
    /// first is 0) and stopping at what `watch` names.
    fn integrate(
        &self,
        speed: f64,
        watch: Watch,
        depths: &[f64],
    ) -> Result<integrators::Solution, RimError> {
        let a0 = self.tip_stretch(speed)?;
        let mut profile = Profile {
            setup: *self,
            speed,
            watch,
        };
        match Solver::new(MethodKind::Dopri, profile_options(speed)).solve(
            &mut profile,
            0.0,
            &[speed, a0],
            depths,
        ) {
            Ok(sol) => Ok(sol),
            Err(source) if matches!(source.error.kind, ErrorKind::TooManySteps(_)) => {
                Err(RimError::NoRim(format!(
                    "at V = {speed:e} the profile was followed {:.1e} cells deep without \
                     reaching its end ({source}): the drag K = {:e} is too small for the rim to \
                     be followed cell by cell (for unit cells and the tanh law with σ₀ = 0.1, \
                     below about K = 3e-8); there the rim is in its continuum limit, \
                     V² ≈ σ₀ w ln 2 / K for the tanh law",
                    source.error.t, self.k
                )))
            }
            Err(source) => Err(RimError::Solve { speed, source }),
        }
    }

    /// `(σ, v)` at `depths` (checked by the caller: ≥ 0, strictly ascending) on the profile of
    /// speed `speed`.
    fn profile(&self, speed: f64, depths: &[f64]) -> Result<Vec<(f64, f64)>, RimError> {
        let mut times = Vec::with_capacity(depths.len() + 1);
        times.push(0.0);
        times.extend(depths.iter().copied().filter(|&d| d > 0.0));
        let sol = self.integrate(speed, Watch::Nothing, &times)?;
        let mut out = Vec::with_capacity(depths.len());
        let mut next = 0;
        for &d in depths {
            if d > 0.0 {
                next += 1;
            }
            let y = &sol.y[next];
            out.push((self.energy.line(y[1]).sigma, y[0]));
        }
        Ok(out)
    }

    /// How deep a search integrates, in units of `w/(KV)` cells: the stress decays over
    /// `scale` of them, and a trial near the separating speed departs from it at a rate of
    /// order `1/(dσ_el/dα at α = 1)` of them, slowly for stiff cells.
    fn search_depth(&self, speed: f64) -> f64 {
        let stiffness = self.energy.line(1.0).dsigma.abs();
        (1e3 * (1.0 + 10.0 * stress_scale(self.growth)) + 100.0 * stiffness) * self.width
            / (self.k * speed)
    }
}

/// What one trial speed does: `v` reaches zero, or turns back up (at depth `turn`, where `v`
/// is least: near the separating speed, the end of the rim).
enum Trial {
    TooSlow,
    TooFast { turn: f64 },
}

/// Integrates the profile for trial speed `speed` until it separates.
fn trial<E: StrainEnergy>(setup: &Setup<'_, E>, speed: f64) -> Result<Trial, RimError> {
    let depth = setup.search_depth(speed);
    let sol = setup.integrate(speed, Watch::Separation, &[0.0, depth])?;
    match sol.events.first() {
        Some(e) if e.fired.contains(&0) => Ok(Trial::TooSlow),
        Some(e) => Ok(Trial::TooFast { turn: e.t }),
        None => Err(RimError::NoRim(format!(
            "at V = {speed}, v neither vanished nor turned back within {depth:e} cells"
        ))),
    }
}

/// Tolerances of every integration in `u`.
fn profile_options(speed: f64) -> Options {
    Options {
        rtol: 1e-10,
        atol: 1e-12 * speed.max(1.0),
        ..Options::default()
    }
}

/// The growth law's stress scale `G(0)/G'(0)` (`σ₀` for [`crate::cell::TanhGrowth`]).
fn stress_scale(growth: &dyn GrowthLaw) -> f64 {
    let (g, dg) = growth.rate(0.0);
    g / dg
}

/// The travelling rim of a free end with drag `k` (`K`, with `m = 0`) and cell width
/// `width = γ₀g₂`, for cells of `energy` growing by `growth` (see the [module docs](self)).
///
/// The growth law must grow unstressed cells (`G(0) > 0`) and slow down under compression
/// (`G'(0) > 0`). The line must be what the [module docs](self) assume: `m = 0`, the area rule
/// with ratio 2 on unit cells, `η = 0`, no active stress, no end force.
///
/// ```
/// use celltissue::proliferation::travelling_rim;
/// use celltissue::cell::TanhGrowth;
/// let rim = travelling_rim(&celltissue::NeoHookean::new(1.0)?, &TanhGrowth::default(), 1e-1, 1.0)?;
/// assert!(rim.epsilon > 0.5); // a rim about one cell wide: far from the continuum limit
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn travelling_rim<E: StrainEnergy>(
    energy: &E,
    growth: &dyn GrowthLaw,
    k: f64,
    width: f64,
) -> Result<RimSpeed, RimError> {
    if !(k > 0.0 && k.is_finite()) {
        return Err(RimError::Parameter {
            key: "K",
            value: k,
            range: "finite and > 0",
        });
    }
    if !(width > 0.0 && width.is_finite()) {
        return Err(RimError::Parameter {
            key: "width",
            value: width,
            range: "finite and > 0",
        });
    }
    let (g0, dg0) = growth.rate(0.0);
    if !(g0 > 0.0 && dg0 > 0.0 && g0.is_finite() && dg0.is_finite()) {
        return Err(RimError::NoRim(format!(
            "the growth law must grow unstressed cells and slow under compression \
             (G(0) = {g0}, G'(0) = {dg0})"
        )));
    }
    let setup = Setup {
        energy,
        growth,
        k,
        width,
    };
    // bracket: a slow trial (halved until it is slow: at large drags the speed falls below
    // the estimate's thousandth, V ≈ 4e-3 at K = 100), then double until too fast
    let mut lo = 1e-3 * (g0 * stress_scale(growth) * width / k).sqrt();
    let mut halvings = 0;
    while matches!(trial(&setup, lo)?, Trial::TooFast { .. }) {
        halvings += 1;
        if halvings > 200 {
            return Err(RimError::NoRim(format!(
                "every speed down to V = {lo:e} is too fast: no slow branch"
            )));
        }
        lo *= 0.5;
    }
    let mut rim_end = None;
    let mut hi = lo;
    for _ in 0..80 {
        hi *= 2.0;
        match trial(&setup, hi)? {
            Trial::TooSlow => lo = hi,
            Trial::TooFast { turn } => {
                rim_end = Some(turn);
                break;
            }
        }
    }
    let mut rim_end = rim_end.ok_or_else(|| RimError::NoRim("no speed is fast enough".into()))?;
    while hi - lo > 1e-10 * hi {
        let mid = 0.5 * (lo + hi);
        match trial(&setup, mid)? {
            Trial::TooSlow => lo = mid,
            Trial::TooFast { turn } => (hi, rim_end) = (mid, turn),
        }
    }
    let speed = hi;
    let a0 = setup.tip_stretch(speed)?;
    let (cell_rate, division_depths) = phase_automaton(&setup, speed, rim_end)?;
    Ok(RimSpeed {
        speed,
        tip_stress: energy.line(a0).sigma,
        width: growth_depth(&setup, speed, 1e-2)?,
        cell_rate,
        division_depths,
        epsilon: k * a0 * speed / (width * stress_scale(growth)),
    })
}

/// Depth at which `G(σ)` falls to `fraction` of `G(0)` along the profile of speed `speed`.
fn growth_depth<E: StrainEnergy>(
    setup: &Setup<'_, E>,
    speed: f64,
    fraction: f64,
) -> Result<f64, RimError> {
    let rate = fraction * setup.growth.rate(0.0).0;
    let tip_stress = setup.energy.line(setup.tip_stretch(speed)?).sigma;
    if setup.growth.rate(tip_stress).0 <= rate {
        // compressed at the tip already below the fraction (K ≥ 1e3 for unit cells and the
        // thesis's law): the growth zone is narrower than the tip itself
        return Ok(0.0);
    }
    let depth = setup.search_depth(speed);
    let sol = setup.integrate(speed, Watch::GrowthBelow(rate), &[0.0, depth])?;
    sol.events.first().map(|e| e.t).ok_or_else(|| {
        RimError::NoRim(format!(
            "growth never falls to {fraction:e} of its unstressed rate"
        ))
    })
}

/// The rim's stress and boundary velocity `(σ, v)` at the given depths (in cells from the tip,
/// strictly ascending, ≥ 0) for the speed `speed` found by [`travelling_rim`] with the same arguments.
/// Depth `j − ½` is the `j`-th cell's centre counted from the tip.
///
/// ```
/// use celltissue::proliferation::{rim_profile, travelling_rim};
/// use celltissue::cell::TanhGrowth;
/// let (e, g) = (celltissue::NeoHookean::new(1.0)?, TanhGrowth::default());
/// let rim = travelling_rim(&e, &g, 1e-2, 1.0)?;
/// let p = rim_profile(&e, &g, 1e-2, 1.0, rim.speed, &[0.0, 0.5, 10.0])?;
/// assert!((p[0].0 - rim.tip_stress).abs() < 1e-12 && p[0].1 == rim.speed);
/// assert!(p[2].0 < p[1].0 && p[2].1 < p[1].1); // compressed and slower inside
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn rim_profile<E: StrainEnergy>(
    energy: &E,
    growth: &dyn GrowthLaw,
    k: f64,
    width: f64,
    speed: f64,
    depths: &[f64],
) -> Result<Vec<(f64, f64)>, RimError> {
    if let Some(bad) = depths.iter().find(|d| !(d.is_finite() && **d >= 0.0)) {
        return Err(RimError::Parameter {
            key: "depths",
            value: *bad,
            range: "finite and >= 0",
        });
    }
    if let Some(w) = depths.windows(2).find(|w| w[1] <= w[0]) {
        return Err(RimError::Parameter {
            key: "depths",
            value: w[1],
            range: "strictly ascending",
        });
    }
    let setup = Setup {
        energy,
        growth,
        k,
        width,
    };
    setup.profile(speed, depths)
}

/// Divisions at the start of the phase automaton that are not counted (its transient), and
/// divisions it counts.
const AUTOMATON_DIVISIONS: (usize, usize) = (1000, 1000);

/// What the phase automaton measures: `dN/dt`, and where the counted divisions happen (as
/// [`RimSpeed::division_depths`]).
type Divisions = (f64, Vec<(usize, f64)>);

/// Runs the phase automaton of the [module docs](self) on the rim of speed `speed`.
fn phase_automaton<E: StrainEnergy>(
    setup: &Setup<'_, E>,
    speed: f64,
    rim_end: f64,
) -> Result<Divisions, RimError> {
    // cells growing at under 10⁻⁴ of G(0) do not divide within the automaton's time
    let slow = growth_depth(setup, speed, 1e-4).unwrap_or(f64::INFINITY);
    // the tip cell grows however slowly (at K ≥ 1e6 for unit cells, below 10⁻⁴ of G(0))
    let depths: Vec<f64> = (1..=rim_end.min(slow).ceil().max(1.0) as usize)
        .map(|j| j as f64 - 0.5)
        .collect();
    let rates: Vec<f64> = setup
        .profile(speed, &depths)?
        .iter()
        .map(|&(sigma, _)| setup.growth.rate(sigma).0)
        .collect();
    let (skip, count) = AUTOMATON_DIVISIONS;
    let mut g = vec![1.0; rates.len()];
    let (mut t, mut start) = (0.0, 0.0);
    let mut at_depth = vec![0usize; rates.len()];
    for division in 0..skip + count {
        if division == skip {
            start = t;
        }
        let (cell, wait) = g
            .iter()
            .zip(&rates)
            .enumerate()
            .filter(|(_, (_, &r))| r > 0.0)
            .map(|(i, (&gi, &r))| (i, (2.0 - gi) / r))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .ok_or_else(|| RimError::NoRim("no cell in the rim grows".into()))?;
        for (gi, r) in g.iter_mut().zip(&rates) {
            *gi += r * wait;
        }
        g[cell] = 1.0;
        g.insert(cell + 1, 1.0);
        g.truncate(rates.len());
        t += wait;
        if division >= skip {
            at_depth[cell] += 1;
        }
    }
    let depths = at_depth
        .iter()
        .enumerate()
        .filter(|(_, &n)| n > 0)
        .map(|(i, &n)| (i + 1, n as f64 / count as f64))
        .collect();
    Ok((count as f64 / (t - start), depths))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cell::TanhGrowth;
    use crate::NeoHookean;

    /// Stiff cells (α → 1) under weak drag (ε → 0): the closed form V² = σ₀ w ln 2 / K of the
    /// rigid rim with σ(0) = 0, corrected for the tip's half-cell of drag. That shifts the upper
    /// limit of `∫G dσ` by `−εσ₀/2`, so V²/V₀² = 1 − G(0)εσ₀/(σ₀ ln 2) and V/V₀ − 1 = −ε/(4 ln 2)
    /// at first order. Measured: −0.376ε, −0.383ε, −0.365ε against −0.361ε; the rest is the
    /// cells' elasticity (σ₀/μ = 10⁻³) and O(ε²).
    #[test]
    fn weak_drag_stiff_cells_reach_the_closed_form() {
        let stiff = NeoHookean::new(100.0).unwrap();
        for (k, w) in [(1e-5, 1.0), (1e-5, 2.0), (1e-4, 1.0)] {
            let rim = travelling_rim(&stiff, &TanhGrowth::default(), k, w).unwrap();
            let closed = (0.1 * w * 2f64.ln() / k).sqrt();
            let rel = rim.speed / closed - 1.0;
            println!(
                "K = {k:e}, w = {w}: V = {} ({rel:+.2e}), eps = {:.2e}",
                rim.speed, rim.epsilon
            );
            assert!(
                rel < 0.0 && rel > -rim.epsilon,
                "{rel} vs eps {}",
                rim.epsilon
            );
        }
    }

    #[test]
    fn bad_parameters_are_named() {
        let e = NeoHookean::new(1.0).unwrap();
        for (k, w, key) in [(f64::NAN, 1.0, "K"), (-1.0, 1.0, "K"), (1e-2, 0.0, "width")] {
            match travelling_rim(&e, &TanhGrowth::default(), k, w) {
                Err(RimError::Parameter { key: got, .. }) => assert_eq!(got, key),
                other => panic!("{other:?}"),
            }
        }
    }
}
