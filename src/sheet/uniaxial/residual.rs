//! The uniaxial sheet's residual: each cell's state (stretches, height, drag factor and the
//! stresses of its law, Maxwell branch, Kelvin–Voigt dashpots and external pressure) and the
//! face, viscous-stretch and growth rows of [`CellArray`] built from it.

use super::UniaxialSheet;
use crate::array::CellArray;
use crate::cell::{kelvin_voigt_sheet, ViscousBranch};
use crate::energy::{SheetResponse, StrainEnergy};
use crate::scalar::Scalar;
use crate::sheet::config::TopBoundary;
use crate::sheet::lift2;
use crate::substrate::{Dissipation, PowerLawDrag};
use integrators::{Pattern, ResidualError};
use std::cell::RefCell;

/// The state of one cell inside a residual evaluation.
#[derive(Clone, Copy)]
struct CellS<S> {
    l1: S,
    l2: S,
    h: S,
    kappa: S,
    s11: S,
    s22: S,
}

impl<E: StrainEnergy> UniaxialSheet<E> {
    /// The elastic stretch rates `α̇ᵢ = (λ̇ᵢ − αᵢ ġᵢ)/gᵢ` of cell `(j, k)` from the rates `yp`
    /// (`ldot` = the prescribed edge's velocity), given its elastic stretches `alpha`.
    #[inline]
    pub(super) fn stretch_rates<S: Scalar>(
        &self,
        y: &[S],
        yp: &[S],
        ldot: f64,
        j: usize,
        k: usize,
        alpha: [S; 2],
    ) -> [S; 2] {
        let l1 = (self.xb_s(yp, ldot, j, k) - self.xb_s(yp, ldot, j - 1, k)) * (1.0 / self.hx);
        let l2 = (self.yb_rate_s(yp, j, k) - self.yb_rate_s(yp, j, k - 1)) * (1.0 / self.hy);
        match &self.params.growth {
            Some(_) => {
                let gi = self.ig(j, k);
                [
                    (l1 - alpha[0] * yp[gi]) / y[gi],
                    (l2 - alpha[1] * yp[gi + 1]) / y[gi + 1],
                ]
            }
            None => [l1, l2],
        }
    }

    /// The law's response at `(λ₁, λ₂)` for cell `c`, cached in `cache` by exact argument
    /// values.
    #[inline]
    fn response(
        &self,
        cache: &RefCell<Vec<(f64, f64, SheetResponse)>>,
        c: usize,
        l1: f64,
        l2: f64,
    ) -> SheetResponse {
        let mut cache = cache.borrow_mut();
        let e = &mut cache[c];
        if e.0 == l1 && e.1 == l2 {
            return e.2;
        }
        let r = self.law.sheet(l1, l2);
        *e = (l1, l2, r);
        r
    }

    /// The substrate dissipation law `κ = (λ₁λ₂)^m` ([`PowerLawDrag`]).
    #[inline(always)]
    pub(super) fn dissipation(&self) -> PowerLawDrag {
        PowerLawDrag {
            m: self.params.drag_exponent,
        }
    }

    /// State of cell `(j, k)` inside a residual; errors on a non-positive stretch. With a
    /// Maxwell branch the rates `(ȧ₁, ȧ₂)` of its viscous stretches are pushed onto `rates`
    /// (kept apart, so that the common cell state stays small). `yp` and the edge velocity
    /// `ldot` enter only through the Kelvin–Voigt stress.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn cell_s<S: Scalar, const KV: bool>(
        &self,
        y: &[S],
        yp: &[S],
        lt: f64,
        ldot: f64,
        j: usize,
        k: usize,
        rates: &mut Vec<[S; 2]>,
    ) -> Result<CellS<S>, ResidualError> {
        let l1 = (self.xb_s(y, lt, j, k) - self.xb_s(y, lt, j - 1, k)) * (1.0 / self.hx);
        let l2 = (self.yb_s(y, j, k) - self.yb_s(y, j, k - 1)) * (1.0 / self.hy);
        let (a, b) = (l1.re(), l2.re());
        if !(a > 0.0 && a.is_finite()) {
            let comp = if self.x_is_unknown(j) {
                Some(self.ix(j, k))
            } else if j > 1 {
                Some(self.ix(j - 1, k))
            } else {
                None
            };
            return Err(ResidualError::Recoverable {
                reason: format!("non-positive stretch λ₁ = {a} in sheet cell (j={j}, k={k})"),
                component: comp,
            });
        }
        if !(b > 0.0 && b.is_finite()) {
            let kk = if self.y_is_unknown(k) { k } else { 0 };
            return Err(ResidualError::Recoverable {
                reason: format!("non-positive stretch λ₂ = {b} in sheet cell (j={j}, k={k})"),
                component: Some(self.iy(j, kk)),
            });
        }
        // a growing cell's laws see its stretch relative to the grown cell, α = λ/g
        let (al1, al2) = match &self.params.growth {
            Some(_) => {
                let gi = self.ig(j, k);
                let ok = |v: f64| v > 0.0 && v.is_finite();
                let (u, v) = (y[gi].re(), y[gi + 1].re());
                if !(ok(u) && ok(v)) {
                    return Err(ResidualError::Recoverable {
                        reason: format!(
                            "growth stretches (g₁, g₂) = ({u}, {v}) of sheet cell (j={j}, k={k}) must be finite and > 0"
                        ),
                        component: Some(if ok(u) { gi + 1 } else { gi }),
                    });
                }
                (l1 / y[gi], l2 / y[gi + 1])
            }
            None => (l1, l2),
        };
        let (a, b) = (al1.re(), al2.re());
        let c = (j - 1) * self.m + (k - 1);
        let branch = self.params.branch.as_ref();
        let (mut s11, mut s22) = if branch.is_none_or(|br| br.keeps_elastic()) {
            if let Err(e) = self.law.admissible([a, b, 1.0 / (a * b)]) {
                return Err(ResidualError::Recoverable {
                    reason: format!("sheet cell (j={j}, k={k}): {e}"),
                    component: self.x_is_unknown(j).then(|| self.ix(j, k)),
                });
            }
            let r = self.response(&self.cache, c, a, b);
            (
                lift2(al1, al2, r.s11, r.tangent[0][0], r.tangent[0][1]),
                lift2(al1, al2, r.s22, r.tangent[1][0], r.tangent[1][1]),
            )
        } else {
            (S::from(0.0), S::from(0.0))
        };
        if let Some(br) = branch {
            let q = self.iq(j, k);
            let av = [y[q], y[q + 1]];
            let (q1, q2) = (av[0].re(), av[1].re());
            if !(br.admissible(q1) && br.admissible(q2)) {
                return Err(ResidualError::Recoverable {
                    reason: format!(
                        "viscous stretches (a₁, a₂) = ({q1}, {q2}) of sheet cell (j={j}, k={k}) must be finite and > 0"
                    ),
                    component: Some(if br.admissible(q1) { q + 1 } else { q }),
                });
            }
            let (e1, e2) = (al1 / av[0], al2 / av[1]);
            let (x1, x2) = (e1.re(), e2.re());
            if let Err(e) = self.law.admissible([x1, x2, 1.0 / (x1 * x2)]) {
                return Err(ResidualError::Recoverable {
                    reason: format!("Maxwell branch of sheet cell (j={j}, k={k}): {e}"),
                    component: Some(q),
                });
            }
            let r = self.response(&self.branch_cache, c, x1, x2);
            let f = br.modulus_ratio(&self.law);
            let t = r.tangent;
            let sb = [
                lift2(e1, e2, f * r.s11, f * t[0][0], f * t[0][1]),
                lift2(e1, e2, f * r.s22, f * t[1][0], f * t[1][1]),
            ];
            s11 += sb[0];
            s22 += sb[1];
            rates.push(br.sheet_rate(av, sb));
        }
        if KV {
            let rate = self.stretch_rates(y, yp, ldot, j, k, [al1, al2]);
            let [v11, v22, _] = kelvin_voigt_sheet(self.params.eta, [al1, al2], rate);
            s11 += v11;
            s22 += v22;
        }
        if self.pressure {
            let pe = self.p_ext[j - 1];
            s11 -= S::from(pe);
            s22 -= S::from(pe);
        }
        let area = l1 * l2;
        let kappa = self.dissipation().kappa(area);
        // the height of an incompressible cell grown in plane: H = β₀ λ₃, λ₃ = 1/(α₁α₂)
        let h = if self.params.growth.is_some() {
            (al1 * al2).recip() * self.params.beta0
        } else {
            area.recip() * self.params.beta0
        };
        Ok(CellS {
            l1,
            l2,
            h,
            kappa,
            s11,
            s22,
        })
    }

    /// The residual; `KV`: whether cells carry the Kelvin–Voigt stress.
    fn residual_with<S: Scalar, const KV: bool>(
        &self,
        t: f64,
        y: &[S],
        yp: &[S],
        r: &mut [S],
    ) -> Result<(), ResidualError> {
        let (n, m) = (self.n, self.m);
        let lt = self.length(t);
        let ldot = if KV { self.length_rate(t) } else { 0.0 };
        let d = self.face_drag;
        let periodic = self.params.top == TopBoundary::Periodic;
        let mut cur: Vec<CellS<S>> = Vec::with_capacity(m);
        let mut next: Vec<CellS<S>> = Vec::with_capacity(m);
        // the viscous stretches' rates of the current and next column (with a branch)
        let (mut cur_rates, mut next_rates) = (Vec::new(), Vec::new());
        for k in 1..=m {
            cur.push(self.cell_s::<S, KV>(y, yp, lt, ldot, 1, k, &mut cur_rates)?);
        }
        for j in 1..=n {
            // viscous stretches of column j
            for (k, rate) in (1..=m).zip(&cur_rates) {
                let q = self.iq(j, k);
                r[q] = yp[q] - rate[0];
                r[q + 1] = yp[q + 1] - rate[1];
            }
            // growth stretches of column j: ġᵢ = G(σᵢᵢ) in the growing directions
            if let Some(g) = &self.params.growth {
                for (k, c) in (1..=m).zip(&cur) {
                    let gi = self.ig(j, k);
                    for (i, sigma) in [c.s11, c.s22].into_iter().enumerate() {
                        r[gi + i] = if g.directions.grows(i) {
                            yp[gi + i] - crate::cell::growth_at(g.law.as_ref(), sigma)
                        } else {
                            yp[gi + i]
                        };
                    }
                }
            }
            // y-faces of column j
            for k in 0..=m {
                if !self.y_is_unknown(k) {
                    continue;
                }
                let row = self.iy(j, k);
                if !periodic && k == m {
                    let c = &cur[m - 1];
                    let l = c.l1 * self.hx;
                    r[row] = yp[row] * (c.kappa * self.top_drag) + c.h * l * c.s22;
                    continue;
                }
                let (a, b) = if k == 0 {
                    (&cur[m - 1], &cur[0])
                } else {
                    (&cur[k - 1], &cur[k])
                };
                let h = (a.h + b.h) * 0.5;
                let l = (a.l1 + b.l1) * (0.5 * self.hx);
                let kap = (a.kappa + b.kappa) * 0.5;
                r[row] = yp[row] * (kap * d) - h * l * (b.s22 - a.s22);
            }
            if j < n {
                next.clear();
                next_rates.clear();
                for k in 1..=m {
                    next.push(self.cell_s::<S, KV>(y, yp, lt, ldot, j + 1, k, &mut next_rates)?);
                }
                for k in 1..=m {
                    let (a, b) = (&cur[k - 1], &next[k - 1]);
                    let row = self.ix(j, k);
                    let h = (a.h + b.h) * 0.5;
                    let w = (a.l2 + b.l2) * (0.5 * self.hy);
                    let kap = (a.kappa + b.kappa) * 0.5;
                    r[row] = yp[row] * (kap * d) - h * w * (b.s11 - a.s11);
                }
                std::mem::swap(&mut cur, &mut next);
                std::mem::swap(&mut cur_rates, &mut next_rates);
            } else if self.free_right() {
                // free side x = l: the last cell's own H, W
                for (k, c) in (1..=m).zip(&cur) {
                    let row = self.ix(n, k);
                    let w = c.l2 * self.hy;
                    r[row] = yp[row] * (c.kappa * self.side_drag) + c.h * w * c.s11;
                }
            }
        }
        Ok(())
    }
}

impl<E: StrainEnergy> CellArray for UniaxialSheet<E> {
    fn dim(&self) -> usize {
        self.n * self.block - if self.free_right() { 0 } else { self.m }
    }

    fn pattern(&self) -> Pattern {
        self.pattern.clone()
    }

    fn residual<S: Scalar>(
        &self,
        t: f64,
        y: &[S],
        yp: &[S],
        r: &mut [S],
    ) -> Result<(), ResidualError> {
        // the elastic path is compiled without the rate terms (no cost for them)
        if self.params.eta > 0.0 {
            self.residual_with::<S, true>(t, y, yp, r)
        } else {
            self.residual_with::<S, false>(t, y, yp, r)
        }
    }

    fn atol(&self) -> Option<Vec<f64>> {
        let a = self.atol_cell?;
        let mut v = vec![a * self.hy; self.dim()];
        for j in 1..=self.n {
            for k in 1..=self.m {
                if self.x_is_unknown(j) {
                    v[self.ix(j, k)] = a * self.hx;
                }
                // viscous and growth stretches are in cell units already
                for i in self.internal(j, k) {
                    v[i] = a;
                }
            }
        }
        Some(v)
    }

    /// Each face position tested through the stretch of its cell in its own direction
    /// (docs/model.md §8.1): `x_b(j, k)` differenced with `x_b(j − 1, k)`, `y_b(j, k)` with
    /// `y_b(j, k − 1)`; the first free face of each row/column (next to the fixed wall or
    /// base) is an anchor measured in cell sizes `h_X`, `h_Y`, and also tested against its
    /// distance to the wall or base; the last x-face of each row is also tested against its
    /// distance to `l(t)` (the stretch error of the cell at the prescribed edge, held to that
    /// cell's own stretch).
    fn error_map(&self) -> Option<integrators::ErrorMap> {
        use integrators::Row;
        let mut rows = vec![Row::Own; self.dim()];
        let k0 = match self.params.top {
            TopBoundary::Free => 1,
            TopBoundary::Periodic => 0,
        };
        for j in 1..=self.n {
            for k in (k0..=self.m).filter(|&k| self.y_is_unknown(k)) {
                rows[self.iy(j, k)] = if k == k0 {
                    Row::Anchor { size: self.hy }
                } else {
                    Row::Difference {
                        partner: self.iy(j, k - 1),
                    }
                };
            }
        }
        for j in (1..=self.n).filter(|&j| self.x_is_unknown(j)) {
            for k in 1..=self.m {
                rows[self.ix(j, k)] = if j == 1 {
                    Row::Anchor { size: self.hx }
                } else {
                    Row::Difference {
                        partner: self.ix(j - 1, k),
                    }
                };
            }
        }
        let mut map = integrators::ErrorMap::from_rows(rows).ok()?;
        // the cells with one side not an unknown: the first column at the wall x = 0, the
        // first row on the base y = 0 (free top), the last column at the prescribed edge l(t);
        // the free face's own error is their stretch error, tested against their own stretch
        let zero = integrators::error_map::fixed(0.0);
        if self.x_is_unknown(1) {
            for k in 1..=self.m {
                map = map.with_end_at(self.ix(1, k), self.hx, zero.clone()).ok()?;
            }
        }
        if k0 == 1 {
            for j in 1..=self.n {
                map = map.with_end_at(self.iy(j, 1), self.hy, zero.clone()).ok()?;
            }
        }
        if self.n >= 2 && !self.free_right() {
            let (ramp, l0, k1) = (self.params.ramp, self.l0(), self.params.k1);
            let edge: integrators::error_map::Position =
                std::sync::Arc::new(move |t| ramp.length(l0, k1, t));
            for k in 1..=self.m {
                map = map
                    .with_end_at(self.ix(self.n - 1, k), self.hx, edge.clone())
                    .ok()?;
            }
        }
        Some(map)
    }

    /// A Kelvin–Voigt cell's stresses and pressure read its stretch rates.
    fn outputs_read_rates(&self) -> bool {
        self.params.eta != 0.0
    }

    fn algebraic(&self) -> Vec<bool> {
        // without drag the face rows hold no rate, unless through the Kelvin–Voigt stress
        let mut v = vec![self.params.drag == 0.0 && self.params.eta == 0.0; self.dim()];
        for j in 1..=self.n {
            for k in 1..=self.m {
                for i in self.internal(j, k) {
                    v[i] = false;
                }
            }
        }
        v
    }
}
