//! A deformation mode written outside the library, in this one file: a line of cells whose
//! boundaries are tethered to the substrate by linear springs, registered by one call and then
//! run from scenarios like the built-in kinds — discrete and continuum, with sweeps, outputs and
//! plots (`docs/guide-deformation-mode.md`):
//!
//! ```text
//! cargo run --release --example tethered_line -- run examples/tethered_line.toml --out /tmp/t
//! ```
//!
//! The model. Cells `j = 1…n` of reference length `h` between boundaries `x₀ = 0` (held) and
//! `x_n = L₀(1 − k₁(1 − e^{−t/t_ramp}))` (pulled in, as in the thesis's Chapter 2); each interior
//! boundary is dragged by the substrate and held near its reference position `X_j` by a tether:
//!
//! `K_h ẋ_j + k_h (x_j − X_j) = σ(λ_{j+1}) − σ(λ_j)`,  `λ_j = (x_j − x_{j−1})/h`,
//!
//! with `σ` the cell law's axial stress. The discrete line has `n = cells`, `h = cell_length`,
//! `K_h = K`, `k_h = tether`; the continuum is the same array on `n = nodes` segments of
//! `h = L₀/n` with drag and tether per unit reference length, `K_h = K h/cell_length` and
//! `k_h = tether·h/cell_length` — the mode's continuum scaling, declared once, in `build`.
//!
//! Validation (`tests/mode_tethered_line.rs`): for a small shortening the steady state solves
//! the linearised discrete problem `k_h h u_j = E (u_{j+1} − 2u_j + u_{j−1})`, `E = σ'(1)`,
//! exactly: `u_j = −k₁L₀ sinh(θj)/sinh(θn)` with `cosh θ = 1 + k_h h/(2E)`.

use celltissue::integrators::{Pattern, ResidualError};
use celltissue::modes::Mode;
use celltissue::observe::{ModelKind, Profile};
use celltissue::registry::{positive, ParamError};
use celltissue::serde::{Deserialize, Serialize};
use celltissue::{AnyEnergy, CellArray, NeoHookean, Scalar, StrainEnergy};

/// The `[model]` keys of `kind = "tethered_line"`.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(crate = "celltissue::serde", deny_unknown_fields, default)]
pub struct TetheredConfig {
    /// Number of cells (≥ 2).
    pub cells: usize,
    /// Reference length of a cell (> 0).
    pub cell_length: f64,
    /// Substrate drag per boundary (> 0).
    #[serde(rename = "K")]
    pub k: f64,
    /// Tether stiffness per boundary (≥ 0).
    pub tether: f64,
    /// Fractional shortening of the pulled end, in [0, 1).
    pub k1: f64,
    /// Time scale of the pull (> 0).
    pub t_ramp: f64,
    /// The cells' strain energy.
    pub law: AnyEnergy,
}

impl Default for TetheredConfig {
    fn default() -> Self {
        Self {
            cells: 20,
            cell_length: 1.0,
            k: 1.0,
            tether: 0.1,
            k1: 0.1,
            t_ramp: 1.0,
            law: AnyEnergy::NeoHookean(NeoHookean::new(1.0).expect("mu = 1 is valid")),
        }
    }
}

/// The tethered line as a cell array: unknowns `x₁ … x_{n−1}`.
pub struct TetheredLine {
    n: usize,
    h: f64,
    drag: f64,
    tether: f64,
    length: f64,
    k1: f64,
    t_ramp: f64,
    law: AnyEnergy,
}

impl TetheredLine {
    /// Boundary `j` (0…n) of the state `y` at time `t`.
    fn x<S: Scalar>(&self, t: f64, y: &[S], j: usize) -> S {
        match j {
            0 => S::from(0.0),
            j if j == self.n => S::from(self.end(t)),
            j => y[j - 1],
        }
    }

    /// The pulled end `x_n(t)`.
    fn end(&self, t: f64) -> f64 {
        self.length * (1.0 - self.k1 * (1.0 - (-t / self.t_ramp).exp()))
    }

    /// The axial stress of cell `j` at stretch `lambda`, lifted into the residual's scalar; a
    /// crushed cell rejects the step, naming the boundary below it.
    fn stress<S: Scalar>(&self, j: usize, lambda: S) -> Result<S, ResidualError> {
        if lambda.re() <= 0.0 {
            return Err(ResidualError::Recoverable {
                reason: format!("cell {j} has a non-positive stretch"),
                component: (j > 1).then(|| j - 2),
            });
        }
        let r = self.law.line(lambda.re());
        Ok(lambda.lift(r.sigma, r.dsigma))
    }
}

impl CellArray for TetheredLine {
    fn dim(&self) -> usize {
        self.n - 1
    }

    fn pattern(&self) -> Pattern {
        Pattern::Banded { lower: 1, upper: 1 }
    }

    fn residual<S: Scalar>(
        &self,
        t: f64,
        y: &[S],
        yp: &[S],
        r: &mut [S],
    ) -> Result<(), ResidualError> {
        let mut below = self.stress(1, (self.x(t, y, 1) - self.x(t, y, 0)) / self.h)?;
        for j in 1..self.n {
            let above = self.stress(j + 1, (self.x(t, y, j + 1) - self.x(t, y, j)) / self.h)?;
            let reference = j as f64 * self.h;
            r[j - 1] =
                yp[j - 1] * self.drag + (y[j - 1] - reference) * self.tether - (above - below);
            below = above;
        }
        Ok(())
    }
}

/// The mode: configuration → array, state → record.
pub struct Tethered;

impl Mode for Tethered {
    type Config = TetheredConfig;
    type Array = TetheredLine;

    fn check(c: &TetheredConfig) -> Result<(), ParamError> {
        if c.cells < 2 {
            return Err(ParamError::range("cells", c.cells, ">= 2"));
        }
        positive("cell_length", c.cell_length)?;
        positive("K", c.k)?;
        if !(c.tether >= 0.0 && c.tether.is_finite()) {
            return Err(ParamError::range("tether", c.tether, "finite and >= 0"));
        }
        if !((0.0..1.0).contains(&c.k1)) {
            return Err(ParamError::range("k1", c.k1, "in [0, 1)"));
        }
        positive("t_ramp", c.t_ramp)
    }

    fn build(
        c: &TetheredConfig,
        model: ModelKind,
        nodes: Option<usize>,
    ) -> Result<(TetheredLine, Vec<f64>), ParamError> {
        let length = c.cells as f64 * c.cell_length;
        let n = match model {
            ModelKind::Discrete => c.cells,
            ModelKind::Continuum => nodes.unwrap_or(4 * c.cells),
        };
        if n < 2 {
            return Err(ParamError::range("nodes", n, ">= 2"));
        }
        let h = length / n as f64;
        // per-boundary drag and tether: per cell discretely, per unit length in the continuum
        let scale = h / c.cell_length;
        let line = TetheredLine {
            n,
            h,
            drag: c.k * scale,
            tether: c.tether * scale,
            length,
            k1: c.k1,
            t_ramp: c.t_ramp,
            law: c.law.clone(),
        };
        let y0 = (1..n).map(|j| j as f64 * h).collect();
        Ok((line, y0))
    }

    fn observe(a: &TetheredLine, t: f64, y: &[f64]) -> Profile {
        let x = |j| a.x(t, y, j);
        let mut p = Profile {
            t,
            ..Default::default()
        };
        for j in 1..=a.n {
            let lambda = (x(j) - x(j - 1)) / a.h;
            p.x_ref.push((j as f64 - 0.5) * a.h);
            p.x.push(0.5 * (x(j) + x(j - 1)));
            p.stretch.push(lambda);
            p.pressure.push(a.law.line(lambda).pressure);
        }
        p
    }

    fn length(a: &TetheredLine, t: f64, _y: &[f64]) -> f64 {
        a.end(t)
    }

    fn extra_series(a: &TetheredLine, _t: f64, y: &[f64]) -> Vec<(String, f64)> {
        // the largest tether force, |k_h (x_j − X_j)|
        let f = (1..a.n)
            .map(|j| (a.tether * (y[j - 1] - j as f64 * a.h)).abs())
            .fold(0.0, f64::max);
        vec![("max_tether_force".into(), f)]
    }
}

/// The one registration line.
pub fn register() {
    celltissue::modes::register::<Tethered>("tethered_line").expect("a new mode name");
}

#[allow(dead_code)]
fn main() {
    register();
    std::process::exit(celltissue::cli::main());
}
