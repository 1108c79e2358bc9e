//! Splitting cells of a [`Line`] into two daughters each (docs/model.md §2.8): one cell in
//! O(N) ([`Line::split_cell`]), or all `k` cells that fire at one time in one O(N + k) pass
//! ([`Line::split_cells`]):
//!
//! * daughters: reference length `L₀g/2` each, `g = 1`, the parent's `μ`, `η`, drag, active
//!   amplitude and phase `t_R`, and with a Maxwell branch the parent's viscous stretch `a_v`
//!   (intensive, like `α`: the branch's elastic stretch `α/a_v` and stress carry over);
//! * a new boundary at the midpoint `x_new = ½(x_{j−1} + x_j)` with the mean of the parent's two
//!   boundary drags (`K` for uniform drag);
//! * indices `> j` shift by one (one `Vec::insert` per per-cell field and one `splice` of the
//!   state; [`Line::split_cells`] moves the tail of each field once, in place, with all
//!   daughters inserted: `expand_in_place`), and the unknown layout is rebuilt.
//!
//! Continuous by construction: every existing boundary position (hence `l`), `Σ L₀g`, and each
//! daughter's elastic stretch `α = λ/g` (equal to the parent's), hence elastic `σ` and `p`, and
//! a Maxwell branch's stress.
//!
//! This is an inherent method of [`Line`] written here (not in `line/`) so the division logic
//! stays in one place; it uses only `Line`'s public fields and `Line::rebuild_layout`.

use super::EventError;
use crate::energy::StrainEnergy;
use crate::line::array::NONE;
use crate::line::Line;

/// What a split did (see [`Line::split_cell`] for a split).
///
/// ```
/// use celltissue::events::Split;
/// // a cell of reference length 1 that grew to g = 2 leaves daughters of reference length 1
/// let s = Split { x_new: 1.5, g_parent: 2.0, l0_daughter: 1.0 };
/// assert_eq!(s.l0_daughter, 1.0 * s.g_parent / 2.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Split {
    /// Position of the new boundary.
    pub x_new: f64,
    /// Parent's growth stretch at division.
    pub g_parent: f64,
    /// Daughters' reference length `L₀g/2`.
    pub l0_daughter: f64,
}

impl<E: StrainEnergy> Line<E> {
    /// Divides cell `j` (1-based) of the state `y` (positions and growth stretches in this
    /// line's layout): the line gains one cell and `y` one boundary and one `g` (O(N)).
    ///
    /// Requires growth (`g` in the state). On a ring the circumference ([`Line::period`]) does
    /// not change.
    ///
    /// ```
    /// use celltissue::line::build::{discrete, LineParams};
    /// use celltissue::boundary::RightEnd;
    /// use celltissue::cell::TanhGrowth;
    /// use celltissue::NeoHookean;
    /// use std::sync::Arc;
    /// let mut p = LineParams::unit_cells(3);
    /// p.right = RightEnd::Free(None);
    /// p.k = 1e-5.into();
    /// p.growth = Some(Arc::new(TanhGrowth::default()));
    /// let mut line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
    /// let mut y = line.initial_state(); // (g1, x1, g2, x2, g3, x3)
    /// y[2] = 2.0; // cell 2 has doubled
    /// let s = line.split_cell(2, 0.0, &mut y).unwrap();
    /// assert_eq!(line.n_cells(), 4);
    /// assert_eq!(s.x_new, 1.5);
    /// assert_eq!(y, vec![1.0, 1.0, 1.0, 1.5, 1.0, 2.0, 1.0, 3.0]);
    /// assert_eq!(line.cells().l0, vec![1.0, 1.0, 1.0, 1.0]);
    /// ```
    pub fn split_cell(&mut self, j: usize, t: f64, y: &mut Vec<f64>) -> Result<Split, EventError> {
        let n = self.n_cells();
        if j == 0 || j > n {
            return Err(EventError::NoSuchCell { cell: j, cells: n });
        }
        let i = j - 1;
        let gk = self.layout.gi[i];
        if gk == NONE {
            return Err(EventError::Unsupported(
                "division without growth (`g` is not in the state)".into(),
            ));
        }
        self.check_state_length(y)?;
        let (xl, _) = self.boundary(j - 1, t, y, y);
        let (xr, _) = self.boundary(j, t, y, y);
        let g = y[gk];
        if !(g > 0.0 && g.is_finite() && xr > xl) {
            return Err(EventError::Degenerate {
                cell: j,
                reason: format!("g = {g}, length = {}", xr - xl),
            });
        }
        let x_new = 0.5 * (xl + xr);
        let l0_parent = self.cells.l0[i];
        let l0_d = 0.5 * l0_parent * g;
        let c = &mut self.cells;
        c.l0[i] = l0_d;
        c.l0.insert(i + 1, l0_d);
        for v in [
            &mut c.mu,
            &mut c.eta,
            &mut c.k_cell,
            &mut c.active_amp,
            &mut c.phase,
            &mut c.x_ref,
            &mut c.p_ext,
        ] {
            let p = v[i];
            v.insert(i + 1, p);
        }
        let k_new = 0.5 * (self.k_face[j - 1] + self.k_face[j]);
        self.k_face.insert(j, k_new);
        self.l0_total += 2.0 * l0_d - l0_parent;
        // (.., g_j, x_j, ..) -> (.., 1, x_new, 1, x_j, ..): boundary j is interior after the
        // split; with a Maxwell branch (.., g_j, a_j, x_j, ..) -> (.., 1, a_j, x_new, 1, a_j, x_j, ..)
        match self.layout.vi[i] {
            NONE => {
                y.splice(gk..gk + 1, [1.0, x_new, 1.0]);
            }
            vk => {
                let a = y[vk];
                y.splice(gk..vk + 1, [1.0, a, x_new, 1.0, a]);
            }
        }
        self.rebuild_layout();
        debug_assert_eq!(y.len(), self.layout.dim);
        debug_assert_eq!(
            self.layout.xi[j],
            gk + 1 + usize::from(self.maxwell.is_some())
        );
        Ok(Split {
            x_new,
            g_parent: g,
            l0_daughter: l0_d,
        })
    }

    /// Divides every cell in `cells` (1-based, strictly increasing) of the state `y` in one
    /// O(N + k) pass: each per-cell field, the boundary drags and `y` are expanded once, in
    /// place, with the daughters inserted (the result is the same as
    /// [`split_cell`](Line::split_cell) applied in decreasing index order). Returns the splits
    /// in the order of `cells`; a split's `x_new` is the new boundary's position. Nothing
    /// changes on error.
    ///
    /// ```
    /// use celltissue::line::build::{discrete, LineParams};
    /// use celltissue::boundary::RightEnd;
    /// use celltissue::cell::TanhGrowth;
    /// use celltissue::NeoHookean;
    /// use std::sync::Arc;
    /// let mut p = LineParams::unit_cells(3);
    /// p.right = RightEnd::Free(None);
    /// p.k = 1e-5.into();
    /// p.growth = Some(Arc::new(TanhGrowth::default()));
    /// let mut line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
    /// let mut y = line.initial_state(); // (g1, x1, g2, x2, g3, x3)
    /// y[0] = 2.0;
    /// y[4] = 2.0;
    /// let s = line.split_cells(&[1, 3], 0.0, &mut y).unwrap();
    /// assert_eq!((s[0].x_new, s[1].x_new), (0.5, 2.5));
    /// assert_eq!(y, vec![1.0, 0.5, 1.0, 1.0, 1.0, 2.0, 1.0, 2.5, 1.0, 3.0]);
    /// assert_eq!(line.cells().l0, vec![1.0, 1.0, 1.0, 1.0, 1.0]);
    /// ```
    pub fn split_cells(
        &mut self,
        cells: &[usize],
        t: f64,
        y: &mut Vec<f64>,
    ) -> Result<Vec<Split>, EventError> {
        let n = self.n_cells();
        self.check_state_length(y)?;
        let mut splits = Vec::with_capacity(cells.len());
        let mut prev = 0;
        for &j in cells {
            if j == 0 || j > n {
                return Err(EventError::NoSuchCell { cell: j, cells: n });
            }
            if j <= prev {
                return Err(EventError::Unsupported(format!(
                    "cells to split must be strictly increasing ({prev} then {j})"
                )));
            }
            prev = j;
            let gk = self.layout.gi[j - 1];
            if gk == NONE {
                return Err(EventError::Unsupported(
                    "division without growth (`g` is not in the state)".into(),
                ));
            }
            let (xl, _) = self.boundary(j - 1, t, y, y);
            let (xr, _) = self.boundary(j, t, y, y);
            let g = y[gk];
            if !(g > 0.0 && g.is_finite() && xr > xl) {
                return Err(EventError::Degenerate {
                    cell: j,
                    reason: format!("g = {g}, length = {}", xr - xl),
                });
            }
            splits.push(Split {
                x_new: 0.5 * (xl + xr),
                g_parent: g,
                l0_daughter: 0.5 * self.cells.l0[j - 1] * g,
            });
        }
        if cells.is_empty() {
            return Ok(splits);
        }
        // 0-based parents
        let at: Vec<usize> = cells.iter().map(|&j| j - 1).collect();
        // per-cell fields: the daughter copies its parent (l0 is replaced below)
        let c = &mut self.cells;
        for v in [
            &mut c.l0,
            &mut c.mu,
            &mut c.eta,
            &mut c.k_cell,
            &mut c.active_amp,
            &mut c.phase,
            &mut c.x_ref,
            &mut c.p_ext,
        ] {
            expand_in_place(v, &at, |e, v| [v[at[e]]; 2]);
        }
        for (shift, (&j, s)) in cells.iter().zip(&splits).enumerate() {
            let i = j - 1 + shift;
            self.l0_total += s.l0_daughter * 2.0 - c.l0[i];
            c.l0[i] = s.l0_daughter;
            c.l0[i + 1] = s.l0_daughter;
        }
        // boundary drags: the new boundary j (between the daughters) has the mean of its
        // parent's two, inserted before the parent's right boundary j
        expand_in_place(&mut self.k_face, cells, |e, kf| {
            let j = cells[e];
            [0.5 * (kf[j - 1] + kf[j]), kf[j]]
        });
        // state: (.., g_j, x_j, ..) -> (.., 1, x_new, 1, x_j, ..), after a ring's x₀; with a
        // Maxwell branch (.., g_j, a_j, x_j, ..) -> (.., 1, a_j, x_new, 1, a_j, x_j, ..)
        let gks: Vec<usize> = cells.iter().map(|&j| self.layout.gi[j - 1]).collect();
        if self.maxwell.is_some() {
            for &k in &gks {
                y[k] = 1.0;
            }
            let vks: Vec<usize> = cells.iter().map(|&j| self.layout.vi[j - 1]).collect();
            expand_in_place(y, &vks, |e, y| {
                let a = y[vks[e]];
                [a, splits[e].x_new, 1.0, a]
            });
        } else {
            expand_in_place(y, &gks, |e, _| [1.0, splits[e].x_new, 1.0]);
        }
        self.rebuild_layout();
        debug_assert_eq!(y.len(), self.layout.dim);
        Ok(splits)
    }
}

impl<E: StrainEnergy> Line<E> {
    /// `Ok` when `y` has this line's number of unknowns (the check before a split or merge
    /// rewrites it).
    pub(crate) fn check_state_length(&self, y: &[f64]) -> Result<(), EventError> {
        if y.len() == self.layout.dim {
            Ok(())
        } else {
            Err(EventError::StateLength {
                got: y.len(),
                expected: self.layout.dim,
            })
        }
    }
}

/// Replaces, in place and from the back, the entry `v[at[e]]` by the `R` entries `with(e, v)`
/// for every `e` (`at` strictly increasing): `v` grows by `(R − 1)·at.len()`, the entries before
/// `at[0]` are not touched, and nothing is allocated while the capacity suffices. A division
/// event therefore moves the tail of each per-cell vector once instead of building a new
/// vector (a fresh allocation of the line's size per field and event cost page faults on long
/// lines). `with` reads `v` at or before `at[e]`, which have not moved yet.
pub(crate) fn expand_in_place<T: Copy + Default, const R: usize>(
    v: &mut Vec<T>,
    at: &[usize],
    mut with: impl FnMut(usize, &[T]) -> [T; R],
) {
    let Some(&last) = at.last() else {
        return;
    };
    debug_assert!(last < v.len() && at.windows(2).all(|w| w[0] < w[1]));
    let old = v.len();
    v.resize(old + (R - 1) * at.len(), T::default());
    // `w`: one past the next entry written; `end`: one past the next entry moved
    let (mut w, mut end) = (v.len(), old);
    for (e, &i) in at.iter().enumerate().rev() {
        let tail = end - i - 1;
        v.copy_within(i + 1..end, w - tail);
        w -= tail;
        let rep = with(e, v);
        w -= R;
        v[w..w + R].copy_from_slice(&rep);
        end = i;
    }
    debug_assert_eq!(w, end);
}

#[cfg(test)]
mod tests {
    use super::expand_in_place;
    use crate::boundary::RightEnd;
    use crate::cell::{MaxwellBranch, TanhGrowth};
    use crate::line::build::{discrete, LineParams};
    use crate::NeoHookean;

    /// Splitting cells one at a time (in decreasing order) and all at once give the same line
    /// and state, also with a Maxwell branch (three unknowns per cell), where each daughter
    /// holds its parent's viscous stretch.
    #[test]
    fn one_by_one_and_at_once_split_a_maxwell_line_alike() {
        for right in [
            RightEnd::Free(None),
            RightEnd::Prescribed(crate::boundary::Ramp::Constant(6.0)),
        ] {
            let mut p = LineParams::unit_cells(6);
            p.right = right;
            p.growth = Some(std::sync::Arc::new(TanhGrowth::default()));
            p.maxwell = Some(MaxwellBranch::standard_linear_solid(1.0, 2.0).unwrap());
            let line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
            let mut y = line.initial_state();
            for (k, v) in y.iter_mut().enumerate() {
                *v += 0.01 * k as f64;
            }
            let (mut a, mut b) = (line.clone(), line);
            let (mut ya, mut yb) = (y.clone(), y.clone());
            for j in [6, 3, 1] {
                a.split_cell(j, 0.0, &mut ya).unwrap();
            }
            b.split_cells(&[1, 3, 6], 0.0, &mut yb).unwrap();
            assert_eq!(ya, yb);
            assert_eq!(a.cells().l0, b.cells().l0);
            let (old, new) = (y, ya);
            let vi = |l: &crate::line::Line<NeoHookean>, c: usize| l.layout().vi[c];
            // daughters of cell 3 (0-based 2) are new cells 3 and 4 (one split before them)
            let parent = old[3 * 2 + 1]; // cell 3's a_v: three unknowns per cell before it
            assert_eq!((new[vi(&a, 3)], new[vi(&a, 4)]), (parent, parent));
        }
    }

    /// The same edits by building a new vector.
    fn expanded<const R: usize>(
        v: &[i32],
        at: &[usize],
        with: impl Fn(usize, &[i32]) -> [i32; R],
    ) -> Vec<i32> {
        let mut out = Vec::new();
        for (i, &x) in v.iter().enumerate() {
            match at.iter().position(|&a| a == i) {
                Some(e) => out.extend_from_slice(&with(e, v)),
                None => out.push(x),
            }
        }
        out
    }

    #[test]
    fn expanding_in_place_is_building_the_expanded_vector() {
        let v: Vec<i32> = (10..30).collect();
        for at in [
            vec![],
            vec![0],
            vec![19],
            vec![0, 1, 2],
            vec![3, 7, 8, 19],
            vec![5],
        ] {
            let dup = |e: usize, v: &[i32]| [v[at[e]], -v[at[e]]];
            let mut a = v.clone();
            expand_in_place(&mut a, &at, dup);
            assert_eq!(a, expanded(&v, &at, dup), "duplicate at {at:?}");
            // reading the entry before, as the boundary drags do
            let mean = |e: usize, v: &[i32]| {
                let i = at[e];
                [v[i.saturating_sub(1)] + v[i], 0, v[i]]
            };
            let mut b = v.clone();
            expand_in_place(&mut b, &at, mean);
            assert_eq!(b, expanded(&v, &at, mean), "three for one at {at:?}");
        }
    }

    #[test]
    fn expanding_in_place_keeps_the_allocation_when_it_fits() {
        let mut v: Vec<f64> = Vec::with_capacity(64);
        v.extend((0..40).map(f64::from));
        let ptr = v.as_ptr();
        expand_in_place(&mut v, &[3, 20], |e, v| [v[[3, 20][e]]; 2]);
        assert_eq!(v.len(), 42);
        assert_eq!(v.as_ptr(), ptr);
        assert_eq!(
            (v[3], v[4], v[5], v[22], v[23]),
            (3.0, 3.0, 4.0, 20.0, 21.0)
        );
    }
}
