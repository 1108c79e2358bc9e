//! `celltissue` command-line interface: `run`, `validate` and `list` scenario files
//! (see `models/README.md`). Exit codes: 0 success, 1 a run or an output failed (results that
//! were computed are still written), 2 bad scenario input (nothing is written).
#![warn(missing_docs)]

mod cli;

fn main() {
    std::process::exit(cli::main());
}
