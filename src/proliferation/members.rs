//! The cells inside a [`CellGrid`] segment: what the rule sees of one of them
//! ([`CellGrid::segment_cell_view`] when they are in phase, [`CellGrid::member_views`] when
//! they divide one by one), their divisions inside the segment
//! ([`CellGrid::divide_members`]), and the split of a segment that has doubled its cells
//! ([`CellGrid::split_full`]).
//!
//! A segment keeps a member list when its cells are not in phase: after a merge (the members
//! were segments that stopped growing), or from the start when the rule draws a threshold for
//! each cell (`random_area`). The members share the segment's stress, which is the mean-field
//! closure: each keeps its own growth stretch (as an offset from the segment's `g`, constant
//! because `ġ = G(σ)` is the same for all), birth time and threshold, and divides when the rule
//! says so. A member's division adds a cell and reference length to its segment without
//! resizing the line. When cells divide one by one from the start ([`CellGrid::asynchronous`]),
//! a growing segment that holds twice its cells at the start splits in two at the member
//! boundary nearest its middle, so the segments keep resolving the line.

use super::cell_grid::{CellGrid, Member};
use crate::energy::StrainEnergy;
use crate::events::CellView;
use crate::observe::DivisionRecord;

/// What a rule that reads mechanics needs of a state, computed once per evaluation of the
/// event functions (so the views of all segments cost O(n), not O(n) each).
pub(crate) struct Geometry {
    /// Zero rates, at which the viscous stress is taken (the event functions see only `y`).
    zero: Vec<f64>,
    /// Every boundary position.
    xs: Vec<f64>,
}

impl<E: StrainEnergy> CellGrid<E> {
    /// The [`Geometry`] of state `y`, or `None` when the rule reads only growth and age.
    pub(crate) fn geometry(&self, t: f64, y: &[f64]) -> Option<Geometry> {
        if !self.dividing.rule.needs_mechanics() {
            return None;
        }
        let zero = vec![0.0; y.len()];
        let xs = self.dividing.boundaries(t, y, &zero);
        Some(Geometry { zero, xs })
    }

    /// What the rule sees of each member of segment `j` (0-based; a member list must exist)
    /// at state `y` (with its [`Geometry`] when the rule reads mechanics): its own area ratio `(g + offset) g₂`, age and threshold; for a rule that
    /// reads mechanics also its share of the segment's length (in proportion to `L₀ g`), the
    /// segment's width, stress and pressure, its centre, and its neighbours' lengths (the
    /// neighbouring segments' mean cell length at the segment's ends).
    pub(crate) fn member_views(
        &self,
        j: usize,
        t: f64,
        y: &[f64],
        geometry: Option<&Geometry>,
    ) -> Vec<CellView> {
        let Some(list) = &self.members[j] else {
            return Vec::new();
        };
        let d = &self.dividing;
        let g = y[d.line.layout.gi[j]];
        let g2 = d.line.g2;
        let mut views: Vec<CellView> = list
            .iter()
            .map(|m| CellView::growth_only((g + m.offset) * g2, t - m.birth, m.threshold))
            .collect();
        let Some(Geometry { zero, xs }) = geometry else {
            return views;
        };
        let segment = d.cell_view(j, t, y, zero, xs);
        let grown: f64 = list.iter().map(|m| m.l0 * (g + m.offset)).sum();
        let lengths: Vec<f64> = list
            .iter()
            .map(|m| segment.length * m.l0 * (g + m.offset) / grown)
            .collect();
        let mean_cell = |k: usize| (xs[k + 1] - xs[k]) / self.multiplicity[k] as f64;
        let n = self.multiplicity.len();
        let outside = [
            if j > 0 { mean_cell(j - 1) } else { f64::NAN },
            if j + 1 < n {
                mean_cell(j + 1)
            } else {
                f64::NAN
            },
        ];
        let mut left = xs[j];
        for (i, v) in views.iter_mut().enumerate() {
            v.length = lengths[i];
            v.width = segment.width;
            v.area = lengths[i] * segment.width;
            v.stress = segment.stress;
            v.pressure = segment.pressure;
            v.position = left + 0.5 * lengths[i];
            v.neighbour_lengths = [
                if i > 0 { lengths[i - 1] } else { outside[0] },
                lengths.get(i + 1).copied().unwrap_or(outside[1]),
            ];
            left += lengths[i];
        }
        views
    }

    /// What a rule that reads mechanics sees of one cell of segment `j` (0-based) whose `c`
    /// cells are in phase: the segment's view with its length and area shared among its
    /// cells, and the neighbouring segments' mean cell lengths as neighbours.
    pub(crate) fn segment_cell_view(
        &self,
        j: usize,
        t: f64,
        y: &[f64],
        geometry: &Geometry,
    ) -> CellView {
        let Geometry { zero, xs } = geometry;
        let mut v = self.dividing.cell_view(j, t, y, zero, xs);
        let m = self.multiplicity[j] as f64;
        let mean_cell = |k: usize| (xs[k + 1] - xs[k]) / self.multiplicity[k] as f64;
        v.length /= m;
        v.area /= m;
        v.neighbour_lengths = [
            if j > 0 { mean_cell(j - 1) } else { f64::NAN },
            if j + 1 < self.multiplicity.len() {
                mean_cell(j + 1)
            } else {
                f64::NAN
            },
        ];
        v
    }

    /// Divides every member of segment `j` (0-based) that has reached the rule: the member
    /// becomes two of half its grown length at `g = 1`, born now, each with a threshold drawn
    /// from the rule's generator, so the segment's reference length and cell count grow while
    /// its grown length and every boundary stay; its `g` (in `y`) is the new `L₀`-weighted
    /// mean. Logs each division at the member's place in the segment and pushes the cells it
    /// added to `added`. `geometry` is the state's (boundaries do not move here, so one serves
    /// every segment of an event).
    pub(crate) fn divide_members(
        &mut self,
        j: usize,
        t: f64,
        y: &mut [f64],
        geometry: Option<&Geometry>,
        added: &mut Vec<usize>,
    ) {
        let values: Vec<f64> = self
            .member_views(j, t, y, geometry)
            .iter()
            .map(|v| self.dividing.rule.event(v))
            .collect();
        let Some(list) = self.members[j].take() else {
            return;
        };
        let line = &self.dividing.line;
        let k = line.layout.gi[j];
        let g = y[k];
        let (xl, xr) = (line.boundary(j, t, y, y).0, line.boundary(j + 1, t, y, y).0);
        let (x0, xn) = (
            line.boundary(0, t, y, y).0,
            line.boundary(line.n_cells(), t, y, y).0,
        );
        let grown: f64 = list.iter().map(|m| m.l0 * (g + m.offset)).sum();
        let per_cell_drag = line.cells.k_cell[j] / self.multiplicity[j] as f64;
        // the member that fired divides even if the located root left it a rounding short
        let first = (0..list.len())
            .max_by(|&a, &b| values[a].total_cmp(&values[b]))
            .unwrap_or(0);
        let (mut out, mut before) = (Vec::with_capacity(list.len() + 1), 0.0);
        for (i, m) in list.into_iter().enumerate() {
            let gm = g + m.offset;
            if i == first || values[i] >= 0.0 {
                let x = xl + (xr - xl) * (before + 0.5 * m.l0 * gm) / grown;
                self.dividing.log.push(DivisionRecord {
                    t,
                    parent: j + 1,
                    x,
                    x_over_length: (x - x0) / (xn - x0),
                    cells_after: 0,
                    age: Some(t - m.birth),
                    cell: None,
                    daughters: None,
                });
                added.push(m.cells);
                self.multiplicity[j] += m.cells;
                let daughter = Member {
                    l0: 0.5 * m.l0 * gm,
                    offset: 1.0,
                    birth: t,
                    ..m
                };
                let (a, b) = (
                    self.dividing.draw_threshold(),
                    self.dividing.draw_threshold(),
                );
                out.extend([
                    Member {
                        threshold: a,
                        ..daughter
                    },
                    Member {
                        threshold: b,
                        ..daughter
                    },
                ]);
            } else {
                out.push(Member { offset: gm, ..m });
            }
            before += m.l0 * gm;
        }
        // the new reference length and mean g; offsets back to relative
        let l0: f64 = out.iter().map(|m| m.l0).sum();
        let g_new = grown / l0;
        out.iter_mut().for_each(|m| m.offset -= g_new);
        let line = &mut self.dividing.line;
        line.l0_total += l0 - line.cells.l0[j];
        line.cells.l0[j] = l0;
        line.cells.k_cell[j] = per_cell_drag * self.multiplicity[j] as f64;
        y[k] = g_new;
        self.members[j] = Some(out);
    }

    /// Splits segment `j` (0-based, with a member list of at least two members) in two at
    /// the member boundary that halves its cells most nearly: each half keeps its members,
    /// its reference length, its `Σ L₀g` (so its own mean `g`) and its share of the drag; the
    /// new boundary sits where the members' grown lengths put it (they share one stretch), so
    /// no boundary moves, `l` and `Σ L₀g` stay and the stress is continuous. The integrator's
    /// history is not carried across (the event that calls this forgets the split map).
    pub(crate) fn split_full(&mut self, j: usize, t: f64, y: &mut Vec<f64>) -> Result<(), String> {
        let Some(list) = self.members[j].take() else {
            return Ok(());
        };
        let total: usize = list.iter().map(|m| m.cells).sum();
        let mut below = 0;
        let cut = list
            .iter()
            .map(|m| {
                below += m.cells;
                below
            })
            .enumerate()
            .take(list.len() - 1)
            .min_by_key(|&(_, b)| (2 * b).abs_diff(total))
            .map_or(1, |(i, _)| i + 1);
        let (left, right) = list.split_at(cut);
        let line = &self.dividing.line;
        let g = y[line.layout.gi[j]];
        let (xl, xr) = (line.boundary(j, t, y, y).0, line.boundary(j + 1, t, y, y).0);
        let part = |ms: &[Member]| {
            let l0: f64 = ms.iter().map(|m| m.l0).sum();
            let grown: f64 = ms.iter().map(|m| m.l0 * (g + m.offset)).sum();
            let cells: usize = ms.iter().map(|m| m.cells).sum();
            (l0, grown, cells)
        };
        let ((l0_a, grown_a, cells_a), (l0_b, grown_b, cells_b)) = (part(left), part(right));
        let x_new = xl + (xr - xl) * grown_a / (grown_a + grown_b);
        let per_cell_drag = line.cells.k_cell[j] / self.multiplicity[j] as f64;
        let (dx, x_ref) = (self.dividing.dx_ref[j], line.cells.x_ref[j]);
        let l0_total = line.l0_total;
        // the line's split (daughters at the midpoint, g = 1), then this split's values
        self.dividing
            .line
            .split_cells(&[j + 1], t, y)
            .map_err(|e| e.to_string())?;
        let line = &mut self.dividing.line;
        line.l0_total = l0_total;
        let c = &mut line.cells;
        (c.l0[j], c.l0[j + 1]) = (l0_a, l0_b);
        (c.k_cell[j], c.k_cell[j + 1]) = (
            per_cell_drag * cells_a as f64,
            per_cell_drag * cells_b as f64,
        );
        let dx_a = dx * l0_a / (l0_a + l0_b);
        // material centres of the two halves of [X − ΔX/2, X + ΔX/2]
        (c.x_ref[j], c.x_ref[j + 1]) = (x_ref - 0.5 * (dx - dx_a), x_ref + 0.5 * dx_a);
        let (ga, gb) = (grown_a / l0_a, grown_b / l0_b);
        y[line.layout.gi[j]] = ga;
        y[line.layout.gi[j + 1]] = gb;
        y[line.layout.xi[j + 1]] = x_new;
        let d = &mut self.dividing;
        d.birth.insert(j + 1, d.birth[j]);
        d.threshold.insert(j + 1, d.threshold[j]);
        d.dx_ref[j] = dx_a;
        d.dx_ref.insert(j + 1, dx - dx_a);
        let shift = |ms: &[Member], gp: f64| -> Vec<Member> {
            ms.iter()
                .map(|m| Member {
                    offset: g + m.offset - gp,
                    ..*m
                })
                .collect()
        };
        self.members[j] = Some(shift(left, ga));
        self.members.insert(j + 1, Some(shift(right, gb)));
        self.multiplicity[j] = cells_a;
        self.multiplicity.insert(j + 1, cells_b);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::array::CellArray;
    use crate::boundary::RightEnd;
    use crate::cell::TanhGrowth;
    use crate::events::{RandomThreshold, SurfaceToVolume};
    use crate::line::build::{continuum, LineParams};
    use crate::NeoHookean;
    use integrators::EventAction;
    use std::sync::Arc;

    /// 20 cells on 5 segments of 4, dividing at thresholds from U[1.8, 2.2].
    fn grid() -> CellGrid<NeoHookean> {
        let mut p = LineParams::unit_cells(20);
        p.right = RightEnd::Free(None);
        p.k = 1e-2.into();
        p.growth = Some(Arc::new(TanhGrowth::default()));
        let line = continuum(NeoHookean::new(1.0).unwrap(), &p, 5).unwrap();
        let rule = RandomThreshold {
            mean: 2.0,
            spread: 0.2,
            seed: 3,
        };
        CellGrid::new(line, 20, Box::new(rule)).unwrap()
    }

    /// A rule that draws thresholds gives every cell its own: segments start as four
    /// single-cell members, and the segment fires when its lowest threshold is reached, for
    /// that member alone.
    #[test]
    fn cells_with_their_own_thresholds_divide_one_by_one() {
        let mut grid = grid();
        assert!(grid.asynchronous);
        let list = grid.members[1].clone().unwrap();
        assert_eq!(list.len(), 4);
        assert!(list
            .iter()
            .all(|m| m.cells == 1 && (1.8..=2.2).contains(&m.threshold)));
        let lowest = list
            .iter()
            .map(|m| m.threshold)
            .fold(f64::INFINITY, f64::min);
        let mut y = grid.dividing.line.initial_state();
        let k = grid.dividing.line.layout.gi[1];
        y[k] = lowest;
        let mut g = vec![0.0; 5];
        grid.events(1.0, &y, &mut g);
        assert!(g[1].abs() < 1e-12 && g[0] < 0.0, "{g:?}");
        let action = grid.handle_event(1.0, &[1], &mut y, &[]).unwrap();
        assert!(matches!(action, EventAction::Modified));
        assert_eq!(
            (grid.segments(), grid.cells(), grid.multiplicity[1]),
            (5, 21, 5)
        );
        // the daughters drew new thresholds
        let after = grid.members[1].as_ref().unwrap();
        assert_eq!(after.len(), 5);
        assert_eq!(after.iter().filter(|m| m.birth == 1.0).count(), 2);
        assert!(after.iter().all(|m| m.threshold != lowest));
    }

    /// A segment split at its middle member keeps every boundary, `l`, `Σ L₀g`, each member's
    /// growth stretch and the stretch `α` on both sides (so the stress), and halves its cells
    /// and drag.
    #[test]
    fn a_full_segment_splits_at_its_middle_keeping_the_mechanics() {
        let mut grid = grid();
        let mut y = grid.dividing.line.initial_state();
        let lay = grid.dividing.line.layout.clone();
        // segment 2 (0-based) grown to g = 1.5, its members at 1.3, 1.5, 1.6, 1.6
        y[lay.gi[2]] = 1.5;
        for (m, off) in grid.members[2]
            .as_mut()
            .unwrap()
            .iter_mut()
            .zip([-0.2, 0.0, 0.1, 0.1])
        {
            m.offset = off;
        }
        let absolute = |grid: &CellGrid<NeoHookean>, y: &[f64], j: usize| -> Vec<f64> {
            let g = y[grid.dividing.line.layout.gi[j]];
            grid.members[j]
                .as_ref()
                .unwrap()
                .iter()
                .map(|m| g + m.offset)
                .collect()
        };
        let grown = |grid: &CellGrid<NeoHookean>, y: &[f64]| -> f64 {
            let line = &grid.dividing.line;
            (0..line.n_cells())
                .map(|j| line.cells.l0[j] * y[line.layout.gi[j]])
                .sum()
        };
        let line = &grid.dividing.line;
        let xs: Vec<f64> = (0..=5).map(|b| line.boundary(b, 0.0, &y, &y).0).collect();
        let alpha = line.eval_cell(3, 0.0, &y, &y).unwrap().alpha;
        let (sum, drag, before) = (
            grown(&grid, &y),
            line.cells.k_cell[2],
            absolute(&grid, &y, 2),
        );
        grid.split_full(2, 0.0, &mut y).unwrap();
        let line = &grid.dividing.line;
        assert_eq!((grid.segments(), grid.cells()), (6, 20));
        assert_eq!((grid.multiplicity[2], grid.multiplicity[3]), (2, 2));
        let after: Vec<f64> = (0..=6).map(|b| line.boundary(b, 0.0, &y, &y).0).collect();
        assert_eq!([&after[..3], &after[4..]].concat(), xs);
        assert!(after[2] < after[3] && after[3] < after[4]);
        assert!((grown(&grid, &y) - sum).abs() < 1e-13 * sum);
        assert!((line.cells.k_cell[2] + line.cells.k_cell[3] - drag).abs() < 1e-15);
        for j in [3, 4] {
            let a = line.eval_cell(j, 0.0, &y, &y).unwrap().alpha;
            assert!((a - alpha).abs() < 1e-14, "cell {j}: α {a} against {alpha}");
        }
        let split = [absolute(&grid, &y, 2), absolute(&grid, &y, 3)].concat();
        assert!(split
            .iter()
            .zip(&before)
            .all(|(a, b)| (a - b).abs() < 1e-14));
        assert_eq!(line.l0_total, 20.0);
    }

    /// A rule that reads the shape sees each member's share of its segment's length, the
    /// segment's width and stress, and neighbours inside the segment.
    #[test]
    fn members_see_their_own_length_under_a_mechanical_rule() {
        let mut p = LineParams::unit_cells(8);
        p.right = RightEnd::Free(None);
        p.growth = Some(Arc::new(TanhGrowth::default()));
        let line = continuum(NeoHookean::new(1.0).unwrap(), &p, 8).unwrap();
        let rule = SurfaceToVolume { critical: 3.0 };
        let mut grid = CellGrid::new(line, 8, Box::new(rule)).unwrap();
        let mut y = grid.dividing.line.initial_state();
        let gi = grid.dividing.line.layout.gi.clone();
        y[gi[2]] = 1.2;
        y[gi[3]] = 1.6;
        grid.merge(&[3], &mut y).unwrap();
        let v = grid.member_views(2, 0.0, &y, grid.geometry(0.0, &y).as_ref());
        let xs: Vec<f64> = (0..=7)
            .map(|b| grid.dividing.line.boundary(b, 0.0, &y, &y).0)
            .collect();
        assert_eq!(v.len(), 2);
        // lengths in proportion to L₀g = 1.2 : 1.6, summing to the segment's
        let seg = xs[3] - xs[2];
        assert!((v[0].length + v[1].length - seg).abs() < 1e-14);
        assert!((v[0].length / v[1].length - 0.75).abs() < 1e-14);
        assert_eq!(v[0].neighbour_lengths[1], v[1].length);
        assert_eq!(v[0].neighbour_lengths[0], xs[2] - xs[1]);
        assert!(v
            .iter()
            .all(|c| c.width.is_finite() && c.stress.is_finite()));
    }
}
