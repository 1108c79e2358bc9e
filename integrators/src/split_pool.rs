//! The rayon pool a two-thread solve splits its passes on ([`crate::Parallelism::Halves`]).
//!
//! A [`rayon::join`] called from a thread outside every rayon pool hands the whole join to a
//! pool worker and blocks the caller on a lock until it is done: two thread wake-ups per split
//! pass. A solve makes dozens of split passes per step (residual, solve halves, norms), each of
//! 0.05–0.5 ms at 10⁵ unknowns, so those hand-offs cost a good part of what the split saves.
//! [`enter`] makes the solving thread itself worker 0 of a two-thread pool (rayon's
//! `use_current_thread`), kept for that thread's lifetime: a split pass then pushes its second
//! half onto the thread's own queue, the other worker steals it, and if that worker is slow to
//! wake the solving thread runs the half itself. Measured on the macroscale line at N = 10⁵,
//! two threads (BENCHMARKS.md, "Two threads below 10⁶ unknowns").
//!
//! Called once per solve by the driver ([`crate::Solver`]); a thread that already is a rayon
//! worker (a parallel sweep's) keeps its own pool.

use std::cell::OnceCell;

thread_local! {
    /// This thread's two-thread pool, once [`enter`] has made it one (`None`: the pool could
    /// not be built, and the thread hands its splits to the global pool as before).
    static HOME: OnceCell<Option<rayon::ThreadPool>> = const { OnceCell::new() };
}

/// Makes the calling thread worker 0 of a two-thread rayon pool for the rest of its life,
/// unless it already belongs to a pool. Returns whether the thread now runs its splits as a
/// pool worker; if the pool cannot be built (the system refuses a thread) the reason is logged
/// and splits go to the global pool, with the same results. (Crate-private: the unit tests
/// below show its use.)
pub(crate) fn enter() -> bool {
    if rayon::current_thread_index().is_some() {
        return true;
    }
    HOME.with(|home| {
        home.get_or_init(|| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(2)
                .use_current_thread()
                .thread_name(|i| format!("integrators-split-{i}"))
                .build()
                .map_err(|e| log::warn!("two-thread pool not built ({e}); using the global pool"))
                .ok()
        })
        .is_some()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_thread_outside_any_pool_becomes_worker_zero_of_its_own_pool() {
        std::thread::spawn(|| {
            assert_eq!(rayon::current_thread_index(), None);
            assert!(enter());
            assert_eq!(rayon::current_thread_index(), Some(0));
            assert_eq!(rayon::current_num_threads(), 2);
            // a second call keeps the same pool
            assert!(enter());
            // both halves of a join run, one of them possibly on the other worker
            let (a, b) = rayon::join(
                || (1..=100u64).sum::<u64>(),
                || (1..=10u64).product::<u64>(),
            );
            assert_eq!((a, b), (5050, 3_628_800));
        })
        .join()
        .expect("the thread and its pool end cleanly");
    }

    #[test]
    fn a_worker_of_another_pool_keeps_it() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        pool.install(|| {
            assert!(enter());
            assert_eq!(rayon::current_num_threads(), 3);
        });
    }
}
