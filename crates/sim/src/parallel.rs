//! Running independent jobs (one per contact island) on a few threads.
//!
//! Each job writes only to its own item, so the results do not depend on the
//! number of threads or on which thread ran which job; workers pull the next
//! item from a shared iterator (large and small islands mix well). Threads are
//! scoped (`std::thread::scope`) and started per call, which costs some tens of
//! microseconds: [`worth_threads`] keeps small steps on the calling thread.

use std::sync::Mutex;

/// Threads to use for `threads` as set in `WorldParams` (0 = every core).
pub fn resolve_threads(threads: usize) -> usize {
    match threads {
        0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
        t => t,
    }
}

/// Whether jobs of this total work (Σ n² over the islands' LCP sizes) are
/// worth starting threads for: about a dense n = 500 problem's worth (nine
/// 3-cube towers, Σ n² = 130k, ran at 600 steps/s on one thread and 410 on
/// two: starting threads twice a step cost more than it saved).
pub fn worth_threads(jobs: usize, work: usize) -> bool {
    jobs >= 2 && work >= 250_000
}

/// Runs `f(state, item)` for every item, on up to `states.len()` threads, each
/// with its own `state` (e.g. a solver workspace). One state: on this thread.
pub fn for_each<T: Send, S: Send>(items: &mut [T], states: &mut [S], f: impl Fn(&mut S, &mut T) + Sync) {
    let threads = states.len().min(items.len());
    if threads <= 1 {
        if let Some(s) = states.first_mut() {
            items.iter_mut().for_each(|it| f(s, it));
        }
        return;
    }
    let queue = Mutex::new(items.iter_mut());
    let next = || queue.lock().unwrap_or_else(|e| e.into_inner()).next();
    std::thread::scope(|scope| {
        for s in states.iter_mut().take(threads) {
            let (f, next) = (&f, &next);
            scope.spawn(move || {
                while let Some(it) = next() {
                    f(s, it);
                }
            });
        }
    });
}
