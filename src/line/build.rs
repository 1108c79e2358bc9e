//! Builders: one physical description ([`LineParams`]) → a [`Line`] on either discretisation.
//!
//! * [`discrete`] — N cells with their own reference lengths; drag `K(X_j)` per boundary.
//! * [`continuum`] — the conservative scheme of docs/model.md §3.3a: `n` segments of length
//!   `h = l₀/n`, fields sampled at segment centres, drag `K·h/L̄` per node (`L̄ = l₀/N`, the mean
//!   reference cell length, since `K` is drag per cell boundary). With `n = N` and unit cells it
//!   *is* the discrete model (same type, same residual), so `n` is independent of `N`.

use super::array::{Cells, Layout, Line};
use super::LineError;
use crate::boundary::RightEnd;
use crate::cell::{Active, Field, GrowthLaw, MaxwellBranch, Sampling};
use crate::energy::StrainEnergy;
use crate::substrate::{DragForm, WidthRule};
use std::f64::consts::PI;
use std::sync::Arc;

/// A line independent of its discretisation: the cells' reference lengths, material fields of
/// `X`, substrate, boundary conditions, active stress and growth.
///
/// ```
/// use celltissue::line::build::{LineParams, discrete, continuum};
/// use celltissue::boundary::{Ramp, RightEnd};
/// use celltissue::NeoHookean;
/// let mut p = LineParams::unit_cells(100);
/// p.right = RightEnd::Prescribed(Ramp::Exponential { l0: 100.0, k1: 0.1, t_ramp: 1.0 });
/// p.k = 1.0.into();
/// let d = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
/// let c = continuum(NeoHookean::new(1.0).unwrap(), &p, 25).unwrap();
/// assert_eq!(d.n_cells(), 100);
/// assert_eq!(c.n_cells(), 25);
/// ```
#[derive(Clone)]
pub struct LineParams {
    /// Reference length of each cell (`N = len`).
    pub ref_lengths: Vec<f64>,
    /// Energy scale field `μ(X)` (the shear modulus for a unit-modulus law).
    pub mu: Field,
    /// Viscosity field `η(X)`.
    pub eta: Field,
    /// Drag field `K(X)` (per boundary).
    pub k: Field,
    /// Active-amplitude field `A(X)` (used only if `active` is set).
    pub active_amp: Field,
    /// Where fields are sampled.
    pub sampling: Sampling,
    /// Drag-area exponent `m`.
    pub m: f64,
    /// Lateral growth stretch `g₂`.
    pub g2: f64,
    /// Aspect ratio `γ₀`.
    pub gamma0: f64,
    /// Shared-width rule.
    pub width: WidthRule,
    /// Drag form.
    pub form: DragForm,
    /// Right end.
    pub right: RightEnd,
    /// Active stress.
    pub active: Option<Active>,
    /// Growth law.
    pub growth: Option<Arc<dyn GrowthLaw>>,
    /// Maxwell branch (Maxwell or standard linear solid cells; docs/viscoelasticity.md).
    pub maxwell: Option<MaxwellBranch>,
    /// External pressure field `p_e(X)` on the cells' lateral faces (docs/model.md §8.2).
    pub p_ext: Field,
    /// Absolute tolerance in cell units.
    pub atol_cell: f64,
}

impl LineParams {
    /// `n` unit cells, μ = 1, η = 0, K = 0, m = 0, γ₀ = g₂ = 1, wall + fixed length `n`.
    ///
    /// ```
    /// use celltissue::line::LineParams;
    /// let p = LineParams::unit_cells(8);
    /// assert_eq!((p.ref_lengths.len(), p.total_length()), (8, 8.0));
    /// ```
    pub fn unit_cells(n: usize) -> Self {
        Self {
            ref_lengths: vec![1.0; n],
            mu: Field::Constant(1.0),
            eta: Field::Constant(0.0),
            k: Field::Constant(0.0),
            active_amp: Field::Constant(1.0),
            sampling: Sampling::Centres,
            m: 0.0,
            g2: 1.0,
            gamma0: 1.0,
            width: WidthRule::Mean,
            form: DragForm::Boundary,
            right: RightEnd::Prescribed(crate::boundary::Ramp::Constant(n as f64)),
            active: None,
            growth: None,
            maxwell: None,
            p_ext: Field::Constant(0.0),
            atol_cell: 1e-8,
        }
    }

    /// `l₀ = Σ L₀,j`.
    ///
    /// ```
    /// let mut p = celltissue::line::LineParams::unit_cells(2);
    /// p.ref_lengths = vec![0.5, 1.5];
    /// assert_eq!(p.total_length(), 2.0);
    /// ```
    pub fn total_length(&self) -> f64 {
        sum_and_check(&self.ref_lengths).0
    }

    /// Checks every parameter; returns `l₀ = Σ L₀,j` (the same sum as
    /// [`total_length`](Self::total_length)), found in the pass that checks the lengths.
    fn check(&self) -> Result<f64, LineError> {
        if self.ref_lengths.is_empty() {
            return Err(LineError::invalid("cells", "0", ">= 1"));
        }
        let (total, all_ok) = sum_and_check(&self.ref_lengths);
        if !all_ok {
            let l = self
                .ref_lengths
                .iter()
                .find(|l| !(**l > 0.0 && l.is_finite()))
                .expect("a bad length exists");
            return Err(LineError::invalid("ref_lengths", l, "finite and > 0"));
        }
        if self.form == DragForm::Centre && self.right.is_periodic() {
            return Err(LineError::CentreFormPeriodic);
        }
        if !(self.gamma0 > 0.0 && self.gamma0.is_finite()) {
            return Err(LineError::invalid("gamma0", self.gamma0, "finite and > 0"));
        }
        if !(self.g2 > 0.0 && self.g2.is_finite()) {
            return Err(LineError::invalid("g2", self.g2, "finite and > 0"));
        }
        if !self.m.is_finite() {
            return Err(LineError::invalid("m", self.m, "finite"));
        }
        self.mu.validate("mu", true).map_err(LineError::Field)?;
        self.eta.validate("eta", false).map_err(LineError::Field)?;
        self.k.validate("K", false).map_err(LineError::Field)?;
        Ok(total)
    }
}

/// `Σ v` and whether every entry is finite and positive, in one branch-free pass. The sum runs
/// in eight interleaved partial sums combined pairwise (a single running sum is one 4-cycle
/// addition per cell in sequence: at N = 10⁴ that was ≈ 5 % of a 100-segment continuum solve).
fn sum_and_check(v: &[f64]) -> (f64, bool) {
    const LANES: usize = 8;
    let mut part = [0.0; LANES];
    let mut all_ok = true;
    let mut chunks = v.chunks_exact(LANES);
    for chunk in &mut chunks {
        for (p, &l) in part.iter_mut().zip(chunk) {
            *p += l;
            all_ok &= l > 0.0 && l.is_finite();
        }
    }
    for (p, &l) in part.iter_mut().zip(chunks.remainder()) {
        *p += l;
        all_ok &= l > 0.0 && l.is_finite();
    }
    let [a, b, c, d, e, f, g, h] = part;
    (((a + b) + (c + d)) + ((e + f) + (g + h)), all_ok)
}

/// Builds a line of `lengths.len()` cells with drag scaled by `drag_scale` per boundary.
fn assemble<E: StrainEnergy>(
    energy: E,
    p: &LineParams,
    lengths: Vec<f64>,
    drag_scale: f64,
) -> Result<Line<E>, LineError> {
    let n = lengths.len();
    let l0_total: f64 = lengths.iter().sum();
    let mut bounds = Vec::with_capacity(n + 1);
    bounds.push(0.0);
    let mut acc = 0.0;
    for l in &lengths {
        acc += l;
        bounds.push(acc);
    }
    let centres: Vec<f64> = (0..n).map(|i| 0.5 * (bounds[i] + bounds[i + 1])).collect();
    let samples: &[f64] = match p.sampling {
        Sampling::Centres => &centres,
        Sampling::IntegerPoints => &bounds[..n],
    };
    let mu = p.mu.sample(samples, l0_total);
    let eta = p.eta.sample(samples, l0_total);
    let k_cell: Vec<f64> =
        p.k.sample(samples, l0_total)
            .into_iter()
            .map(|k| k * drag_scale)
            .collect();
    let k_face: Vec<f64> = match &p.k {
        // a per-cell list has no boundary values: average the neighbours
        Field::PerCell { .. } | Field::Random { .. } => (0..=n)
            .map(|b| {
                let l = if b >= 1 { k_cell[b - 1] } else { k_cell[0] };
                let r = if b < n { k_cell[b] } else { k_cell[n - 1] };
                0.5 * (l + r)
            })
            .collect(),
        f => bounds
            .iter()
            .map(|&x| f.eval(x, l0_total) * drag_scale)
            .collect(),
    };
    let active_amp = p.active_amp.sample(samples, l0_total);
    let p_ext = p.p_ext.sample(samples, l0_total);
    if let Some(bad) = p_ext.iter().find(|x| !x.is_finite()) {
        return Err(LineError::invalid(
            "external_pressure",
            bad,
            "finite at every cell",
        ));
    }
    let phase = centres.iter().map(|&x| 2.0 * PI * x / l0_total).collect();
    for (key, v) in [("mu", &mu), ("eta", &eta), ("K", &k_cell)] {
        if let Some(bad) = v.iter().find(|x| !x.is_finite() || **x < 0.0) {
            return Err(LineError::invalid(
                key,
                bad,
                "finite and >= 0 at every cell",
            ));
        }
    }
    if let Some(bad) = mu.iter().find(|x| **x <= 0.0) {
        return Err(LineError::invalid("mu", bad, "> 0 at every cell"));
    }
    let right = match &p.right {
        RightEnd::Prescribed(r) => RightEnd::Prescribed(r.clone()),
        other => other.clone(),
    };
    let mut line = Line {
        energy,
        cells: Cells {
            l0: lengths,
            x_ref: centres,
            mu,
            eta,
            k_cell,
            active_amp,
            phase,
            p_ext,
        },
        k_face,
        m: p.m,
        g2: p.g2,
        gamma0: p.gamma0,
        width: p.width,
        form: p.form,
        right,
        active: p.active,
        growth: p.growth.clone(),
        maxwell: p.maxwell,
        l0_total,
        period: l0_total,
        atol_cell: p.atol_cell,
        threads: 1,
        layout: Layout::default(),
        uniform: Default::default(),
    };
    line.rebuild_layout();
    if line.layout.dim == 0 {
        return Err(LineError::invalid(
            "cells",
            n,
            ">= 2 for a prescribed right end without growth (no unknowns otherwise)",
        ));
    }
    Ok(line)
}

/// The discrete model: one cell per entry of `p.ref_lengths`.
///
/// ```
/// use celltissue::line::build::{discrete, LineParams};
/// use celltissue::{CellArray, NeoHookean};
/// let line = discrete(NeoHookean::new(1.0)?, &LineParams::unit_cells(5))?;
/// assert_eq!((line.n_cells(), line.l0_total()), (5, 5.0));
/// assert_eq!(line.dim(), 4); // x₁ … x₄ (x₀ = 0 and the prescribed x₅ are not unknowns)
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn discrete<E: StrainEnergy>(energy: E, p: &LineParams) -> Result<Line<E>, LineError> {
    p.check()?;
    assemble(energy, p, p.ref_lengths.clone(), 1.0)
}

/// The conservative continuum scheme with `n` segments of length `h = l₀/n` (docs/model.md §3.3a).
///
/// ```
/// use celltissue::line::build::{continuum, LineParams};
/// use celltissue::NeoHookean;
/// let line = continuum(NeoHookean::new(1.0)?, &LineParams::unit_cells(100), 20)?;
/// assert_eq!((line.n_cells(), line.l0_total()), (20, 100.0)); // 20 segments of h = 5
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn continuum<E: StrainEnergy>(
    energy: E,
    p: &LineParams,
    n: usize,
) -> Result<Line<E>, LineError> {
    let l0 = p.check()?;
    if n == 0 {
        return Err(LineError::invalid("nodes", n, ">= 1"));
    }
    let h = l0 / n as f64;
    let mean_cell = l0 / p.ref_lengths.len() as f64;
    assemble(energy, p, vec![h; n], h / mean_cell)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::NeoHookean;

    #[test]
    fn bad_reference_lengths_are_named_and_good_ones_give_l0() {
        let law = NeoHookean::new(1.0).unwrap();
        let mut p = LineParams::unit_cells(7);
        p.ref_lengths[3] = 0.5;
        assert_eq!(p.check().unwrap(), p.total_length());
        assert_eq!(continuum(law, &p, 3).unwrap().l0_total, 6.5);
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            p.ref_lengths[5] = bad;
            for e in [discrete(law, &p).err(), continuum(law, &p, 3).err()] {
                let msg = e.expect("rejected").to_string();
                assert!(msg.contains("ref_lengths"), "{bad}: {msg}");
            }
        }
    }

    #[test]
    fn the_lane_sum_is_the_sum_and_finds_any_bad_length() {
        // every remainder length; non-uniform lengths, so the summation order shows
        for n in [1, 7, 8, 9, 1003] {
            let v: Vec<f64> = (0..n)
                .map(|i| 0.5 + (0.37 * i as f64).sin().abs())
                .collect();
            let sequential: f64 = v.iter().sum();
            let (sum, ok) = sum_and_check(&v);
            assert!(ok);
            assert!((sum - sequential).abs() <= 1e-14 * sequential, "n={n}");
            for i in [0, n / 2, n - 1] {
                let mut w = v.clone();
                w[i] = -w[i];
                assert!(!sum_and_check(&w).1, "n={n} i={i}");
            }
        }
    }
}
