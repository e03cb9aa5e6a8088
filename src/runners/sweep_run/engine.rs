//! The one engine of sweeps and Monte Carlo campaigns: a function called on every item on worker
//! threads, each call guarded by `catch_unwind` so a panic is counted instead of ending the
//! campaign. Workers take the next item from a shared counter, so runs of different lengths
//! are shared out; results are stored by item index, so the thread count never changes them.
//! Runtime layer (threads).

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// The text of a panic payload.
pub fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "non-text panic payload".into())
}

/// One call's outcome: what `run` returned, or the panic's message.
type Guarded<R, E> = Result<Result<R, E>, String>;

/// Calls `run` on every item on `threads` worker threads (at least one, at most one per item).
/// Each result is `Ok`, or `Err` with the panic's message; `progress` is told the number of
/// items done after each one. The first `Err` that `run` returns (by item index among those
/// that ran) stops the hand-out and is returned: a fault of the campaign's set-up, not of a run.
pub fn map_guarded<T, R, E, F>(
    items: &[T],
    threads: usize,
    progress: &(dyn Fn(usize) + Sync),
    run: F,
) -> Result<Vec<Result<R, String>>, E>
where
    T: Sync,
    R: Send,
    E: Send,
    F: Fn(&T) -> Result<R, E> + Sync,
{
    let threads = threads.clamp(1, items.len().max(1));
    let next = AtomicUsize::new(0);
    let done = AtomicUsize::new(0);
    let stop = AtomicBool::new(false);
    let worker = || {
        let mut mine: Vec<(usize, Guarded<R, E>)> = Vec::new();
        while !stop.load(Ordering::Relaxed) {
            let i = next.fetch_add(1, Ordering::Relaxed);
            let Some(item) = items.get(i) else { break };
            let result = catch_unwind(AssertUnwindSafe(|| run(item))).map_err(|p| panic_message(p.as_ref()));
            if matches!(result, Ok(Err(_))) {
                stop.store(true, Ordering::Relaxed);
            }
            mine.push((i, result));
            progress(done.fetch_add(1, Ordering::Relaxed) + 1);
        }
        mine
    };
    let per_worker: Vec<Vec<_>> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..threads).map(|_| scope.spawn(worker)).collect();
        handles.into_iter().map(|h| h.join().unwrap_or_default()).collect()
    });
    let mut slots: Vec<Option<Guarded<R, E>>> = (0..items.len()).map(|_| None).collect();
    for (i, r) in per_worker.into_iter().flatten() {
        slots[i] = Some(r);
    }
    let mut out = Vec::with_capacity(items.len());
    for slot in slots {
        out.push(match slot {
            Some(Ok(Ok(r))) => Ok(r),
            Some(Ok(Err(e))) => return Err(e),
            Some(Err(panic)) => Err(panic),
            None => Err("run lost: its worker stopped".into()),
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn results_are_in_item_order_whatever_the_thread_count_and_panics_are_counted() {
        let items: Vec<u64> = (0..50).collect();
        for threads in [1, 2, 16] {
            let counted = AtomicUsize::new(0);
            let out = map_guarded(
                &items,
                threads,
                &|_| {
                    counted.fetch_add(1, Ordering::Relaxed);
                },
                |&x| {
                    assert_ne!(x, 7, "boom");
                    Ok::<_, ()>(x * x)
                },
            )
            .unwrap();
            assert_eq!(counted.load(Ordering::Relaxed), 50);
            for (i, r) in out.iter().enumerate() {
                match r {
                    Err(msg) => assert!(i == 7 && msg.contains("boom"), "{i}: {msg}"),
                    Ok(v) => assert_eq!(*v, (i * i) as u64),
                }
            }
        }
    }

    #[test]
    fn a_set_up_error_stops_the_campaign() {
        let items: Vec<u64> = (0..1000).collect();
        let err = map_guarded(&items, 2, &|_| {}, |&x| if x == 3 { Err("bad set-up") } else { Ok(x) });
        assert_eq!(err.unwrap_err(), "bad set-up");
    }
}
