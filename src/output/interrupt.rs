//! SIGINT/SIGTERM handling for a sweep (crate `ctrlc`, with its `termination` feature): the
//! first signal sets a flag that the caller polls between and during runs, so it can stop
//! waiting for the run in progress, write the finished runs and record the others as
//! interrupted; a second signal exits at once (status 130).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// Exit status after an interrupt (128 + SIGINT).
pub const INTERRUPTED: i32 = 130;

/// The flag raised by the first SIGINT/SIGTERM. Installing twice returns the same flag's
/// clone only once (`ctrlc` allows one handler per process); later calls get a flag that is
/// never raised.
pub fn install() -> Arc<AtomicBool> {
    let flag = Arc::new(AtomicBool::new(false));
    let f = flag.clone();
    let result = ctrlc::set_handler(move || {
        if f.swap(true, Ordering::SeqCst) {
            std::process::exit(INTERRUPTED);
        }
        eprintln!(
            "\ninterrupted: writing the finished runs (interrupt again to quit without writing)"
        );
    });
    if let Err(e) = result {
        log::warn!("cannot install the interrupt handler: {e}");
    }
    flag
}
