//! A user-defined law (Yeoh, W = C₁(I₁−3) + C₂(I₁−3)²) in a few lines, its responses by AD, and
//! a short line relaxation with it. Run: `cargo run --release --example custom_energy`.
use celltissue::boundary::{Ramp, RightEnd};
use celltissue::line::{build::discrete, run::integrate, LineParams, SolveSettings};
use celltissue::{ArrayProblem, StrainEnergy};
use num_dual::DualNum;

/// Yeoh law; small-strain shear modulus μ = 2C₁.
struct Yeoh {
    c1: f64,
    c2: f64,
}

impl StrainEnergy for Yeoh {
    fn energy<D: DualNum<Primitive = f64> + Copy>(&self, l: [D; 3]) -> D {
        let j1 = l[0] * l[0] + l[1] * l[1] + l[2] * l[2] - 3.0;
        j1 * self.c1 + j1 * j1 * self.c2
    }
    fn shear_modulus(&self) -> f64 {
        2.0 * self.c1
    }
}

fn main() {
    let law = Yeoh { c1: 0.5, c2: 0.2 };
    for a in [0.8, 1.0, 1.25] {
        let (r, s) = (law.line(a), law.sheet(a, 1.0));
        println!("a = {a}: line σ_el = {:.5}, dσ/da = {:.5}, p = {:.5}; sheet σ11 = {:.5}, σ22 = {:.5}, ∂σ11/∂λ1 = {:.5}",
            r.sigma, r.dsigma, r.pressure, s.s11, s.s22, s.tangent[0][0]);
    }
    // 20 cells, drag K = 1, right end shortened by 10 % (exponential ramp, MODEL.md §2.6).
    let mut p = LineParams::unit_cells(20);
    p.k = 1.0.into();
    p.right = RightEnd::Prescribed(Ramp::Exponential {
        l0: 20.0,
        k1: 0.1,
        t_ramp: 1.0,
    });
    let mut problem = ArrayProblem::new(discrete(law, &p).expect("valid line"));
    let traj = integrate(
        &mut problem,
        &SolveSettings::default(),
        &[0.0, 0.5, 1.0, 2.0, 5.0],
    );
    for s in &traj.snapshots {
        let (lo, hi) = s
            .lambda
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), &l| (a.min(l), b.max(l)));
        let pmax = s.pressure.iter().cloned().fold(f64::MIN, f64::max);
        println!(
            "t = {:4.1}: length = {:.5}, λ ∈ [{lo:.5}, {hi:.5}], max p = {pmax:.5}",
            s.t,
            s.x[20] - s.x[0]
        );
    }
    assert!(traj.error.is_none(), "{:?}", traj.error);
}
