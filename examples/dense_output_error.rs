//! The one-step methods' output error on a stiff cell cluster, interpolated against landed
//! (docs/model.md §8.1): the Fig 2.8 line (`models/fig2_8.toml`, discrete, N = 100, Gaussian
//! stiff cluster, exponential ramp), outputs every 0.05 on [0, 10], for one method, drag K and
//! rtol (atol = rtol/100). Prints, with dense output between step ends
//! (`land_on_outputs = Some(false)`) and with the default (steps end at each output for every
//! method but BDF), the steps, the largest relative stretch error at t = 0.5 and over every
//! output, in units of rtol, against a BDF run at rtol 1e-11.
//!
//! Run: `cargo run --release --example dense_output_error -- radau 1e-5 1e-6`.

use celltissue::drive::{drive_observed, DriveObserver};
use celltissue::line::build::discrete;
use celltissue::line::run::{LineModel, SolveSettings};
use celltissue::scenario::ModelConfig;
use celltissue::{ArrayProblem, NeoHookean};
use std::path::Path;

/// The stretches at every output.
struct Stretches(Vec<Vec<f64>>);

impl<A: LineModel> integrators::Observer<ArrayProblem<A>> for Stretches {
    fn output(&mut self, p: &ArrayProblem<A>, t: f64, y: &[f64], yp: &[f64]) {
        let s = p.array.observe(t, y, yp).expect("observable state");
        self.0.push(s.lambda);
    }
}

impl<A: LineModel> DriveObserver<ArrayProblem<A>> for Stretches {}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(method), Some(k), Some(rtol)) = (
        args.first(),
        args.get(1).and_then(|v| v.parse::<f64>().ok()),
        args.get(2).and_then(|v| v.parse::<f64>().ok()),
    ) else {
        eprintln!("usage: dense_output_error METHOD K RTOL, e.g. radau 1e-5 1e-6");
        std::process::exit(2);
    };
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/fig2_8.toml");
    let sets = [
        format!("sweep.values=[{k}]"),
        "model.models=[\"discrete\"]".to_string(),
    ];
    let scenario = celltissue::scenario::load(&file, &sets).expect("fig2_8 loads");
    let ModelConfig::Line(cfg) = &scenario.runs[0].config else {
        unreachable!("fig2_8 is a line")
    };
    let outputs: Vec<f64> = (0..=200).map(|i| i as f64 * 0.05).collect();
    let run = |method: &str, rtol: f64, land: Option<bool>| {
        let line = discrete(
            NeoHookean::new(1.0).expect("μ > 0"),
            &cfg.params(rtol / 100.0),
        );
        let mut prob = ArrayProblem::new(line.expect("valid line"));
        let settings = SolveSettings {
            method: method.parse().unwrap_or_else(|e| {
                eprintln!("{e}");
                std::process::exit(2)
            }),
            rtol,
            atol: rtol / 100.0,
            land_on_outputs: land,
            ..Default::default()
        };
        let y0 = prob.array.initial_state();
        let breakpoints = prob.array.breakpoints();
        let mut seen = Stretches(Vec::new());
        let driven = drive_observed(&mut prob, &settings, &y0, &outputs, &breakpoints, &mut seen);
        if let Some(e) = driven.error {
            eprintln!("{method} at rtol {rtol:e}: {e}");
            std::process::exit(1);
        }
        (seen.0, driven.stats.steps)
    };
    let (reference, _) = run("bdf", 1e-11, None);
    let errors = |x: &[Vec<f64>]| -> Vec<f64> {
        x.iter()
            .zip(&reference)
            .map(|(u, v)| {
                let e = u.iter().zip(v).map(|(a, b)| ((a - b) / b).abs());
                e.fold(0.0f64, f64::max) / rtol
            })
            .collect()
    };
    let most = |e: &[f64]| e.iter().copied().fold(0.0f64, f64::max);
    for (what, land) in [("interpolated", Some(false)), ("default", None)] {
        let (s, steps) = run(method, rtol, land);
        let e = errors(&s);
        println!(
            "{method} K = {k:e} rtol = {rtol:e} {what}: {steps} steps, stretch error at t = 0.5 \
             {:.2}·rtol, over all outputs {:.2}·rtol",
            e[10],
            most(&e)
        );
    }
}
