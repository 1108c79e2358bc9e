//! The line's residual rows (docs/model.md §2.9): the per-face forces and the boundary, centre,
//! end, growth and flow rows, and the sweep over the cells that writes them — serial, on two
//! threads for long lines, and with the layout's fast paths (contiguous unknowns, uniform
//! fields). [`super::Line`]'s `CellArray::residual` calls [`Line::residual_cells`].

use super::*;

impl<E: StrainEnergy> Line<E> {
    /// `k_face[b]`, without reading the vector when it is uniform.
    #[inline(always)]
    pub(super) fn k_face_at(&self, b: usize) -> f64 {
        self.uniform.k_face.unwrap_or_else(|| self.k_face[b])
    }

    /// The force across the face between cells `p` and `cur`: `W_face (σ_cur − σ_p)`.
    #[inline(always)]
    pub(super) fn face_force<S: Scalar>(&self, p: &CellEval<S>, cur: &CellEval<S>) -> S {
        self.width.face(p.w, cur.w) * (cur.sigma - p.sigma)
    }

    /// Row of interior boundary `b` in the boundary drag form (cells `p = b`, `cur = b + 1`).
    #[inline(always)]
    pub(super) fn boundary_row<S: Scalar>(
        &self,
        b: usize,
        p: &CellEval<S>,
        cur: &CellEval<S>,
    ) -> S {
        let f = self.face_force(p, cur);
        let kappa = (p.kappa + cur.kappa) * 0.5;
        kappa * p.vr * self.k_face_at(b) - f
    }

    /// Row of interior boundary `b` in the cell-centre drag form: cell `p = b`'s drag minus
    /// the face forces `f_prev` (left of cell `b`) and `f` (right of it).
    #[inline(always)]
    pub(super) fn centre_row<S: Scalar>(&self, b: usize, p: &CellEval<S>, f_prev: S, f: S) -> S {
        p.kappa * (p.vl + p.vr) * self.cells.k_cell[b - 1] - f_prev - f
    }

    /// Row of the free right end (cell `p = N`; `f_prev` is the face force left of cell `N`,
    /// used by the cell-centre form).
    #[inline(always)]
    pub(super) fn end_row<S: Scalar>(&self, t: f64, p: &CellEval<S>, f_prev: S) -> S {
        let n = self.n_cells();
        let f_n = -(p.w * p.sigma) + self.f_ext(t);
        match self.form {
            DragForm::Boundary => p.kappa * p.vr * self.k_face[n] - f_n,
            DragForm::Centre => p.kappa * (p.vl + p.vr) * self.cells.k_cell[n - 1] - f_prev - f_n,
        }
    }

    /// Row of cell `cur`'s growth stretch: `ġ − G(σ)` (`ypg` is `ġ`).
    #[inline(always)]
    pub(super) fn growth_row<S: Scalar>(
        &self,
        law: &dyn GrowthLaw,
        ypg: S,
        cur: &CellEval<S>,
    ) -> S {
        ypg - crate::cell::growth_at(law, cur.sigma)
    }

    /// Row of cell `cur`'s viscous stretch: `ȧ_v − a_v σ_m(α/a_v)/η_m`.
    #[inline(always)]
    pub(super) fn flow_row<S: Scalar>(
        &self,
        b: &MaxwellBranch,
        av: S,
        avd: S,
        cur: &CellEval<S>,
    ) -> S {
        avd - b.rate(av, b.stress(&self.energy, cur.alpha, av))
    }

    /// Applied force on a free right end at `t` (0 if none).
    #[inline]
    pub(super) fn f_ext(&self, t: f64) -> f64 {
        match &self.right {
            RightEnd::Free(Some(f)) => f(t).0,
            _ => 0.0,
        }
    }

    /// The residual with cells `1..c0` on this thread and `c0..=N` on a second one, or `None`
    /// when the line cannot be split there (a ring, or `c0` outside `2..N`). The rows of cells
    /// `1..c0` all come before the row of boundary `c0 − 1`, which starts the second half's
    /// rows, so the halves write disjoint slices of `r`. Same result as the serial sweep,
    /// including which error is reported (the first half's, if both fail).
    pub(super) fn residual_two_threads<S: Scalar>(
        &self,
        t: f64,
        y: &[S],
        yp: &[S],
        r: &mut [S],
        c0: usize,
    ) -> Option<Result<(), ResidualError>> {
        let n = self.n_cells();
        if self.right.is_periodic() || c0 < 2 || c0 > n {
            return None;
        }
        let split = self.layout.xi[c0 - 1];
        if split == NONE {
            return None;
        }
        let (ra, rb) = r.split_at_mut(split);
        // the second half on a rayon worker (no thread started per residual)
        let (res_a, res_b) = rayon::join(
            || self.residual_cells(t, y, yp, ra, 0, 1, c0 - 1),
            || self.residual_cells(t, y, yp, rb, split, c0, n),
        );
        Some(res_a.and(res_b))
    }

    /// The residual rows of cells `first..=last` (and of the free right end when `last = N`),
    /// written to `r[row − off]`: the serial sweep is `(1, N)` with `off = 0`; a sweep that
    /// starts inside the line first evaluates the two cells before `first` for its running
    /// state (the previous cell and, for the cell-centre form, the face force left of it), so
    /// every row is computed by the same expression as in the serial sweep.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn residual_cells<S: Scalar>(
        &self,
        t: f64,
        y: &[S],
        yp: &[S],
        r: &mut [S],
        off: usize,
        first: usize,
        last: usize,
    ) -> Result<(), ResidualError> {
        if let (Some(yf), Some(ypf), Some(rf)) = (S::as_f64s(y), S::as_f64s(yp), S::as_f64s_mut(r))
        {
            if let Some(res) = self.residual_blocked(t, yf, ypf, rf, off, first, last) {
                return res;
            }
            if let Some(res) = self.residual_blocked_growing(t, yf, ypf, rf, off, first, last) {
                return res;
            }
        }
        let ind = Indexed(&self.layout);
        match (self.contiguous(), self.uniform.extended) {
            (Some(lk), false) => {
                self.residual_cells_in::<S, _, false>(lk, t, y, yp, r, off, first, last)
            }
            (Some(lk), true) => {
                self.residual_cells_in::<S, _, true>(lk, t, y, yp, r, off, first, last)
            }
            (None, false) if self.interleaved().is_some() => {
                let lk = self.interleaved().expect("checked");
                self.residual_cells_in::<S, _, false>(lk, t, y, yp, r, off, first, last)
            }
            (None, false) => {
                self.residual_cells_in::<S, _, false>(ind, t, y, yp, r, off, first, last)
            }
            (None, true) => {
                self.residual_cells_in::<S, _, true>(ind, t, y, yp, r, off, first, last)
            }
        }
    }

    /// The layout of a line without growth that is not a ring, if `self.layout` is that of
    /// the current `N` and right end: boundary `j`'s unknown is `j − 1` (the wall `x₀` is not
    /// an unknown), so the residual need not stream `layout.xi` and `layout.gi`. Derived from
    /// the same inputs as `Line::rebuild_layout` and checked against the layout's size in
    /// O(1), so it is never out of step with the layout itself.
    #[inline]
    pub(super) fn contiguous(&self) -> Option<Contiguous> {
        if self.growth.is_some() || self.maxwell.is_some() || self.right.is_periodic() {
            return None;
        }
        let n = self.n_cells();
        let last = n - 1 + self.right.is_free() as usize;
        (self.layout.dim == last && self.layout.xi.len() == n + 1 && self.layout.gi.len() == n)
            .then_some(Contiguous { last })
    }

    /// The layout of a growing line without Maxwell branch that is not a ring, if
    /// `self.layout` is that of the current `N` and right end (checked in O(1) against the
    /// layout's size, as [`Line::contiguous`] is).
    #[inline]
    pub(super) fn interleaved(&self) -> Option<Interleaved> {
        if self.growth.is_none() || self.maxwell.is_some() || self.right.is_periodic() {
            return None;
        }
        let n = self.n_cells();
        let last = n - 1 + self.right.is_free() as usize;
        (self.layout.dim == n + last && self.layout.xi.len() == n + 1 && self.layout.gi.len() == n)
            .then_some(Interleaved { last })
    }

    /// [`residual_cells`](Line::residual_cells) with the layout read through `lk`.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(super) fn residual_cells_in<S: Scalar, L: Lookup, const EXT: bool>(
        &self,
        lay: L,
        t: f64,
        y: &[S],
        yp: &[S],
        r: &mut [S],
        off: usize,
        first: usize,
        last: usize,
    ) -> Result<(), ResidualError> {
        let n = self.n_cells();
        // F_{b−1} for the cell-centre form (F₀ = 0 at the wall).
        let (mut prev, mut f_prev, mut left) = if first == 1 {
            let prev = if self.right.is_periodic() {
                Some(self.eval_cell(n, t, y, yp)?)
            } else {
                None
            };
            (prev, S::from(0.0), self.boundary_in(lay, 0, t, y, yp))
        } else {
            let lb = self.boundary_in(lay, first - 2, t, y, yp);
            let (p, right) = self.eval_cell_in::<S, L, EXT>(lay, first - 1, t, y, yp, lb)?;
            let f_prev = if first >= 3 {
                let llb = self.boundary_in(lay, first - 3, t, y, yp);
                let (pp, _) = self.eval_cell_in::<S, L, EXT>(lay, first - 2, t, y, yp, llb)?;
                self.face_force(&pp, &p)
            } else {
                S::from(0.0)
            };
            (Some(p), f_prev, right)
        };
        // in f64, the growth rows go to the law in blocks (`GrowthLaw::values`): each row's
        // unknown and stress wait in `pending` until the block is full
        let batch = S::as_f64s(y).is_some();
        let mut pending = GrowthRows::default();
        for c in first..=last {
            let (cur, right) = self.eval_cell_in::<S, L, EXT>(lay, c, t, y, yp, left)?;
            left = right;
            let gk = lay.gi(c - 1);
            if gk != NONE {
                if let Some(law) = &self.growth {
                    if batch {
                        if pending.push(gk, cur.sigma.re()) {
                            pending.flush(law.as_ref(), yp, r, off);
                        }
                    } else {
                        r[gk - off] = self.growth_row(law.as_ref(), yp[gk], &cur);
                    }
                }
            }
            let vk = lay.vi(c - 1);
            if vk != NONE {
                if let Some(b) = &self.maxwell {
                    r[vk - off] = self.flow_row(b, y[vk], yp[vk], &cur);
                }
            }
            if let Some(p) = prev {
                let b = c - 1;
                let row = lay.xi(b);
                match self.form {
                    DragForm::Boundary => {
                        if row != NONE {
                            r[row - off] = self.boundary_row(b, &p, &cur);
                        }
                    }
                    DragForm::Centre => {
                        let f = self.face_force(&p, &cur);
                        if row != NONE {
                            r[row - off] = self.centre_row(b, &p, f_prev, f);
                        }
                        f_prev = f;
                    }
                }
            }
            prev = Some(cur);
        }
        if let Some(law) = &self.growth {
            pending.flush(law.as_ref(), yp, r, off);
        }
        if last == n && self.right.is_free() {
            let p = prev.expect("at least one cell");
            r[lay.xi(n) - off] = self.end_row(t, &p, f_prev);
        }
        Ok(())
    }
}

/// Growth rows per call of [`GrowthLaw::values`].
const GROWTH_BLOCK: usize = 64;

/// Growth rows `ġ − G(σ)` waiting for their block's law call: each row's unknown and its
/// cell's stress. The rows written are bitwise [`Line::growth_row`]'s (`GrowthLaw::values`
/// is `value` per entry).
pub(super) struct GrowthRows {
    unknown: [usize; GROWTH_BLOCK],
    sigma: [f64; GROWTH_BLOCK],
    len: usize,
}

impl Default for GrowthRows {
    fn default() -> Self {
        Self {
            unknown: [0; GROWTH_BLOCK],
            sigma: [0.0; GROWTH_BLOCK],
            len: 0,
        }
    }
}

impl GrowthRows {
    /// Queues the row of unknown `k` at stress `sigma`; `true` when the block is full.
    #[inline(always)]
    pub(super) fn push(&mut self, k: usize, sigma: f64) -> bool {
        self.unknown[self.len] = k;
        self.sigma[self.len] = sigma;
        self.len += 1;
        self.len == GROWTH_BLOCK
    }

    /// Writes the queued rows into `r` (row `k` at `r[k − off]`) and empties the queue.
    #[inline(never)]
    pub(super) fn flush<S: Scalar>(
        &mut self,
        law: &dyn GrowthLaw,
        yp: &[S],
        r: &mut [S],
        off: usize,
    ) {
        let mut g = [0.0; GROWTH_BLOCK];
        let g = &mut g[..self.len];
        law.values(&self.sigma[..self.len], g);
        for (&k, &gk) in self.unknown[..self.len].iter().zip(g.iter()) {
            r[k - off] = yp[k] - S::from(gk);
        }
        self.len = 0;
    }
}
