//! SIGINT/SIGTERM handling for a sweep (crate `ctrlc`, with its `termination` feature): the
//! first signal sets a flag that the caller polls between and during runs; it then stops the
//! solves in progress (`integrators::interrupt`: each keeps the steps it took), writes the
//! finished runs with those cut short, and records the latter as interrupted; a second signal
//! exits at once (status 130), unless it comes within [`SAME_INTERRUPT`] of the first (the
//! same request delivered twice, as `timeout` does).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, OnceLock};
use std::time::{Duration, Instant};

/// Exit status after an interrupt (128 + SIGINT).
pub const INTERRUPTED: i32 = 130;

/// A signal within this time of the first is the same interrupt, not a second one: coreutils'
/// `timeout` sends SIGTERM to the program and then to its whole process group, so the program
/// gets it twice within microseconds (and a scheduler stopping a job may signal a script and
/// the program it runs alike). Taken as "interrupt again", that second copy made the program
/// quit without writing, in two runs of three under `timeout`. A person interrupting again
/// takes longer than this.
pub const SAME_INTERRUPT: Duration = Duration::from_millis(500);

/// The flag raised by the first SIGINT/SIGTERM, lowered again for this run. The handler is
/// installed once per process (`ctrlc` allows one); later calls, e.g. a program that runs the
/// CLI several times ([`crate::cli::main_from`]), get the same flag.
pub(crate) fn install() -> Arc<AtomicBool> {
    static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();
    // when the first signal of this run came (ctrlc calls the handler on a thread of its own,
    // not in the signal's context, so a lock is fine)
    static FIRST: Mutex<Option<Instant>> = Mutex::new(None);
    let flag = FLAG.get_or_init(|| {
        let flag = Arc::new(AtomicBool::new(false));
        let f = flag.clone();
        let result = ctrlc::set_handler(move || {
            let now = Instant::now();
            let mut first = FIRST.lock().unwrap_or_else(|e| e.into_inner());
            if f.swap(true, Ordering::SeqCst) {
                if first.is_some_and(|t| now.duration_since(t) < SAME_INTERRUPT) {
                    return;
                }
                std::process::exit(INTERRUPTED);
            }
            *first = Some(now);
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
    *FIRST.lock().unwrap_or_else(|e| e.into_inner()) = None;
    flag.store(false, Ordering::SeqCst);
    flag.clone()
}
