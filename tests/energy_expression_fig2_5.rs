//! A strain energy written in the scenario (`law = "expression"`, docs/model.md §1.1) runs the
//! whole Fig 2.5 scenario (discrete N = 100 and continuum n = 101, K = 1e-5 … 10).
//!
//! * Against the neo-Hookean energy differentiated the same way (nested-dual AD of `W`, a law
//!   registered by this test): series and profiles agree to 1e-8 relative. This isolates the
//!   parser, the evaluator and the registry wiring.
//! * Against the built-in `neo_hookean` (hand-written closed-form responses): the responses
//!   differ from AD by an ulp or two, which is enough to change some of BDF's step-size and
//!   order decisions (e.g. 118 vs 117 steps for the continuum at K = 1e-5), so the two runs
//!   agree only to the integration error: measured ≤ 1.2e-5 relative at the scenario's
//!   rtol = 1e-6 (and ≤ 2.5e-7 at rtol = 1e-10 — the integrator's own sensitivity to round-off,
//!   not the law's). The test asserts 1e-4, the validation tolerance of docs/model.md §5.

use celltissue::energy::registry;
use celltissue::observe::RunRecord;
use celltissue::scenario::{execute, load_str};
use celltissue::StrainEnergy;
use num_dual::DualNum;
use std::path::Path;

/// Neo-Hookean through the default AD responses (no closed-form overrides).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct AdNeoHookean {
    mu: f64,
}

impl StrainEnergy for AdNeoHookean {
    fn energy<D: DualNum<Primitive = f64> + Copy>(&self, l: [D; 3]) -> D {
        (l[0] * l[0] + l[1] * l[1] + l[2] * l[2] - 3.0) * (0.5 * self.mu)
    }
    fn shear_modulus(&self) -> f64 {
        self.mu
    }
}

fn run(text: &str) -> Vec<RunRecord> {
    let sc = load_str(text, Path::new("fig2_5.toml"), &[]).expect("scenario loads");
    sc.runs.iter().map(execute::run_spec).collect()
}

fn fig2_5_with(law: Option<&str>) -> String {
    let base =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("models/fig2_5.toml"))
            .unwrap();
    match law {
        None => base,
        Some(law) => {
            let text = base.replace("mu = 1.0\n", &format!("mu = 1.0\nlaw = {law}\n"));
            assert_ne!(base, text, "the law line was inserted");
            text
        }
    }
}

const EXPRESSION: &str = r#"{ law = "expression", W = "mu/2*(I1 - 3)", mu = 1.0 }"#;

#[test]
fn expression_reproduces_ad_neo_hookean_to_1e_8() {
    registry::register::<AdNeoHookean>("neo_hookean_ad").unwrap();
    let reference = run(&fig2_5_with(Some(
        r#"{ law = "neo_hookean_ad", mu = 1.0 }"#,
    )));
    let expr = run(&fig2_5_with(Some(EXPRESSION)));
    compare(&reference, &expr, 1e-8);
}

#[test]
fn expression_matches_closed_form_neo_hookean_to_integration_error() {
    compare(
        &run(&fig2_5_with(None)),
        &run(&fig2_5_with(Some(EXPRESSION))),
        1e-4,
    );
}

/// `|a − b| ≤ rel·max(|a|, |b|, 1e-12)` for every series and profile value of every run.
fn compare(builtin: &[RunRecord], expr: &[RunRecord], rel: f64) {
    let close = |a: f64, b: f64| (a - b).abs() <= rel * a.abs().max(b.abs()).max(1e-12);
    assert_eq!(builtin.len(), 8); // 4 drags × (discrete, continuum)
    assert_eq!(builtin.len(), expr.len());
    for (a, b) in builtin.iter().zip(expr) {
        assert!(a.error.is_none() && b.error.is_none(), "{}", a.label);
        assert_eq!(a.label, b.label);
        assert_eq!(b.parameters["law"]["law"], "expression");
        let (sa, sb) = (&a.series, &b.series);
        assert_eq!(sa.t, sb.t);
        for (name, x, y) in [
            ("length", &sa.length, &sb.length),
            ("max_pressure", &sa.max_pressure, &sb.max_pressure),
            ("min_pressure", &sa.min_pressure, &sb.min_pressure),
            ("max_stretch", &sa.max_stretch, &sb.max_stretch),
            ("min_stretch", &sa.min_stretch, &sb.min_stretch),
        ] {
            assert_eq!(x.len(), sa.t.len());
            for (i, (u, v)) in x.iter().zip(y).enumerate() {
                assert!(
                    close(*u, *v),
                    "{} {name}[{i}]: {u} vs {v} (tolerance {rel:e})",
                    a.label
                );
            }
        }
        for (pa, pb) in a.profiles.iter().zip(&b.profiles) {
            for (u, v) in pa.pressure.iter().zip(&pb.pressure) {
                assert!(close(*u, *v), "{} p(t = {}): {u} vs {v}", a.label, pa.t);
            }
            for (u, v) in pa.stretch.iter().zip(&pb.stretch) {
                assert!(close(*u, *v), "{} λ(t = {}): {u} vs {v}", a.label, pa.t);
            }
        }
    }
}

/// A bad formula in a scenario stops loading with the key path and the position.
#[test]
fn bad_formula_names_key_and_position() {
    let text = r#"
name = "bad"
[output]
series = { start = 0.01, stop = 1, count = 3, spacing = "log" }
profiles = [0]
[model]
kind = "line"
cells = 4
law = { law = "expression", W = "mu/2*(I1 - 3) + nu", mu = 1.0 }
"#;
    let Err(err) = load_str(text, Path::new("bad.toml"), &[]) else {
        panic!("rejected")
    };
    let err = err.to_string();
    assert!(err.contains("model.law"), "{err}");
    assert!(err.contains("W at position 17: unknown name `nu`"), "{err}");
    let sheet = r#"
name = "bad"
[output]
series = { start = 0.01, stop = 1, count = 3, spacing = "log" }
profiles = [0]
[model]
kind = "shear"
law = { law = "expression", W = "mu/2*(I1 - 3)" }
"#;
    let Err(err) = load_str(sheet, Path::new("bad.toml"), &[]) else {
        panic!("rejected")
    };
    let err = err.to_string();
    assert!(
        err.contains("model.law") && err.contains("unknown name `mu`"),
        "{err}"
    );
}
