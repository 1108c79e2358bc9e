//! Fuzz of the scenario loader and validator (proptest): mutated bundled scenarios, `--set`
//! overrides with extreme values and random keys, and raw byte garbage must each give `Ok` or a
//! [`ScenarioError`] — never a panic, an abort or a hang (every case is bounded in time), and
//! never a message of unbounded size.
//!
//! The default run (part of `cargo test`) is 3000 cases over three strategies. The long run:
//!
//! ```sh
//! SCENARIO_FUZZ_CASES=40000 cargo test --release --test integration scenario_fuzz:: -- --nocapture
//! ```
//!
//! (`SCENARIO_FUZZ_CASES` cases per strategy; three strategies.)

use celltissue::scenario::{load_str, ScenarioError};
use proptest::prelude::*;
use std::path::Path;
use std::sync::mpsc;
use std::time::Duration;

/// Longest a single load may take before the case counts as a hang.
const CASE_LIMIT: Duration = Duration::from_secs(10);

fn cases(default: u32) -> u32 {
    std::env::var("SCENARIO_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// The bundled scenarios (the mutation seeds).
fn seeds() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("models");
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    files
        .iter()
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect()
}

/// Loads on a worker thread with a time bound; panics (fails the case) on a hang, on a panic
/// inside the loader, or on an oversized message.
fn check(text: String, sets: Vec<String>) -> Result<(), TestCaseError> {
    let (tx, rx) = mpsc::channel();
    let worker = std::thread::Builder::new()
        // the main thread's stack size: a recursion that needs more is a finding
        .stack_size(8 << 20)
        .spawn(move || {
            let r = std::panic::catch_unwind(|| load_str(&text, Path::new("fuzz.toml"), &sets));
            let _ = tx.send(r.map(|r| r.err().map(|e: ScenarioError| e.to_string())));
        })
        .expect("spawn");
    match rx.recv_timeout(CASE_LIMIT) {
        Ok(Ok(Some(message))) => {
            prop_assert!(
                message.len() < 20_000,
                "message of {} bytes: {}…",
                message.len(),
                &message[..200]
            );
            let _ = worker.join();
            Ok(())
        }
        Ok(Ok(None)) => {
            let _ = worker.join();
            Ok(())
        }
        Ok(Err(_)) => Err(TestCaseError::fail("the loader panicked")),
        Err(_) => Err(TestCaseError::fail(format!(
            "the loader took more than {CASE_LIMIT:?} (a hang)"
        ))),
    }
}

/// Values that have broken parsers and validators before: extremes, non-finite, huge integers,
/// wrong types, deep nesting, long strings.
fn nasty_value() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("nan".to_string()),
        Just("-inf".to_string()),
        Just("inf".to_string()),
        Just("0".to_string()),
        Just("-1".to_string()),
        Just("1e-300".to_string()),
        Just("5e-324".to_string()),
        Just("1e300".to_string()),
        Just("1.0001".to_string()),
        Just("9223372036854775807".to_string()),
        Just("-9223372036854775808".to_string()),
        Just("4294967296".to_string()),
        Just("1000000000000000000".to_string()),
        Just("true".to_string()),
        Just("\"\"".to_string()),
        Just("\"x\"".to_string()),
        Just("[]".to_string()),
        Just("{}".to_string()),
        Just("[[[[[[[[[[[[[[[[1]]]]]]]]]]]]]]]]".to_string()),
        Just(
            "{ type = \"gaussian\", base = 1, amplitude = 1, centre = nan, width = 1e-200 }"
                .to_string()
        ),
        Just("{ type = \"random\", low = 0, high = 0, seed = 1 }".to_string()),
        Just("{ type = \"piecewise\", breaks = [0.5, 0.5], values = [1, 2, 3] }".to_string()),
        Just("{ type = \"per_cell\", values = [] }".to_string()),
        Just("{ rule = \"age\", period = 1e-300 }".to_string()),
        Just("{ law = \"neo_hookean\", mu = -1 }".to_string()),
        Just("{ start = 0, stop = 1e300, count = 1000000 }".to_string()),
        Just("{ start = 5e-324, stop = 1, count = 3, spacing = \"log\" }".to_string()),
        (-1e6f64..1e6).prop_map(|v| format!("{v:e}")),
        any::<i64>().prop_map(|v| v.to_string()),
        any::<f64>().prop_map(|v| if v.is_finite() {
            format!("{v:e}")
        } else {
            "nan".into()
        }),
        "[a-z_]{0,12}".prop_map(|s| format!("\"{s}\"")),
        (1usize..100_000).prop_map(|n| format!("\"{}\"", "x".repeat(n))),
    ]
}

/// Keys a scenario can hold (and some it cannot).
fn key() -> impl Strategy<Value = String> {
    prop_oneof![
        prop::sample::select(vec![
            "model.cells",
            "model.nodes",
            "model.K",
            "model.eta",
            "model.mu",
            "model.mu.width",
            "model.mu.centre",
            "model.k1",
            "model.t_ramp",
            "model.cell_length",
            "model.ref_lengths",
            "model.right_end",
            "model.gauge",
            "model.growth",
            "model.growth.sigma0",
            "model.division",
            "model.division.ratio",
            "model.division.period",
            "model.division.max_cells",
            "model.division.rule",
            "model.division.mean",
            "model.division.spread",
            "model.division.seed",
            "model.division.batch_within",
            "model.division.cell_grid",
            "model.division.cell_grid.merge_below",
            "model.division.cell_grid.merge_stress_within",
            "model.division.cell_grid.merge_max",
            "model.division.cell_grid.merge_batch",
            "model.viscosity",
            "model.viscosity.mu_m",
            "model.viscosity.eta_m",
            "model.continuum_scheme",
            "model.law",
            "model.energy",
            "model.kind",
            "model.models",
            "model.cells_x",
            "model.cells_y",
            "model.form",
            "model.force",
            "model.active",
            "model.sampling",
            "model.m",
            "model.drag_exponent",
            "solver.rtol",
            "solver.atol",
            "solver.method",
            "solver.threads",
            "solver.linear_solver",
            "solver.jacobian_age",
            "solver.newton_alpha_bound",
            "solver.max_steps",
            "solver.newton_factor",
            "solver.krylov_max_iters",
            "solver.land_on_outputs",
            "solver.interpolate_rates",
            "solver.norm",
            "output.series",
            "output.profiles",
            "output.series.count",
            "sweep.values",
            "sweep.parameter",
            "sweep.labels",
            "sweep.grid",
            "sweep.zip",
            "sweep.ensemble",
            "sweep.ensemble.realisations",
            "sweep.ensemble.first_seed",
            "sweep.ensemble.parameter",
            "plots.time_axis",
            "name",
            "figure",
        ])
        .prop_map(str::to_string),
        "[a-z]{1,6}(\\.[a-z0-9]{1,6}){0,20}",
    ]
}

/// A line-level mutation of a seed scenario.
fn mutate(seed: &str, line: usize, how: u8, value: &str, key: &str) -> String {
    let mut lines: Vec<String> = seed.lines().map(str::to_string).collect();
    if lines.is_empty() {
        return value.to_string();
    }
    let i = line % lines.len();
    match how % 6 {
        // replace the value of a `key = value` line
        0 => {
            if let Some((k, _)) = lines[i].split_once('=') {
                lines[i] = format!("{k}= {value}");
            }
        }
        1 => lines.insert(
            i,
            format!("{} = {value}", key.rsplit('.').next().unwrap_or(key)),
        ),
        2 => {
            lines.remove(i);
        }
        3 => lines[i] = lines[i].chars().rev().collect(),
        4 => lines.insert(i, format!("[{key}]")),
        _ => {
            let dup = lines[i].clone();
            lines.insert(i, dup);
        }
    }
    lines.join("\n")
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(1000), failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn mutated_bundled_scenarios_never_panic_or_hang(
        which in any::<prop::sample::Index>(),
        line in 0usize..200,
        how in any::<u8>(),
        value in nasty_value(),
        key in key(),
        again in proptest::option::of((0usize..200, any::<u8>(), nasty_value())),
    ) {
        let seeds = seeds();
        let seed = &seeds[which.index(seeds.len())];
        let mut text = mutate(seed, line, how, &value, &key);
        if let Some((l, h, v)) = again {
            text = mutate(&text, l, h, &v, &key);
        }
        check(text, Vec::new())?;
    }

    #[test]
    fn set_overrides_never_panic_or_hang(
        which in any::<prop::sample::Index>(),
        sets in prop::collection::vec((key(), nasty_value()), 1..4),
    ) {
        let seeds = seeds();
        let seed = seeds[which.index(seeds.len())].clone();
        let sets = sets.into_iter().map(|(k, v)| format!("{k}={v}")).collect();
        check(seed, sets)?;
    }

    #[test]
    fn arbitrary_text_never_panics_or_hangs(
        text in prop_oneof![
            ".{0,400}",
            prop::collection::vec(any::<u8>(), 0..400)
                .prop_map(|b| String::from_utf8_lossy(&b).into_owned()),
            ("[a-z_.]{1,30}", nasty_value()).prop_map(|(k, v)| format!("{k} = {v}")),
        ],
        set in proptest::option::of(".{0,60}"),
    ) {
        check(text, set.into_iter().collect())?;
    }
}

#[test]
fn deep_nesting_and_long_keys_are_errors() {
    // a 10 000-deep array in the file itself
    let deep = format!("name = {}1{}", "[".repeat(10_000), "]".repeat(10_000));
    check(deep, Vec::new()).unwrap();
    let deep_table = format!("name = \"x\"\n{} = 1", vec!["a"; 10_000].join("."));
    check(deep_table, Vec::new()).unwrap();
    let inline = format!("x = {}1{}", "{ a = ".repeat(5_000), " }".repeat(5_000));
    check(inline, Vec::new()).unwrap();
}
