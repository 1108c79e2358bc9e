//! A binary of one's own with the whole `celltissue` command line: it registers a
//! time-stepping method (fixed-step implicit Euler, written below against the `Method` trait;
//! `docs/guide-method.md` explains it) and a strain energy (Yeoh), then hands over to
//! `celltissue::cli::main`. Scenarios then name them like the built-in ones:
//!
//! ```text
//! cargo run --release --example custom_cli -- run models/fig2_5.toml --out /tmp/out \
//!     --set solver.method=implicit_euler
//! cargo run --release --example custom_cli -- validate models/fig2_5.toml \
//!     --set 'model.law={law="yeoh",c1=0.5,c2=0.2}'
//! ```
//!
//! Only `celltissue` is used (the integrators and the AD numbers are re-exported by it).
use celltissue::num_dual::DualNum;
use celltissue::serde::{Deserialize, Serialize};
use celltissue::StrainEnergy;

use celltissue::integrators::error::{ErrorKind, SolverError};
use celltissue::integrators::linalg::{LinearSolver, Matrix};
use celltissue::integrators::system::{StepFailure, System};
use celltissue::method::Method;

/// Backward (implicit) Euler with a fixed step `h`: `F(t + h, y₁, (y₁ − y₀)/h) = 0`, solved
/// by Newton's method on the iteration matrix `∂F/∂y + (1/h)·∂F/∂ẏ`. First order, L-stable.
pub struct ImplicitEuler {
    h: f64,
    t: f64,
    t_prev: f64,
    y: Vec<f64>,
    yp: Vec<f64>,
    y_prev: Vec<f64>,
    work: Option<(Matrix, LinearSolver)>,
}

impl ImplicitEuler {
    /// A method taking steps of `h` (the last one shortened to land on the stop time).
    pub fn new(h: f64) -> Self {
        Self {
            h,
            t: 0.0,
            t_prev: 0.0,
            y: vec![],
            yp: vec![],
            y_prev: vec![],
            work: None,
        }
    }
}

/// A step failure as the driver's error at time `t`.
fn fail(f: StepFailure, t: f64) -> SolverError {
    match f {
        StepFailure::Fatal(e) => e,
        StepFailure::Recoverable { reason, component } => {
            SolverError::new(reason.into(), t, component)
        }
    }
}

impl Method for ImplicitEuler {
    fn name(&self) -> &'static str {
        "implicit_euler"
    }

    fn start(
        &mut self,
        sys: &mut System<'_>,
        t: f64,
        y: &[f64],
        yp: &[f64],
        _h: Option<f64>,
    ) -> Result<(), SolverError> {
        (self.t, self.t_prev) = (t, t);
        (self.y, self.yp, self.y_prev) = (y.to_vec(), yp.to_vec(), y.to_vec());
        // workspaces for the (possibly new) dimension and pattern
        self.work = Some((sys.new_matrix(), sys.new_linear_solver()));
        Ok(())
    }

    fn step(&mut self, sys: &mut System<'_>, t_stop: f64) -> Result<usize, SolverError> {
        let h = self.h.min(t_stop - self.t);
        let t1 = self.t + h;
        let n = self.y.len();
        let (jac, lu) = self.work.as_mut().expect("started");
        // Newton from the explicit predictor y₀ + h·ẏ₀, one Jacobian per step
        let mut y1: Vec<f64> = self
            .y
            .iter()
            .zip(&self.yp)
            .map(|(y, yp)| y + h * yp)
            .collect();
        let mut yp1 = vec![0.0; n];
        let mut r = vec![0.0; n];
        let mut w = vec![0.0; n];
        sys.error_weights(&self.y, &mut w);
        for (yp, (a, b)) in yp1.iter_mut().zip(y1.iter().zip(&self.y)) {
            *yp = (a - b) / h;
        }
        sys.jacobian(t1, &y1, &yp1, 1.0 / h, jac)
            .map_err(|f| fail(f, self.t))?;
        sys.factor(lu, jac).map_err(|f| fail(f, self.t))?;
        let mut converged = false;
        for _ in 0..sys.opts.max_newton_iters.max(8) {
            sys.residual(t1, &y1, &yp1, &mut r)
                .map_err(|f| fail(f, self.t))?;
            sys.solve(lu, &mut r);
            for i in 0..n {
                y1[i] -= r[i];
                yp1[i] = (y1[i] - self.y[i]) / h;
            }
            // converged when the correction is far below the tolerance (weighted RMS)
            if System::wrms(&r, &w) < 1e-3 {
                converged = true;
                break;
            }
        }
        if !converged {
            return Err(SolverError::new(ErrorKind::NewtonFailure, self.t, None));
        }
        self.y_prev = std::mem::replace(&mut self.y, y1);
        self.yp = yp1;
        (self.t_prev, self.t) = (self.t, t1);
        Ok(1) // one accepted step: the driver counts it
    }

    fn t(&self) -> f64 {
        self.t
    }
    fn t_prev(&self) -> f64 {
        self.t_prev
    }
    fn y(&self) -> &[f64] {
        &self.y
    }
    fn yp(&self) -> &[f64] {
        &self.yp
    }
    fn h_next(&self) -> f64 {
        self.h
    }

    /// Dense output: the straight line between the last two states (first order, as the method).
    fn interpolate(&self, t: f64, y: &mut [f64], yp: &mut [f64]) {
        let s = if self.t > self.t_prev {
            (t - self.t_prev) / (self.t - self.t_prev)
        } else {
            1.0
        };
        for i in 0..y.len() {
            y[i] = self.y_prev[i] + s * (self.y[i] - self.y_prev[i]);
            yp[i] = self.yp[i];
        }
    }
}

/// Yeoh's law `W = c₁(I₁ − 3) + c₂(I₁ − 3)²` (shear modulus `2c₁`), parameters by name.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(crate = "celltissue::serde", deny_unknown_fields)]
pub struct Yeoh {
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
    celltissue::method::register(celltissue::method::CustomMethod {
        name: "implicit_euler",
        build: || Box::new(ImplicitEuler::new(1e-3)),
        stiff: true,
    })
    .expect("a new method name");
    celltissue::energy::registry::register::<Yeoh>("yeoh").expect("a new law name");
    std::process::exit(celltissue::cli::main());
}
