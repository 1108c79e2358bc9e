//! Helpers shared by integration tests (each test file that needs them declares `mod common;`).

/// The polynomial ramp's strain `ε(t) = −k₁ s(t/t_r)`, `s(v) = 3v² − 2v³` (held after `t_r`).
pub fn poly_strain(t: f64, k1: f64, t_r: f64) -> f64 {
    let v = (t / t_r).min(1.0);
    -k1 * (3.0 * v * v - 2.0 * v * v * v)
}

/// The linear Maxwell branch's stress under that ramp, `E_m ∫₀^{min(t,t_r)} ε'(u) e^{−(t−u)/τ} du`
/// (`E_m` the branch's small-strain modulus: `4μ_m` on the line, `3μ_m` in the sheet's
/// uniaxial stress), by composite Simpson on 4000 panels.
pub fn maxwell_ramp_stress(t: f64, k1: f64, t_r: f64, modulus: f64, tau: f64) -> f64 {
    let top = t.min(t_r);
    if top <= 0.0 {
        return 0.0;
    }
    let f = |u: f64| {
        let v = u / t_r;
        -k1 * (6.0 * v - 6.0 * v * v) / t_r * (-(t - u) / tau).exp()
    };
    let m = 4000;
    let h = top / m as f64;
    let mut s = f(0.0) + f(top);
    for i in 1..m {
        s += f(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    modulus * s * h / 3.0
}

/// Sheet and shear solver settings: BDF with the given tolerances (atol in cell units) under
/// the max norm, every cell's stretch error tested on its own (`SolveSettings::default`'s
/// norm).
pub fn sheet_solver(rtol: f64, atol: f64) -> celltissue::SolveSettings {
    celltissue::SolveSettings {
        rtol,
        atol,
        ..Default::default()
    }
}

/// The Fig 3.3 line: 100 unit cells, free right end, drag `k`, the tanh growth law (σ₀ = 0.1),
/// cell-unit atol 1e-10.
pub fn fig3_3_line(k: f64) -> celltissue::line::build::LineParams {
    let mut p = celltissue::line::build::LineParams::unit_cells(100);
    p.right = celltissue::boundary::RightEnd::Free(None);
    p.k = k.into();
    p.growth = Some(std::sync::Arc::new(celltissue::cell::TanhGrowth::default()));
    p.atol_cell = 1e-10;
    p
}

/// The proliferation benchmark's dividing line: 100 unit neo-Hookean cells (μ = 1), free right
/// end, drag `k`, η = 0, the tanh growth law (σ₀ = 0.1), the area rule, seed 0, the line's
/// default atol.
pub fn area_dividing_line(k: f64) -> celltissue::events::Dividing<celltissue::NeoHookean> {
    viscous_area_dividing_line(k, 0.0)
}

/// [`area_dividing_line`] with Kelvin–Voigt cells of viscosity `eta`.
pub fn viscous_area_dividing_line(
    k: f64,
    eta: f64,
) -> celltissue::events::Dividing<celltissue::NeoHookean> {
    let mut p = celltissue::line::build::LineParams::unit_cells(100);
    p.right = celltissue::boundary::RightEnd::Free(None);
    p.k = k.into();
    p.eta = eta.into();
    p.growth = Some(std::sync::Arc::new(celltissue::cell::TanhGrowth::default()));
    let energy = celltissue::NeoHookean::new(1.0).expect("μ > 0");
    let line = celltissue::line::build::discrete(energy, &p).expect("valid line");
    let rule = Box::new(celltissue::events::AreaDoubling::default());
    celltissue::events::Dividing::new(line, rule, 0).expect("a growing line divides")
}

/// What a dividing run cost and where it ended (counters from `Stats`; "Jacobians" are
/// evaluations of the pair `∂F/∂y`, `∂F/∂ẏ`).
pub struct DivisionCost {
    pub divisions: usize,
    pub steps: usize,
    pub rejected: usize,
    pub newton_failures: usize,
    pub jacobians: usize,
    /// Each division's time, in the order the log holds them.
    pub times: Vec<f64>,
    /// The line's final length.
    pub length: f64,
}

/// Runs `div` over `[0, t_end]` with `settings` (the run must succeed) and reports its cost.
pub fn division_cost(
    div: celltissue::events::Dividing<celltissue::NeoHookean>,
    settings: &celltissue::line::run::SolveSettings,
    t_end: f64,
) -> DivisionCost {
    let mut prob = celltissue::ArrayProblem::new(div);
    let traj = celltissue::line::run::integrate(&mut prob, settings, &[0.0, t_end]);
    assert!(traj.error.is_none(), "{:?}", traj.error);
    let s = traj.stats;
    DivisionCost {
        divisions: prob.array.log.len(),
        steps: s.steps,
        rejected: s.rejected_steps,
        newton_failures: s.newton_failures,
        jacobians: s.jacobian_evals / 2,
        times: prob.array.log.records.iter().map(|r| r.t).collect(),
        length: traj.snapshots.last().expect("a snapshot").length(),
    }
}

/// The largest relative difference of a profile field between two runs of one scenario,
/// profile by profile and cell by cell (the runs must have the same profiles and cells).
pub fn profile_gap(
    a: &celltissue::observe::RunRecord,
    b: &celltissue::observe::RunRecord,
    field: fn(&celltissue::observe::Profile) -> &[f64],
) -> f64 {
    assert_eq!(a.profiles.len(), b.profiles.len(), "profile counts differ");
    a.profiles
        .iter()
        .zip(&b.profiles)
        .flat_map(|(p, q)| {
            assert_eq!(field(p).len(), field(q).len(), "cell counts differ");
            field(p).iter().zip(field(q))
        })
        .map(|(x, y)| ((x - y) / y).abs())
        .fold(0.0, f64::max)
}

/// Runs the first run of scenario `text` with `method`, `norm` and `rtol` (atol = rtol/100)
/// set over the file's own, at most `max_steps` steps; the run must finish.
pub fn run_with(
    text: &str,
    method: &str,
    norm: &str,
    rtol: f64,
    max_steps: usize,
) -> celltissue::observe::RunRecord {
    let sets = [
        format!("solver.method=\"{method}\""),
        format!("solver.norm=\"{norm}\""),
        format!("solver.rtol={rtol}"),
        format!("solver.atol={}", rtol * 1e-2),
        format!("solver.max_steps={max_steps}"),
    ];
    let s = celltissue::scenario::load_str(text, std::path::Path::new("case.toml"), &sets)
        .expect("scenario loads");
    let rec = celltissue::scenario::execute::run_spec(&s.runs[0]);
    assert!(
        rec.error.is_none(),
        "{method} {norm} rtol {rtol}: {:?}",
        rec.error
    );
    rec
}

/// Largest stretch difference over cells and profiles (both directions on a sheet; tan θ on
/// a shear column), over the contract's weight `|λ| + atol/rtol` (atol = rtol/100 here);
/// `None` where a profile's cell counts differ (a division on either side of an output).
pub fn stretch_error(
    a: &celltissue::observe::RunRecord,
    b: &celltissue::observe::RunRecord,
) -> Option<f64> {
    let mut worst = 0.0f64;
    for (p, q) in a.profiles.iter().zip(&b.profiles) {
        if p.stretch.len() != q.stretch.len() {
            return None;
        }
        let pairs = [
            (Some(&p.stretch), Some(&q.stretch)),
            (p.extra.get("stretch_y"), q.extra.get("stretch_y")),
        ];
        for (a, b) in pairs.into_iter().filter_map(|(a, b)| a.zip(b)) {
            for (x, y) in a.iter().zip(b) {
                worst = worst.max((x - y).abs() / (y.abs() + 1e-2));
            }
        }
    }
    Some(worst)
}

/// Runs the bundled `models/<name>.toml` with the `--set`-style overrides, one record per run
/// (model × sweep value), each asserted to have finished.
pub fn bundled_runs(name: &str, sets: &[&str]) -> Vec<celltissue::observe::RunRecord> {
    let f = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("models/{name}.toml"));
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let s = celltissue::scenario::load(&f, &sets).expect("scenario loads");
    s.runs
        .iter()
        .map(|r| {
            let rec = celltissue::scenario::execute::run_spec(r);
            assert!(rec.error.is_none(), "{name} {}: {:?}", r.label, rec.error);
            rec
        })
        .collect()
}
