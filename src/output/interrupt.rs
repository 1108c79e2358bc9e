//! SIGINT/SIGTERM handling for a sweep (crate `ctrlc`, with its `termination` feature): the
//! first signal sets a flag that the caller polls between and during runs; it then stops the
//! solves in progress (`integrators::interrupt`: each keeps the steps it took), writes the
//! finished runs with those cut short, and records the latter as interrupted; a second signal
//! exits at once (status 130).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};

/// Exit status after an interrupt (128 + SIGINT).
pub const INTERRUPTED: i32 = 130;

/// The flag raised by the first SIGINT/SIGTERM, lowered again for this run. The handler is
/// installed once per process (`ctrlc` allows one); later calls, e.g. a program that runs the
/// CLI several times ([`crate::cli::main_from`]), get the same flag.
pub(crate) fn install() -> Arc<AtomicBool> {
    static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();
    let flag = FLAG.get_or_init(|| {
        let flag = Arc::new(AtomicBool::new(false));
        let f = flag.clone();
        let result = ctrlc::set_handler(move || {
            if f.swap(true, Ordering::SeqCst) {
                std::process::exit(INTERRUPTED);
            }
            eprintln!(
                "\ninterrupted: stopping the runs and writing what they computed (interrupt again \
                 to quit without writing)"
            );
        });
        if let Err(e) = result {
            log::warn!("cannot install the interrupt handler: {e}");
        }
        flag
    });
    flag.store(false, Ordering::SeqCst);
    flag.clone()
}
