//! The command-line interface as a library function (feature `cli`, on by default): argument
//! parsing (clap) and the commands `run`, `merge`, `validate` and `list`.
//!
//! A binary of one's own gets the whole interface with its own laws and methods: register them
//! (strain energies with [`crate::energy::registry::register`], time-stepping methods with
//! [`crate::method::register`]), then call [`main`]. Scenarios then name them like the
//! built-in ones (`law = { law = "my_law", … }`, `solver.method = "my_method"`).
//!
//! ```no_run
//! // the `main` of a binary of one's own
//! celltissue::energy::registry::register::<celltissue::NeoHookean>("my_neo_hookean")
//!     .expect("a new name");
//! std::process::exit(celltissue::cli::main());
//! ```

mod catalogue;
mod commands;
mod merge;

use clap::{Parser, Subcommand};
use std::path::PathBuf;

/// Exit code: success.
pub const OK: i32 = 0;
/// Exit code: a run failed or outputs could not be written (computed results are kept).
pub const RUN_FAILED: i32 = 1;
/// Exit code: the scenario or the command line is invalid (nothing was written).
pub const BAD_INPUT: i32 = 2;

/// Discrete and continuum mechanics of cells in tissues: run the thesis scenarios.
#[derive(Debug, Parser)]
#[command(name = "celltissue", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run a scenario: writes DIR/summary.json, CSV series and profiles, and PNG plots.
    Run {
        /// Scenario file (or the name of a bundled scenario, e.g. fig2_5).
        scenario: PathBuf,
        /// Output directory (created if missing).
        #[arg(long, short)]
        out: PathBuf,
        /// Override a key before validation, e.g. --set model.cells=50 --set solver.method=radau.
        /// A swept key cannot be set (an error): change the swept values instead, e.g.
        /// --set sweep.values=[0.1].
        #[arg(long = "set", value_name = "KEY=VALUE")]
        sets: Vec<String>,
        /// Remove a key of the scenario before validation, so that it takes its default, e.g.
        /// --unset solver.jacobian_age --set solver.method=radau (a BDF-only key).
        #[arg(long = "unset", value_name = "KEY")]
        unsets: Vec<String>,
        /// No progress lines on stderr.
        #[arg(long, short)]
        quiet: bool,
        /// Replace the outputs in a directory used by another scenario (only files celltissue
        /// wrote there, listed in its manifest, are removed).
        #[arg(long)]
        replace: bool,
        /// Write data files only, no PNG plots.
        #[arg(long)]
        no_plots: bool,
        /// Runs of the sweep to run at once (threads); outputs are the same as with 1.
        #[arg(long, short, default_value_t = 1, value_name = "N")]
        jobs: u64,
        /// Run only shard I of N of the sweep (0-based; run k goes to shard k mod N), or
        /// `auto` for a SLURM job array (SLURM_ARRAY_TASK_ID / SLURM_ARRAY_TASK_COUNT).
        /// Writes OUT/shard.json; combine the shards with `celltissue merge`.
        #[arg(long, value_name = "I/N|auto")]
        shard: Option<String>,
    },
    /// Combine the output directories of `run --shard` into what one `run` writes.
    Merge {
        /// The shards' output directories (any order).
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Output directory (created if missing).
        #[arg(long, short)]
        out: PathBuf,
        /// No summary line on stderr.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Parse and validate a scenario (and overrides) without running it.
    Validate {
        /// Scenario file (or bundled scenario name).
        scenario: PathBuf,
        /// Override a key before validation.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        sets: Vec<String>,
        /// Remove a key before validation (it takes its default).
        #[arg(long = "unset", value_name = "KEY")]
        unsets: Vec<String>,
    },
    /// List the bundled scenarios (models/*.toml beside the crate and in the current directory).
    List,
}

/// Parses the process's command line and runs the command; returns the exit code
/// ([`OK`], [`RUN_FAILED`] or [`BAD_INPUT`]). A binary of one's own registers its laws, then
/// hands over:
///
/// ```no_run
/// // the body of the binary's `main`
/// celltissue::energy::registry::register::<celltissue::NeoHookean>("my_law").unwrap();
/// std::process::exit(celltissue::cli::main());
/// ```
pub fn main() -> i32 {
    main_from(std::env::args_os())
}

/// As [`main`], with the arguments given (the first is the program name).
///
/// ```
/// // `--help` prints the usage and succeeds
/// assert_eq!(celltissue::cli::main_from(["celltissue", "list"]), celltissue::cli::OK);
/// assert_eq!(celltissue::cli::main_from(["celltissue", "frobnicate"]), celltissue::cli::BAD_INPUT);
/// ```
pub fn main_from<I, T>(args: I) -> i32
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    // RUST_LOG=info (or debug) for run and write diagnostics; warnings by default
    // (microsecond timestamps: the stages of a run's write phase take milliseconds)
    let _ = env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn"))
        .format_timestamp_micros()
        .try_init();
    let cli = match Cli::try_parse_from(args) {
        Ok(c) => c,
        Err(e) => {
            let code = if e.use_stderr() { BAD_INPUT } else { OK };
            let _ = e.print();
            return code;
        }
    };
    match cli.command {
        Command::Run {
            scenario,
            out,
            sets,
            unsets,
            quiet,
            replace,
            no_plots,
            jobs,
            shard,
        } => commands::run(
            &catalogue::resolve(&scenario),
            &out,
            &sets,
            &unsets,
            commands::RunOptions {
                quiet,
                replace,
                no_plots,
                jobs: usize::try_from(jobs).unwrap_or(usize::MAX),
                shard,
            },
        ),
        Command::Merge { dirs, out, quiet } => merge::merge(&dirs, &out, quiet),
        Command::Validate {
            scenario,
            sets,
            unsets,
        } => commands::validate(&catalogue::resolve(&scenario), &sets, &unsets),
        Command::List => commands::list(),
    }
}
