//! `celltissue` command-line interface: `run`, `validate`, `merge` and `list` scenario files
//! (see `models/README.md`). Exit codes: 0 success, 1 a run or an output failed (results that
//! were computed are still written), 2 bad scenario input (nothing is written). The interface
//! itself is the library's [`celltissue::cli`], so a binary of one's own with extra laws and
//! methods registered gets all of it (see `examples/custom_cli.rs`).
#![warn(missing_docs)]

fn main() {
    std::process::exit(celltissue::cli::main());
}
