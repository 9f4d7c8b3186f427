//! Timestamps comparable across processes.
//!
//! `std::time::Instant` cannot cross a process boundary, so every stamp in a message is
//! CLOCK_MONOTONIC in nanoseconds: one clock shared by all processes on the machine.

/// Nanoseconds of CLOCK_MONOTONIC, comparable between processes on one machine.
pub fn monotonic_now_ns() -> u64 {
    let mut time = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `time` is a valid, writable timespec and CLOCK_MONOTONIC is always supported on
    // Linux, so clock_gettime only writes into it.
    let result = unsafe { libc::clock_gettime(libc::CLOCK_MONOTONIC, &mut time) };
    if result != 0 {
        return 0;
    }
    (time.tv_sec as u64)
        .saturating_mul(1_000_000_000)
        .saturating_add(time.tv_nsec as u64)
}

/// Nanoseconds elapsed since `earlier_ns` (0 if the clock did not advance).
pub fn elapsed_since_ns(earlier_ns: u64) -> u64 {
    monotonic_now_ns().saturating_sub(earlier_ns)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn monotonic_clock_never_goes_back() {
        let first_ns = monotonic_now_ns();
        let second_ns = monotonic_now_ns();
        assert!(first_ns > 0);
        assert!(second_ns >= first_ns);
    }
}
