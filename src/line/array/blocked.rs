//! The thesis's line swept in blocks of cells: the `f64` residual ([`Line::residual_blocked`])
//! and the iteration matrix ([`Line::jacobian_blocked`]) of a line without growth, Maxwell
//! branch, external pressure or active stress, with uniform fields, the boundary drag form
//! and `κ ≡ 1` (`m = 0`). Each block's stretches, stresses and widths are computed first in a
//! loop without branches or early exits, which the compiler turns into vector instructions
//! (two cells per division), and the rows (or Jacobian rows) are then written from them by the
//! general sweeps' own row expressions ([`Line::boundary_row`], [`Line::end_row`],
//! [`Line::emit`]). The per-cell expressions are those of [`Line::eval_core`] in the same
//! order, so every value is bitwise the one the general sweeps ([`super::residual`],
//! [`super::jacobian`]) write. A block with a cell outside the model's domain hands the
//! residual back to the general sweep, which reports it; the Jacobian evaluates that block
//! again cell by cell by the general expression, which names the first such cell.
//!
//! Written by hand because it is a restructuring of two loops, not an algorithm a crate
//! offers: the general sweeps' cell-by-cell `Result` keeps them scalar. Measured on the raw
//! Chapter 2 line at N = 1000 (BENCHMARKS.md), where the residual was about a quarter and the
//! Jacobian an eighth of the solve.

use super::jacobian::LocalCell;
use super::*;
use crate::energy::LawVisitor;
use integrators::linalg::{EntrySink, Matrix};
use num_dual::DualNum;

/// Cells per block: the block's stretches, stresses and widths stay in L1 between the two
/// loops.
pub(super) const BLOCK: usize = 64;

/// The line's uniform constants a block's cells are evaluated with.
#[derive(Clone, Copy)]
pub(super) struct Uniform {
    pub(super) inv_l0: f64,
    pub(super) mu: f64,
    pub(super) eta: f64,
    /// `γ₀ g₂` (a cell's width is this over its stretch).
    pub(super) w_scale: f64,
}

impl<E: StrainEnergy> Line<E> {
    /// The constants of the blocked sweep when it applies to this line as it is now (read
    /// from the public fields at each call, so an edit cannot leave it stale), else `None`.
    #[inline]
    fn blocked_constants(&self) -> Option<Uniform> {
        let u = &self.uniform;
        if u.extended
            || self.active.is_some()
            || self.m != 0.0
            || self.form != DragForm::Boundary
            || self.contiguous().is_none()
        {
            return None;
        }
        Some(Uniform {
            inv_l0: u.inv_l0?,
            mu: u.mu?,
            eta: u.eta?,
            w_scale: self.gamma0 * self.g2,
        })
    }

    /// Runs `block` with the line's law: the registry's [`crate::AnyEnergy`] picks its law
    /// once for the whole block ([`crate::AnyEnergy::visit`]), not at every cell.
    #[inline(always)]
    pub(crate) fn with_law<V: LawVisitor>(&self, block: V) -> V::Output {
        match self.energy.as_any_energy() {
            Some(law) => law.visit(block),
            None => block.visit(&self.energy),
        }
    }

    /// Cell `c` by the general `f64` expression, its layout read through `lk` (the cells of a
    /// blocked sweep that are not in a block: next to an end that is not an unknown, and the
    /// cell before a sweep's first block).
    #[inline]
    pub(super) fn general_cell<L: Lookup>(
        &self,
        lk: L,
        c: usize,
        t: f64,
        y: &[f64],
        yp: &[f64],
    ) -> Result<CellEval<f64>, ResidualError> {
        let left = self.boundary_in(lk, c - 1, t, y, yp);
        self.eval_cell_in::<f64, L, false>(lk, c, t, y, yp, left)
            .map(|(e, _)| e)
    }

    /// The rows of [`Line::residual_cells`] for `f64` state, in blocks (module docs), or
    /// `None` when the blocked sweep does not apply or a block meets a cell outside the
    /// model's domain (the caller then runs the general sweep, which names that cell).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn residual_blocked(
        &self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
        off: usize,
        first: usize,
        last: usize,
    ) -> Option<Result<(), ResidualError>> {
        let uniform = self.blocked_constants()?;
        let lk = self.contiguous()?;
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
        // entry 0: the cell before the block; entries 1..=len: the block's cells
        let mut sig = [0.0; BLOCK + 1];
        let mut wid = [0.0; BLOCK + 1];
        let mut c = first;
        while c <= last {
            // cells whose two boundaries are unknowns c − 2 and c − 1
            let end = block_end(c, last, lk.last);
            if end == c {
                let cur = match general(c) {
                    Ok(e) => e,
                    Err(e) => return Some(Err(e)),
                };
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
            let cells = Stretches::of(y, yp, c, end, uniform);
            let (vl, vr) = (cells.vl, cells.vr);
            (sig[0], wid[0]) = (p.sigma, p.w);
            let ok = self.with_law(Block {
                cells,
                sig: &mut sig[1..=len],
                wid: &mut wid[1..=len],
            });
            if !ok {
                return None;
            }
            // boundary c + k − 1 (unknown c + k − 2) between cells c + k − 1 and c + k; the
            // velocity of the left cell's right boundary is the right cell's left one
            let cell = |k: usize, vr: f64| block_cell(sig[k], wid[k], vr);
            let rows = &mut r[c - 2 - off..end - 2 - off];
            match (self.width, self.uniform.k_face) {
                // Line::boundary_row with κ = 1, uniform K and the width rule fixed, so that
                // the loop has no branch left (the blocks' test pins it to boundary_row)
                (WidthRule::Mean, Some(kf)) => {
                    face_rows(rows, &sig[..=len], &wid[..=len], vl, kf, |a, b| {
                        WidthRule::Mean.face(a, b)
                    })
                }
                (WidthRule::Min, Some(kf)) => {
                    face_rows(rows, &sig[..=len], &wid[..=len], vl, kf, |a, b| {
                        WidthRule::Min.face(a, b)
                    })
                }
                (_, None) => {
                    for (k, row) in rows.iter_mut().enumerate() {
                        *row = self.boundary_row(c + k - 1, &cell(k, vl[k]), &cell(k + 1, vr[k]));
                    }
                }
            }
            prev = Some(cell(len, vr[len - 1]));
            c = end;
        }
        if last == n && self.right.is_free() {
            let p = prev.expect("at least one cell");
            r[lk.xi(n) - off] = self.end_row(t, &p, 0.0);
        }
        Some(Ok(()))
    }
}

/// The boundary positions and velocities of a block's cells (`xl[k]`, `xr[k]`: cell `k`'s left
/// and right boundary) and the line's uniform constants.
struct Stretches<'a> {
    xl: &'a [f64],
    xr: &'a [f64],
    vl: &'a [f64],
    vr: &'a [f64],
    uniform: Uniform,
}

/// A block's cells as [`Block`] evaluates them: the line's `η` and each cell's stress and
/// width by [`Line::eval_core`]'s expressions (`VISCOUS`: `η ≠ 0`), with whether every cell
/// is in the model's domain.
pub(super) trait BlockCells {
    /// The line's uniform `η`.
    fn eta(&self) -> f64;
    /// Each cell's stress and width into `sig`, `wid`; whether every cell is in the domain.
    fn stresses<E: StrainEnergy, const VISCOUS: bool>(
        &self,
        energy: &E,
        sig: &mut [f64],
        wid: &mut [f64],
    ) -> bool;
}

impl<'a> Stretches<'a> {
    /// Cells `c..end` of a line whose boundary `j` is unknown `j − 1` (`c ≥ 2`, every cell's
    /// right boundary an unknown).
    #[inline(always)]
    fn of(y: &'a [f64], yp: &'a [f64], c: usize, end: usize, uniform: Uniform) -> Self {
        Self {
            xl: &y[c - 2..end - 2],
            xr: &y[c - 1..end - 1],
            vl: &yp[c - 2..end - 2],
            vr: &yp[c - 1..end - 1],
            uniform,
        }
    }
}

/// The end (exclusive) of the block of cells from `c` in a sweep up to cell `last`: the cells
/// whose both boundaries are unknowns (`2 ≤ c`, right boundary `≤ unknown_last`), at most
/// [`BLOCK`] of them; `c` itself when cell `c` is not such a cell (it is then evaluated alone).
#[inline(always)]
pub(super) fn block_end(c: usize, last: usize, unknown_last: usize) -> usize {
    if c >= 2 && c <= unknown_last {
        (c + BLOCK).min(last + 1).min(unknown_last + 1)
    } else {
        c
    }
}

/// The last cell of a block as the next row needs it: stress, width, the velocity of its
/// right boundary and `κ = 1`; the other fields are not read by the boundary and end rows.
#[inline(always)]
pub(super) fn block_cell(sigma: f64, w: f64, vr: f64) -> CellEval<f64> {
    CellEval {
        lam: 0.0,
        alpha: 0.0,
        alpha_dot: 0.0,
        sigma_el: 0.0,
        sigma,
        w,
        kappa: 1.0,
        vl: 0.0,
        vr,
        g: 1.0,
    }
}

impl BlockCells for Stretches<'_> {
    fn eta(&self) -> f64 {
        self.uniform.eta
    }
    /// Each cell's stress and width into `sig`, `wid` by [`Line::eval_core`]'s expressions in
    /// its order (`VISCOUS`: `η ≠ 0`); whether every stretch is in the model's domain
    /// (positive, finite and admissible for `energy`), tested by comparisons only (`a < ∞`
    /// rather than `is_finite`'s bit test), so that the loop stays in vector lanes.
    #[inline(always)]
    fn stresses<E: StrainEnergy, const VISCOUS: bool>(
        &self,
        energy: &E,
        sig: &mut [f64],
        wid: &mut [f64],
    ) -> bool {
        let Uniform {
            inv_l0,
            mu,
            eta,
            w_scale,
        } = self.uniform;
        let len = sig.len();
        let (xl, xr, vl, vr) = (
            &self.xl[..len],
            &self.xr[..len],
            &self.vl[..len],
            &self.vr[..len],
        );
        let wid = &mut wid[..len];
        let mut ok = true;
        for k in 0..len {
            let a = (xr[k] - xl[k]) * inv_l0;
            ok &= (a > 0.0)
                & (a < f64::INFINITY)
                & crate::energy::in_domain(energy, [a, 1.0 / a, 1.0]);
            let inv_a = a.recip();
            let mut s = mu * energy.line(a).sigma;
            if VISCOUS {
                let alpha_dot = (vr[k] - vl[k]) * inv_l0;
                s += alpha_dot * eta * (inv_a * inv_a + 1.0);
            }
            sig[k] = s;
            wid[k] = inv_a * w_scale;
        }
        ok
    }
}

/// One block's stresses and widths ([`BlockCells::stresses`]) as a computation over the
/// concrete law, so that the registry's [`crate::AnyEnergy`] dispatches once per block and its
/// law's response inlines into the vectorised loop.
pub(super) struct Block<'a, C> {
    pub(super) cells: C,
    pub(super) sig: &'a mut [f64],
    pub(super) wid: &'a mut [f64],
}

impl<C: BlockCells> LawVisitor for Block<'_, C> {
    /// Whether every cell is in the model's domain.
    type Output = bool;
    // Not inlined: `AnyEnergy::visit` holds one copy per law, and inlined into that match the
    // loop lost its law's inlined response (the registry's neo-Hookean line took 18 % more
    // instructions than the concrete law's; a call per block of 64 cells costs nothing).
    // The dual block below is the other way round: not inlined, it cost 17 % more.
    #[inline(never)]
    fn visit<L: StrainEnergy>(self, law: &L) -> bool {
        let Block { cells, sig, wid } = self;
        // the viscous term's test taken out of the loop, which then has no branch
        if cells.eta() != 0.0 {
            cells.stresses::<L, true>(law, sig, wid)
        } else {
            cells.stresses::<L, false>(law, sig, wid)
        }
    }
}

/// [`Block`] for the Jacobian: each cell of the block in dual numbers seeded along its right
/// boundary (`x` with 1, `v` with `cj`), by [`Line::eval_core`]'s expressions in its order
/// (without growth, `g ≡ 1`).
struct DualBlock<'a, 'b> {
    cells: Stretches<'b>,
    cj: f64,
    sig: &'a mut [Dual64],
    wid: &'a mut [Dual64],
}

impl LawVisitor for DualBlock<'_, '_> {
    /// Whether every stretch is in the model's domain.
    type Output = bool;
    #[inline(always)]
    fn visit<L: StrainEnergy>(self, law: &L) -> bool {
        let DualBlock {
            cells,
            cj,
            sig,
            wid,
        } = self;
        let d = Dual64::new;
        let Uniform {
            inv_l0,
            mu,
            eta,
            w_scale,
        } = cells.uniform;
        let mut ok = true;
        for (k, (sk, wk)) in sig.iter_mut().zip(wid.iter_mut()).enumerate() {
            let lam = (d(cells.xr[k], 1.0) - d(cells.xl[k], 0.0)) * inv_l0;
            let a = lam.re;
            ok &=
                (a > 0.0) & (a < f64::INFINITY) & crate::energy::in_domain(law, [a, 1.0 / a, 1.0]);
            let alpha_dot = (d(cells.vr[k], cj) - d(cells.vl[k], 0.0)) * inv_l0;
            let resp = law.line(a);
            let mut s = lam.lift(mu * resp.sigma, mu * resp.dsigma);
            let inv_a = DualNum::recip(&lam);
            if eta != 0.0 {
                s += alpha_dot * eta * (inv_a * inv_a + 1.0);
            }
            *sk = s;
            *wk = inv_a * w_scale;
        }
        ok
    }
}

/// [`Line::boundary_row`] of the boundaries between consecutive cells of a block, for a
/// uniform `K` (`kf`) and `κ = 1`: `rows[k]` is the row between cells `k` and `k + 1` of
/// `sig`, `wid` (stress and width; entry 0 the cell before the block), whose shared boundary
/// moves at `v[k]`. The same operations in the same order as `boundary_row`.
#[inline(always)]
pub(super) fn face_rows(
    rows: &mut [f64],
    sig: &[f64],
    wid: &[f64],
    v: &[f64],
    kf: f64,
    face: impl Fn(f64, f64) -> f64,
) {
    let kappa = (1.0 + 1.0) * 0.5;
    let len = rows.len();
    let (sig, wid, v) = (&sig[..=len], &wid[..=len], &v[..len]);
    for k in 0..len {
        let f = face(wid[k], wid[k + 1]) * (sig[k + 1] - sig[k]);
        rows[k] = kappa * v[k] * kf - f;
    }
}

impl<E: StrainEnergy> Line<E> {
    /// The whole iteration matrix of [`Line::jacobian_into`] for the lines of
    /// [`Line::residual_blocked`], in blocks ([`Line::jacobian_boundaries`]); from
    /// [`PAR_MIN_CELLS`] cells with two threads, a band matrix is filled in two column windows
    /// at once ([`integrators::linalg::BandMatrix::split_columns_mut`]) and the two rows that straddle them after.
    /// Every entry is added once into the zeroed matrix, so the result is the serial one bit
    /// for bit, and so is the error: the first cell outside the model's domain in the line's
    /// order. `None` when the blocked sweep does not apply.
    pub(super) fn jacobian_blocked(
        &self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        cj: f64,
        jac: &mut JacobianSink,
    ) -> Option<Result<(), ResidualError>> {
        self.blocked_constants()?;
        let n = self.n_cells();
        if self.threads >= 2 && n >= PAR_MIN_CELLS {
            if let Matrix::Banded(band) = jac {
                // boundary b's row (unknown b − 1) has columns b − 2 ..= b: boundaries
                // 1 ..= c − 1 lie in columns < c, boundaries c + 2 ..= N − 1 and the end in
                // columns ≥ c; boundaries c and c + 1 straddle the windows
                let c = n / 2;
                let (mut left, mut right) = band.split_columns_mut(c);
                let (first, second) = rayon::join(
                    || self.jacobian_boundaries(t, y, yp, cj, &mut left, 1, c - 1, false),
                    || self.jacobian_boundaries(t, y, yp, cj, &mut right, c + 2, n - 1, true),
                );
                let middle = first
                    .and_then(|()| self.jacobian_boundaries(t, y, yp, cj, jac, c, c + 1, false));
                return Some(middle.and(second));
            }
        }
        Some(self.jacobian_boundaries(t, y, yp, cj, jac, 1, n - 1, true))
    }

    /// The Jacobian rows of boundaries `b0..=b1` (`1 ≤ b0`, `b1 ≤ N − 1`; none when
    /// `b1 < b0`) and, with `end`, of a free right end, added into `jac`: each block's cells
    /// (`b0..=b1 + 1`) are evaluated in dual numbers seeded along their right boundaries, by
    /// [`Line::eval_core`]'s expressions in its order and without its early exit, and each row
    /// is emitted by the general sweep's own [`Line::emit`] and row expressions, so every
    /// entry is bitwise the general sweep's. A block with a cell outside the model's domain is
    /// evaluated again cell by cell by [`Line::eval_core`], which names the first such cell.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn jacobian_boundaries<J: EntrySink>(
        &self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        cj: f64,
        jac: &mut J,
        b0: usize,
        b1: usize,
        end: bool,
    ) -> Result<(), ResidualError> {
        let uniform = self
            .blocked_constants()
            .expect("called for the lines of the blocked sweep");
        let lk = self.contiguous().expect("a contiguous layout");
        let n = self.n_cells();
        let d = Dual64::new;
        // a cell seeded along its right boundary (x with 1, v with cj), as the general sweep
        let local = |s: CellEval<Dual64>| LocalCell { s, g: s };
        let general = |c: usize| -> Result<LocalCell, ResidualError> {
            let (l, r) = (self.boundary(c - 1, t, y, yp), self.boundary(c, t, y, yp));
            let xl = (d(l.0, 0.0), d(l.1, 0.0));
            let xr = (d(r.0, 1.0), d(r.1, cj));
            self.eval_core(c, t, xl, xr, (d(1.0, 0.0), d(0.0, 0.0)))
                .map(local)
        };
        let boundary_rows = |jac: &mut J, b: usize, p: &LocalCell, q: &LocalCell| {
            self.emit(jac, lk.xi(b), b, [p, q], None, cj, |e| {
                self.boundary_row(b, &e[0], &e[1])
            });
        };
        let last_cell = (b1 + 1).min(n);
        let mut prev = general(b0)?;
        let mut sig = [d(0.0, 0.0); BLOCK];
        let mut wid = [d(0.0, 0.0); BLOCK];
        let mut c = b0 + 1;
        while c <= last_cell {
            if c > lk.last {
                // the last cell, next to a prescribed end
                let cur = general(c)?;
                boundary_rows(jac, c - 1, &prev, &cur);
                prev = cur;
                c += 1;
                continue;
            }
            let stop = (c + BLOCK).min(last_cell + 1).min(lk.last + 1);
            let len = stop - c;
            let cells = Stretches::of(y, yp, c, stop, uniform);
            let (vl, vr) = (cells.vl, cells.vr);
            let ok = self.with_law(DualBlock {
                cells,
                cj,
                sig: &mut sig[..len],
                wid: &mut wid[..len],
            });
            if !ok {
                for cell in c..stop {
                    general(cell)?;
                }
                unreachable!("a block failed the domain test that every one of its cells passes");
            }
            for k in 0..len {
                let z = d(0.0, 0.0);
                let cur = local(CellEval {
                    lam: z,
                    alpha: z,
                    alpha_dot: z,
                    sigma_el: z,
                    sigma: sig[k],
                    w: wid[k],
                    kappa: d(1.0, 0.0),
                    vl: d(vl[k], 0.0),
                    vr: d(vr[k], cj),
                    g: d(1.0, 0.0),
                });
                boundary_rows(jac, c + k - 1, &prev, &cur);
                prev = cur;
            }
            c = stop;
        }
        if end && self.right.is_free() {
            debug_assert_eq!(last_cell, n);
            self.emit(jac, lk.xi(n), n, [&prev], None, cj, |e| {
                self.end_row(t, &e[0], d(0.0, 0.0))
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cell::Field;
    use crate::line::build::{discrete, LineParams};
    use crate::NeoHookean;

    /// A uniform line of `n` cells that the blocked sweep applies to.
    fn line(n: usize, eta: f64, width: WidthRule, free: bool) -> Line<NeoHookean> {
        let mut p = LineParams::unit_cells(n);
        p.k = Field::Constant(0.3);
        p.eta = Field::Constant(eta);
        p.width = width;
        p.gamma0 = 1.3;
        if free {
            p.right = RightEnd::Free(None);
        }
        discrete(NeoHookean::new(2.0).unwrap(), &p).unwrap()
    }

    fn state(n: usize) -> (Vec<f64>, Vec<f64>) {
        let y = (0..n)
            .map(|i| (i + 1) as f64 + 0.2 * ((i as f64) * 0.7).sin())
            .collect();
        let yp = (0..n).map(|i| 0.1 * ((i as f64) * 1.3).cos()).collect();
        (y, yp)
    }

    /// The rows of cells `first..=last` by the general sweep (the blocked one bypassed).
    fn general(
        l: &Line<NeoHookean>,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
        off: usize,
        first: usize,
        last: usize,
    ) -> Result<(), ResidualError> {
        let lk = l.contiguous().unwrap();
        l.residual_cells_in::<f64, _, false>(lk, 0.4, y, yp, r, off, first, last)
    }

    #[test]
    fn blocked_rows_are_the_general_rows_bitwise() {
        // several blocks and a partial one, every sub-range start a two-thread half uses,
        // with and without viscosity, both width rules, free and prescribed ends
        let n = 2 * BLOCK + 17;
        for (l, case) in cases(n) {
            let (y, yp) = state(l.dim());
            for first in [1, 2, 3, BLOCK, BLOCK + 1, n - 1, n] {
                let off = if first == 1 { 0 } else { first - 2 };
                let mut want = vec![f64::NAN; y.len() - off];
                general(&l, &y, &yp, &mut want, off, first, n).unwrap();
                let mut got = vec![f64::NAN; y.len() - off];
                l.residual_blocked(0.4, &y, &yp, &mut got, off, first, n)
                    .expect("the blocked sweep applies")
                    .unwrap();
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&got), bits(&want), "{case} first={first}");
            }
        }
    }

    /// The lines of `n` cells the blocked sweeps are checked on: with and without viscosity,
    /// both width rules, free and prescribed ends (with a label).
    fn cases(n: usize) -> impl Iterator<Item = (Line<NeoHookean>, String)> {
        [0.0, 0.7].into_iter().flat_map(move |eta| {
            [WidthRule::Mean, WidthRule::Min]
                .into_iter()
                .flat_map(move |width| {
                    [false, true].into_iter().map(move |free| {
                        let case = format!("eta={eta} {width:?} free={free}");
                        (line(n, eta, width, free), case)
                    })
                })
        })
    }

    #[test]
    fn the_registry_law_gives_the_concrete_laws_rows_and_jacobian_bitwise() {
        // AnyEnergy picks its law once per block (AnyEnergy::visit): the same rows as the
        // line built on the concrete law, for η = 0 and η ≠ 0
        let n = 2 * BLOCK + 17;
        for eta in [0.0, 0.7] {
            let concrete = line(n, eta, WidthRule::Mean, true);
            let mut p = LineParams::unit_cells(n);
            p.k = Field::Constant(0.3);
            p.eta = Field::Constant(eta);
            p.gamma0 = 1.3;
            p.right = RightEnd::Free(None);
            let law = crate::AnyEnergy::from(NeoHookean::new(2.0).unwrap());
            let any = discrete(law, &p).unwrap();
            let (y, yp) = state(n);
            let (mut a, mut b) = (vec![f64::NAN; n], vec![f64::NAN; n]);
            concrete
                .residual_blocked(0.4, &y, &yp, &mut a, 0, 1, n)
                .unwrap()
                .unwrap();
            any.residual_blocked(0.4, &y, &yp, &mut b, 0, 1, n)
                .unwrap()
                .unwrap();
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&a), bits(&b), "eta={eta}");
            // and the same iteration matrix
            let mut ja = Matrix::zeros(n, &concrete.pattern());
            let mut jb = Matrix::zeros(n, &any.pattern());
            concrete
                .jacobian_blocked(0.4, &y, &yp, 2.0, &mut ja)
                .unwrap()
                .unwrap();
            any.jacobian_blocked(0.4, &y, &yp, 2.0, &mut jb)
                .unwrap()
                .unwrap();
            let (Matrix::Banded(ma), Matrix::Banded(mb)) = (&ja, &jb) else {
                unreachable!("a line's pattern is banded")
            };
            assert_eq!(bits(&ma.data), bits(&mb.data), "eta={eta}");
        }
    }

    #[test]
    fn a_collapsed_cell_in_a_block_hands_over_to_the_general_sweep() {
        let n = 2 * BLOCK + 17;
        let l = line(n, 0.7, WidthRule::Mean, true);
        for bad in [2, 40, BLOCK + 1, n] {
            let (mut y, yp) = state(l.dim());
            // boundary `bad` onto boundary `bad − 1`: cell `bad` has zero stretch
            y[bad - 1] = y[bad - 2];
            let mut r = vec![0.0; y.len()];
            assert!(l.residual_blocked(0.4, &y, &yp, &mut r, 0, 1, n).is_none());
            let err = l.residual_cells(0.4, &y, &yp, &mut r, 0, 1, n).unwrap_err();
            assert!(err.to_string().contains(&format!("cell {bad} ")), "{err}");
        }
    }

    /// The iteration matrix of `l` by the general sweep (uniform fields hidden, so the
    /// blocked sweep does not apply; the fields' vectors hold the same values).
    fn general_jacobian(l: &Line<NeoHookean>, y: &[f64], yp: &[f64], cj: f64) -> Matrix {
        let mut slow = l.clone();
        slow.uniform = UniformFields::default();
        assert!(slow.blocked_constants().is_none());
        let mut m = Matrix::zeros(l.dim(), &l.pattern());
        assert!(slow.jacobian_into(0.4, y, yp, cj, &mut m).unwrap());
        m
    }

    #[test]
    fn blocked_jacobian_is_the_general_jacobian_bitwise() {
        let n = 2 * BLOCK + 17;
        for (l, case) in cases(n) {
            let (y, yp) = state(l.dim());
            let want = general_jacobian(&l, &y, &yp, 3.5);
            let mut got = Matrix::zeros(l.dim(), &l.pattern());
            l.jacobian_blocked(0.4, &y, &yp, 3.5, &mut got)
                .expect("the blocked sweep applies")
                .unwrap();
            for i in 0..l.dim() {
                for j in i.saturating_sub(1)..(i + 2).min(l.dim()) {
                    let (g, w) = (got.get(i, j), want.get(i, j));
                    assert_eq!(g.to_bits(), w.to_bits(), "{case} ({i}, {j})");
                }
            }
            // and the public entry point takes it
            let mut via = Matrix::zeros(l.dim(), &l.pattern());
            assert!(l.jacobian_into(0.4, &y, &yp, 3.5, &mut via).unwrap());
            let mid = (via.get(n / 2, n / 2), got.get(n / 2, n / 2));
            assert_eq!(mid.0.to_bits(), mid.1.to_bits());
        }
    }

    #[test]
    fn a_collapsed_cell_is_the_general_sweeps_error() {
        let n = 2 * BLOCK + 17;
        let l = line(n, 0.7, WidthRule::Mean, true);
        let mut slow = l.clone();
        slow.uniform = UniformFields::default();
        for bad in [1, 2, 40, BLOCK + 1, n] {
            let (mut y, yp) = state(l.dim());
            // cell `bad` collapsed (cell 1 against the wall at 0)
            y[bad - 1] = if bad == 1 { 0.0 } else { y[bad - 2] };
            let mut m = Matrix::zeros(l.dim(), &l.pattern());
            let err = l
                .jacobian_blocked(0.4, &y, &yp, 1.0, &mut m)
                .unwrap()
                .unwrap_err();
            let want = slow.jacobian_into(0.4, &y, &yp, 1.0, &mut m).unwrap_err();
            assert_eq!(err, want);
            assert!(err.to_string().contains(&format!("cell {bad} ")), "{err}");
        }
    }

    #[test]
    fn two_thread_jacobian_is_the_one_thread_jacobian_bitwise() {
        // a line long enough to split, filled in two column windows and the straddling rows
        let n = PAR_MIN_CELLS + 21;
        for free in [true, false] {
            let mut l = line(n, 0.7, WidthRule::Mean, free);
            let (y, yp) = state(l.dim());
            let mut one = Matrix::zeros(l.dim(), &l.pattern());
            l.jacobian_blocked(0.4, &y, &yp, 2.5, &mut one)
                .unwrap()
                .unwrap();
            l.set_threads(2);
            let mut two = Matrix::zeros(l.dim(), &l.pattern());
            l.jacobian_blocked(0.4, &y, &yp, 2.5, &mut two)
                .unwrap()
                .unwrap();
            let (Matrix::Banded(a), Matrix::Banded(b)) = (&one, &two) else {
                unreachable!("a line's pattern is banded")
            };
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&a.data), bits(&b.data), "free={free}");
            // a collapsed cell in either window or between them: the one-thread error
            let c = n / 2;
            for bad in [3, c - 1, c, c + 1, c + 2, c + 3, n - 1] {
                let mut yb = y.clone();
                yb[bad - 1] = yb[bad - 2];
                l.set_threads(1);
                let serial = l.jacobian_blocked(0.4, &yb, &yp, 2.5, &mut one).unwrap();
                l.set_threads(2);
                let split = l.jacobian_blocked(0.4, &yb, &yp, 2.5, &mut two).unwrap();
                assert!(serial.is_err());
                assert_eq!(split, serial, "bad={bad}");
            }
        }
    }

    #[test]
    fn lines_outside_the_thesis_case_take_the_general_sweep() {
        let (y, yp) = state(20);
        let mut r = vec![0.0; 20];
        let mut l = line(20, 0.0, WidthRule::Mean, true);
        assert!(l.residual_blocked(0.0, &y, &yp, &mut r, 0, 1, 20).is_some());
        l.m = 1.0;
        assert!(l.residual_blocked(0.0, &y, &yp, &mut r, 0, 1, 20).is_none());
        l.m = 0.0;
        l.form = DragForm::Centre;
        assert!(l.residual_blocked(0.0, &y, &yp, &mut r, 0, 1, 20).is_none());
        let mut p = LineParams::unit_cells(20);
        p.right = RightEnd::Free(None);
        p.mu = Field::gaussian_bump(1.0, 1.0, 0.5, 0.2);
        let l = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
        assert!(l.residual_blocked(0.0, &y, &yp, &mut r, 0, 1, 20).is_none());
    }
}
