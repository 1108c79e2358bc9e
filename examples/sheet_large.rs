//! Large-sheet run for the performance report: `cargo run --release --example sheet_large --
//! <n> [t_end]` integrates an n × n discrete free-top sheet (K = ½, m = 0, neo-Hookean, BDF
//! rtol 1e-6, atol 1e-8 in cell units, max error norm as the cell arrays' default) to `t_end`
//! (default 10) and prints wall time, work counters and cost per step and per cell-step.
//!
//! The linear solver is the sparse direct LU unless `LINSOLVE=iterative` (ILU(0) +
//! BiCGStab stopped by the Newton-aware rule with `newton_factor = KRYLOV_FACTOR`, default
//! 0.01, or at relative preconditioned residual `KRYLOV_RTOL`, default 1e-8; `KRYLOV_FACTOR=0`
//! leaves only the latter); `NORM=rms` selects the RMS norm; `NEWTON_ALPHA_BOUND=1` sets
//! `BdfOptions::newton_alpha_bound`. `FINAL_STATE=path` writes the
//! state at `t_end` as raw little-endian `f64`s (to compare runs).
//! `FAMILY=macro` runs the macroscale-fixed family instead of the thesis's raw parameters
//! (`K = 1/(2n)`, ramp time `n`, default `t_end = n`): `n × n` cells then resolve the same tissue
//! problem and the step count does not grow with `n`.

use celltissue::array::ArrayProblem;
use celltissue::sheet::ramp::Ramp;
use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
use celltissue::NeoHookean;
use integrators::{ErrorNorm, IterativeSettings, LinearSolverChoice, MethodKind, Options, Solver};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n: usize = args.first().and_then(|a| a.parse().ok()).unwrap_or(100);
    // FAMILY=macro: the macroscale-fixed family of the line benchmark carried to the sheet
    // (K_th = 1/N, i.e. K = 1/(2N); ramp time N; default t_end = N), where N × N cells resolve
    // the same tissue problem; default: the thesis's raw parameters (K = ½, unit ramp time)
    let macro_family = std::env::var("FAMILY").is_ok_and(|v| v == "macro");
    let nf = n as f64;
    let t_end: f64 = args
        .get(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(if macro_family { nf } else { 10.0 });
    let law = NeoHookean::new(1.0).expect("valid law");
    let mut p = SheetParams {
        cells_x: n,
        cells_y: n,
        ..Default::default()
    };
    if macro_family {
        p.drag = 0.5 / nf;
        p.ramp = Ramp::Exponential { t_ramp: nf };
    }
    let start = std::time::Instant::now();
    let sheet = UniaxialSheet::discrete(law, &p)
        .expect("valid sheet")
        .with_cell_atol(1e-8);
    let y0 = sheet.initial_state();
    let mut prob = ArrayProblem::new(sheet);
    let build = start.elapsed().as_secs_f64();
    let env = |k: &str| std::env::var(k).ok();
    let linear_solver = match env("LINSOLVE").as_deref() {
        None | Some("direct") => LinearSolverChoice::Direct,
        Some("iterative") => LinearSolverChoice::Iterative(IterativeSettings {
            rtol: env("KRYLOV_RTOL")
                .and_then(|v| v.parse().ok())
                .unwrap_or(IterativeSettings::default().rtol),
            newton_factor: env("KRYLOV_FACTOR")
                .and_then(|v| v.parse().ok())
                .unwrap_or(IterativeSettings::default().newton_factor),
            ..IterativeSettings::default()
        }),
        Some(other) => {
            eprintln!("LINSOLVE = {other:?} must be \"direct\" or \"iterative\"");
            std::process::exit(2);
        }
    };
    let norm = match env("NORM").as_deref() {
        None => ErrorNorm::Max,
        Some(v) => ErrorNorm::parse(v).unwrap_or_else(|e| {
            eprintln!("NORM: {e}");
            std::process::exit(2);
        }),
    };
    let opts = Options {
        rtol: 1e-6,
        atol: 1e-8,
        norm,
        linear_solver,
        bdf: integrators::BdfOptions {
            newton_alpha_bound: env("NEWTON_ALPHA_BOUND").is_some_and(|v| v == "1"),
            ..Default::default()
        },
        ..Options::default()
    };
    let label = format!("{linear_solver:?}, {norm:?} norm");
    match Solver::new(MethodKind::Bdf, opts).solve(&mut prob, 0.0, &y0, &[t_end]) {
        Ok(sol) => {
            let wall = start.elapsed().as_secs_f64();
            if let Some(path) = env("FINAL_STATE") {
                // raw little-endian f64 of the state at t_end, for comparing runs
                let bytes: Vec<u8> = sol.y[0].iter().flat_map(|v| v.to_le_bytes()).collect();
                if let Err(e) = std::fs::write(&path, bytes) {
                    eprintln!("FINAL_STATE = {path:?}: {e}");
                    std::process::exit(2);
                }
            }
            let s = sol.stats;
            let per_step = wall / s.steps.max(1) as f64;
            println!(
                "{n}x{n} cells, {} unknowns, t_end {t_end} [{label}]: wall {wall:.3} s (build \
                 {build:.3} s), steps {}, rejected {}, jacobians {}, factorizations {}, symbolic \
                 {}, newton {}, linear solves {}, krylov iterations {} (failures {}); \
                 {per_step:.3e} s/step, {:.3e} s/(step·cell)",
                y0.len(),
                s.steps,
                s.rejected_steps,
                s.jacobian_evals,
                s.factorizations,
                s.symbolic_factorizations,
                s.newton_iterations,
                s.linear_solves,
                s.krylov_iterations,
                s.krylov_failures,
                per_step / (n * n) as f64
            );
        }
        Err(e) => {
            eprintln!("{n}x{n}: solve failed: {e}");
            std::process::exit(1);
        }
    }
}
