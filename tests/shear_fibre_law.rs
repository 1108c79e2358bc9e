//! A fibre law in the simple-shear column (docs/model.md §1.5): simple shear turns the principal
//! axes, so an HGO cell's response must follow its fibre through the deformation gradient. The
//! steady column (τ(T) = F_A/β₀ in every cell) is checked against a root of the shear stress
//! computed here from `W(F)` at the full gradient, independent of the law's code; a law that
//! reads its stretches along the cell's axes without saying how it shears is refused.

use celltissue::energy::Expression;
use celltissue::observe::ModelKind;
use celltissue::runner::OutputTimes;
use celltissue::sheet::shear::{ShearBuildError, ShearColumn, ShearParams};
use celltissue::sheet::{run_shear, ShearConfig};
use celltissue::{AnyEnergy, Hgo, SolveSettings};

/// HGO at simple shear `[[1, T, 0], [0, s, 0], [0, 0, 1]]` from `C = FᵀF` written out:
/// `I₁ = 2 + T² + s²`, fibre `a = (cos θ, sin θ, 0)`, `I₄ = (cos θ + T sin θ)² + s² sin²θ`.
fn w(p: (f64, f64, f64, f64), t: f64, s: f64) -> f64 {
    let (c, k1, k2, th) = p;
    let i1 = 2.0 + t * t + s * s;
    let i4 = (th.cos() + t * th.sin()).powi(2) + (s * th.sin()).powi(2);
    let e = i4 - 1.0;
    let fibre = if e > 0.0 {
        k1 / (2.0 * k2) * ((k2 * e * e).exp() - 1.0)
    } else {
        0.0
    };
    0.5 * c * (i1 - 3.0) + fibre
}

/// The steady amount of shear: the root of `dW/dT = force` by bisection on central differences,
/// and the pressure `∂W/∂F₂₂` there.
fn steady(p: (f64, f64, f64, f64), force: f64) -> (f64, f64) {
    let h = 1e-6;
    let tau = |t: f64| (w(p, t + h, 1.0) - w(p, t - h, 1.0)) / (2.0 * h);
    let (mut lo, mut hi) = (0.0, force / p.0); // the matrix alone shears furthest
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if tau(mid) < force {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let t = 0.5 * (lo + hi);
    (t, (w(p, t, 1.0 + h) - w(p, t, 1.0 - h)) / (2.0 * h))
}

#[test]
fn fibre_law_column_reaches_the_shear_of_its_sheared_fibre() {
    let settings = SolveSettings {
        rtol: 1e-10,
        atol: 1e-12,
        ..Default::default()
    };
    // θ = 0.5: fibres stretched by the shear; −0.5: compressed at first and still at the steady
    // shear (T < 2 cot θ), so the matrix alone carries F_A (T = F_A/c = 2 exactly); 1.2: steep.
    for (theta, matrix_only) in [(0.5, false), (-0.5, true), (1.2, false)] {
        let p = (0.5, 1.0, 1.0, theta);
        let (t_ref, p_ref) = steady(p, 1.0);
        if matrix_only {
            assert!((t_ref - 2.0).abs() < 1e-9);
        }
        let law = AnyEnergy::from(Hgo::new(p.0, p.1, p.2, p.3).unwrap());
        let cfg = ShearConfig {
            law: law.clone(),
            ..Default::default()
        };
        cfg.validate().unwrap();
        for (model, grid) in [
            (ModelKind::Discrete, None),
            (ModelKind::Continuum, Some(40)),
        ] {
            let rec = run_shear(
                &cfg,
                &law,
                model,
                grid,
                &settings,
                &OutputTimes::at(&[4000.0]),
            )
            .unwrap();
            assert!(rec.error.is_none(), "{:?}", rec.error);
            let s = &rec.series;
            for t in [s.max_stretch[0], s.min_stretch[0]] {
                assert!(
                    (t - t_ref).abs() < 1e-7,
                    "θ = {theta} {model:?}: tan θ {t} vs {t_ref}"
                );
            }
            for q in [s.max_pressure[0], s.min_pressure[0]] {
                assert!(
                    (q - p_ref).abs() < 1e-6,
                    "θ = {theta} {model:?}: p {q} vs {p_ref}"
                );
            }
            let top = rec.series.extra["top_displacement"][0];
            assert!((top - 10.0 * t_ref).abs() < 1e-6, "θ = {theta}: top {top}");
        }
    }
}

#[test]
fn a_law_reading_its_stretches_along_the_cell_axes_is_refused_by_the_column() {
    let axial = Expression::new("mu/2*(I1 - 3) + k*(l1 - 1)^2", [("mu", 1.0), ("k", 1.0)]).unwrap();
    let p = ShearParams::default();
    assert_eq!(
        ShearColumn::discrete(axial.clone(), &p).err(),
        Some(ShearBuildError::Law)
    );
    let cfg = ShearConfig {
        law: axial.into(),
        ..Default::default()
    };
    let e = cfg.validate().unwrap_err();
    assert_eq!(e.key, "law");
    assert!(e.expected.contains("symmetric in l1 and l2"), "{e}");
    // the same term written for both in-plane stretches is a law of the principal stretches
    let both = Expression::new(
        "mu/2*(I1 - 3) + k*((l1 - 1)^2 + (l2 - 1)^2)",
        [("mu", 1.0), ("k", 1.0)],
    )
    .unwrap();
    assert!(ShearColumn::discrete(both, &p).is_ok());
}
