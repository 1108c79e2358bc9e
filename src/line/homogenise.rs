//! Cell-scale heterogeneity on a coarser continuum grid: the effective values of the cells each
//! segment holds.
//!
//! The continuum of docs/model.md §3 assumes fields that vary over many cells, and samples them
//! at segment centres. A per-cell list (given, or a random field drawn once per cell) varies
//! from cell to cell, so a segment of several cells read at its centre cell would be another
//! tissue. Within a segment much shorter than the length over which the drag acts, the cells
//! carry one force, so they act in series, and the segment gets the values that reproduce their
//! combined response (docs/model.md §3.3, "Cell-scale heterogeneity"):
//!
//! * `μ`: the length-weighted harmonic mean (equal compliance at rest);
//! * `η`: `μ̄² Σ wᵢηᵢ/μᵢ²` (the same mean creep time, so uniform `η/μ` keeps its ratio);
//! * active amplitude and external pressure: `μ̄ Σ wᵢaᵢ/μᵢ` (the same additive stress at rest);
//! * drag `K` (per boundary): the mean over the boundaries the segment holds, weighting each
//!   cell by the part of it inside.
//!
//! [`super::build`] calls [`homogenised`] when some field jumps between cells (a list of one
//! value per cell, a random field drawn per cell, a piecewise field) and the grid is not the
//! cells themselves; smooth fields alone are still sampled at centres.

use super::build::{sample_points, LineParams};
use crate::cell::Field;

/// A field's effective value on each segment of a grid, one list per field of [`LineParams`].
pub(crate) struct SegmentValues {
    pub(crate) mu: Vec<f64>,
    pub(crate) eta: Vec<f64>,
    pub(crate) k: Vec<f64>,
    pub(crate) active_amp: Vec<f64>,
    pub(crate) p_ext: Vec<f64>,
}

/// The effective values on the segments between `faces` (`0 = F₀ < … < Fₙ = l₀`) of the cells
/// of `p`, or `None` when no field of `p` jumps between cells (a per-cell list or a piecewise
/// field: the continuum samples smooth fields at centres) or each segment is within one cell.
pub(crate) fn homogenised(p: &LineParams, faces: &[f64]) -> Option<SegmentValues> {
    let cells = p.ref_lengths.len();
    let fields = [&p.mu, &p.eta, &p.k, &p.active_amp, &p.p_ext];
    if !fields.iter().any(|f| jumps_between_cells(f, cells)) {
        return None;
    }
    let overlaps = Overlaps::new(&p.ref_lengths, faces);
    if overlaps.single.iter().all(Option::is_some) {
        return None;
    }
    // each cell's values as the discrete line samples them
    let mut bounds = Vec::with_capacity(cells + 1);
    bounds.push(0.0);
    for l in &p.ref_lengths {
        bounds.push(bounds.last().unwrap_or(&0.0) + l);
    }
    let l0 = bounds[cells];
    let points = sample_points(p.sampling, &bounds);
    let [mu, eta, k, active_amp, p_ext] = fields.map(|f| f.sample(&points, l0));
    let n = faces.len() - 1;
    let mut out = SegmentValues {
        mu: Vec::with_capacity(n),
        eta: Vec::with_capacity(n),
        k: overlaps.mean(&k, |i| 1.0 / p.ref_lengths[i]).collect(),
        active_amp: Vec::with_capacity(n),
        p_ext: Vec::with_capacity(n),
    };
    let cell = |c: usize| CellValues {
        mu: mu[c],
        eta: eta[c],
        active_amp: active_amp[c],
        p_ext: p_ext[c],
    };
    for (s, parts) in overlaps.start.windows(2).enumerate() {
        let mixed = match overlaps.single[s] {
            Some(c) => {
                out.k[s] = k[c];
                cell(c)
            }
            None => {
                let mut series = InSeries::default();
                for &(c, inside) in &overlaps.parts[parts[0]..parts[1]] {
                    series.add(inside, &cell(c));
                }
                series.values()
            }
        };
        out.mu.push(mixed.mu);
        out.eta.push(mixed.eta);
        out.active_amp.push(mixed.active_amp);
        out.p_ext.push(mixed.p_ext);
    }
    Some(out)
}

/// A cell's (or segment's) values that combine in series.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CellValues {
    pub(crate) mu: f64,
    pub(crate) eta: f64,
    pub(crate) active_amp: f64,
    pub(crate) p_ext: f64,
}

/// Cells in series, added one by one with their lengths: [`InSeries::values`] are those of
/// one element with the same compliance, mean creep time and stress at rest (the module's
/// rules). Used by the continuum's segments and by the cell-number grid's merges.
#[derive(Default)]
pub(crate) struct InSeries {
    length: f64,
    compliance: f64,
    creep: f64,
    active: f64,
    pressure: f64,
}

impl InSeries {
    /// Adds a cell of length `w` (any positive measure of it).
    pub(crate) fn add(&mut self, w: f64, c: &CellValues) {
        let j = w / c.mu;
        self.length += w;
        self.compliance += j;
        self.creep += j * c.eta / c.mu;
        self.active += j * c.active_amp;
        self.pressure += j * c.p_ext;
    }

    /// The values of the element the cells added so far make.
    pub(crate) fn values(&self) -> CellValues {
        let mu = self.length / self.compliance;
        let per_length = mu / self.length;
        CellValues {
            mu,
            eta: mu * self.creep * per_length,
            active_amp: self.active * per_length,
            p_ext: self.pressure * per_length,
        }
    }
}

/// Whether `f` jumps from cell to cell on a line of `cells` cells: a list of one value per
/// cell, a random field (drawn once per cell) or a piecewise field.
pub(crate) fn jumps_between_cells(f: &Field, cells: usize) -> bool {
    match f {
        Field::PerCell { values } => values.len() == cells,
        Field::Piecewise { .. } | Field::Random { .. } => true,
        _ => false,
    }
}

/// The means of the per-cell `values` of cells of `lengths` over each segment between
/// `faces`, weighting each cell by its part inside, or `None` when each segment is within
/// one cell (where reading that cell is the same).
pub(crate) fn segment_means(lengths: &[f64], faces: &[f64], values: &[f64]) -> Option<Vec<f64>> {
    let overlaps = Overlaps::new(lengths, faces);
    if overlaps.single.iter().all(Option::is_some) {
        return None;
    }
    let means = overlaps.mean(values, |_| 1.0).zip(&overlaps.single);
    Some(means.map(|(m, s)| s.map_or(m, |c| values[c])).collect())
}

/// The parts of the cells inside each segment of a grid: `(cell, length inside)` pairs,
/// segment by segment, in one sweep along the line.
struct Overlaps {
    /// `parts[start[s]..start[s + 1]]` are segment `s`'s.
    start: Vec<usize>,
    parts: Vec<(usize, f64)>,
    /// The cell filling a segment alone (up to rounding of the faces), whose values it keeps
    /// exactly.
    single: Vec<Option<usize>>,
}

impl Overlaps {
    fn new(lengths: &[f64], faces: &[f64]) -> Self {
        let n = faces.len() - 1;
        let mut start = Vec::with_capacity(n + 1);
        let mut parts = Vec::with_capacity(n + lengths.len());
        let mut single = Vec::with_capacity(n);
        let (mut cell, mut cell_start) = (0, 0.0);
        for s in 0..n {
            start.push(parts.len());
            let (a, b) = (faces[s], faces[s + 1]);
            loop {
                let cell_end = cell_start + lengths[cell];
                let inside = cell_end.min(b) - cell_start.max(a);
                if inside > 0.0 {
                    parts.push((cell, inside));
                }
                // the last cell takes whatever rounding leaves at the right end
                if cell_end > b || cell + 1 == lengths.len() {
                    break;
                }
                cell += 1;
                cell_start = cell_end;
            }
            let mine = &parts[start[s]..];
            let h = b - a;
            single.push(
                mine.iter()
                    .find(|&&(_, inside)| inside >= h * (1.0 - 1e-9))
                    .map(|&(c, _)| c),
            );
        }
        start.push(parts.len());
        Self {
            start,
            parts,
            single,
        }
    }

    /// Each segment's mean of `values` over its cells, weighting each by the length inside
    /// times `weight(cell)`.
    fn mean<'a>(
        &'a self,
        values: &'a [f64],
        weight: impl Fn(usize) -> f64 + 'a,
    ) -> impl Iterator<Item = f64> + 'a {
        self.start.windows(2).map(move |w| {
            let (mut sum, mut total) = (0.0, 0.0);
            for &(c, inside) in &self.parts[w[0]..w[1]] {
                let wt = inside * weight(c);
                sum += wt * values[c];
                total += wt;
            }
            sum / total
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn faces(n: usize, l0: f64) -> Vec<f64> {
        (0..=n).map(|i| l0 * i as f64 / n as f64).collect()
    }

    #[test]
    fn cells_in_series_give_the_harmonic_modulus_and_the_mean_creep_time() {
        let mut p = LineParams::unit_cells(4);
        p.mu = Field::PerCell {
            values: vec![1.0, 2.0, 4.0, 4.0],
        };
        p.eta = Field::PerCell {
            values: vec![3.0, 6.0, 0.0, 8.0],
        };
        p.k = Field::PerCell {
            values: vec![1.0, 3.0, 5.0, 7.0],
        };
        let v = homogenised(&p, &faces(2, 4.0)).expect("two cells per segment");
        // 1/μ̄ = (1 + 1/2)/2 = 3/4; η/μ = 3 in both cells, so η̄ = 3μ̄
        assert!((v.mu[0] - 4.0 / 3.0).abs() < 1e-15 && (v.eta[0] - 4.0).abs() < 1e-14);
        // equal moduli: the plain means
        assert_eq!((v.mu[1], v.eta[1], v.k), (4.0, 4.0, vec![2.0, 6.0]));
    }

    #[test]
    fn a_segment_straddling_unequal_cells_weights_each_by_its_part() {
        let mut p = LineParams::unit_cells(3);
        p.ref_lengths = vec![0.5, 1.0, 1.5]; // boundaries 0, 0.5, 1.5, 3
        p.mu = Field::PerCell {
            values: vec![1.0, 2.0, 3.0],
        };
        p.k = p.mu.clone();
        let v = homogenised(&p, &faces(2, 3.0)).expect("mixed segments");
        // [0, 1.5] = 0.5 of cell 0 + cell 1; [1.5, 3] = cell 2 alone
        assert!((1.0 / v.mu[0] - (0.5 / 1.0 + 1.0 / 2.0) / 1.5).abs() < 1e-15);
        assert_eq!(v.mu[1], 3.0);
        // drag by boundaries: cell 0 counts 0.5/0.5 = 1, cell 1 counts 1
        assert!((v.k[0] - 1.5).abs() < 1e-15);
    }

    #[test]
    fn smooth_fields_and_one_cell_segments_are_left_to_the_sampler() {
        let mut p = LineParams::unit_cells(4);
        p.mu = Field::Gaussian {
            base: 1.0,
            amplitude: 1.0,
            centre: 0.5,
            width: 0.1,
        };
        assert!(homogenised(&p, &faces(2, 4.0)).is_none());
        p.mu = Field::PerCell {
            values: vec![1.0, 2.0, 3.0, 4.0],
        };
        assert!(homogenised(&p, &faces(4, 4.0)).is_none());
        assert!(homogenised(&p, &faces(8, 4.0)).is_none()); // half cells: each in one cell
                                                            // a piecewise field jumping inside a segment
        p.mu = Field::Piecewise {
            breaks: vec![0.5],
            values: vec![1.0, 3.0],
        };
        assert!(homogenised(&p, &faces(4, 4.0)).is_none());
        let v = homogenised(&p, &faces(1, 4.0)).expect("one segment of four cells");
        assert!((v.mu[0] - 1.5).abs() < 1e-15); // 1/μ̄ = (1 + 1/3)/2
    }
}
