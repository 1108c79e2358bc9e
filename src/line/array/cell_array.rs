//! [`Line`] as a [`CellArray`]: its size, pattern, residual and Jacobian entry points, tolerances,
//! error map and which unknowns are algebraic — the interface the integrators see.

use super::*;

impl<E: StrainEnergy> CellArray for Line<E> {
    fn dim(&self) -> usize {
        self.layout.dim
    }

    fn set_threads(&mut self, threads: usize) {
        self.threads = threads.max(1);
    }

    fn pattern(&self) -> Pattern {
        if self.right.is_periodic() {
            return Pattern::Sparse(Arc::new(SparsityPattern::from_entries(
                self.layout.dim,
                &self.jacobian_entries(),
            )));
        }
        // `rebuild_layout` numbers every cell's unknowns alike (g, a_v, then x), so the rows of
        // an interior cell are a shift of its neighbour's and only the ends can widen the band:
        // the first and last `BAND_WINDOW` cells and boundaries give the whole line's band,
        // without a walk over all N cells at every division (tested against the full walk)
        const BAND_WINDOW: usize = 4;
        let n = self.n_cells();
        let (mut lower, mut upper) = (0, 0);
        let mut widen = |i: usize, j: usize| {
            if i > j {
                lower = lower.max(i - j);
            } else {
                upper = upper.max(j - i);
            }
        };
        if n <= 2 * BAND_WINDOW + 2 {
            self.for_each_jacobian_entry(widen);
        } else {
            let tail = n - BAND_WINDOW;
            self.for_each_jacobian_entry_in(1..=BAND_WINDOW, 0..=BAND_WINDOW, &mut widen);
            self.for_each_jacobian_entry_in(tail..=n, tail..=n, &mut widen);
        }
        Pattern::Banded { lower, upper }
    }

    fn residual<S: Scalar>(
        &self,
        t: f64,
        y: &[S],
        yp: &[S],
        r: &mut [S],
    ) -> Result<(), ResidualError> {
        let n = self.n_cells();
        if n >= PAR_MIN_CELLS && self.threads >= 2 {
            if let Some(res) = self.residual_two_threads(t, y, yp, r, n / 2) {
                return res;
            }
        }
        self.residual_cells(t, y, yp, r, 0, 1, n)
    }

    fn jacobian(
        &self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        c: f64,
        jac: &mut JacobianSink,
    ) -> Result<bool, ResidualError> {
        self.jacobian_into(t, y, yp, c, jac)
    }

    fn atol(&self) -> Option<Vec<f64>> {
        let n = self.n_cells();
        let lay = &self.layout;
        let mut a = vec![self.atol_cell; lay.dim];
        for b in 0..=n {
            let k = lay.xi[b];
            if k == NONE {
                continue;
            }
            let left = if b >= 1 {
                self.cells.l0[b - 1]
            } else {
                self.cells.l0[n - 1]
            };
            let right = if b < n { self.cells.l0[b] } else { left };
            a[k] = self.atol_cell * left.min(right);
        }
        Some(a)
    }

    /// Positions tested through their cell's stretch (docs/model.md §8.1): boundary `b` is
    /// differenced with boundary `b − 1` when both are unknowns; the first free boundary is an
    /// anchor measured in lengths of its cell, and also against its distance to the wall (the
    /// stretch error of the first cell); the last free boundary before a prescribed end is
    /// also tested against its distance to `l(t)` (the stretch error of the end's cell, held
    /// to that cell's own stretch however crushed it is); on a ring the seam cell, from
    /// `x_{N−1}` to `x₀ + P`, is tested as the difference of its ends' errors
    /// ([`integrators::ErrorMap::with_seam`]); growth stretches keep their own test.
    fn error_map(&self) -> Option<integrators::ErrorMap> {
        use integrators::Row;
        let n = self.n_cells();
        let lay = &self.layout;
        // the boundaries' rows in increasing index (`xi` increases with `b`); the others (growth
        // stretches, viscous stretches) are own rows, not listed: no row per unknown is built
        // at each division event
        let rows = (0..=n).filter(|&b| lay.xi[b] != NONE).map(|b| {
            let row = match b.checked_sub(1).map(|c| (c, lay.xi[c])) {
                Some((_, p)) if p != NONE => Row::Difference { partner: p },
                Some((c, _)) => Row::Anchor {
                    size: self.cells.l0[c],
                },
                None => Row::Anchor {
                    size: self.cells.l0[0],
                },
            };
            (lay.xi[b], row)
        });
        let mut map = integrators::ErrorMap::from_listed_rows(lay.dim, rows).ok()?;
        if self.right.is_periodic() {
            // the seam cell N, from x_{N−1} to x_N = x₀ + P: no difference row holds it
            let (first, last) = (lay.xi[0], n.checked_sub(1).map_or(NONE, |b| lay.xi[b]));
            if n >= 2 && last != NONE {
                let l0 = self.cells.l0[n - 1];
                map = if first != NONE {
                    map.with_seam(first, last, l0, self.period).ok()?
                } else {
                    // a gauged ring (x₀ = 0 pinned): cell N ends at P, cell 1 starts at 0
                    use integrators::error_map::fixed;
                    map.with_end_at(last, l0, fixed(self.period))
                        .ok()?
                        .with_end_at(lay.xi[1], self.cells.l0[0], fixed(0.0))
                        .ok()?
                };
            }
            return Some(map);
        }
        // the cells with one end not an unknown (the first, at the wall x₀ = 0; the last, at
        // the prescribed end l(t)): the other end's own error is their stretch error, tested
        // against their own stretch
        if n >= 1 && lay.xi[0] == NONE && lay.xi[1] != NONE {
            let wall = integrators::error_map::fixed(0.0);
            map = map.with_end_at(lay.xi[1], self.cells.l0[0], wall).ok()?;
        }
        if let RightEnd::Prescribed(ramp) = &self.right {
            let k = n.checked_sub(1).map_or(NONE, |b| lay.xi[b]);
            if k != NONE {
                let ramp = ramp.clone();
                let end: integrators::error_map::Position =
                    std::sync::Arc::new(move |t| ramp.eval(t).0);
                map = map.with_end_at(k, self.cells.l0[n - 1], end).ok()?;
            }
        }
        Some(map)
    }

    fn algebraic(&self) -> Vec<bool> {
        let n = self.n_cells();
        let lay = &self.layout;
        let mut alg = vec![false; lay.dim];
        let periodic = self.right.is_periodic();
        let eta_at = |c: usize| -> f64 {
            if c >= 1 && c <= n {
                self.cells.eta[c - 1]
            } else if periodic {
                self.cells.eta[if c == 0 { n - 1 } else { 0 }]
            } else {
                0.0
            }
        };
        for b in 0..=n {
            let k = lay.xi[b];
            if k == NONE {
                continue;
            }
            let drag = match self.form {
                DragForm::Boundary => self.k_face[b],
                DragForm::Centre => self.cells.k_cell[b.max(1) - 1],
            };
            let visc = eta_at(b) != 0.0 || eta_at(b + 1) != 0.0;
            alg[k] = drag == 0.0 && !visc;
        }
        alg
    }

    /// A Kelvin–Voigt cell's stress (and pressure) reads its strain rate.
    fn outputs_read_rates(&self) -> bool {
        self.cells.eta.iter().any(|&e| e != 0.0)
    }
}
