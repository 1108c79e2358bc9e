//! A user-defined Yeoh law `W = C₁(I₁−3) + C₂(I₁−3)²` (μ = 2C₁): responses by AD, then a short
//! line relaxation (20 cells, K = 1, end shortened 10 %). `cargo run --release --example custom_energy`
use celltissue::boundary::{Ramp, RightEnd};
use celltissue::line::{build::discrete, run::integrate, LineParams, SolveSettings};
use celltissue::{ArrayProblem, StrainEnergy};
use num_dual::DualNum;

struct Yeoh(f64, f64);
impl StrainEnergy for Yeoh {
    fn energy<D: DualNum<Primitive = f64> + Copy>(&self, l: [D; 3]) -> D {
        let j1 = l[0] * l[0] + l[1] * l[1] + l[2] * l[2] - 3.0;
        j1 * self.0 + j1 * j1 * self.1
    }
    fn shear_modulus(&self) -> f64 {
        2.0 * self.0
    }
}

fn main() {
    let law = Yeoh(0.5, 0.2);
    for a in [0.8, 1.0, 1.25] {
        let (r, s) = (law.line(a), law.sheet(a, 1.0));
        println!(
            "a={a}: line σ={:.5} dσ/da={:.5} p={:.5}",
            r.sigma, r.dsigma, r.pressure
        );
        println!(
            "       sheet σ11={:.5} σ22={:.5} tangent={:.4?}",
            s.s11, s.s22, s.tangent
        );
    }
    let mut p = LineParams::unit_cells(20);
    p.k = 1.0.into();
    p.right = RightEnd::Prescribed(Ramp::Exponential {
        l0: 20.0,
        k1: 0.1,
        t_ramp: 1.0,
    });
    let mut prob = ArrayProblem::new(discrete(law, &p).expect("valid line"));
    let traj = integrate(
        &mut prob,
        &SolveSettings::default(),
        &[0.0, 0.5, 1.0, 2.0, 5.0],
    );
    assert!(traj.error.is_none(), "{:?}", traj.error);
    for s in &traj.snapshots {
        let lmin = s.lambda.iter().cloned().fold(f64::MAX, f64::min);
        let pmax = s.pressure.iter().cloned().fold(f64::MIN, f64::max);
        println!(
            "t={:.1}: length={:.5} min λ={lmin:.5} max p={pmax:.5}",
            s.t,
            s.x[20] - s.x[0]
        );
    }
}
