//! The accuracy contract (docs/model.md §8.1) beyond the bundled cases: random lines, sheets
//! and shear columns (seeded proptest strategies over the scenario keys: laws, fields, drag,
//! viscosity, Maxwell branches; on lines prescribed, free, growing, dividing and periodic ends,
//! rings of dividing cells, the continuum on the cell-number grid, active stress; on sheets a
//! free or periodic top, a prescribed or growing free side; external pressure; on columns the
//! force and both forms; the discrete array and the continuum, BDF, Radau IIA and ESDIRK, max
//! and rms norms; and Dormand–Prince on lines of few cells on strong drag, where it is not
//! stiff), each run at rtol 1e-6 and against Radau IIA and
//! BDF at rtol 1e-10. A stretch error is relative to the contract's weight, over every cell
//! (both directions on a sheet, tan θ on a column) and three profile times.
//!
//! * A tighter tolerance finishes wherever a looser one did: every case whose rtol 1e-6 run
//!   finishes also finishes at rtol 1e-10 with Radau IIA and with BDF (two kinds of tight run
//!   used to stop on rounding: `roundoff_floor.rs`).
//! * BDF, Radau IIA and Dormand–Prince with the max norm hold every stretch within
//!   [`CONTRACT`]·rtol of the
//!   reference wherever the reference is itself trustworthy, i.e. the two rtol 1e-10 runs
//!   agree within a tenth of the loose run's rtol (on a ring of Maxwell cells under periodic
//!   active stress on weak drag they part by 1.5e-7: the ring amplifies a one-ulp change of K
//!   to a few 1e-8, docs/model.md §8.1). The sweep prints the distribution of error / rtol per method and norm; ESDIRK's
//!   error grows like rtol^{2/3} (BENCHMARKS.md, "Methods on cell models") and the rms norm
//!   dilutes it by up to √N, so those are reported, not bounded.
//!
//! The default run (part of `cargo test`) draws [`DEFAULT_CASES`] cases of each; the long run
//! (about 50 s in all; `accuracy_contract_fuzz::random_sheets` or `random_shear` for
//! one kind alone):
//!
//! ```sh
//! CONTRACT_FUZZ_CASES=600 cargo test --release --test integration accuracy_contract_fuzz:: -- --nocapture
//! ```

use crate::common::stretch_error;
use celltissue::observe::RunRecord;
use celltissue::scenario::{execute::run_spec, load_str};
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use std::path::Path;

/// Cases of the default run.
const DEFAULT_CASES: u32 = 90;

/// Most steps a fuzz run may take (`solver.max_steps`).
const MAX_STEPS: u64 = 200_000;

/// The bound on the largest stretch error, in units of rtol, for BDF and Radau IIA with the
/// max norm. The contract is local (each step's error in stretch units within rtol); the
/// global error it buys is a small multiple of rtol where the array relaxes faster than it is
/// driven (within 10·rtol on the families of `accuracy_contract.rs`, asserted there), and
/// grows where a cell is crushed faster than it relaxes (50·rtol for a segment crushed to
/// λ = 0.11 under K = 1.1 in 0.06 time units, the worst of 600 lines). This bound separates
/// that accumulation from a broken error test: the position-based test it replaced erred by
/// 10³·rtol at the end cells, and the shear column's cell-centre form, while it still tested
/// its centres by position, by 86·rtol.
const CONTRACT: f64 = 100.0;

/// A cell law and its parameters (a `law` table).
fn law() -> impl Strategy<Value = String> {
    prop_oneof![
        (0.3f64..3.0).prop_map(|mu| format!("{{ law = \"neo_hookean\", mu = {mu} }}")),
        (0.1f64..1.0, 0.05f64..0.5)
            .prop_map(|(c1, c2)| format!("{{ law = \"mooney_rivlin\", c1 = {c1}, c2 = {c2} }}")),
        (0.5f64..3.0, -3.0f64..4.0).prop_filter_map("alpha", |(m, a): (f64, f64)| {
            // μ_p α_p > 0: the modulus takes the exponent's sign
            (a.abs() > 0.3).then(|| {
                let m = m.copysign(a);
                format!("{{ law = \"ogden\", terms = [[{m}, {a}]] }}")
            })
        }),
        (0.5f64..2.0, 3.0f64..50.0)
            .prop_map(|(mu, jm)| format!("{{ law = \"gent\", mu = {mu}, jm = {jm} }}")),
    ]
}

/// A field over the line: constant, a Gaussian bump or seeded random values, in `[lo, hi)`
/// (a bump adds up to three times its base).
fn field(lo: f64, hi: f64) -> impl Strategy<Value = String> {
    prop_oneof![
        (lo..hi).prop_map(|v| format!("{v}")),
        (lo..hi, 0.0f64..3.0, 0.0f64..1.0, 0.03f64..0.3).prop_map(|(b, a, c, w)| format!(
            "{{ type = \"gaussian\", base = {b}, amplitude = {a}, centre = {c}, width = {w} }}"
        )),
        (lo..hi, lo..hi, any::<u32>()).prop_map(|(a, b, s)| format!(
            "{{ type = \"random\", low = {}, high = {}, seed = {s} }}",
            a.min(b),
            a.max(b)
        )),
    ]
}

/// Uniform in the logarithm over `[lo, hi)`.
fn log_uniform(lo: f64, hi: f64) -> impl Strategy<Value = f64> {
    (lo.log10()..hi.log10()).prop_map(|e| 10f64.powf(e))
}

/// The cells' dissipation: Kelvin–Voigt `eta`, or a Maxwell branch.
fn dissipation(sheet: bool) -> impl Strategy<Value = String> {
    // a sheet takes Kelvin–Voigt viscosity as a `viscosity` table only
    let kelvin_voigt = move |e: f64| {
        if sheet {
            format!("viscosity = {{ model = \"kelvin_voigt\", eta = {e} }}\n")
        } else {
            format!("eta = {e}\n")
        }
    };
    prop_oneof![
        3 => Just(kelvin_voigt(0.0)),
        2 => log_uniform(1e-3, 10.0).prop_map(kelvin_voigt),
        1 => (log_uniform(0.1, 3.0), log_uniform(0.1, 10.0), prop_oneof![Just("maxwell"), Just("standard_linear_solid")])
            .prop_map(|(m, e, kind)| format!(
                "viscosity = {{ model = \"{kind}\", mu_m = {m}, eta_m = {e} }}\n"
            )),
    ]
}

/// How the line is driven, and its extras.
fn drive() -> impl Strategy<Value = String> {
    prop_oneof![
        3 => (-0.5f64..0.5, prop_oneof![Just("exponential"), Just("polynomial")], log_uniform(0.1, 10.0))
            .prop_map(|(k1, ramp, tr)| format!(
                "right_end = \"prescribed\"\nk1 = {k1}\nramp = \"{ramp}\"\nt_ramp = {tr}\n"
            )),
        1 => (-0.3f64..0.3).prop_map(|f| format!("right_end = \"free\"\nforce = {f}\n")),
        1 => (log_uniform(0.03, 1.0), prop_oneof![Just(""), Just("division = { rule = \"area\", max_cells = 150 }\n")])
            .prop_map(|(s0, div)| format!(
                "right_end = \"free\"\ngrowth = {{ sigma0 = {s0} }}\n{div}"
            )),
        1 => (0.2f64..1.5, 0.0f64..3.0).prop_map(|(b, w)| format!(
            "right_end = \"periodic\"\nactive = {{ beta = -{b}, omega = {w} }}\n"
        )),
    ]
}

/// How a dividing line is driven: a free end of growing cells dividing by the area rule (the
/// continuum on the cell-number grid for a third of them), or a ring of dividing cells inside
/// its fixed circumference.
fn division_drive() -> impl Strategy<Value = String> {
    prop_oneof![
        (
            log_uniform(0.03, 1.0),
            prop_oneof![
                Just("division = { rule = \"area\", max_cells = 150 }\n"),
                // the continuum on the cell-number grid (the discrete line ignores the key)
                Just("division = { rule = \"area\", max_cells = 150, cell_grid = { merge_below = 1e-3 } }\n"),
            ],
        )
            .prop_map(|(s0, div)| format!(
                "right_end = \"free\"\ngrowth = {{ sigma0 = {s0} }}\n{div}"
            )),
        log_uniform(0.03, 10.0).prop_map(|s0| format!(
            "right_end = \"periodic\"\ngrowth = {{ sigma0 = {s0} }}\n\
             division = {{ rule = \"area\", max_cells = 150 }}\n"
        )),
    ]
}

/// A random line scenario: 2–59 cells (or 2–39 continuum segments), its law, μ field, drag
/// (zero for half the prescribed ends), area exponent, dissipation, drive, external
/// pressure, end time, method (BDF, ESDIRK or Radau IIA) and norm.
fn case() -> impl Strategy<Value = String> {
    line_case(
        2..60,
        prop_oneof![Just(0.0), log_uniform(1e-6, 10.0)].boxed(),
        prop_oneof![Just("bdf"), Just("esdirk"), Just("radau")].boxed(),
        drive().boxed(),
    )
}

/// A random dividing line or ring of 2–59 cells (the continuum on the cell-number grid, or
/// on a plain grid), with the line's laws, fields, drag, dissipation and extras.
fn division_case() -> impl Strategy<Value = String> {
    line_case(
        2..60,
        log_uniform(1e-6, 10.0).boxed(),
        prop_oneof![Just("bdf"), Just("esdirk"), Just("radau")].boxed(),
        division_drive().boxed(),
    )
    .prop_map(|text| {
        // the proliferating continuum has no ring (the loader says so): rings run discrete
        match text.split_once("models = [\"continuum\"]\nnodes = ") {
            Some((head, tail)) if text.contains("\"periodic\"") => {
                let rest = tail.split_once('\n').map_or("", |(_, r)| r);
                format!("{head}models = [\"discrete\"]\n{rest}")
            }
            _ => text,
        }
    })
}

/// A random line Dormand–Prince can run: 2–11 cells (or segments) on strong drag,
/// K ∈ [1, 10), where the line is not stiff unless its cells are (a stiff case stops early
/// and says so, and is not counted).
fn dopri_case() -> impl Strategy<Value = String> {
    line_case(
        2..12,
        log_uniform(1.0, 10.0).boxed(),
        Just("dopri").boxed(),
        drive().boxed(),
    )
}

/// A random line with `cells` cells (or segments), drag `drag`, method `method` and drive
/// `drive`.
fn line_case(
    cells: std::ops::Range<usize>,
    drag: BoxedStrategy<f64>,
    method: BoxedStrategy<&'static str>,
    drive: BoxedStrategy<String>,
) -> impl Strategy<Value = String> {
    (
        (cells.clone(), law(), field(0.3, 3.0)),
        (drag, prop_oneof![Just(0.0), Just(1.0)]),
        dissipation(false),
        drive,
        prop_oneof![3 => Just(String::new()), 1 => (-0.5f64..0.5).prop_map(|p| format!("external_pressure = {p}\n"))],
        log_uniform(0.2, 20.0),
        method,
        prop_oneof![3 => Just("max"), 1 => Just("rms")],
        prop_oneof![
            2 => Just("models = [\"discrete\"]\n".to_string()),
            1 => (cells.start..cells.end.min(40)).prop_map(|n| format!("models = [\"continuum\"]\nnodes = {n}\n"))
        ],
    )
        .prop_map(|((cells, law, mu), (k, m), diss, drive, pe, t, method, norm, model)| {
            // a free or growing end needs drag to be determined; a ring at K = 0 a gauge
            let k = if k == 0.0 && !drive.contains("prescribed") { 1e-3 } else { k };
            // the cell-number grid needs a whole number of cells per segment
            let model = match model.split_once("nodes = ") {
                Some((head, n)) if drive.contains("cell_grid") => {
                    let n: usize = n.trim().parse().expect("nodes");
                    let d = (1..=n).rev().find(|d| cells % d == 0).unwrap_or(1);
                    format!("{head}nodes = {d}\n")
                }
                _ => model,
            };
            let text = format!(
                "name = \"fuzz\"\n[solver]\nmethod = \"{method}\"\nnorm = \"{norm}\"\n\
                 [output]\nseries = {{ start = 0, stop = {t}, count = 5 }}\n\
                 profiles = [{}, {}, {t}]\n[model]\nkind = \"line\"\n{model}\
                 cells = {cells}\nlaw = {law}\nmu = {mu}\nK = {k}\nm = {m}\n{diss}{drive}{pe}",
                t / 4.0,
                t / 2.0,
            );
            text
        })
}

/// A random sheet scenario: a few cells each way, either top, the side prescribed or (growing)
/// free, Kelvin–Voigt or Maxwell cells, the discrete sheet or its continuum.
fn sheet_case() -> impl Strategy<Value = String> {
    let side = prop_oneof![
        3 => (-0.3f64..0.3, log_uniform(0.1, 10.0)).prop_map(|(k1, tr)| format!(
            "k1 = {k1}\nramp = {{ kind = \"exponential\", t_ramp = {tr} }}\n"
        )),
        1 => (log_uniform(0.03, 1.0), prop_oneof![Just("both"), Just("x"), Just("y")]).prop_map(
            |(s0, dirs)| format!(
                "right = \"free\"\ngrowth = {{ sigma0 = {s0} }}\ngrowth_directions = \"{dirs}\"\n"
            )
        ),
    ];
    (
        (1usize..9, 1usize..7, law()),
        (log_uniform(1e-4, 10.0), prop_oneof![Just(0.0), Just(1.0)]),
        dissipation(true),
        side,
        prop_oneof![Just("free"), Just("periodic")],
        prop_oneof![3 => Just(String::new()), 1 => (-0.3f64..0.3).prop_map(|p| format!("external_pressure = {p}\n"))],
        log_uniform(0.2, 10.0),
        (prop_oneof![Just("bdf"), Just("esdirk"), Just("radau")], prop_oneof![3 => Just("max"), 1 => Just("rms")]),
        prop_oneof![2 => Just("discrete"), 1 => Just("continuum")],
    )
        .prop_map(|((nx, ny, law), (k, m), diss, side, top, pe, t, (method, norm), model)| {
            let text = format!(
                "name = \"fuzz\"\n[solver]\nmethod = \"{method}\"\nnorm = \"{norm}\"\n\
                 [output]\nseries = {{ start = 0, stop = {t}, count = 5 }}\n\
                 profiles = [{}, {}, {t}]\n[model]\nkind = \"sheet\"\nmodels = [\"{model}\"]\n\
                 cells_x = {nx}\ncells_y = {ny}\nlaw = {law}\nk_th = {k}\ndrag_exponent = {m}\n\
                 top = \"{top}\"\n{diss}{side}{pe}",
                t / 4.0,
                t / 2.0,
            );
            text
        })
}

/// A random shear column: its cells, law, drag, Kelvin–Voigt viscosity, the force at its
/// top, the edge form or the thesis's cell-centre form, discrete or continuum.
fn shear_case() -> impl Strategy<Value = String> {
    (
        (2usize..60, law(), log_uniform(1e-3, 10.0)),
        prop_oneof![2 => Just(0.0), 1 => log_uniform(1e-3, 10.0)],
        (0.2f64..2.0, log_uniform(0.2, 50.0)),
        (
            prop_oneof![Just("bdf"), Just("esdirk"), Just("radau")],
            prop_oneof![3 => Just("max"), 1 => Just("rms")],
        ),
        prop_oneof![
            2 => Just("models = [\"discrete\"]\nform = \"edge\"\n".to_string()),
            1 => Just("models = [\"discrete\"]\nform = \"cell_centre\"\n".to_string()),
            1 => (2usize..80).prop_map(|n| format!("models = [\"continuum\"]\nnodes = {n}\n")),
        ],
    )
        .prop_map(
            |((cells, law, k), eta, (force, t), (method, norm), model)| {
                let text = format!(
                    "name = \"fuzz\"\n[solver]\nmethod = \"{method}\"\nnorm = \"{norm}\"\n\
                 [output]\nseries = {{ start = 0, stop = {t}, count = 5 }}\n\
                 profiles = [{}, {}, {t}]\n[model]\nkind = \"shear\"\n{model}\
                 cells = {cells}\nlaw = {law}\nk_th = {k}\nforce = {force}\n\
                 viscosity = {{ model = \"kelvin_voigt\", eta = {eta} }}\n",
                    t / 4.0,
                    t / 2.0,
                );
                text
            },
        )
}

/// The scenario's (first) run at `rtol` (atol = rtol/100), with `method` instead of the
/// case's own when given; `Err` says whether the loader rejected it or the run failed.
fn run(text: &str, rtol: f64, method: Option<&str>) -> Result<RunRecord, String> {
    run_set(text, rtol, method, None)
}

/// [`run`] with one more `--set` (`extra`).
fn run_set(
    text: &str,
    rtol: f64,
    method: Option<&str>,
    extra: Option<&str>,
) -> Result<RunRecord, String> {
    let mut sets = vec![
        format!("solver.rtol={rtol}"),
        format!("solver.atol={}", rtol * 1e-2),
        // a case that crawls (a cell collapsing, a method whose Newton iteration stalls) stops
        // in seconds instead of minutes; no finishing case here takes 10⁵ steps
        format!("solver.max_steps={MAX_STEPS}"),
    ];
    if let Some(m) = method {
        sets.push(format!("solver.method=\"{m}\""));
    }
    sets.extend(extra.map(str::to_string));
    let sc = load_str(text, Path::new("fuzz.toml"), &sets).map_err(|e| format!("rejected: {e}"))?;
    let r = run_spec(&sc.runs[0]);
    match &r.error {
        Some(e) => Err(format!("failed: {e}")),
        None => Ok(r),
    }
}

/// A BDF case's largest stretch error / rtol at rtol 1e-6 with BDF held to order 2, against
/// Radau IIA at rtol 1e-10; `None` for another method or a run that fails.
fn low_order_error(text: &str, tags: &str) -> Option<f64> {
    if !tags.starts_with("bdf") {
        return None;
    }
    let low = run_set(text, 1e-6, None, Some("solver.max_order=2")).ok()?;
    let reference = run(text, 1e-10, Some("radau")).ok()?;
    stretch_error(&low, &reference).map(|e| e / 1e-6)
}

/// A one-line summary of a case: method, norm, model, end, and its extras.
fn tags(text: &str) -> String {
    let pick = |key: &str| {
        text.lines()
            .find_map(|l| l.strip_prefix(key))
            .map(|v| {
                v.trim()
                    .trim_matches(|c| c == '"' || c == '[' || c == ']')
                    .to_string()
            })
            .unwrap_or_default()
    };
    let mut t = vec![
        pick("method = "),
        pick("norm = "),
        pick("models = ").trim_matches('"').to_string(),
        pick("right_end = "),
    ];
    for (key, tag) in [
        ("maxwell", "maxwell"),
        ("standard_linear_solid", "maxwell"),
        ("growth", "growth"),
        ("division", "division"),
        ("external_pressure", "pressure"),
        ("active", "active"),
    ] {
        if text.contains(key) {
            t.push(tag.to_string());
        }
    }
    if text.contains("\nK = 0\n") {
        t.push("K=0".into());
    }
    // a line's own `eta = …`, or the Kelvin–Voigt viscosity table's (not the active stress's
    // `beta = …` nor a Maxwell branch's `eta_m = …`)
    let viscous = text
        .lines()
        .any(|l| l.starts_with("eta = ") && l != "eta = 0")
        || (text.contains("\"kelvin_voigt\"") && !text.contains("eta = 0 }"));
    if viscous {
        t.push("kelvin-voigt".into());
    }
    t.join(",")
}

/// What one case gave.
enum Outcome {
    /// Rejected by the loader (a combination the scenario does not take), and why.
    Rejected(String),
    /// The rtol 1e-6 run failed (its message), and whether Radau IIA at rtol 1e-10 finished.
    LooseFailed(String, bool),
    /// The rtol 1e-6 run finished and a tight one did not (its message).
    TightFailed(String),
    /// A division fell between an output and the neighbouring step on one side only.
    CellsDiffer,
    /// Largest stretch error of the loose run against Radau IIA at rtol 1e-10, and the gap
    /// between that reference and BDF at rtol 1e-10 (the reference's trust: two methods
    /// whose errors differ in kind agree), both over the contract's weight.
    Measured { error: f64, reference_gap: f64 },
}

/// Runs one case: at rtol 1e-6 with its own method, then (if that finished, or to tell the
/// kind of its failure) Radau IIA and BDF at rtol 1e-10.
fn outcome(text: &str) -> Outcome {
    let loose = match run(text, 1e-6, None) {
        Err(e) if e.starts_with("rejected") => return Outcome::Rejected(e),
        Err(e) => {
            let tight_finishes = run(text, 1e-10, Some("radau")).is_ok();
            return Outcome::LooseFailed(e, tight_finishes);
        }
        Ok(r) => r,
    };
    let tight =
        run(text, 1e-10, Some("radau")).and_then(|r| run(text, 1e-10, Some("bdf")).map(|s| (r, s)));
    match tight {
        Err(e) => Outcome::TightFailed(e),
        Ok((radau, bdf)) => match (stretch_error(&loose, &radau), stretch_error(&bdf, &radau)) {
            (Some(error), Some(reference_gap)) => Outcome::Measured {
                error,
                reference_gap,
            },
            _ => Outcome::CellsDiffer,
        },
    }
}

/// The sweep's findings over `strategy`: each case's index, tags, text and outcome.
fn sweep(strategy: impl Strategy<Value = String>) -> Vec<(u32, String, String, Outcome)> {
    let n: u32 = std::env::var("CONTRACT_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(DEFAULT_CASES);
    let mut runner = TestRunner::new_with_rng(
        Config {
            cases: n,
            failure_persistence: None,
            ..Config::default()
        },
        TestRng::deterministic_rng(RngAlgorithm::ChaCha),
    );
    // `CONTRACT_FUZZ_FROM=k` runs only the cases from the k-th on (the earlier ones are drawn
    // and dropped, so case numbers stay those of the full sweep), and names each as it starts
    let from: u32 = std::env::var("CONTRACT_FUZZ_FROM")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0);
    (0..n)
        .filter_map(|k| {
            let text = strategy.new_tree(&mut runner).expect("a case").current();
            if k < from {
                return None;
            }
            if from > 0 {
                println!("case {k} [{}] starts\n{}", tags(&text), text);
            }
            let started = std::time::Instant::now();
            let o = outcome(&text);
            if started.elapsed().as_secs_f64() > 10.0 {
                println!("case {k} [{}] took {:.0?}", tags(&text), started.elapsed());
            }
            Some((k, tags(&text), text, o))
        })
        .collect()
}

/// Prints the sweep's distribution of error / rtol per method and norm, and fails on a case
/// that finishes at rtol 1e-6 but not at 1e-10, or on BDF or Radau IIA with the max norm
/// erring by more than [`CONTRACT`]·rtol where the references agree.
fn check(cases: Vec<(u32, String, String, Outcome)>) {
    let mut broken = vec![];
    let mut by_kind: std::collections::BTreeMap<String, Vec<f64>> = Default::default();
    let (mut rejected, mut loose_failed, mut untrusted, mut differ) = (0, 0, 0, 0);
    let (mut only_tight, mut too_long, mut stiff, mut high_order) = (0, 0, 0, 0);
    for (k, tags, text, o) in &cases {
        match o {
            Outcome::Rejected(e) => {
                rejected += 1;
                println!("case {k} [{tags}]: {e}");
            }
            // Dormand–Prince stopping early on a stiff case, as it should (not a case for it)
            Outcome::LooseFailed(e, _) if e.contains("the problem is stiff here") => stiff += 1,
            Outcome::LooseFailed(e, false) => {
                loose_failed += 1;
                println!("case {k} [{tags}]: fails at rtol 1e-6 and 1e-10: {e}");
            }
            Outcome::LooseFailed(e, true) => {
                only_tight += 1;
                println!(
                    "case {k} [{tags}]: fails at rtol 1e-6 but finishes at 1e-10 (Radau IIA): {e}\n{text}"
                );
            }
            Outcome::TightFailed(e) if e.contains("maximum number of steps") => {
                // a tolerance near what the state resolves costs far more steps (docs/model.md
                // §8.1): reported, as the cap on the fuzz's runs is not the scenario's
                too_long += 1;
                println!(
                    "case {k} [{tags}]: a rtol 1e-10 run needs more than {MAX_STEPS} steps: {e}"
                );
            }
            Outcome::TightFailed(e) => broken.push(format!(
                "case {k} [{tags}]: finishes at rtol 1e-6, not tighter: {e}\n{text}"
            )),
            Outcome::CellsDiffer => differ += 1,
            Outcome::Measured {
                error,
                reference_gap,
            } => {
                let ratio = error / 1e-6;
                if *reference_gap > 1e-7 {
                    untrusted += 1;
                    println!(
                        "case {k} [{tags}]: references part by {reference_gap:.1e} (error {ratio:.1}·rtol, not held)"
                    );
                    continue;
                }
                let kind: String = tags.split(',').take(2).collect::<Vec<_>>().join(",");
                by_kind.entry(kind.clone()).or_default().push(ratio);
                let bounded = matches!(kind.as_str(), "bdf,max" | "radau,max" | "dopri,max");
                if bounded && ratio > CONTRACT {
                    // Where the model itself grows a cell-to-cell zigzag (rings of Maxwell
                    // cells whose periodic active stress softens them), BDF's orders 3–5,
                    // which damp it least, put the most of their error into it. Reported
                    // where BDF held to order 2 meets the bound (docs/model.md §8.1); anything
                    // else fails.
                    match low_order_error(text, tags) {
                        Some(e) if e <= CONTRACT => {
                            high_order += 1;
                            println!(
                                "case {k} [{tags}]: stretch error {ratio:.1}·rtol, {e:.1}·rtol \
                                 with BDF up to order 2"
                            );
                        }
                        _ => broken.push(format!(
                            "case {k} [{tags}]: stretch error {ratio:.1}·rtol\n{text}"
                        )),
                    }
                }
                if ratio > 10.0 {
                    println!("case {k} [{tags}]: stretch error {ratio:.1}·rtol");
                }
            }
        }
    }
    println!(
        "{} cases: {rejected} rejected by the loader, {loose_failed} failing at rtol 1e-6 and \
         1e-10 (a cell collapsing, chains locking), {only_tight} failing at rtol 1e-6 only, \
         {too_long} whose rtol 1e-10 run passes {MAX_STEPS} steps, {differ} with a division at \
         an output, {untrusted} whose references part, {stiff} too stiff for an explicit method, \
         {high_order} where BDF's orders 3–5 amplify an oscillation",
        cases.len()
    );
    let measured: usize = by_kind.values().map(Vec::len).sum();
    for (kind, mut r) in by_kind {
        r.sort_by(f64::total_cmp);
        let q = |f: f64| r[((r.len() - 1) as f64 * f).round() as usize];
        println!(
            "{kind}: {} cases, error / rtol median {:.2}, 90 % {:.2}, largest {:.1}, above 10: {}",
            r.len(),
            q(0.5),
            q(0.9),
            q(1.0),
            r.iter().filter(|&&x| x > 10.0).count()
        );
    }
    // the sweep measures most of what it draws, or it checks nothing
    assert!(
        measured * 10 >= (cases.len() - stiff) * 8,
        "only {measured} of {} cases measured ({stiff} too stiff)",
        cases.len()
    );
    assert!(broken.is_empty(), "{}", broken.join("\n\n"));
}

#[test]
fn random_lines_hold_the_contract_and_a_tighter_tolerance_always_finishes() {
    check(sweep(case()));
}

#[test]
fn random_dividing_lines_and_rings_hold_the_contract() {
    check(sweep(division_case()));
}

#[test]
fn random_non_stiff_lines_hold_the_contract_with_dormand_prince() {
    check(sweep(dopri_case()));
}

#[test]
fn random_sheets_hold_the_contract_and_a_tighter_tolerance_always_finishes() {
    check(sweep(sheet_case()));
}

#[test]
fn random_shear_columns_hold_the_contract_and_a_tighter_tolerance_always_finishes() {
    check(sweep(shear_case()));
}
