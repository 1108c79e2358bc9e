//! The sheet's per-cell fields in `f64` for observers and writers ([`UniaxialSheet::cells`]):
//! stretches, height, stresses and pressure including a Maxwell branch, the Kelvin–Voigt stress
//! and the external pressure, and the viscous stretches.

use super::{zero_response, SheetCell, UniaxialSheet};
use crate::cell::{kelvin_voigt_sheet, ViscousBranch};
use crate::energy::{SheetResponse, StrainEnergy};
use crate::substrate::Dissipation;

impl<E: StrainEnergy> UniaxialSheet<E> {
    /// Per-cell fields at state `y` with rates `yp`, time `t` (column-major: index
    /// `(j−1)·m + (k−1)`). The stresses and the pressure include the branch, the Kelvin–Voigt
    /// stress (the only use of `yp`) and the external pressure.
    ///
    /// ```
    /// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
    /// let p = SheetParams { cells_x: 2, cells_y: 1, ..Default::default() };
    /// let sheet = UniaxialSheet::discrete(celltissue::NeoHookean::new(1.0)?, &p)?;
    /// let mut y = sheet.initial_state();
    /// y[sheet.ix(1, 1)] = 1.2; // the first cell stretched by 20 %, the second compressed
    /// let c = sheet.cells(0.0, &y, &vec![0.0; y.len()]);
    /// assert!((c[0].stretch[0] - 1.2).abs() < 1e-15 && (c[1].stretch[0] - 0.8).abs() < 1e-15);
    /// assert!(c[0].s11 > 0.0 && c[1].s11 < 0.0); // tension, compression
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn cells(&self, t: f64, y: &[f64], yp: &[f64]) -> Vec<SheetCell> {
        let (lt, ldot) = (self.length(t), self.length_rate(t));
        let branch = self.params.branch.as_ref();
        let respond = |l1: f64, l2: f64| {
            if l1 > 0.0 && l2 > 0.0 {
                self.law.sheet(l1, l2)
            } else {
                SheetResponse {
                    s11: f64::NAN,
                    s22: f64::NAN,
                    pressure: f64::NAN,
                    tangent: [[f64::NAN; 2]; 2],
                }
            }
        };
        let mut out = Vec::with_capacity(self.n * self.m);
        for j in 1..=self.n {
            let pe = self.p_ext[j - 1];
            for k in 1..=self.m {
                let x = [self.xb_s(y, lt, j - 1, k), self.xb_s(y, lt, j, k)];
                let yy = [self.yb_s(y, j, k - 1), self.yb_s(y, j, k)];
                let l1 = (x[1] - x[0]) / self.hx;
                let l2 = (yy[1] - yy[0]) / self.hy;
                let growth = match self.growth() {
                    Some(_) => [y[self.ig(j, k)], y[self.ig(j, k) + 1]],
                    None => [1.0, 1.0],
                };
                // stretches relative to the grown cell
                let (a1, a2) = (l1 / growth[0], l2 / growth[1]);
                let l3 = 1.0 / (a1 * a2);
                let mut r = if branch.is_none_or(|br| br.keeps_elastic()) {
                    respond(a1, a2)
                } else {
                    zero_response()
                };
                let mut viscous = [1.0, 1.0];
                if let Some(br) = branch {
                    let q = self.iq(j, k);
                    viscous = [y[q], y[q + 1]];
                    let rb = respond(a1 / viscous[0], a2 / viscous[1]);
                    let f = br.modulus_ratio(&self.law);
                    r.s11 += f * rb.s11;
                    r.s22 += f * rb.s22;
                    r.pressure += f * rb.pressure;
                }
                if self.params.eta > 0.0 && a1 > 0.0 && a2 > 0.0 {
                    let rate = self.stretch_rates(y, yp, ldot, j, k, [a1, a2]);
                    let [v11, v22, vp] = kelvin_voigt_sheet(self.params.eta, [a1, a2], rate);
                    r.s11 += v11;
                    r.s22 += v22;
                    r.pressure += vp;
                }
                out.push(SheetCell {
                    j,
                    k,
                    x,
                    y: yy,
                    reference: [(j as f64 - 0.5) * self.hx, (k as f64 - 0.5) * self.hy],
                    stretch: [l1, l2, l3],
                    height: self.params.beta0 * l3,
                    pressure: r.pressure + pe,
                    s11: r.s11 - pe,
                    s22: r.s22 - pe,
                    kappa: self.dissipation().kappa(l1 * l2),
                    viscous,
                    growth,
                });
            }
        }
        out
    }
}
