//! Load generators for `hopnav bench realtime`: threads that compete with the process graph
//! for the CPU, or for the memory bandwidth and the cache the renderer and the VOs live in.
//!
//! They spin on purpose (a hog that sleeps loads nothing), and stop when the [`Hogs`] handle
//! is dropped, so an error or an early return cannot leave them running.

use std::hint::black_box;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::thread::JoinHandle;

/// What a hog competes for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum HogKind {
    /// Integer arithmetic in registers: takes CPU time only.
    Cpu,
    /// Reads and writes a buffer four times a typical last-level cache, a cache line at a
    /// time: takes memory bandwidth and evicts the graph's working sets.
    Memory,
}

impl HogKind {
    /// Its name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Cpu => "cpu",
            Self::Memory => "memory",
        }
    }
}

/// Bytes each memory hog streams through.
const MEMORY_HOG_BYTES: usize = 64 << 20;
/// Bytes between the words a memory hog touches: one cache line.
const CACHE_LINE_BYTES: usize = 64;

/// Running hogs; dropping the handle stops and joins them.
#[derive(Debug)]
pub struct Hogs {
    stop: Arc<AtomicBool>,
    /// Rounds of work done by all hogs (a hog that did none loaded nothing).
    rounds: Arc<AtomicU64>,
    threads: Vec<JoinHandle<()>>,
}

impl Hogs {
    /// Starts `count` hogs of `kind`.
    pub fn start(count: usize, kind: HogKind) -> std::io::Result<Self> {
        let mut hogs = Self {
            stop: Arc::new(AtomicBool::new(false)),
            rounds: Arc::new(AtomicU64::new(0)),
            threads: Vec::with_capacity(count),
        };
        for index in 0..count {
            let (stop, rounds) = (Arc::clone(&hogs.stop), Arc::clone(&hogs.rounds));
            let thread = std::thread::Builder::new()
                .name(format!("hog-{}-{index}", kind.name()))
                .spawn(move || match kind {
                    HogKind::Cpu => spin_cpu(&stop, &rounds),
                    HogKind::Memory => stream_memory(&stop, &rounds),
                })?;
            // On an error the threads started so far stop when `hogs` drops.
            hogs.threads.push(thread);
        }
        Ok(hogs)
    }

    /// Rounds of work done so far by all hogs.
    pub fn rounds(&self) -> u64 {
        self.rounds.load(Ordering::Relaxed)
    }
}

impl Drop for Hogs {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        for thread in self.threads.drain(..) {
            // A hog cannot panic (no indexing out of range, no allocation after its start);
            // a join error would only mean it already ended.
            let _ = thread.join();
        }
    }
}

fn spin_cpu(stop: &AtomicBool, rounds: &AtomicU64) {
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    while !stop.load(Ordering::Relaxed) {
        for _ in 0..100_000 {
            state = black_box(state.rotate_left(5) ^ state.wrapping_mul(0x2545_f491_4f6c_dd1d));
        }
        rounds.fetch_add(1, Ordering::Relaxed);
    }
}

fn stream_memory(stop: &AtomicBool, rounds: &AtomicU64) {
    let mut buffer = vec![0_u64; MEMORY_HOG_BYTES / size_of::<u64>()];
    let stride = CACHE_LINE_BYTES / size_of::<u64>();
    while !stop.load(Ordering::Relaxed) {
        // One pass over the buffer, one word per cache line read and written back.
        let mut index = 0;
        while index < buffer.len() {
            buffer[index] = black_box(buffer[index].wrapping_add(1));
            index += stride;
        }
        rounds.fetch_add(1, Ordering::Relaxed);
    }
    black_box(&buffer);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hogs_of_both_kinds_work_until_dropped_and_then_stop() {
        for kind in [HogKind::Cpu, HogKind::Memory] {
            let hogs = Hogs::start(2, kind).expect("threads start");
            let deadline = std::time::Instant::now() + std::time::Duration::from_secs(20);
            while hogs.rounds() < 2 && std::time::Instant::now() < deadline {
                std::thread::sleep(std::time::Duration::from_millis(5));
            }
            assert!(hogs.rounds() >= 2, "{kind:?} hogs did no work");
            let rounds = Arc::clone(&hogs.rounds);
            drop(hogs);
            let after_stop = rounds.load(Ordering::Relaxed);
            std::thread::sleep(std::time::Duration::from_millis(50));
            assert_eq!(
                rounds.load(Ordering::Relaxed),
                after_stop,
                "{kind:?} hogs still run"
            );
        }
    }

    #[test]
    fn no_hogs_is_a_valid_baseline() {
        let hogs = Hogs::start(0, HogKind::Cpu).expect("nothing to start");
        assert_eq!(hogs.rounds(), 0);
    }
}
