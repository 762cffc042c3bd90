//! Independent runs on a few threads: `verify`'s levels, `boundary`'s scan points and changes,
//! a sweep's spot checks. Work items are taken in order by `jobs` scoped threads; results come
//! back in item order. The calling thread only waits: it calls `tick` about five times a
//! second and after every item, so a caller can show progress or look for Ctrl-C (Python's
//! signal check must run on the thread that holds the interpreter).

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc;
use std::time::Duration;

/// How often the waiting thread calls `tick` when no item ends.
const TICK: Duration = Duration::from_millis(200);

/// `work(0)`, …, `work(n − 1)` on `jobs` threads (at least one, at most `n`), in item order.
/// A worker that panics ends the scope with that panic, as a sequential loop would.
pub fn map<R: Send>(
    n: usize,
    jobs: usize,
    work: &(dyn Fn(usize) -> R + Sync),
    tick: &mut dyn FnMut(),
) -> Vec<R> {
    let next = AtomicUsize::new(0);
    let mut results: Vec<Option<R>> = (0..n).map(|_| None).collect();
    std::thread::scope(|s| {
        let (tx, rx) = mpsc::channel();
        for _ in 0..jobs.clamp(1, n.max(1)) {
            let (tx, next) = (tx.clone(), &next);
            s.spawn(move || {
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    if i >= n {
                        break;
                    }
                    if tx.send((i, work(i))).is_err() {
                        break;
                    }
                }
            });
        }
        drop(tx);
        loop {
            match rx.recv_timeout(TICK) {
                Ok((i, r)) => results[i] = Some(r),
                Err(mpsc::RecvTimeoutError::Timeout) => {}
                Err(mpsc::RecvTimeoutError::Disconnected) => break,
            }
            tick();
        }
    });
    // Every index was sent once: a worker that panicked would have ended the scope.
    results.into_iter().flatten().collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn results_come_back_in_item_order_whatever_the_jobs() {
        for jobs in [0, 1, 2, 7] {
            let mut ticks = 0;
            let out = map(
                5,
                jobs,
                &|i| {
                    std::thread::sleep(Duration::from_millis(((5 - i) * 3) as u64));
                    i * i
                },
                &mut || ticks += 1,
            );
            assert_eq!(out, vec![0, 1, 4, 9, 16], "jobs = {jobs}");
            assert!(ticks >= 5, "a tick per item at least, {ticks}");
        }
        assert!(map(0, 2, &|i| i, &mut || {}).is_empty());
    }
}
