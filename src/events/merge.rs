//! Merging pairs of neighbouring cells of a [`Line`] into one segment ([`Line::merge_cells`]):
//! the inverse of a split, used by the cell-number grid
//! ([`crate::proliferation::CellGrid`]) to coarsen cells that have stopped growing.
//!
//! * the merged segment: reference length `L₀ = L₀,a + L₀,b`, growth stretch the
//!   `L₀`-weighted mean `g = (L₀,a g_a + L₀,b g_b)/L₀` (so `Σ L₀g` and the growth of length,
//!   `Σ L₀ G`, are unchanged), drag `k_cell` the sum, the other fields `L₀`-weighted means;
//! * a Maxwell branch's viscous stretch `a_v` (docs/viscoelasticity.md) is the mean weighted
//!   by the grown lengths `L₀g`, so the branch's rest lengths `L₀ g a_v` add up as the lengths
//!   do (its elastic stretch and stress are unchanged when the two cells' were equal);
//! * the boundary between them is removed, and half its drag goes to each neighbouring face
//!   (the total drag is unchanged);
//! * every other boundary keeps its position, so `l` is unchanged; the merged segment's
//!   elastic stretch is the length-weighted mean of the two, exact when they were equal.
//!
//! All pairs of one event in one O(N + k) pass, like [`Line::split_cells`].

use super::EventError;
use crate::energy::StrainEnergy;
use crate::line::array::NONE;
use crate::line::homogenise::{CellValues, InSeries};
use crate::line::Line;

impl<E: StrainEnergy> Line<E> {
    /// Merges cell `j` with cell `j + 1` for each `j` of `firsts` (1-based, increasing, pairs
    /// not overlapping) in the state `y`: the line loses one cell per pair, `y` one boundary
    /// and one `g`.
    ///
    /// ```
    /// use celltissue::line::build::{discrete, LineParams};
    /// use celltissue::boundary::RightEnd;
    /// use celltissue::cell::TanhGrowth;
    /// use celltissue::NeoHookean;
    /// use std::sync::Arc;
    /// let mut p = LineParams::unit_cells(4);
    /// p.right = RightEnd::Free(None);
    /// p.k = 1.0.into();
    /// p.growth = Some(Arc::new(TanhGrowth::default()));
    /// let mut line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
    /// let mut y = line.initial_state(); // (g1, x1, g2, x2, g3, x3, g4, x4)
    /// y[4] = 1.5; // cell 3 has grown
    /// line.merge_cells(&[2], &mut y).unwrap();
    /// assert_eq!(line.n_cells(), 3);
    /// assert_eq!(line.cells().l0, vec![1.0, 2.0, 1.0]);
    /// // boundary 2 is gone; the merged g is the mean (1 + 1.5)/2
    /// assert_eq!(y, vec![1.0, 1.0, 1.25, 3.0, 1.0, 4.0]);
    /// assert_eq!(line.k_face().iter().sum::<f64>(), 5.0); // the drag of 5 faces kept
    /// ```
    pub fn merge_cells(&mut self, firsts: &[usize], y: &mut Vec<f64>) -> Result<(), EventError> {
        let n = self.n_cells();
        if self.right.is_periodic() {
            return Err(EventError::Unsupported("merging cells on a ring".into()));
        }
        self.check_state_length(y)?;
        let mut next = 1;
        for &j in firsts {
            if j < next || j + 1 > n {
                return Err(EventError::Unsupported(format!(
                    "cells to merge must be increasing, not overlapping and not the last \
                     ({j} of {n})"
                )));
            }
            if self.layout.gi[j - 1] == NONE {
                return Err(EventError::Unsupported(
                    "merging cells that do not grow (`g` is not in the state)".into(),
                ));
            }
            next = j + 2;
        }
        if firsts.is_empty() {
            return Ok(());
        }
        let k = firsts.len();
        let c = &mut self.cells;
        let (mut out, mut l0, mut kc) = (
            Vec::with_capacity(y.len() - 2 * k),
            Vec::with_capacity(n - k),
            Vec::with_capacity(n - k),
        );
        let mut means: [Vec<f64>; 6] = Default::default();
        let mut kf = Vec::with_capacity(self.k_face.len() - k);
        kf.push(self.k_face[0]);
        if self.layout.xi[0] != NONE {
            out.push(y[self.layout.xi[0]]);
        }
        let mut f = firsts.iter().peekable();
        let mut i = 0;
        while i < n {
            let merge = f.next_if(|&&j| j == i + 1).is_some();
            let (a, b) = (i, if merge { i + 1 } else { i });
            let (la, lb) = (c.l0[a], if merge { c.l0[b] } else { 0.0 });
            let w = la + lb;
            let mean = |v: &[f64]| (la * v[a] + lb * v[b]) / w;
            let ga = y[self.layout.gi[a]];
            let gb = y[self.layout.gi[b]];
            // a cell left alone keeps its values bit for bit
            out.push(if merge { (la * ga + lb * gb) / w } else { ga });
            let (va, vb) = (self.layout.vi[a], self.layout.vi[b]);
            if va != NONE {
                // the branch's rest lengths add: `a_v` weighted by the grown lengths
                let (ra, rb) = (la * ga, lb * gb);
                out.push(if merge {
                    (ra * y[va] + rb * y[vb]) / (ra + rb)
                } else {
                    y[va]
                });
            }
            let xk = self.layout.xi[b + 1];
            if xk != NONE {
                out.push(y[xk]);
            }
            l0.push(w);
            kc.push(c.k_cell[a] + if merge { c.k_cell[b] } else { 0.0 });
            // the material values of two cells in series, weighted by their grown lengths;
            // positions and phases by reference length
            let values = |i: usize| CellValues {
                mu: c.mu[i],
                eta: c.eta[i],
                active_amp: c.active_amp[i],
                p_ext: c.p_ext[i],
            };
            let v = if merge && values(a) != values(b) {
                let mut series = InSeries::default();
                series.add(la * ga, &values(a));
                series.add(lb * gb, &values(b));
                series.values()
            } else {
                values(a)
            };
            let [mu, eta, active_amp, p_ext, phase, x_ref] = &mut means;
            mu.push(v.mu);
            eta.push(v.eta);
            active_amp.push(v.active_amp);
            p_ext.push(v.p_ext);
            phase.push(if merge { mean(&c.phase) } else { c.phase[a] });
            x_ref.push(if merge { mean(&c.x_ref) } else { c.x_ref[a] });
            if merge {
                // the removed face a + 1 gives half its drag to each neighbour
                let half = 0.5 * self.k_face[a + 1];
                *kf.last_mut().expect("face 0 is in") += half;
                kf.push(self.k_face[b + 1] + half);
            } else {
                kf.push(self.k_face[a + 1]);
            }
            i = b + 1;
        }
        let [mu, eta, active_amp, p_ext, phase, x_ref] = means;
        c.mu = mu;
        c.eta = eta;
        c.active_amp = active_amp;
        c.phase = phase;
        c.x_ref = x_ref;
        c.p_ext = p_ext;
        c.l0 = l0;
        c.k_cell = kc;
        self.k_face = kf;
        self.l0_total = self.cells.l0.iter().sum();
        *y = out;
        self.rebuild_layout();
        debug_assert_eq!(y.len(), self.layout.dim);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use crate::cell::{Field, TanhGrowth};
    use crate::line::build::{discrete, LineParams};
    use crate::NeoHookean;
    use std::sync::Arc;

    /// Three growing unit cells with a free end and K = 1.
    fn three_growing_cells() -> LineParams {
        let mut p = LineParams::unit_cells(3);
        p.right = crate::boundary::RightEnd::Free(None);
        p.k = 1.0.into();
        p.growth = Some(Arc::new(TanhGrowth::default()));
        p
    }

    #[test]
    fn two_cells_merge_into_their_series_element() {
        let mut p = three_growing_cells();
        p.mu = Field::PerCell {
            values: vec![1.0, 3.0, 2.0],
        };
        p.eta = Field::PerCell {
            values: vec![2.0, 6.0, 0.0],
        };
        let mut line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
        let mut y = line.initial_state();
        line.merge_cells(&[1], &mut y).unwrap();
        let c = line.cells();
        // compliance 1/1 + 1/3 over a length of 2: μ = 1.5; η/μ = 2 in both, so η = 2μ
        assert!((c.mu[0] - 1.5).abs() < 1e-15 && (c.eta[0] - 3.0).abs() < 1e-14);
        assert_eq!((c.mu[1], c.eta[1]), (2.0, 0.0));
    }

    /// Two standard-linear-solid cells merge with the branch's rest lengths `L₀ g a_v` added
    /// (`a_v` the mean weighted by grown length); a cell left alone keeps its `g` and `a_v`
    /// bit for bit; equal cells keep their branch's elastic stretch `α/a_v`.
    #[test]
    fn a_branch_merges_by_its_rest_lengths() {
        let mut p = three_growing_cells();
        p.maxwell = Some(crate::cell::MaxwellBranch::standard_linear_solid(1.0, 2.0).unwrap());
        let mut line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
        // (g1, a1, x1, g2, a2, x2, g3, a3, x3): cells 1 and 2 differ, cell 3 is alone
        let mut y = vec![1.2, 0.9, 1.1, 1.6, 1.05, 3.0, 1.1, 0.97, 4.3];
        let rest = 1.2 * 0.9 + 1.6 * 1.05;
        line.merge_cells(&[1], &mut y).unwrap();
        assert_eq!(line.n_cells(), 2);
        let lay = line.layout();
        let (g, a) = (y[lay.gi[0]], y[lay.vi[0]]);
        assert!((2.0 * g * a - rest).abs() < 1e-14, "{g} {a}");
        assert_eq!((y[lay.gi[1]], y[lay.vi[1]], y[lay.xi[2]]), (1.1, 0.97, 4.3));
        // two equal cells: the merged one has their stretch and branch stretch
        let mut line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
        let mut y = vec![1.3, 0.95, 1.2, 1.3, 0.95, 2.4, 1.0, 1.0, 3.4];
        line.merge_cells(&[1], &mut y).unwrap();
        let lay = line.layout();
        assert!((y[lay.gi[0]] - 1.3).abs() < 1e-15 && (y[lay.vi[0]] - 0.95).abs() < 1e-15);
        assert_eq!(y[lay.xi[1]], 2.4);
    }
}
