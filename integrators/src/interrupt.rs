//! Stopping a running solve from outside it: an [`Interrupt`] is a shared flag that a signal
//! handler, a Python `KeyboardInterrupt` or any other thread raises, and every solve run
//! inside [`Interrupt::scope`] on that thread checks before each step. A solve that finds it
//! raised stops with [`crate::ErrorKind::Interrupted`], keeping the steps it had taken (as any
//! failed solve does), so the caller can write what was computed.
//!
//! The flag is installed per thread rather than passed in [`crate::Options`], so that every
//! model's run function (which builds its own options) is interruptible without a new
//! parameter; a solve outside any scope is never interrupted, and solves on other threads
//! (other tests, other scopes) do not see this one's flag.

use std::cell::RefCell;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// A flag shared by the thread that raises it and the solves that check it.
///
/// ```
/// use integrators::interrupt::Interrupt;
/// let stop = Interrupt::new();
/// let seen = stop.scope(|| Interrupt::current().is_some_and(|i| i.is_raised()));
/// assert!(!seen);
/// stop.raise();
/// assert!(stop.scope(|| Interrupt::current().is_some_and(|i| i.is_raised())));
/// assert!(Interrupt::current().is_none()); // outside the scope
/// ```
#[derive(Clone, Debug, Default)]
pub struct Interrupt(Arc<AtomicBool>);

thread_local! {
    static CURRENT: RefCell<Option<Interrupt>> = const { RefCell::new(None) };
}

impl Interrupt {
    /// A flag not yet raised.
    pub fn new() -> Self {
        Self::default()
    }

    /// Raises the flag: every solve in a scope of it stops before its next step.
    pub fn raise(&self) {
        self.0.store(true, Ordering::SeqCst);
    }

    /// Whether the flag has been raised.
    pub fn is_raised(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }

    /// Runs `f` with this flag installed on the current thread (the previous one, if any, is
    /// restored afterwards, also when `f` panics).
    pub fn scope<R>(&self, f: impl FnOnce() -> R) -> R {
        /// Puts the previous flag back when dropped.
        struct Restore(Option<Interrupt>);
        impl Drop for Restore {
            fn drop(&mut self) {
                let previous = self.0.take();
                CURRENT.with(|c| *c.borrow_mut() = previous);
            }
        }
        let previous = CURRENT.with(|c| c.borrow_mut().replace(self.clone()));
        let _restore = Restore(previous);
        f()
    }

    /// The flag installed on the current thread by [`Interrupt::scope`], if any.
    pub fn current() -> Option<Interrupt> {
        CURRENT.with(|c| c.borrow().clone())
    }
}
