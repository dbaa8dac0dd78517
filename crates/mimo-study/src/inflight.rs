//! The items in flight bounded by their estimated memory (docs/studies.md "Limits"): a study
//! works within the 4 GiB budget of a `mimo` command (docs/design.md §7) whatever the number of
//! worker threads. The worlds take what [`crate::prepare::world_bytes`] estimates; each item in
//! flight takes what [`item_bytes`] estimates; a worker starts its next item only when that
//! item's estimate fits beside those of the items running ([`InFlight`]). An item never waits
//! for memory when nothing else runs, and a plan with an item that alone would not fit beside the
//! worlds is refused before anything runs (`crate::prepare`).
//!
//! An item streams its tables to disk as they come (`crate::item`), so it holds the engine's and
//! the test article's state, one chunk of rows per table, and then the score of its one run,
//! which reads the run's truth and tracks whole. Measured peak resident memory of one-cell,
//! one-run studies of scenario 7 over 1000 s on one thread (`/usr/bin/time -v mimo study PLAN
//! --threads 1`, the plans of `raid_targets = [N]`), less the world's estimate: 50 MB with the
//! scenario's 7 targets, 214 MB with 64 raid aircraft (71 targets), 702 MB with 256 (263
//! targets). [`item_bytes`] is a linear fit lying above each.

use mimo_sim::World;
use std::sync::{Condvar, Mutex};

/// What an item holds whatever its size (the engine, the test article, the table writers'
/// buffers, the score's fixed part).
const BASE_BYTES: f64 = 64.0 * 1024.0 * 1024.0;
/// What an item holds per target and simulated second (the score's truth and tracks, the
/// tracker's and engine's state).
pub const BYTES_PER_TARGET_SECOND: f64 = 2600.0;

/// Estimated peak memory (bytes) of one item of `world` (its scenario's targets, raid aircraft
/// included, and duration).
pub fn item_bytes(world: &World) -> u64 {
    item_bytes_of(world.scenario.targets.len(), world.scenario.duration_s)
}

/// Estimated peak memory (bytes) of one item of a run of `targets` targets over `duration_s`.
pub fn item_bytes_of(targets: usize, duration_s: f64) -> u64 {
    (BASE_BYTES + BYTES_PER_TARGET_SECOND * targets as f64 * duration_s.max(0.0)) as u64
}

/// The memory of the items in flight: each takes its estimate before it starts and gives it
/// back when it ends.
#[derive(Debug)]
pub struct InFlight {
    budget: u64,
    /// Bytes taken by the items running, and how many run.
    taken: Mutex<(u64, usize)>,
    freed: Condvar,
}

/// An item's share of the budget, given back when dropped.
#[derive(Debug)]
pub struct Share<'a> {
    gate: &'a InFlight,
    bytes: u64,
}

impl InFlight {
    /// Items in flight sharing `budget` bytes.
    pub fn new(budget: u64) -> InFlight {
        InFlight { budget, taken: Mutex::new((0, 0)), freed: Condvar::new() }
    }

    /// Wait until `bytes` fit beside the items running (or none runs), then take them.
    pub fn enter(&self, bytes: u64) -> Share<'_> {
        let mut taken = self.taken.lock().unwrap_or_else(|e| e.into_inner());
        while taken.1 > 0 && taken.0.saturating_add(bytes) > self.budget {
            taken = self.freed.wait(taken).unwrap_or_else(|e| e.into_inner());
        }
        taken.0 += bytes;
        taken.1 += 1;
        Share { gate: self, bytes }
    }
}

impl Drop for Share<'_> {
    fn drop(&mut self) {
        let mut taken = self.gate.taken.lock().unwrap_or_else(|e| e.into_inner());
        taken.0 -= self.bytes;
        taken.1 -= 1;
        self.gate.freed.notify_all();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};

    /// Eight workers, items of 3 units under a budget of 10: never more than three in flight,
    /// never more than the budget taken, and every item done.
    #[test]
    fn items_in_flight_never_exceed_the_budget() {
        let gate = InFlight::new(10);
        let (running, most, done) = (AtomicUsize::new(0), AtomicUsize::new(0), AtomicU64::new(0));
        std::thread::scope(|scope| {
            for _ in 0..8 {
                scope.spawn(|| {
                    for _ in 0..50 {
                        let _share = gate.enter(3);
                        let now = running.fetch_add(1, Ordering::SeqCst) + 1;
                        most.fetch_max(now, Ordering::SeqCst);
                        std::thread::yield_now();
                        running.fetch_sub(1, Ordering::SeqCst);
                        done.fetch_add(1, Ordering::SeqCst);
                    }
                });
            }
        });
        assert_eq!(done.into_inner(), 400);
        let most = most.into_inner();
        assert!((1..=3).contains(&most), "{most} in flight");
        assert_eq!(*gate.taken.lock().expect("lock"), (0, 0), "every share given back");
    }

    /// The measurements quoted in the module docs: the estimate lies above each, within 2×.
    #[test]
    fn the_estimate_covers_the_measured_peaks() {
        // (targets, raid aircraft, measured peak RSS in kB of 1000 s)
        for (targets, raid, kb) in [(7usize, 0u32, 57_516.0), (71, 64, 282_416.0), (263, 256, 953_608.0)] {
            let mut s = mimo_scenario::load_standard(7).expect("scenario 7");
            s.duration_s = 1000.0;
            let world = crate::prepare::world_bytes(&s, raid) as f64;
            let item = kb * 1024.0 - world;
            let est = item_bytes_of(targets, 1000.0) as f64;
            assert!(est >= item && est <= 2.0 * item, "{targets} targets: {est} for {item}");
        }
    }

    /// An item larger than the budget still runs, alone.
    #[test]
    fn an_item_larger_than_the_budget_runs_alone() {
        let gate = InFlight::new(10);
        let big = gate.enter(25);
        assert_eq!(*gate.taken.lock().expect("lock"), (25, 1));
        drop(big);
        let (a, b) = (gate.enter(5), gate.enter(5));
        assert_eq!(*gate.taken.lock().expect("lock"), (10, 2));
        drop((a, b));
    }
}
