//! A growing line's `f64` residual swept in blocks of cells ([`Line::residual_blocked_growing`]):
//! the rows of a dividing line in the thesis's setting (growth by a law of the stress, no
//! Maxwell branch, external pressure or active stress, uniform fields, the boundary drag form,
//! `κ ≡ 1`). Each block's positions, velocities and growth stretches are gathered from the
//! interleaved layout (`g` of cell `i + 1` at unknown `2i`, boundary `j` at `2j − 1`), its
//! stresses and widths computed in a loop without branches or early exits (vector
//! instructions, two cells per division), the boundary rows written by
//! [`super::blocked`]'s face rows and the growth rows `ġ − G(σ)` handed to the law in blocks
//! ([`crate::cell::GrowthLaw::values`]). The per-cell expressions are [`Line::eval_core`]'s in
//! its order, so every row is bitwise the general sweep's ([`super::residual`]); a block with a
//! cell outside the model's domain hands the call back to that sweep, which names the cell.
//!
//! Written by hand for the reason [`super::blocked`] is: the general sweep's cell-by-cell
//! `Result` keeps it scalar, and a dividing line spends most of its time in residuals.

use super::blocked::{block_cell, block_end, face_rows, Block, BlockCells, Uniform, BLOCK};
use super::residual::GrowthRows;
use super::*;

impl<E: StrainEnergy> Line<E> {
    /// The rows of [`Line::residual_cells`] for `f64` state of a growing line in the setting
    /// of the module docs, in blocks, or `None` when the blocked sweep does not apply or a
    /// block meets a cell outside the model's domain (the caller then runs the general sweep,
    /// which names that cell).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn residual_blocked_growing(
        &self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
        off: usize,
        first: usize,
        last: usize,
    ) -> Option<Result<(), ResidualError>> {
        let u = &self.uniform;
        if u.extended || self.active.is_some() || self.m != 0.0 || self.form != DragForm::Boundary {
            return None;
        }
        let lk = self.interleaved()?;
        let law = self.growth.as_deref()?;
        let kf = u.k_face?;
        // (a dividing line's reference lengths differ once cells have divided: each cell's
        // 1/L₀ is then gathered with the block, as `eval_core` computes it)
        let inv_l0 = u.inv_l0;
        let uniform = Uniform {
            inv_l0: inv_l0.unwrap_or(f64::NAN),
            mu: u.mu?,
            eta: u.eta?,
            w_scale: self.gamma0 * self.g2,
        };
        let n = self.n_cells();
        let general = |c: usize| self.general_cell(lk, c, t, y, yp);
        let mut prev = if first == 1 {
            None
        } else {
            match general(first - 1) {
                Ok(e) => Some(e),
                Err(e) => return Some(Err(e)),
            }
        };
        let mut pending = GrowthRows::default();
        let mut cells = GrowingCells::default();
        // entry 0: the cell before the block; entries 1..=len: the block's cells
        let mut sig = [0.0; BLOCK + 1];
        let mut wid = [0.0; BLOCK + 1];
        let mut rows = [0.0; BLOCK];
        let mut c = first;
        while c <= last {
            // cells whose two boundaries are unknowns (2c − 3 and 2c − 1)
            let end = block_end(c, last, lk.last);
            if end == c {
                let cur = match general(c) {
                    Ok(e) => e,
                    Err(e) => return Some(Err(e)),
                };
                if pending.push(lk.gi(c - 1), cur.sigma) {
                    pending.flush(law, yp, r, off);
                }
                if let Some(p) = prev {
                    let row = lk.xi(c - 1);
                    if row != NONE {
                        r[row - off] = self.boundary_row(c - 1, &p, &cur);
                    }
                }
                prev = Some(cur);
                c += 1;
                continue;
            }
            // a block starts at cell 2 or later, so its previous cell has been evaluated
            let p = prev.expect("the cell before a block is evaluated");
            let len = end - c;
            cells.gather(y, yp, (&self.cells.l0, inv_l0), c, len, uniform);
            (sig[0], wid[0]) = (p.sigma, p.w);
            let ok = self.with_law(Block {
                cells: &cells,
                sig: &mut sig[1..=len],
                wid: &mut wid[1..=len],
            });
            if !ok {
                return None;
            }
            // boundary c + k − 1 between cells c + k − 1 and c + k moves at cell c + k's vl
            let (rs, sg, wd) = (&mut rows[..len], &sig[..=len], &wid[..=len]);
            // the width rule fixed, so that the loop has no branch left
            match self.width {
                WidthRule::Mean => {
                    face_rows(rs, sg, wd, &cells.vl, kf, |a, b| WidthRule::Mean.face(a, b))
                }
                WidthRule::Min => {
                    face_rows(rs, sg, wd, &cells.vl, kf, |a, b| WidthRule::Min.face(a, b))
                }
            }
            for (k, &row) in rows[..len].iter().enumerate() {
                r[lk.xi(c + k - 1) - off] = row;
                if pending.push(lk.gi(c + k - 1), sig[k + 1]) {
                    pending.flush(law, yp, r, off);
                }
            }
            prev = Some(block_cell(sig[len], wid[len], cells.vr[len - 1]));
            c = end;
        }
        pending.flush(law, yp, r, off);
        if last == n && self.right.is_free() {
            let p = prev.expect("at least one cell");
            r[lk.xi(n) - off] = self.end_row(t, &p, 0.0);
        }
        Some(Ok(()))
    }
}

/// One block's cells gathered from the interleaved layout: cell `k`'s left and right
/// boundary positions and velocities, its growth stretch and rate, and the line's uniform
/// constants.
struct GrowingCells {
    inv_l0: [f64; BLOCK],
    xl: [f64; BLOCK],
    xr: [f64; BLOCK],
    vl: [f64; BLOCK],
    vr: [f64; BLOCK],
    g: [f64; BLOCK],
    gd: [f64; BLOCK],
    len: usize,
    uniform: Uniform,
}

impl Default for GrowingCells {
    fn default() -> Self {
        Self {
            inv_l0: [0.0; BLOCK],
            xl: [0.0; BLOCK],
            xr: [0.0; BLOCK],
            vl: [0.0; BLOCK],
            vr: [0.0; BLOCK],
            g: [0.0; BLOCK],
            gd: [0.0; BLOCK],
            len: 0,
            uniform: Uniform {
                inv_l0: 0.0,
                mu: 0.0,
                eta: 0.0,
                w_scale: 0.0,
            },
        }
    }
}

impl BlockCells for &GrowingCells {
    fn eta(&self) -> f64 {
        self.uniform.eta
    }
    /// Each cell's stress and width into `sig`, `wid` by [`Line::eval_core`]'s expressions
    /// with growth, in its order (`VISCOUS`: `η ≠ 0`); whether every cell is in the model's
    /// domain (positive, finite elastic stretch admissible for `energy`, positive growth
    /// stretch), tested by comparisons only so that the loop stays in vector lanes.
    #[inline(always)]
    fn stresses<E: StrainEnergy, const VISCOUS: bool>(
        &self,
        energy: &E,
        sig: &mut [f64],
        wid: &mut [f64],
    ) -> bool {
        let Uniform {
            mu, eta, w_scale, ..
        } = self.uniform;
        let len = self.len;
        let (sig, wid) = (&mut sig[..len], &mut wid[..len]);
        let mut ok = true;
        for k in 0..len {
            let inv_l0 = self.inv_l0[k];
            let g = self.g[k];
            let lam = (self.xr[k] - self.xl[k]) * inv_l0;
            let a = lam / g;
            ok &= (a > 0.0)
                & (a < f64::INFINITY)
                & (g > 0.0)
                & crate::energy::in_domain(energy, [a, 1.0 / a, 1.0]);
            let mut s = mu * energy.line(a).sigma;
            let inv_a = a.recip();
            if VISCOUS {
                let inv_g = g.recip();
                let alpha_dot = (self.vr[k] - self.vl[k]) * inv_l0 * inv_g - a * self.gd[k] * inv_g;
                s += alpha_dot * eta * (inv_a * inv_a + 1.0);
            }
            sig[k] = s;
            wid[k] = inv_a * w_scale;
        }
        ok
    }
}

impl GrowingCells {
    /// Cells `c..c + len` (`c ≥ 2`, both boundaries of each an unknown): boundary `j` at
    /// `2j − 1`, the growth stretch of cell `i + 1` at `2i`; `1/L₀` the line's uniform one
    /// or each cell's `1/L₀` from the reference lengths `l0`.
    #[inline(always)]
    fn gather(
        &mut self,
        y: &[f64],
        yp: &[f64],
        (l0, inv_l0): (&[f64], Option<f64>),
        c: usize,
        len: usize,
        uniform: Uniform,
    ) {
        match inv_l0 {
            Some(v) => self.inv_l0[..len].fill(v),
            None => {
                for (o, &l) in self.inv_l0[..len].iter_mut().zip(&l0[c - 1..c - 1 + len]) {
                    *o = 1.0 / l;
                }
            }
        }
        // cell c + k: left boundary 2(c + k) − 3, growth stretch 2(c + k) − 2, right 2(c + k) − 1
        let b0 = 2 * c - 3;
        let (ys, yps) = (&y[b0..b0 + 2 * len + 1], &yp[b0..b0 + 2 * len + 1]);
        for k in 0..len {
            let i = 2 * k;
            self.xl[k] = ys[i];
            self.g[k] = ys[i + 1];
            self.xr[k] = ys[i + 2];
            self.vl[k] = yps[i];
            self.gd[k] = yps[i + 1];
            self.vr[k] = yps[i + 2];
        }
        self.len = len;
        self.uniform = uniform;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cell::{Field, TanhGrowth};
    use crate::line::build::{discrete, LineParams};
    use crate::NeoHookean;

    /// A uniform growing line of `n` cells that the blocked sweep applies to; with `halves`,
    /// every third cell has half the reference length (as daughters have).
    fn line(n: usize, eta: f64, width: WidthRule, free: bool) -> Line<NeoHookean> {
        line_of(n, eta, width, free, false)
    }

    fn line_of(n: usize, eta: f64, width: WidthRule, free: bool, halves: bool) -> Line<NeoHookean> {
        let mut p = LineParams::unit_cells(n);
        if halves {
            p.ref_lengths = (0..n).map(|i| if i % 3 == 0 { 0.5 } else { 1.0 }).collect();
        }
        p.k = Field::Constant(0.3);
        p.eta = Field::Constant(eta);
        p.width = width;
        p.gamma0 = 1.3;
        p.growth = Some(Arc::new(TanhGrowth {
            sigma0: 0.3,
            gm: 1.7,
        }));
        if free {
            p.right = RightEnd::Free(None);
        }
        discrete(NeoHookean::new(2.0).unwrap(), &p).unwrap()
    }

    /// A state of `l` with growth stretches between 1 and 2 and cell lengths near 1.
    fn state(l: &Line<NeoHookean>) -> (Vec<f64>, Vec<f64>) {
        let mut y = l.initial_state();
        let gi = &l.layout().gi;
        for (i, &k) in gi.iter().enumerate() {
            y[k] = 1.0 + 0.5 * (1.0 + ((i as f64) * 0.37).sin());
        }
        // boundaries near their initial positions (within a prescribed end's wall at N)
        for c in 1..=l.n_cells() {
            let k = l.layout().xi[c];
            if k != NONE {
                y[k] = c as f64 + 0.1 * ((c as f64) * 0.9).sin();
            }
        }
        let yp = (0..y.len())
            .map(|i| 0.1 * ((i as f64) * 1.3).cos())
            .collect();
        (y, yp)
    }

    /// The rows of cells `first..=last` by the general sweep (the blocked one bypassed).
    #[allow(clippy::too_many_arguments)]
    fn general(
        l: &Line<NeoHookean>,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
        off: usize,
        first: usize,
        last: usize,
    ) -> Result<(), ResidualError> {
        let lk = l.interleaved().unwrap();
        l.residual_cells_in::<f64, _, false>(lk, 0.4, y, yp, r, off, first, last)
    }

    /// The first row a two-thread half starting at cell `first` writes.
    fn offset(l: &Line<NeoHookean>, first: usize) -> usize {
        if first == 1 {
            0
        } else {
            l.layout().xi[first - 1]
        }
    }

    #[test]
    fn blocked_growing_rows_are_the_general_rows_bitwise() {
        // several blocks and a partial one, sub-ranges as the two-thread halves use them,
        // with and without viscosity, equal and unequal reference lengths, both width rules,
        // free and prescribed ends
        let n = 2 * BLOCK + 17;
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        for (eta, halves) in [(0.0, false), (0.7, false), (0.0, true), (0.7, true)] {
            for width in [WidthRule::Mean, WidthRule::Min] {
                for free in [false, true] {
                    let l = line_of(n, eta, width, free, halves);
                    assert_eq!(l.uniform.inv_l0.is_none(), halves);
                    let (y, yp) = state(&l);
                    for first in [1, 2, 3, BLOCK, BLOCK + 1, n - 1, n] {
                        let off = offset(&l, first).min(l.layout().gi[first - 1]);
                        let mut want = vec![f64::NAN; y.len() - off];
                        general(&l, &y, &yp, &mut want, off, first, n).unwrap();
                        let mut got = vec![f64::NAN; y.len() - off];
                        l.residual_blocked_growing(0.4, &y, &yp, &mut got, off, first, n)
                            .expect("the blocked sweep applies")
                            .unwrap();
                        assert_eq!(
                            bits(&got),
                            bits(&want),
                            "eta={eta} halves={halves} {width:?} free={free} first={first}"
                        );
                    }
                    // the public residual takes this path
                    let mut r = vec![f64::NAN; y.len()];
                    l.residual(0.4, &y, &yp, &mut r).unwrap();
                    let mut want = vec![f64::NAN; y.len()];
                    general(&l, &y, &yp, &mut want, 0, 1, n).unwrap();
                    assert_eq!(
                        bits(&r),
                        bits(&want),
                        "eta={eta} halves={halves} {width:?} free={free}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_collapsed_growing_cell_is_the_general_sweeps_error() {
        // a cell squeezed through zero, or a growth stretch at zero, inside a block: the
        // blocked sweep hands over and the residual names the cell as the general sweep does
        let n = 2 * BLOCK + 17;
        let l = line(n, 0.7, WidthRule::Mean, true);
        for bad in [BLOCK + 5, n - 1] {
            for g_zero in [false, true] {
                let (mut y, yp) = state(&l);
                if g_zero {
                    y[l.layout().gi[bad - 1]] = 0.0;
                } else {
                    y[l.layout().xi[bad]] = y[l.layout().xi[bad - 1]] - 0.1;
                }
                let mut got = vec![0.0; y.len()];
                assert!(l
                    .residual_blocked_growing(0.4, &y, &yp, &mut got, 0, 1, n)
                    .is_none());
                let err = l.residual(0.4, &y, &yp, &mut got).unwrap_err();
                let mut want = vec![0.0; y.len()];
                let general_err = general(&l, &y, &yp, &mut want, 0, 1, n).unwrap_err();
                assert_eq!(format!("{err:?}"), format!("{general_err:?}"));
                assert!(
                    format!("{err:?}").contains(&format!("cell {bad} ")),
                    "{err:?}"
                );
            }
        }
    }

    #[test]
    fn growing_lines_outside_the_setting_take_the_general_sweep() {
        let n = 20;
        let (y, yp) = state(&line(n, 0.0, WidthRule::Mean, true));
        let mut r = vec![0.0; y.len()];
        // cell-centre drag
        let mut l = line(n, 0.0, WidthRule::Mean, true);
        l.form = DragForm::Centre;
        assert!(l
            .residual_blocked_growing(0.4, &y, &yp, &mut r, 0, 1, n)
            .is_none());
        // a drag factor κ = (g g₂)^m
        let mut l = line(n, 0.0, WidthRule::Mean, true);
        l.m = 1.0;
        assert!(l
            .residual_blocked_growing(0.4, &y, &yp, &mut r, 0, 1, n)
            .is_none());
        // a line without growth
        let mut p = LineParams::unit_cells(n);
        p.right = RightEnd::Free(None);
        let plain = discrete(NeoHookean::new(2.0).unwrap(), &p).unwrap();
        let (y, yp) = (plain.initial_state(), vec![0.0; plain.dim()]);
        let mut r = vec![0.0; y.len()];
        assert!(plain
            .residual_blocked_growing(0.4, &y, &yp, &mut r, 0, 1, n)
            .is_none());
    }
}
