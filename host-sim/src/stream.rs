//! Ordered parallel streaming: items `0..count` (animation frames) are produced in parallel on
//! rayon's work-stealing pool and handed to a consumer (the encoder) one by one, in order.
//!
//! Guarantees:
//! - **Order**: the consumer sees items `0, 1, 2, ...` exactly once each, whatever the number of
//!   threads, so an encoder fed this way writes the same bytes as a one-thread run.
//! - **Bounded memory**: items are produced in chunks of `chunk` (a few per thread; see
//!   [`default_chunk`]); while one chunk is produced the previous one waits in a one-slot channel
//!   and the one before it is being consumed, so at most `3 * chunk` items are alive at any time,
//!   whatever `count` is.
//! - **Overlap**: production (all cores) and consumption (one thread) run at the same time.
//! - **Errors and stops**: the first error (of the producer or the consumer) ends the stream;
//!   no later chunk is started. A set `stop` flag (Ctrl-C, [`crate::interrupt`]) is checked
//!   before each chunk and each item and ends the stream with [`Stopped::Interrupted`].

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;

use rayon::prelude::*;

/// Why a stream ended early.
#[derive(Debug, PartialEq, Eq)]
pub enum Stopped<E> {
    /// The stop flag was set.
    Interrupted,
    /// Producing or consuming an item failed.
    Failed(E),
}

/// Items per chunk for the current rayon pool: two per thread (so a slow item rarely leaves
/// threads idle at the end of a chunk).
pub fn default_chunk() -> usize {
    2 * rayon::current_num_threads().max(1)
}

/// Produces items `0..count` with `produce` on rayon's pool, `chunk` at a time, and hands them in
/// order to `consume` on the calling thread. See the module documentation for the guarantees.
pub fn ordered<T, E, P, C>(
    count: u32,
    chunk: usize,
    stop: &AtomicBool,
    produce: P,
    mut consume: C,
) -> Result<(), Stopped<E>>
where
    T: Send,
    E: Send,
    P: Fn(u32) -> Result<T, E> + Sync,
    C: FnMut(u32, T) -> Result<(), E>,
{
    let chunk = u32::try_from(chunk.max(1)).unwrap_or(u32::MAX);
    let produce = &produce;
    std::thread::scope(|s| {
        let (tx, rx) = mpsc::sync_channel::<Result<Vec<T>, E>>(1);
        s.spawn(move || {
            let mut start = 0u32;
            while start < count && !stop.load(Ordering::Relaxed) {
                let end = start.saturating_add(chunk).min(count);
                let items: Result<Vec<T>, E> = (start..end).into_par_iter().map(produce).collect();
                let failed = items.is_err();
                // A closed channel means the consumer has stopped.
                if tx.send(items).is_err() || failed {
                    return;
                }
                start = end;
            }
        });
        let mut next = 0u32;
        // Returning early drops `rx`: the producer's next send fails and it ends.
        for items in rx {
            for item in items.map_err(Stopped::Failed)? {
                if stop.load(Ordering::Relaxed) {
                    return Err(Stopped::Interrupted);
                }
                consume(next, item).map_err(Stopped::Failed)?;
                next += 1;
            }
        }
        if next < count {
            return Err(Stopped::Interrupted);
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::AtomicUsize;

    /// An item that counts how many of its kind are alive.
    struct Tracked<'a> {
        index: u32,
        live: &'a AtomicUsize,
    }

    impl Drop for Tracked<'_> {
        fn drop(&mut self) {
            self.live.fetch_sub(1, Ordering::SeqCst);
        }
    }

    fn run_tracked(threads: usize, count: u32, chunk: usize) -> (Vec<u32>, usize) {
        let live = AtomicUsize::new(0);
        let peak = AtomicUsize::new(0);
        let stop = AtomicBool::new(false);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut seen = Vec::new();
        pool.install(|| {
            ordered(
                count,
                chunk,
                &stop,
                |i| {
                    let n = live.fetch_add(1, Ordering::SeqCst) + 1;
                    peak.fetch_max(n, Ordering::SeqCst);
                    // Uneven work, so items finish out of order.
                    let spin = (i.wrapping_mul(2_654_435_761) >> 20) % 2000;
                    let mut x = 0u64;
                    for k in 0..spin {
                        x = std::hint::black_box(x.wrapping_add(u64::from(k)));
                    }
                    Ok::<_, ()>(Tracked {
                        index: i + u32::from(x == u64::MAX),
                        live: &live,
                    })
                },
                |i, t| {
                    assert_eq!(i, t.index);
                    seen.push(t.index);
                    Ok(())
                },
            )
        })
        .unwrap();
        assert_eq!(live.load(Ordering::SeqCst), 0);
        (seen, peak.load(Ordering::SeqCst))
    }

    #[test]
    fn items_arrive_in_order_with_at_most_three_chunks_alive() {
        for threads in [1, 2, 4] {
            let chunk = 2 * threads;
            let (seen, peak) = run_tracked(threads, 1000, chunk);
            assert_eq!(seen, (0..1000).collect::<Vec<_>>(), "{threads} threads");
            assert!(
                peak <= 3 * chunk,
                "{threads} threads: {peak} items alive at once, bound {}",
                3 * chunk
            );
        }
    }

    #[test]
    fn the_first_error_ends_the_stream() {
        let stop = AtomicBool::new(false);
        let mut seen = Vec::new();
        let r = ordered(
            100,
            4,
            &stop,
            |i| if i == 10 { Err(i) } else { Ok(i) },
            |_, i| {
                seen.push(i);
                Ok(())
            },
        );
        assert_eq!(r, Err(Stopped::Failed(10)));
        assert_eq!(seen, (0..8).collect::<Vec<_>>());
        let mut seen = 0;
        let r = ordered(100, 4, &stop, Ok::<u32, u32>, |i, _| {
            seen += 1;
            if i == 5 {
                Err(99)
            } else {
                Ok(())
            }
        });
        assert_eq!(r, Err(Stopped::Failed(99)));
        assert_eq!(seen, 6);
    }

    #[test]
    fn a_set_stop_flag_interrupts() {
        let stop = AtomicBool::new(false);
        let mut seen = 0;
        let r = ordered(1000, 4, &stop, Ok::<u32, ()>, |i, _| {
            seen += 1;
            if i == 20 {
                stop.store(true, Ordering::Relaxed);
            }
            Ok(())
        });
        assert_eq!(r, Err(Stopped::Interrupted));
        assert_eq!(seen, 21);
        // Nothing at all when stopped before the start; an empty stream is complete.
        let r = ordered(10, 4, &stop, Ok::<u32, ()>, |_, _| Ok(()));
        assert_eq!(r, Err(Stopped::Interrupted));
        let r = ordered(0, 4, &AtomicBool::new(false), Ok::<u32, ()>, |_, _| Ok(()));
        assert_eq!(r, Ok(()));
    }
}
