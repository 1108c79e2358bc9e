//! The thesis's own continuum discretisation (docs/model.md §3.3b; thesis (2.74)–(2.79), App. A.1),
//! kept as a *reproduction mode* for Table 2.1: `n` nodes, `dX = l₀/(n−1)`, centred differences
//! of the expanded (non-conservative) PDE
//!
//! `K ẋ − ηγ₀[λ⁻¹(1+λ⁻²) ẋ_XX − 2λ⁻⁴ x_XX ẋ_X] = (γ₀/λ)[μ σ_el'(λ) x_XX + μ_X σ_el(λ)]`
//!
//! (for neo-Hookean `(γ₀/λ) μ σ_el' = 2γ₀μ(1+λ⁻⁴)`), wall at node 1 and prescribed `l(t)` at
//! node n. No growth. Output quantities live at the nodes; the end pressure uses the one-sided
//! second-order `λ_n`. Prefer the conservative scheme ([`crate::line::build::continuum`]) for
//! new work.

use super::build::{drawn_per_cell, CellCensus, LineParams};
use super::observe::Snapshot;
use super::run::LineModel;
use super::LineError;
use crate::array::CellArray;
use crate::boundary::{Ramp, RightEnd};
use crate::energy::StrainEnergy;
use crate::scalar::Scalar;
use integrators::{Pattern, ResidualError};

/// The thesis finite-difference scheme as a [`CellArray`]: unknowns are the interior node
/// positions `x₂..x_{n−1}`.
///
/// ```
/// use celltissue::line::build::LineParams;
/// use celltissue::line::thesis_scheme::ThesisLine;
/// use celltissue::boundary::{Ramp, RightEnd};
/// use celltissue::NeoHookean;
/// let mut p = LineParams::unit_cells(100);
/// p.k = 1.0.into();
/// p.right = RightEnd::Prescribed(Ramp::Exponential { l0: 100.0, k1: 0.1, t_ramp: 1.0 });
/// let th = ThesisLine::new(NeoHookean::new(1.0).unwrap(), &p, 101).unwrap();
/// assert_eq!(th.nodes(), 101);
/// ```
#[derive(Clone, Debug)]
pub struct ThesisLine<E: StrainEnergy> {
    energy: E,
    ramp: Ramp,
    dx: f64,
    x_ref: Vec<f64>,
    mu: Vec<f64>,
    mu_x: Vec<f64>,
    eta: Vec<f64>,
    k: Vec<f64>,
    gamma0: f64,
    atol_cell: f64,
    /// The cells each node stands for: those within half a spacing of it (`N` in all).
    node_cells: Vec<f64>,
}

impl<E: StrainEnergy> ThesisLine<E> {
    /// Builds the scheme on `n ≥ 3` nodes from the line description (fields sampled at the
    /// nodes; `K` is used as the drag per unit reference length of unit cells, as in the thesis).
    ///
    /// ```
    /// use celltissue::line::thesis_scheme::ThesisLine;
    /// use celltissue::line::LineParams;
    /// let p = LineParams::unit_cells(10);
    /// assert!(ThesisLine::new(celltissue::NeoHookean::new(1.0)?, &p, 2).is_err()); // needs n ≥ 3
    /// assert_eq!(ThesisLine::new(celltissue::NeoHookean::new(1.0)?, &p, 21)?.nodes(), 21);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn new(energy: E, p: &LineParams, n: usize) -> Result<Self, LineError> {
        if n < 3 {
            return Err(LineError::invalid("nodes", n, ">= 3 for the thesis scheme"));
        }
        let ramp = match &p.right {
            RightEnd::Prescribed(r) => r.clone(),
            _ => {
                return Err(LineError::Combination(
                    "the thesis scheme supports only a prescribed right end".into(),
                ))
            }
        };
        if p.growth.is_some() || p.active.is_some() {
            return Err(LineError::Combination(
                "the thesis scheme supports neither growth nor active stress".into(),
            ));
        }
        let drawn = drawn_per_cell(p);
        let p = drawn.as_ref().unwrap_or(p);
        let l0 = p.total_length();
        let mean_cell = l0 / p.ref_lengths.len() as f64;
        let dx = l0 / (n - 1) as f64;
        let x_ref: Vec<f64> = (0..n).map(|i| i as f64 * dx).collect();
        // cells of unequal lengths: drag K/L(X) per unit X, per-cell lists read where each
        // node's cell is
        let cells = CellCensus::of_unequal(&p.ref_lengths);
        let sample = |f: &crate::cell::Field| match &cells {
            Some(c) => c.sample(f, &x_ref, l0),
            None => f.sample(&x_ref, l0),
        };
        let mu = sample(&p.mu);
        let mu_x = (0..n)
            .map(|i| {
                if i == 0 || i == n - 1 {
                    0.0
                } else {
                    (mu[i + 1] - mu[i - 1]) / (2.0 * dx)
                }
            })
            .collect();
        let eta = sample(&p.eta);
        let k = sample(&p.k)
            .into_iter()
            .zip(&x_ref)
            .map(|(k, &x)| match &cells {
                Some(c) => k / c.length_at(x),
                None => k / mean_cell,
            })
            .collect();
        let count_to = |x: f64| {
            let x = x.clamp(0.0, l0);
            cells.as_ref().map_or(x / mean_cell, |c| c.count_to(x))
        };
        let node_cells = x_ref
            .iter()
            .map(|&x| count_to(x + 0.5 * dx) - count_to(x - 0.5 * dx))
            .collect();
        Ok(Self {
            energy,
            ramp,
            dx,
            x_ref,
            mu,
            mu_x,
            eta,
            k,
            gamma0: p.gamma0,
            atol_cell: p.atol_cell,
            node_cells,
        })
    }

    /// Number of nodes `n`.
    ///
    /// ```
    /// use celltissue::line::thesis_scheme::ThesisLine;
    /// use celltissue::line::LineParams;
    /// let th = ThesisLine::new(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(10), 11)?;
    /// assert_eq!(th.nodes(), 11);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn nodes(&self) -> usize {
        self.x_ref.len()
    }

    #[inline]
    fn node<S: Scalar>(&self, i: usize, t: f64, y: &[S], yp: &[S]) -> (S, S) {
        let n = self.nodes();
        if i == 0 {
            (S::from(0.0), S::from(0.0))
        } else if i == n - 1 {
            let (l, ld) = self.ramp.eval(t);
            (S::from(l), S::from(ld))
        } else {
            (y[i - 1], yp[i - 1])
        }
    }

    /// Node stretch `λ_i` and rate: centred inside, one-sided second order at the ends.
    fn stretch(&self, i: usize, t: f64, y: &[f64], yp: &[f64]) -> (f64, f64) {
        let n = self.nodes();
        let h2 = 2.0 * self.dx;
        let p = |k| self.node::<f64>(k, t, y, yp);
        let (a, b, c, s) = if i == 0 {
            (p(0), p(1), p(2), 1.0)
        } else if i == n - 1 {
            (p(n - 1), p(n - 2), p(n - 3), -1.0)
        } else {
            let ((xm, vm), (xp, vp)) = (p(i - 1), p(i + 1));
            return ((xp - xm) / h2, (vp - vm) / h2);
        };
        // (∓3x₁ ± 4x₂ ∓ x₃)/(2dX) with s = +1 at the left end, −1 at the right end
        (
            s * (-3.0 * a.0 + 4.0 * b.0 - c.0) / h2,
            s * (-3.0 * a.1 + 4.0 * b.1 - c.1) / h2,
        )
    }
}

impl<E: StrainEnergy> CellArray for ThesisLine<E> {
    fn dim(&self) -> usize {
        self.nodes() - 2
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
        let n = self.nodes();
        let dx = self.dx;
        let inv2 = 1.0 / (2.0 * dx);
        let invsq = 1.0 / (dx * dx);
        let mut prev = self.node(0, t, y, yp);
        let mut cur = self.node(1, t, y, yp);
        for i in 1..n - 1 {
            let next = self.node(i + 1, t, y, yp);
            let lam = (next.0 - prev.0) * inv2;
            let l = lam.re();
            if !(l > 0.0 && l.is_finite()) {
                return Err(ResidualError::Recoverable {
                    reason: format!("node {} has non-positive stretch λ = {l:.6e}", i + 1),
                    component: Some(i - 1),
                });
            }
            let x_xx = (next.0 - cur.0 * 2.0 + prev.0) * invsq;
            let v_x = (next.1 - prev.1) * inv2;
            let v_xx = (next.1 - cur.1 * 2.0 + prev.1) * invsq;
            let resp = self.energy.line(l);
            let inv_l = lam.recip();
            let sig = lam.lift(resp.sigma, resp.dsigma);
            // σ_el'(λ) with its λ-derivative from a central difference of the law's tangent
            // (LineResponse has no third derivative; this only feeds the Newton matrix).
            let hh = 1e-6 * l.max(1e-3);
            let d2 =
                (self.energy.line(l + hh).dsigma - self.energy.line(l - hh).dsigma) / (2.0 * hh);
            let dsig = (lam - l) * d2 + resp.dsigma;
            let rhs = inv_l * self.gamma0 * (dsig * x_xx * self.mu[i] + sig * self.mu_x[i]);
            let mut lhs = cur.1 * self.k[i];
            let eta = self.eta[i];
            if eta != 0.0 {
                let il2 = inv_l * inv_l;
                lhs -= (inv_l * (il2 + 1.0) * v_xx - il2 * il2 * x_xx * v_x * 2.0)
                    * (eta * self.gamma0);
            }
            r[i - 1] = lhs - rhs;
            prev = cur;
            cur = next;
        }
        Ok(())
    }

    fn atol(&self) -> Option<Vec<f64>> {
        Some(vec![self.atol_cell * self.dx; self.dim()])
    }

    /// The nodes tested through their segments' stretches, as a cell array's boundaries are
    /// (docs/model.md §8.1): the node next to the wall against one segment and against its
    /// distance to the wall, every other one as the difference with the node before it, and
    /// the last one, before the prescribed end, also against its distance to `l(t)`.
    fn error_map(&self) -> Option<integrators::ErrorMap> {
        use integrators::{ErrorMap, Row};
        let dim = self.dim();
        let rows = (0..dim)
            .map(|k| match k {
                0 => Row::Anchor { size: self.dx },
                _ => Row::Difference { partner: k - 1 },
            })
            .collect();
        let map = ErrorMap::from_rows(rows).ok()?;
        if dim == 0 {
            return Some(map);
        }
        let ramp = self.ramp.clone();
        map.with_end_at(0, self.dx, integrators::error_map::fixed(0.0))
            .ok()?
            .with_end_at(
                dim - 1,
                self.dx,
                std::sync::Arc::new(move |t| ramp.eval(t).0),
            )
            .ok()
    }

    fn algebraic(&self) -> Vec<bool> {
        (1..self.nodes() - 1)
            .map(|i| self.k[i] == 0.0 && self.eta[i] == 0.0)
            .collect()
    }

    /// A Kelvin–Voigt cell's stress reads its strain rate.
    fn outputs_read_rates(&self) -> bool {
        self.eta.iter().any(|&e| e != 0.0)
    }
}

impl<E: StrainEnergy> LineModel for ThesisLine<E> {
    fn initial_state(&self) -> Vec<f64> {
        self.x_ref[1..self.nodes() - 1].to_vec()
    }
    fn initial_derivative_guess(&self) -> Vec<f64> {
        vec![0.0; self.dim()]
    }
    fn observe(&self, t: f64, y: &[f64], yp: &[f64]) -> Result<Snapshot, ResidualError> {
        let n = self.nodes();
        let mut s = Snapshot {
            t,
            x_ref: self.x_ref.clone(),
            mu: self.mu.clone(),
            cell_counts: Some(self.node_cells.clone()),
            ..Default::default()
        };
        for i in 0..n {
            let (x, _) = self.node::<f64>(i, t, y, yp);
            let (lam, lam_t) = self.stretch(i, t, y, yp);
            if !(lam > 0.0 && lam.is_finite()) {
                let end = i == 0 || i == n - 1;
                return Err(ResidualError::Recoverable {
                    reason: format!(
                        "node {} has non-positive stretch λ = {lam:.6e}{}",
                        i + 1,
                        if end {
                            " (its one-sided difference: the profile bends more sharply than \
                             the node spacing resolves, as a drag boundary layer thinner than \
                             it does; more nodes, or the conservative scheme)"
                        } else {
                            ""
                        }
                    ),
                    component: (i >= 1 && i < n - 1).then(|| i - 1),
                });
            }
            let resp = self.energy.line(lam);
            let eta = self.eta[i];
            s.x.push(x);
            s.centre.push(x);
            s.lambda.push(lam);
            s.alpha.push(lam);
            s.sigma_el.push(self.mu[i] * resp.sigma);
            s.sigma
                .push(self.mu[i] * resp.sigma + eta * lam_t * (1.0 + 1.0 / (lam * lam)));
            s.pressure
                .push(self.mu[i] * resp.pressure - eta * lam_t / (lam * lam));
            s.width.push(self.gamma0 / lam);
            s.kappa.push(1.0);
            s.g.push(1.0);
            s.g_dot.push(0.0);
        }
        Ok(s)
    }
}
