//! Analytic reference solutions of the line (docs/model.md §5.2–§5.3), drawn as dashed overlays on
//! the Chapter 2 figures ([`crate::output::figures`]) and usable in tests:
//!
//! * [`uniform_k0`] — no drag (`K = 0`), uniform properties, any ramp: the exact nonlinear
//!   solution is spatially uniform, `λ(t) = l(t)/l₀`, `p = μ p_el(λ) − η λ̇ λ⁻²` (Fig 2.7);
//! * [`linear_exponential`] — small displacement, `η = 0`, uniform neo-Hookean cells,
//!   exponential ramp: the complete linear solution (particular term + Fourier series) that
//!   replaces the thesis's (2.45)/(2.48) (Fig 2.5's "analytical solutions");
//! * [`quasi_static`] — the static equilibrium at the current length `l(t)`, for any `μ(X)` and
//!   law: the long-time limit of every prescribed-end run, and the whole solution as `K, η → 0`
//!   (Figs 2.6, 2.8, 2.9).
//!
//! [`reference_for`] picks the one that applies to a [`LineConfig`].

use super::array::Line;
use super::build::discrete;
use super::config::{LineConfig, RightEndKind};
use super::static_solve::{static_equilibrium, static_equilibrium_from, StaticSolution};
use super::LineError;
use crate::boundary::RampKind;
use crate::cell::{Field, ViscosityModel};
use crate::energy::{AnyEnergy, StrainEnergy};
use crate::observe::{AnalyticReference, ReferencePositions, ReferenceProfile};
use std::cell::OnceCell;
use std::f64::consts::PI;
use std::rc::Rc;

/// Which analytic solution applies to a configuration (see [`reference_for`]).
///
/// ```
/// use celltissue::line::analytic::{reference_for, Reference};
/// use celltissue::line::LineConfig;
/// // η = 1 with drag: no closed form, the static equilibrium at l(t) (where it applies)
/// let cfg = LineConfig { eta: 1.0.into(), ..Default::default() };
/// assert_eq!(reference_for(&cfg), Some(Reference::QuasiStatic));
/// assert_eq!(Reference::QuasiStatic.label(), "static equilibrium at l(t)");
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reference {
    /// [`uniform_k0`]: exact (K = 0, uniform properties).
    UniformK0,
    /// [`linear_exponential`]: linear theory (η = 0, uniform neo-Hookean, exponential ramp).
    Linear,
    /// [`quasi_static`]: static equilibrium at `l(t)` (exact as `t → ∞` or `K, η → 0`).
    QuasiStatic,
}

impl Reference {
    /// Legend text.
    ///
    /// ```
    /// use celltissue::line::analytic::Reference;
    /// assert_eq!(Reference::UniformK0.label(), "exact (K = 0, uniform)");
    /// ```
    pub fn label(self) -> &'static str {
        match self {
            Reference::UniformK0 => "exact (K = 0, uniform)",
            Reference::Linear => "linear theory (§5.3 series)",
            Reference::QuasiStatic => "static equilibrium at l(t)",
        }
    }
}

fn constant(f: &Field) -> Option<f64> {
    match f {
        Field::Constant(v) => Some(*v),
        _ => None,
    }
}

/// The analytic solution that applies to `cfg`, if any: a prescribed right end, no growth, no
/// active stress and no Maxwell branch; then [`Reference::UniformK0`] if `K = 0` with uniform
/// `μ`, Kelvin–Voigt `η` (top-level or `viscosity`) and external pressure (any cell lengths);
/// else, for cells of equal length, [`Reference::Linear`] for `η = 0`, uniform neo-Hookean `μ`,
/// uniform `K` and external pressure, the exponential ramp and a small shortening
/// `|k₁| ≤` [`LINEAR_MAX_STRAIN`]; else [`Reference::QuasiStatic`] (any cell lengths: each cell
/// takes its stretch from the one stress). A uniform external pressure adds itself to every
/// pressure.
///
/// ```
/// use celltissue::line::analytic::{reference_for, Reference};
/// use celltissue::line::LineConfig;
/// use celltissue::cell::ViscosityModel;
/// let cfg = LineConfig { k: 0.0.into(), eta: 1.0.into(), ..Default::default() };
/// assert_eq!(reference_for(&cfg), Some(Reference::UniformK0));
/// // viscous cells are outside the linear theory, whichever key gives their viscosity
/// let kv = Some(ViscosityModel::KelvinVoigt { eta: 5.0 });
/// let viscous = LineConfig { viscosity: kv, ..Default::default() };
/// assert_eq!(reference_for(&viscous), Some(Reference::QuasiStatic));
/// // a Maxwell branch: none applies
/// let mx = Some(ViscosityModel::Maxwell { mu_m: 1.0, eta_m: 1.0 });
/// assert_eq!(reference_for(&LineConfig { viscosity: mx, ..Default::default() }), None);
/// ```
pub fn reference_for(cfg: &LineConfig) -> Option<Reference> {
    if cfg.right_end != RightEndKind::Prescribed || cfg.growth.is_some() || cfg.active.is_some() {
        return None;
    }
    // a Maxwell branch carries a stress none of these solutions follows
    if matches!(
        cfg.viscosity,
        Some(ViscosityModel::Maxwell { .. } | ViscosityModel::StandardLinearSolid { .. })
    ) {
        return None;
    }
    let (k, mu, eta) = (constant(&cfg.k), constant(&cfg.mu), constant(&cfg.kv_eta()));
    // a uniform external pressure only adds itself to the pressure; a varying one moves the
    // cells, which only the static equilibrium follows
    let uniform_pe = constant(&cfg.external_pressure).is_some();
    // without drag every cell carries the same stress, so one stretch l(t)/l₀ whatever the
    // cells' lengths
    if k == Some(0.0) && mu.is_some() && eta.is_some() && uniform_pe {
        return Some(Reference::UniformK0);
    }
    let neo = matches!(cfg.law, crate::energy::AnyEnergy::NeoHookean(_));
    if cfg.equal_cells()
        && eta == Some(0.0)
        && mu.is_some()
        && k.is_some()
        && neo
        && cfg.ramp == RampKind::Exponential
        && cfg.g2 == 1.0
        && cfg.k1.abs() <= LINEAR_MAX_STRAIN
        && uniform_pe
    {
        return Some(Reference::Linear);
    }
    Some(Reference::QuasiStatic)
}

/// `(λ, p)` of the exact uniform solution without drag at time `t`: `λ = l(t)/l₀` and
/// `p = μ p_el(λ) − η λ̇ λ⁻²` (docs/model.md §5.3; for the polynomial ramp and neo-Hookean cells
/// `p = (μ + 6ηk₁ t(1−t))/(1 − k₁s)²` during the ramp). Requires uniform `μ`, `η`.
///
/// ```
/// use celltissue::line::analytic::uniform_k0;
/// use celltissue::line::LineConfig;
/// use celltissue::boundary::RampKind;
/// let cfg = LineConfig { k: 0.0.into(), eta: 1.0.into(), ramp: RampKind::Polynomial, ..Default::default() };
/// let (l, p) = uniform_k0(&cfg, 0.5).unwrap();
/// assert!((l - 0.95).abs() < 1e-12);
/// assert!((p - (1.0 + 6.0 * 0.1 * 0.25) / 0.95f64.powi(2)).abs() < 1e-12);
/// ```
pub fn uniform_k0(cfg: &LineConfig, t: f64) -> Option<(f64, f64)> {
    let (mu, eta) = (constant(&cfg.mu)?, constant(&cfg.kv_eta())?);
    let pe = constant(&cfg.external_pressure)?;
    let l0 = cfg.l0();
    let (l, ld) = cfg.ramp().eval(t);
    let (lam, lam_dot) = (l / l0, ld / l0);
    let p = mu * cfg.law.line(lam).pressure - eta * lam_dot / (lam * lam) + pe;
    (lam.is_finite() && p.is_finite()).then_some((lam, p))
}

/// Most terms of the Fourier series in [`linear_exponential`].
pub const MAX_TERMS: usize = 20_000;

/// Largest strain `|λ − 1|` (and shortening `|k₁|`) at which the linear theory is used: it drops
/// terms of second order in the strain, a few per cent of the stretch change at 0.25. Where the
/// linear solution itself predicts a larger strain (large drag, fast ramp: cells next to the
/// moving end compress far more than `k₁`) it is outside its assumptions and not drawn.
pub const LINEAR_MAX_STRAIN: f64 = 0.25;

/// Most reference positions at which [`profile`] evaluates an analytic solution: the overlays
/// cost the same at every N (the series at every cell centre cost 39 s at N = 1000).
pub const PROFILE_SAMPLES: usize = 201;

/// `(λ, p)` at reference position `x` and time `t` of the linear small-displacement solution for
/// the exponential ramp with `η = 0` (docs/model.md §5.3): `λ = 1 − k₁ + k₁ d̆_X`,
/// `p = μ(1 + 2k₁) − 2μk₁ d̆_X`, with `t_s = K/(4γ₀μL₀)` and
/// `d̆ = l₀ sin(aX)/sin(al₀) e^{−t} + Σ 2(−1)ⁿ t_s/(k_n(k_n² − t_s)) sin(k_nX) e^{−k_n² t/t_s}`,
/// `a = √t_s`, `k_n = nπ/l₀` (the series is summed until its terms fall below 1e-16; at `t = 0`
/// the exact `d̆_X = 1`). Valid for `k₁ ≪ 1`. `None` where the result cannot be trusted: at the
/// resonances `t_s = k_n²`, where the series has not converged within [`MAX_TERMS`] terms
/// (very small `t/t_s`), or where the strain `|λ − 1|` exceeds [`LINEAR_MAX_STRAIN`] (outside
/// the small-displacement assumption; this also excludes any `λ ≤ 0`).
///
/// ```
/// use celltissue::line::analytic::linear_exponential;
/// // K → 0: uniform compression, λ = 1 − k₁ + k₁e^{−t}
/// let (l, _) = linear_exponential(30.0, 1.0, 1e-9, 0.1, 100.0, 1.0, 1.0, 1.0).unwrap();
/// assert!((l - (0.9 + 0.1 * (-1.0f64).exp())).abs() < 1e-6);
/// ```
#[allow(clippy::too_many_arguments)]
pub fn linear_exponential(
    x: f64,
    t: f64,
    k: f64,
    k1: f64,
    l0: f64,
    mu: f64,
    gamma0: f64,
    cell_length: f64,
) -> Option<(f64, f64)> {
    let series = LinearSeries {
        k,
        k1,
        l0,
        mu,
        gamma0,
        cell_length,
    };
    series.at(&[x], t)?.pop()
}

/// The parameters of [`linear_exponential`]'s series, summed at many positions at once by
/// [`LinearSeries::at`].
#[derive(Clone, Copy, Debug)]
struct LinearSeries {
    k: f64,
    k1: f64,
    l0: f64,
    mu: f64,
    gamma0: f64,
    cell_length: f64,
}

impl LinearSeries {
    /// `(λ, p)` at each of `xs` at time `t`, or `None` where [`linear_exponential`] gives
    /// `None` at any of them. The series' coefficients and decay, and when it has converged, do
    /// not depend on the position: each term is formed once and added at every position (the
    /// positions' loop has no division and vectorises), so a profile costs a few flops per
    /// position and term instead of a division and a dozen flops.
    fn at(&self, xs: &[f64], t: f64) -> Option<Vec<(f64, f64)>> {
        let Self {
            k,
            k1,
            l0,
            mu,
            gamma0,
            cell_length,
        } = *self;
        if t <= 0.0 {
            return Some(vec![(1.0, mu); xs.len()]);
        }
        let ts = k / (4.0 * gamma0 * mu * cell_length);
        let a = ts.sqrt();
        let s = (a * l0).sin();
        if ts.is_nan() || ts <= 0.0 || s.abs() < 1e-12 {
            return None;
        }
        let head = l0 * a / s * (-t).exp();
        let mut dx: Vec<f64> = xs.iter().map(|&x| head * (a * x).cos()).collect();
        // cos(k_n X) by rotation and e^{−k_n² t/t_s} = q^{n²} by the ratio q^{2n+1}: a few flops
        // per term instead of a cos and an exp
        let (rc, rs): (Vec<f64>, Vec<f64>) = xs
            .iter()
            .map(|&x| {
                let theta = PI * x / l0;
                (theta.cos(), theta.sin())
            })
            .unzip();
        let (mut c, mut sn) = (rc.clone(), rs.clone());
        // the terms' factors, until the series has converged (or not, within MAX_TERMS: then
        // nothing is summed)
        let tau = PI * PI * t / (l0 * l0 * ts);
        let mut decay = (-tau).exp();
        let mut ratio = (-3.0 * tau).exp();
        let ratio_step = (-2.0 * tau).exp();
        let mut terms = Vec::new();
        let mut converged = false;
        for n in 1..=MAX_TERMS {
            let kn = n as f64 * PI / l0;
            let coef = 2.0 * ts / (kn * kn - ts);
            if !coef.is_finite() {
                return None;
            }
            if decay * coef.abs() < 1e-16 && kn * kn > ts {
                converged = true;
                break;
            }
            let sign = if n % 2 == 0 { 1.0 } else { -1.0 };
            terms.push(sign * coef * decay);
            decay *= ratio;
            ratio *= ratio_step;
        }
        if !converged {
            // truncating a series that has not converged drew λ down to −5
            return None;
        }
        let m = xs.len();
        {
            let (d, c, sn, rc, rs) = (&mut dx[..m], &mut c[..m], &mut sn[..m], &rc[..m], &rs[..m]);
            for term in terms {
                // slices of one length: the loop runs on vectors of positions
                for i in 0..m {
                    d[i] += term * c[i];
                    (c[i], sn[i]) = (c[i] * rc[i] - sn[i] * rs[i], sn[i] * rc[i] + c[i] * rs[i]);
                }
            }
        }
        dx.iter()
            .map(|&dx| {
                let lam = 1.0 - k1 + k1 * dx;
                let p = mu * (1.0 + 2.0 * k1) - 2.0 * mu * k1 * dx;
                let small = (lam - 1.0).abs() <= LINEAR_MAX_STRAIN;
                (lam.is_finite() && p.is_finite() && small).then_some((lam, p))
            })
            .collect()
    }
}

/// The static equilibrium of the discrete line of `cfg` held at its prescribed length `l(t)`
/// (docs/model.md §5.2): every cell at the same stress, stretches adding up to `l(t)`.
///
/// ```
/// use celltissue::line::analytic::quasi_static;
/// use celltissue::line::LineConfig;
/// let s = quasi_static(&LineConfig::default(), 1e3).unwrap();
/// assert!((s.max_pressure() - 1.0 / 0.81).abs() < 1e-9);   // uniform: p = μ/(1 − k₁)²
/// ```
pub fn quasi_static(cfg: &LineConfig, t: f64) -> Result<StaticSolution, LineError> {
    let line = discrete(cfg.law.clone(), &cfg.params(1e-8))?;
    let (l, _) = cfg.ramp().eval(t);
    static_equilibrium(&line, l)
}

/// What the references of one configuration share across times, each computed once: the
/// cells' reference lengths and centres, the relaxation time, the discrete line, and the
/// static equilibrium at each time that is asked for again (a profile time: its profile and
/// its positions, and maybe a series point) or started from (the last one solved). Every other
/// solution is dropped after use, so a long series of a long line holds no more than its
/// profiles do. (At 10⁶ cells with a Gaussian μ, rebuilding the line, resampling its fields
/// and solving the same equilibrium again for every series time, every profile and every set
/// of static positions was 4.7 s of a 10.3 s run whose solve took 5.5 s.)
struct Shared<'a> {
    cfg: &'a LineConfig,
    lengths: Vec<f64>,
    centres: Vec<f64>,
    tau: OnceCell<f64>,
    line: OnceCell<Option<Line<AnyEnergy>>>,
    /// The times whose solutions are kept (as bits).
    keep: Vec<u64>,
    /// The kept solutions, by time (as bits); `None` where none could be found.
    statics: Vec<(u64, Option<Rc<StaticSolution>>)>,
    /// The last solution found, which the next solve starts from.
    last: Option<Rc<StaticSolution>>,
}

impl<'a> Shared<'a> {
    /// For `cfg`, keeping the solutions at `keep`.
    fn new(cfg: &'a LineConfig, keep: &[f64]) -> Self {
        let lengths = cfg.lengths();
        let centres = lengths
            .iter()
            .scan(0.0, |acc, l| {
                *acc += l;
                Some(*acc - 0.5 * l)
            })
            .collect();
        Self {
            cfg,
            lengths,
            centres,
            tau: OnceCell::new(),
            line: OnceCell::new(),
            keep: keep.iter().map(|t| t.to_bits()).collect(),
            statics: Vec::new(),
            last: None,
        }
    }

    /// [`quasi_static_applies`] with the relaxation time computed once.
    fn applies(&self, t: f64) -> bool {
        let tau = *self.tau.get_or_init(|| relaxation_time(self.cfg));
        applies_with(self.cfg, tau, t)
    }

    /// [`quasi_static`] at `t` (`None` if it cannot be found), solved once for a kept time.
    fn quasi_static(&mut self, t: f64) -> Option<Rc<StaticSolution>> {
        let bits = t.to_bits();
        if let Some((_, s)) = self.statics.iter().find(|(b, _)| *b == bits) {
            return s.clone();
        }
        let cfg = self.cfg;
        let line = self
            .line
            .get_or_init(|| discrete(cfg.law.clone(), &cfg.params(1e-8)).ok());
        let (l, _) = cfg.ramp().eval(t);
        // started from the last equilibrium found (output times are near one another)
        let s = line
            .as_ref()
            .and_then(|line| static_equilibrium_from(line, l, self.last.as_deref()).ok())
            .map(Rc::new);
        if s.is_some() {
            self.last.clone_from(&s);
        }
        if self.keep.contains(&bits) {
            self.statics.push((bits, s.clone()));
        }
        s
    }
}

/// Slowest linear relaxation time of the line, `τ = K l₀²/(π² 4γ₀ μ_min L₀) + η_max/(2μ_min)`
/// (docs/model.md §3.4: diffusion `t_s l₀²/π²` of the longest mode plus the Kelvin–Voigt `t_k`),
/// with the extreme values of the sampled fields.
///
/// ```
/// use celltissue::line::analytic::relaxation_time;
/// use celltissue::line::LineConfig;
/// // 100 unit cells, K = 1, μ = 1, η = 0.5: 100²/(4π²) + 0.5/2
/// let cfg = LineConfig { eta: 0.5.into(), ..Default::default() };
/// let expected = 1e4 / (4.0 * std::f64::consts::PI.powi(2)) + 0.25;
/// assert!((relaxation_time(&cfg) - expected).abs() < 1e-9);
/// ```
pub fn relaxation_time(cfg: &LineConfig) -> f64 {
    let lengths = cfg.lengths();
    let l0 = cfg.l0();
    let centres: Vec<f64> = lengths
        .iter()
        .scan(0.0, |acc, l| {
            *acc += l;
            Some(*acc - 0.5 * l)
        })
        .collect();
    let min = |f: &Field| {
        f.sample(&centres, l0)
            .into_iter()
            .fold(f64::INFINITY, f64::min)
    };
    let max = |f: &Field| {
        f.sample(&centres, l0)
            .into_iter()
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let mu = min(&cfg.mu).max(f64::MIN_POSITIVE);
    let l_cell = lengths.iter().copied().fold(f64::INFINITY, f64::min);
    max(&cfg.k) * l0 * l0 / (PI * PI * 4.0 * cfg.gamma0 * mu * l_cell)
        + max(&cfg.kv_eta()) / (2.0 * mu)
}

/// Whether the static equilibrium at `l(t)` describes the run at `t`: the line relaxes much
/// faster than the ramp (`τ ≤ 0.05 t_ramp`), or the ramp is over and the line has relaxed
/// (`t ≥ 5 t_ramp + 10 τ`); see [`relaxation_time`].
///
/// ```
/// use celltissue::line::analytic::quasi_static_applies;
/// use celltissue::line::LineConfig;
/// // K = 1 on 100 cells relaxes in τ ≈ 253, far slower than the unit ramp
/// let cfg = LineConfig::default();
/// assert!(!quasi_static_applies(&cfg, 100.0));
/// assert!(quasi_static_applies(&cfg, 3000.0)); // t ≥ 5 + 10τ
/// // with K = 1e-4 the line follows the ramp
/// let fast = LineConfig { k: 1e-4.into(), ..Default::default() };
/// assert!(quasi_static_applies(&fast, 0.5));
/// ```
pub fn quasi_static_applies(cfg: &LineConfig, t: f64) -> bool {
    applies_with(cfg, relaxation_time(cfg), t)
}

/// [`quasi_static_applies`] for the relaxation time `tau`.
fn applies_with(cfg: &LineConfig, tau: f64, t: f64) -> bool {
    tau <= 0.05 * cfg.t_ramp || t >= 5.0 * cfg.t_ramp + 10.0 * tau
}

/// `(X, λ, p)` of the applicable reference solution at time `t` at cell centres of the
/// discrete line — all of them for the static equilibrium, at most [`PROFILE_SAMPLES`] evenly
/// spread ones (first and last included) for the closed forms — or `None` if none applies at
/// `t` (the static equilibrium only where [`quasi_static_applies`]) or it cannot be evaluated.
///
/// ```
/// use celltissue::line::analytic::profile;
/// use celltissue::line::LineConfig;
/// // K = 0, η = 1: the uniform solution; after the exponential ramp λ = 1 − k₁
/// let cfg = LineConfig { k: 0.0.into(), eta: 1.0.into(), ..Default::default() };
/// let p = profile(&cfg, 50.0).unwrap();
/// assert!(p.iter().all(|&(_, l, _)| (l - 0.9).abs() < 1e-9));
/// // K = 1 mid-ramp: no reference applies
/// assert!(profile(&LineConfig::default(), 0.5).is_none());
/// ```
pub fn profile(cfg: &LineConfig, t: f64) -> Option<Vec<(f64, f64, f64)>> {
    profile_with(&mut Shared::new(cfg, &[]), t)
}

/// [`profile`] with what the times share.
fn profile_with(sh: &mut Shared<'_>, t: f64) -> Option<Vec<(f64, f64, f64)>> {
    let cfg = sh.cfg;
    let centres = sample(&sh.centres, PROFILE_SAMPLES);
    match reference_for(cfg)? {
        Reference::UniformK0 => {
            let (lam, p) = uniform_k0(cfg, t)?;
            Some(centres.iter().map(|&x| (x, lam, p)).collect())
        }
        Reference::Linear => {
            let (k, mu) = (constant(&cfg.k)?, constant(&cfg.mu)?);
            let l0 = cfg.l0();
            let l_cell = sh.lengths.first().copied()?;
            let series = LinearSeries {
                k,
                k1: cfg.k1,
                l0,
                mu,
                gamma0: cfg.gamma0,
                cell_length: l_cell,
            };
            let at = series.at(&centres, t)?;
            let pe = constant(&cfg.external_pressure)?;
            Some(
                centres
                    .iter()
                    .zip(at)
                    .map(|(&x, (lam, p))| (x, lam, p + pe))
                    .collect(),
            )
        }
        Reference::QuasiStatic => {
            if !sh.applies(t) {
                return None;
            }
            let s = sh.quasi_static(t)?;
            Some(
                sh.centres
                    .iter()
                    .zip(s.lambda.iter().zip(&s.pressure))
                    .map(|(&x, (&l, &p))| (x, l, p))
                    .collect(),
            )
        }
    }
}

/// At most `m` of `v`, evenly spread, first and last included.
fn sample(v: &[f64], m: usize) -> Vec<f64> {
    sample_indices(v.len(), m).map(|i| v[i]).collect()
}

/// The indices of [`sample`]: all of `0..len` when `len ≤ m`, else `m` evenly spread ones,
/// first and last included.
fn sample_indices(len: usize, m: usize) -> impl Iterator<Item = usize> + Clone {
    let (count, last) = if len <= m || m < 2 {
        (len, None)
    } else {
        (m, Some(len - 1))
    };
    (0..count).map(move |i| match last {
        None => i,
        Some(last) => (i * last + (m - 1) / 2) / (m - 1),
    })
}

/// `(max p, min λ)` of the applicable reference solution at time `t` (see [`profile`]).
///
/// ```
/// use celltissue::line::analytic::extremes;
/// use celltissue::line::LineConfig;
/// // K = 0, η = 1, after the exponential ramp: uniform λ = 0.9, p = 1/λ²
/// let cfg = LineConfig { k: 0.0.into(), eta: 1.0.into(), ..Default::default() };
/// let (p, l) = extremes(&cfg, 50.0).unwrap();
/// assert!((l - 0.9).abs() < 1e-9 && (p - 1.0 / 0.81).abs() < 1e-9);
/// ```
pub fn extremes(cfg: &LineConfig, t: f64) -> Option<(f64, f64)> {
    extremes_with(&mut Shared::new(cfg, &[]), t)
}

/// [`extremes`] with what the times share.
fn extremes_with(sh: &mut Shared<'_>, t: f64) -> Option<(f64, f64)> {
    // the static equilibrium's own extremes, without building its every-cell profile
    if reference_for(sh.cfg)? == Reference::QuasiStatic {
        if !sh.applies(t) {
            return None;
        }
        let s = sh.quasi_static(t)?;
        return Some((s.max_pressure(), s.min_stretch()));
    }
    let prof = profile_with(sh, t)?;
    let pmax = prof.iter().map(|q| q.2).fold(f64::NEG_INFINITY, f64::max);
    let lmin = prof.iter().map(|q| q.1).fold(f64::INFINITY, f64::min);
    Some((pmax, lmin))
}

/// Static boundary positions `x₀..x_N` at `l(t)` with the reference positions `X₀..X_N`
/// (Fig 2.6's static macroscale solution), where [`quasi_static_applies`].
///
/// ```
/// use celltissue::line::analytic::static_positions;
/// use celltissue::line::LineConfig;
/// // K = 1e-5 (quasi-static throughout), uniform cells: uniform strain x = (l/l₀)X
/// let cfg = LineConfig { k: 1e-5.into(), ..Default::default() };
/// let xs = static_positions(&cfg, 20.0).unwrap();
/// let l = xs.last().unwrap().1;
/// assert!(xs.iter().all(|&(xr, x)| (x - l / 100.0 * xr).abs() < 1e-9));
/// ```
pub fn static_positions(cfg: &LineConfig, t: f64) -> Option<Vec<(f64, f64)>> {
    static_positions_with(&mut Shared::new(cfg, &[]), t)
}

/// [`static_positions`] with what the times share.
fn static_positions_with(sh: &mut Shared<'_>, t: f64) -> Option<Vec<(f64, f64)>> {
    reference_for(sh.cfg)?;
    if !sh.applies(t) {
        return None;
    }
    let s = sh.quasi_static(t)?;
    let xref = std::iter::once(0.0).chain(sh.lengths.iter().scan(0.0, |acc, l| {
        *acc += l;
        Some(*acc)
    }));
    Some(xref.zip(s.x.iter().copied()).collect())
}

/// The applicable analytic solution of `cfg` at the series and profile times where it
/// applies ([`crate::observe::AnalyticReference`]); `None` if none applies at any of them.
///
/// ```
/// use celltissue::line::analytic::reference;
/// use celltissue::line::LineConfig;
/// // η = 0, K = 1, 10 % shortening by the exponential ramp: the linear theory, which holds
/// // at the start and once the strain is small everywhere, not mid-ramp (cells next to the
/// // moving end are compressed far beyond k₁ = 0.1)
/// let r = reference(&LineConfig::default(), &[0.0, 1.0, 1000.0], &[1.0, 1000.0]).unwrap();
/// assert_eq!(r.label, "linear theory (§5.3 series)");
/// assert_eq!(r.series.t, [0.0, 1000.0]);
/// assert!((r.series.min_stretch[1] - 0.896126).abs() < 1e-6);
/// assert_eq!(r.profiles.len(), 1);
/// // a free end: no analytic solution
/// let free = LineConfig { right_end: celltissue::line::config::RightEndKind::Free, ..Default::default() };
/// assert!(reference(&free, &[1.0], &[]).is_none());
/// ```
pub fn reference(
    cfg: &LineConfig,
    series_times: &[f64],
    profile_times: &[f64],
) -> Option<AnalyticReference> {
    let kind = reference_for(cfg)?;
    let mut r = AnalyticReference {
        label: kind.label().to_string(),
        ..Default::default()
    };
    let mut sh = Shared::new(cfg, profile_times);
    for &t in series_times {
        if let Some((p, l)) = extremes_with(&mut sh, t) {
            r.series.t.push(t);
            r.series.max_pressure.push(p);
            r.series.min_stretch.push(l);
        }
    }
    for &t in profile_times {
        if let Some(prof) = profile_with(&mut sh, t) {
            r.profiles.push(ReferenceProfile {
                t,
                x_ref: prof.iter().map(|q| q.0).collect(),
                stretch: prof.iter().map(|q| q.1).collect(),
                pressure: prof.iter().map(|q| q.2).collect(),
            });
        }
        if let Some(xs) = static_positions_with(&mut sh, t) {
            // at most PROFILE_SAMPLES boundaries, first and last included, as the closed-form
            // profiles: the overlay's cost and size do not grow with N
            let picked = sample_indices(xs.len(), PROFILE_SAMPLES);
            r.equilibrium.push(ReferencePositions {
                t,
                x_ref: picked.clone().map(|i| xs[i].0).collect(),
                x: picked.map(|i| xs[i].1).collect(),
            });
        }
    }
    let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
    r.profiles
        .retain(|p| finite(&p.x_ref) && finite(&p.stretch) && finite(&p.pressure));
    r.equilibrium.retain(|p| finite(&p.x_ref) && finite(&p.x));
    let keep: Vec<bool> = (0..r.series.t.len())
        .map(|i| r.series.max_pressure[i].is_finite() && r.series.min_stretch[i].is_finite())
        .collect();
    let filter = |v: &mut Vec<f64>| {
        let mut k = keep.iter();
        v.retain(|_| *k.next().unwrap_or(&false));
    };
    filter(&mut r.series.t);
    filter(&mut r.series.max_pressure);
    filter(&mut r.series.min_stretch);
    let empty = r.series.t.is_empty() && r.profiles.is_empty() && r.equilibrium.is_empty();
    (!empty).then_some(r)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The series term by term with `cos` and `exp` (the form of docs/model.md §5.3).
    fn direct(x: f64, t: f64, k: f64, k1: f64, l0: f64) -> f64 {
        let ts = k / 4.0;
        let a = ts.sqrt();
        let mut dx = l0 * a * (a * x).cos() / (a * l0).sin() * (-t).exp();
        for n in 1..=200_000 {
            let kn = n as f64 * PI / l0;
            let sign = if n % 2 == 0 { 1.0 } else { -1.0 };
            dx += sign * 2.0 * ts / (kn * kn - ts) * (kn * x).cos() * (-kn * kn * t / ts).exp();
        }
        1.0 - k1 + k1 * dx
    }

    #[test]
    fn recurrences_match_the_direct_series() {
        for &(x, t, k) in &[
            (0.5, 1.0, 1.0),
            (37.3, 0.01, 10.0),
            (99.5, 10.0, 1e-2),
            (0.5, 1e-3, 1.0),
        ] {
            let (lam, _) = linear_exponential(x, t, k, 0.1, 100.0, 1.0, 1.0, 1.0).unwrap();
            let d = direct(x, t, k, 0.1, 100.0);
            assert!((lam - d).abs() < 1e-11, "x {x} t {t} K {k}: {lam} vs {d}");
        }
        // a whole profile at once (every term added at every position): each position its
        // own direct series
        let series = LinearSeries {
            k: 1e-3,
            k1: 0.1,
            l0: 100.0,
            mu: 1.0,
            gamma0: 1.0,
            cell_length: 1.0,
        };
        let xs: Vec<f64> = (0..20).map(|j| 5.0 * j as f64 + 0.5).collect();
        for t in [1e-2, 0.3, 1.0, 10.0] {
            let at = series.at(&xs, t).unwrap();
            for (&x, &(lam, p)) in xs.iter().zip(&at) {
                let d = direct(x, t, 1e-3, 0.1, 100.0);
                assert!((lam - d).abs() < 1e-11, "x {x} t {t}: {lam} vs {d}");
                // p = μ(1 + 2k₁) − 2μk₁d̆_X and λ = 1 − k₁ + k₁d̆_X: p = 3 − 2λ here
                assert!((p - (3.0 - 2.0 * lam)).abs() < 1e-12, "x {x} t {t}");
            }
        }
    }

    #[test]
    fn the_static_equilibrium_overlay_is_sampled_and_exact_at_its_samples() {
        // 20 000 quasi-static cells (K = 1e-5): the positions at ≤ PROFILE_SAMPLES boundaries,
        // first and last included, each the uniform strain x = (l/l₀)X of the full solution
        let cfg = LineConfig {
            cells: 20_000,
            k: 1e-5.into(),
            ..Default::default()
        };
        let r = reference(&cfg, &[], &[2e5]).unwrap();
        let e = &r.equilibrium[0];
        assert_eq!(
            (e.x.len(), e.x_ref.len()),
            (PROFILE_SAMPLES, PROFILE_SAMPLES)
        );
        assert_eq!((e.x_ref[0], *e.x_ref.last().unwrap()), (0.0, 20_000.0));
        let l = *e.x.last().unwrap();
        assert!((l - 18_000.0).abs() < 1e-6, "{l}");
        for (&xr, &x) in e.x_ref.iter().zip(&e.x) {
            assert!((x - 0.9 * xr).abs() < 1e-8 * (1.0 + xr), "{xr}: {x}");
        }
        // and a piecewise-constant μ (two runs) inverts each run to its own stretch
        let stiff = LineConfig {
            cells: 10,
            k: 1e-5.into(),
            mu: crate::cell::Field::PerCell {
                values: vec![1.0, 1.0, 1.0, 1.0, 1.0, 4.0, 4.0, 4.0, 4.0, 4.0],
            },
            ..Default::default()
        };
        let s = quasi_static(&stiff, 1e3).unwrap();
        assert!(s.lambda[..5].iter().all(|&l| l == s.lambda[0]));
        assert!(s.lambda[5..].iter().all(|&l| l == s.lambda[5]));
        assert!(s.lambda[0] < s.lambda[5]);
        let sum: f64 = s.lambda.iter().sum();
        assert!((sum - 9.0).abs() < 1e-12, "{sum}");
        let stress = |mu: f64, l: f64| mu * (l * l - 1.0 / (l * l));
        assert!((stress(1.0, s.lambda[0]) - stress(4.0, s.lambda[5])).abs() < 1e-12);
    }

    #[test]
    fn a_reference_over_many_times_is_each_times_own_solution() {
        // Gaussian μ (every cell its own), quasi-static: one line and one equilibrium per time,
        // each started from the last; the same as solving each time alone
        let cfg = LineConfig {
            cells: 2_000,
            k: 1e-8.into(),
            mu: crate::cell::Field::gaussian_bump(1.0, 1.0, 0.5, 0.1),
            ..Default::default()
        };
        let times = [0.1, 0.5, 1.0, 3.0];
        let r = reference(&cfg, &times, &times).unwrap();
        assert_eq!(r.label, Reference::QuasiStatic.label());
        assert_eq!((r.series.t.len(), r.equilibrium.len()), (4, 4));
        for (i, &t) in times.iter().enumerate() {
            let alone = quasi_static(&cfg, t).unwrap();
            let (p, l) = (alone.max_pressure(), alone.min_stretch());
            assert!((r.series.max_pressure[i] - p).abs() <= 1e-12 * p, "t = {t}");
            assert!((r.series.min_stretch[i] - l).abs() <= 1e-12 * l, "t = {t}");
            let prof = &r.profiles[i];
            for (&x, &lam) in prof.x_ref.iter().zip(&prof.stretch) {
                let j = (x - 0.5) as usize; // unit cells: centre j + ½
                assert!((lam - alone.lambda[j]).abs() <= 1e-12, "t = {t}, cell {j}");
            }
            let last = *r.equilibrium[i].x.last().unwrap();
            assert!((last - alone.x[2_000]).abs() <= 1e-9, "t = {t}");
        }
    }

    #[test]
    fn an_unconverged_series_is_not_drawn() {
        // l₀ = 1000, K = 10, t = 1e-3 needs ~10⁵ terms: refused rather than truncated
        assert!(linear_exponential(0.5, 1e-3, 10.0, 0.1, 1000.0, 1.0, 1.0, 1.0).is_none());
    }

    #[test]
    fn overlays_cost_the_same_at_every_n_and_never_draw_negative_stretch() {
        let cfg = |n: usize| LineConfig {
            cells: n,
            k: 10.0.into(),
            eta: 0.0.into(),
            ..Default::default()
        };
        assert_eq!(reference_for(&cfg(20_000)), Some(Reference::Linear));
        for t in [1e-3, 0.1, 1.0, 10.0, 1000.0] {
            if let Some(p) = profile(&cfg(20_000), t) {
                assert!(p.len() <= PROFILE_SAMPLES);
                assert!(p.iter().all(|q| q.1 > 0.0));
                assert_eq!(p.first().unwrap().0, 0.5);
                assert_eq!(p.last().unwrap().0, 19_999.5);
            }
        }
        // a large shortening is outside the linear theory
        let big = LineConfig {
            k1: 0.6,
            ..cfg(100)
        };
        assert_eq!(reference_for(&big), Some(Reference::QuasiStatic));
    }
}
