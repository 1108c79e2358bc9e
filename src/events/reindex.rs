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
//! A cell split ahead of its own division time ([`Line::split_cells_ahead`], for divisions a
//! window brings forward) leaves daughters of the parent's split at its time, run back over
//! the advance ([`Ahead`]): `Σ L₀g` falls by about their growth over it, and on a free end the
//! boundaries beyond the parent move in so that `α` stays continuous.
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
/// let s = Split { x_new: 1.5, g_parent: 2.0, l0_daughter: 1.0, g_daughter: 1.0, tail_shift: 0.0 };
/// assert_eq!(s.l0_daughter, 1.0 * s.g_parent / 2.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Split {
    /// Position of the new boundary.
    pub x_new: f64,
    /// Parent's growth stretch at division.
    pub g_parent: f64,
    /// Daughters' reference length `L₀g/2` (`L₀(g + ġΔt)/2` when split ahead, [`Ahead`]).
    pub l0_daughter: f64,
    /// Daughters' growth stretch after the split: 1 (`1 − ġ_dΔt` when split ahead).
    pub g_daughter: f64,
    /// How far the boundaries beyond the parent moved: 0, or when split ahead on a free end
    /// the change of the daughters' length that keeps their elastic stretch the parent's
    /// ([`Line::split_cells_ahead`]).
    pub tail_shift: f64,
}

/// How far ahead of its own division time a cell is split ([`Line::split_cells_ahead`]), as
/// the growth made over the advance `Δt`: the parent's `ġΔt`, which the daughters' reference
/// length takes (`L₀(g + ġΔt)/2`, the split of the parent it would have been at its time), and
/// each daughter's `ġ_dΔt`, taken off its starting `g = 1`. The daughters are then the
/// daughters of a split at `t + Δt`, run back to `t` along their own growth (to first order in
/// `Δt`): their lineage keeps its schedule, and the line does not gain the growth the early
/// daughters would make over the advance (docs/model.md §2.8).
///
/// ```
/// use celltissue::events::Ahead;
/// let a = Ahead { parent: 0.01, daughter: 0.01 };
/// assert_eq!(Ahead::default(), Ahead { parent: 0.0, daughter: 0.0 }); // a split at its time
/// assert!(a.parent > 0.0);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Ahead {
    /// The parent's growth `ġΔt` over the advance.
    pub parent: f64,
    /// Each daughter's growth `ġ_dΔt` over the advance.
    pub daughter: f64,
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
            g_daughter: 1.0,
            tail_shift: 0.0,
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
        self.split_cells_ahead(cells, &[], t, y)
    }

    /// [`split_cells`](Line::split_cells) with each cell split ahead of its own division time
    /// by the growth `ahead[e]` (one per cell, or empty for none; see [`Ahead`]): the
    /// daughters take reference length `L₀(g + ġΔt)/2` and start from `g = 1 − ġ_dΔt`. Their
    /// grown length `L₀g` can then fall short of the parent's (by about the daughters' growth
    /// over the advance, less the parent's). On a free end every boundary beyond the parent
    /// moves in by that difference times the parent's elastic stretch ([`Split::tail_shift`]),
    /// so each daughter keeps the parent's elastic stretch and the line's stresses do not
    /// jump; on a prescribed end or a ring the boundaries stay and the daughters are
    /// stretched.
    ///
    /// ```
    /// use celltissue::boundary::RightEnd;
    /// use celltissue::cell::TanhGrowth;
    /// use celltissue::events::Ahead;
    /// use celltissue::line::build::{discrete, LineParams};
    /// use celltissue::NeoHookean;
    /// use std::sync::Arc;
    /// let mut p = LineParams::unit_cells(2);
    /// p.right = RightEnd::Free(None);
    /// p.k = 1e-5.into();
    /// p.growth = Some(Arc::new(TanhGrowth::default()));
    /// let mut line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
    /// let mut y = line.initial_state(); // (g1, x1, g2, x2)
    /// y[0] = 1.98; // cell 1 would reach g = 2 after growing by 0.02 more
    /// let ahead = [Ahead { parent: 0.02, daughter: 0.02 }];
    /// let s = line.split_cells_ahead(&[1], &ahead, 0.0, &mut y).unwrap();
    /// assert_eq!((s[0].l0_daughter, s[0].g_daughter), (1.0, 0.98));
    /// // the daughters' grown length 2 · 1.0 · 0.98 against the parent's 1.98: the free end's
    /// // boundaries move in by 1 − 1.96/1.98 of the parent's length 1
    /// let d = 1.96 / 1.98 - 1.0;
    /// assert!((s[0].tail_shift - d).abs() < 1e-15);
    /// let want = [0.98, 0.5 * (1.0 + d), 0.98, 1.0 + d, 1.0, 2.0 + d];
    /// assert!(y.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-15));
    /// ```
    pub fn split_cells_ahead(
        &mut self,
        cells: &[usize],
        ahead: &[Ahead],
        t: f64,
        y: &mut Vec<f64>,
    ) -> Result<Vec<Split>, EventError> {
        let n = self.n_cells();
        if !(ahead.is_empty() || ahead.len() == cells.len()) {
            return Err(EventError::Unsupported(format!(
                "{} advances for {} cells to split",
                ahead.len(),
                cells.len()
            )));
        }
        self.check_state_length(y)?;
        let mut splits = Vec::with_capacity(cells.len());
        let mut prev = 0;
        // a free end's boundaries beyond a daughter pair shorter in grown length than its
        // parent move in by the difference (times the parent's elastic stretch): the shift of
        // each split, and the sum of the earlier ones
        let free = self.right.is_free();
        let mut shifts = Vec::new();
        let mut cum = 0.0;
        for (e, &j) in cells.iter().enumerate() {
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
            let a = ahead.get(e).copied().unwrap_or_default();
            let (g_at, g_d) = (g + a.parent, 1.0 - a.daughter);
            if !(g_at > 0.0 && g_at.is_finite() && g_d > 0.0 && g_d.is_finite()) {
                return Err(EventError::Degenerate {
                    cell: j,
                    reason: format!(
                        "split ahead of its time: the parent's g would be {g_at} at its \
                         division and the daughters' g would start at {g_d} (the window \
                         brings it forward too far)"
                    ),
                });
            }
            let l0_d = 0.5 * self.cells.l0[j - 1] * g_at;
            // the daughters' grown length over the parent's: 1 at the division's own time
            let s = 2.0 * l0_d * g_d / (self.cells.l0[j - 1] * g);
            let shift = if free && a != Ahead::default() {
                (s - 1.0) * (xr - xl)
            } else {
                0.0
            };
            splits.push(Split {
                x_new: xl + cum + 0.5 * (xr - xl + shift),
                g_parent: g,
                l0_daughter: l0_d,
                g_daughter: g_d,
                tail_shift: shift,
            });
            if shift != 0.0 {
                shifts.push((j, shift));
            }
            cum += shift;
        }
        if cells.is_empty() {
            return Ok(splits);
        }
        // boundary b (old index) moves by the shifts of the splits at cells j ≤ b
        if !shifts.is_empty() {
            let mut next = shifts.iter().peekable();
            let mut cum = 0.0;
            for b in shifts[0].0..=n {
                while let Some(&&(j, d)) = next.peek() {
                    if j > b {
                        break;
                    }
                    cum += d;
                    next.next();
                }
                let k = self.layout.xi[b];
                if k != NONE {
                    y[k] += cum;
                }
            }
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
        // state: (.., g_j, x_j, ..) -> (.., g_d, x_new, g_d, x_j, ..) with g_d = 1 unless split
        // ahead, after a ring's x₀; with a Maxwell branch (.., g_j, a_j, x_j, ..) ->
        // (.., g_d, a_j, x_new, g_d, a_j, x_j, ..)
        let gks: Vec<usize> = cells.iter().map(|&j| self.layout.gi[j - 1]).collect();
        if self.maxwell.is_some() {
            for (&k, s) in gks.iter().zip(&splits) {
                y[k] = s.g_daughter;
            }
            let vks: Vec<usize> = cells.iter().map(|&j| self.layout.vi[j - 1]).collect();
            expand_in_place(y, &vks, |e, y| {
                let a = y[vks[e]];
                [a, splits[e].x_new, splits[e].g_daughter, a]
            });
        } else {
            expand_in_place(y, &gks, |e, _| {
                let s = &splits[e];
                [s.g_daughter, s.x_new, s.g_daughter]
            });
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
    use super::{expand_in_place, Ahead};
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

    /// Cells split ahead of their time: on a free end every cell keeps its elastic stretch
    /// (the daughters their parent's) and the boundaries beyond each parent move in by the
    /// pair's shortfall in grown length; on a prescribed end every old boundary stays and the
    /// daughters are stretched by that shortfall. `Σ L₀g` falls by the shortfall either way.
    #[test]
    fn a_split_ahead_keeps_the_stretches_on_a_free_end_and_the_boundaries_on_a_fixed_one() {
        for free in [true, false] {
            let mut p = LineParams::unit_cells(6);
            p.right = if free {
                RightEnd::Free(None)
            } else {
                RightEnd::Prescribed(crate::boundary::Ramp::Constant(6.3))
            };
            p.growth = Some(std::sync::Arc::new(TanhGrowth::default()));
            let mut line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
            let mut y = line.initial_state();
            // g and x interleaved: growth 1.1–1.6 and uneven lengths
            for (k, v) in y.iter_mut().enumerate() {
                *v += if k % 2 == 0 {
                    0.1 * (k / 2 + 1) as f64
                } else {
                    0.05 * k as f64
                };
            }
            let alpha = |l: &crate::line::Line<NeoHookean>, y: &[f64], j: usize| {
                l.eval_cell::<f64>(j, 0.0, y, &vec![0.0; y.len()])
                    .unwrap()
                    .alpha
            };
            let grown = |l: &crate::line::Line<NeoHookean>, y: &[f64]| -> f64 {
                (0..l.n_cells())
                    .map(|i| l.cells().l0[i] * y[l.layout().gi[i]])
                    .sum()
            };
            let xs = |l: &crate::line::Line<NeoHookean>, y: &[f64]| -> Vec<f64> {
                (0..=l.n_cells())
                    .map(|b| l.boundary(b, 0.0, y, y).0)
                    .collect()
            };
            let before: Vec<f64> = (1..=6).map(|j| alpha(&line, &y, j)).collect();
            let (x_before, sum_before) = (xs(&line, &y), grown(&line, &y));
            let (g2, g5) = (y[2], y[8]);
            let ahead = [
                Ahead {
                    parent: 0.03,
                    daughter: 0.03,
                },
                Ahead {
                    parent: 0.01,
                    daughter: 0.01,
                },
            ];
            let s = line
                .split_cells_ahead(&[2, 5], &ahead, 0.0, &mut y)
                .unwrap();
            // the shortfall of each pair (parent L₀ = 1)
            let short = [
                g2 - (g2 + 0.03) * (1.0 - 0.03),
                g5 - (g5 + 0.01) * (1.0 - 0.01),
            ];
            assert!((sum_before - short[0] - short[1] - grown(&line, &y)).abs() < 1e-14);
            assert_eq!((s[0].g_daughter, s[1].g_daughter), (0.97, 0.99));
            let x_after = xs(&line, &y);
            // old cells 1..6 are new 1, (2, 3), 4, 5, (6, 7), 8
            let new_of = [vec![1], vec![2, 3], vec![4], vec![5], vec![6, 7], vec![8]];
            for (old, news) in new_of.iter().enumerate() {
                for &j in news {
                    let a = alpha(&line, &y, j);
                    if free || news.len() == 1 {
                        assert!((a - before[old]).abs() < 1e-14, "cell {j}: α {a}");
                    } else {
                        // stretched by the parent's grown length over the pair's
                        let k = usize::from(old == 4);
                        let g = [g2, g5][k];
                        let want = before[old] * g / (g - short[k]);
                        assert!((a - want).abs() < 1e-14, "cell {j}: α {a} against {want}");
                    }
                }
            }
            // old boundary b is new b + (splits at cells ≤ b)
            for (b, &x) in x_before.iter().enumerate() {
                let shifts: f64 = s
                    .iter()
                    .zip([2, 5])
                    .filter(|&(_, j)| j <= b)
                    .map(|(s, _)| s.tail_shift)
                    .sum();
                let nb = b + [2, 5].iter().filter(|&&j| j <= b).count();
                let want = if free { x + shifts } else { x };
                assert!((x_after[nb] - want).abs() < 1e-14, "boundary {b}");
            }
            assert_eq!(s[0].tail_shift != 0.0, free);
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
