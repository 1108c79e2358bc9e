//! One cell of the line evaluated from the state ([`Line::eval_cell`]): stretch, width,
//! elastic, viscous and active stress, pressure and drag factor, generic over the scalar — the
//! piece the residual ([`super::residual`]) and the Jacobian ([`super::jacobian`]) sweeps share —
//! and the named errors for states outside the model's domain.

use super::*;

impl<E: StrainEnergy> Line<E> {
    /// Evaluates cell `j` (1-based). Rejects non-positive or non-finite stretch with a
    /// recoverable error naming the cell and the unknown.
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(4))?;
    /// // cell 2 compressed to 0.8 between x₁ = 1 and x₂ = 1.8
    /// let c = line.eval_cell(2, 0.0, &[1.0, 1.8, 3.0], &[0.0; 3])?;
    /// assert!((c.alpha - 0.8).abs() < 1e-15 && c.sigma < 0.0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[inline]
    pub fn eval_cell<S: Scalar>(
        &self,
        j: usize,
        t: f64,
        y: &[S],
        yp: &[S],
    ) -> Result<CellEval<S>, ResidualError> {
        let left = self.boundary(j - 1, t, y, yp);
        self.eval_cell_from(j, t, y, yp, left).map(|(e, _)| e)
    }

    /// [`eval_cell`](Line::eval_cell) with the left boundary's `(x, v)` already known (the
    /// residual streams over the cells and hands each cell's right boundary to the next, so
    /// every boundary is looked up once); also returns the right boundary's `(x, v)`.
    #[inline(always)]
    pub(crate) fn eval_cell_from<S: Scalar>(
        &self,
        j: usize,
        t: f64,
        y: &[S],
        yp: &[S],
        left: (S, S),
    ) -> Result<(CellEval<S>, (S, S)), ResidualError> {
        self.eval_cell_in::<S, Indexed, true>(Indexed(&self.layout), j, t, y, yp, left)
    }

    /// [`eval_cell_from`](Line::eval_cell_from) with the layout read through `lk`.
    #[inline(always)]
    pub(super) fn eval_cell_in<S: Scalar, L: Lookup, const EXT: bool>(
        &self,
        lk: L,
        j: usize,
        t: f64,
        y: &[S],
        yp: &[S],
        left: (S, S),
    ) -> Result<(CellEval<S>, (S, S)), ResidualError> {
        let right = self.boundary_in(lk, j, t, y, yp);
        let growth = match lk.gi(j - 1) {
            NONE => (S::from(1.0), S::from(0.0)),
            k => (y[k], yp[k]),
        };
        let mut e = self.eval_core(j, t, left, right, growth)?;
        // `EXT = false` compiles the test out of the thesis's sweep (measured: the runtime
        // test alone cost ≈ 7 % of the f64 residual)
        if EXT && self.uniform.extended {
            let av = match lk.vi(j - 1) {
                NONE => S::from(1.0),
                k => y[k],
            };
            self.extend_cell(j, &mut e, av)?;
        }
        Ok((e, right))
    }

    /// Cell `j` (1-based) from its left and right boundaries' `(x, v)` and its `(g, ġ)`
    /// (a Maxwell branch and an external pressure are added by [`Line::extend_cell`]): the
    /// one expression of a cell's stretch, stresses, width and drag factor, shared by the
    /// residual (any scalar) and the line's own Jacobian ([`Line::jacobian_into`], which seeds
    /// the cell's local directions in dual numbers).
    #[inline(always)]
    pub(super) fn eval_core<S: Scalar>(
        &self,
        j: usize,
        t: f64,
        (xl, vl): (S, S),
        (xr, vr): (S, S),
        (g, gd): (S, S),
    ) -> Result<CellEval<S>, ResidualError> {
        let c = &self.cells;
        let i = j - 1;
        // divisions bound the f64 sweep (≈ 5 per cell): 1/L₀ of a uniform line is computed
        // once, and without growth (g ≡ 1, ġ ≡ 0) `λ/g` and `1/g` are skipped — the general
        // expressions reduce exactly (x/1 = x, x·1 = x, x − 0 = x), so the rows are bitwise
        // the same
        let inv_l0 = match self.uniform.inv_l0 {
            Some(v) => v,
            None => 1.0 / c.l0[i],
        };
        let lam = (xr - xl) * inv_l0;
        let growing = self.growth.is_some();
        let alpha = if growing { lam / g } else { lam };
        let a = alpha.re();
        if !(a > 0.0 && a.is_finite() && g.re() > 0.0) {
            return Err(ResidualError::Recoverable {
                reason: format!(
                    "cell {j} has non-positive or non-finite stretch (λ = {:.6e}, g = {:.6e})",
                    lam.re(),
                    g.re()
                ),
                component: self.blame(j),
            });
        }
        if let Err(e) = self.energy.admissible([a, 1.0 / a, 1.0]) {
            return Err(self.outside_domain(j, e));
        }
        let alpha_dot = if growing {
            let inv_g = g.recip();
            (vr - vl) * inv_l0 * inv_g - alpha * gd * inv_g
        } else {
            (vr - vl) * inv_l0
        };
        let resp = self.energy.line(a);
        let mu = self.uniform.mu.unwrap_or_else(|| c.mu[i]);
        let sigma_el = alpha.lift(mu * resp.sigma, mu * resp.dsigma);
        let inv_a = alpha.recip();
        let mut sigma = sigma_el;
        let eta = self.uniform.eta.unwrap_or_else(|| c.eta[i]);
        if eta != 0.0 {
            sigma += alpha_dot * eta * (inv_a * inv_a + 1.0);
        }
        if let Some(act) = &self.active {
            let amp = c.active_amp[i] * act.b(t, c.phase[i]);
            if amp != 0.0 {
                sigma += ((lam - 1.0) * (0.5 * act.beta) + 1.0) * amp;
            }
        }
        let w = inv_a * (self.gamma0 * self.g2);
        let kappa = drag_factor(g, self.g2, self.m);
        Ok(CellEval {
            lam,
            alpha,
            alpha_dot,
            sigma_el,
            sigma,
            w,
            kappa,
            vl,
            vr,
            g,
        })
    }

    /// Adds cell `j`'s Maxwell branch (at viscous stretch `av`) and external pressure to its
    /// evaluation `e` (a Maxwell cell, without elastic law, loses its elastic stress). Called
    /// after [`Line::eval_core`] only when the line has either (`uniform.extended`), so the
    /// thesis's cell keeps its lean expression.
    #[inline(never)]
    pub(super) fn extend_cell<S: Scalar>(
        &self,
        j: usize,
        e: &mut CellEval<S>,
        av: S,
    ) -> Result<(), ResidualError> {
        if let Some(b) = &self.maxwell {
            if !b.admissible(av.re()) {
                return Err(self.bad_viscous_stretch(j, av.re()));
            }
            let ae = e.alpha.re() / av.re();
            if let Err(err) = self.energy.admissible([ae, 1.0 / ae, 1.0]) {
                return Err(self.outside_domain(j, err));
            }
            if !b.keeps_elastic() {
                e.sigma -= e.sigma_el;
                e.sigma_el = S::from(0.0);
            }
            e.sigma += b.stress(&self.energy, e.alpha, av);
        }
        let pe = self
            .uniform
            .p_ext
            .unwrap_or_else(|| self.cells.p_ext[j - 1]);
        if pe != 0.0 {
            e.sigma -= pe;
        }
        Ok(())
    }

    /// The recoverable error of cell `j` whose viscous stretch is not admissible.
    #[cold]
    #[inline(never)]
    pub(super) fn bad_viscous_stretch(&self, j: usize, av: f64) -> ResidualError {
        ResidualError::Recoverable {
            reason: format!(
                "cell {j} has non-positive or non-finite viscous stretch a_v = {av:.6e}"
            ),
            component: Some(self.layout.vi[j - 1]),
        }
    }

    /// The recoverable error of cell `j` whose state is outside the law's domain.
    #[cold]
    #[inline(never)]
    pub(super) fn outside_domain(&self, j: usize, e: crate::energy::EnergyError) -> ResidualError {
        ResidualError::Recoverable {
            reason: format!("cell {j}: {e}"),
            component: self.blame(j),
        }
    }
}
