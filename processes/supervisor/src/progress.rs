//! What the watchdog reads of a process from `/proc`: whether it is stopped or busy, and how
//! much CPU time its threads have used.

use std::path::PathBuf;

/// The threads of `pid`: thread id and `/proc/<pid>/task/<tid>` (none if the process is gone).
pub(crate) fn threads_of(pid: u32) -> impl Iterator<Item = (libc::pid_t, PathBuf)> {
    std::fs::read_dir(format!("/proc/{pid}/task"))
        .into_iter()
        .flatten()
        .flatten()
        .filter_map(|task| {
            let tid = task.file_name().to_str()?.parse::<libc::pid_t>().ok()?;
            Some((tid, task.path()))
        })
}

/// What the watchdog can tell about a silent process from /proc: whether it can make
/// progress at all, and how much CPU time it has used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ProgressSample {
    /// Stopped (SIGSTOP) or traced: it cannot run until someone resumes it.
    pub stopped: bool,
    /// Some thread is running or waiting for a CPU, or in uninterruptible I/O: busy, not idle.
    pub busy: bool,
    /// CPU time of all its threads, nanoseconds: from `schedstat`, exact to the nanosecond,
    /// so that a process that ran for a millisecond counts as having run (`stat`'s 10 ms
    /// clock ticks stand still over a short run; the fallback when `schedstat` is missing).
    pub cpu_time_ns: u64,
}

/// Nanoseconds per `stat` clock tick (USER_HZ is 100 on every Linux ABI).
const NS_PER_CLOCK_TICK: u64 = 10_000_000;

impl ProgressSample {
    /// Reads `/proc/<pid>` (`None` if the process is gone).
    pub fn read(pid: u32) -> Option<Self> {
        let (state, stat_cpu_ns) = read_stat(&format!("/proc/{pid}/stat"))?;
        let mut sample = Self {
            stopped: matches!(state, 'T' | 't'),
            busy: is_busy(state),
            cpu_time_ns: stat_cpu_ns,
        };
        // Every thread: a process whose main thread waits for its workers is busy while they
        // run or queue for a CPU.
        let mut schedstat_ns = Some(0u64);
        let mut threads = 0;
        for (_, path) in threads_of(pid) {
            threads += 1;
            if let Some((thread_state, _)) = read_stat(&path.join("stat").to_string_lossy()) {
                sample.busy |= is_busy(thread_state);
            }
            schedstat_ns = schedstat_ns.and_then(|total| {
                let text = std::fs::read_to_string(path.join("schedstat")).ok()?;
                Some(total + parse_schedstat_run_ns(&text)?)
            });
        }
        if let Some(run_ns) = schedstat_ns.filter(|_| threads > 0) {
            sample.cpu_time_ns = run_ns;
        }
        Some(sample)
    }
}

fn is_busy(state: char) -> bool {
    matches!(state, 'R' | 'D')
}

/// The state letter and the user + system CPU time in nanoseconds of a `stat` file.
fn read_stat(path: &str) -> Option<(char, u64)> {
    parse_stat(&std::fs::read_to_string(path).ok()?)
}

fn parse_stat(stat: &str) -> Option<(char, u64)> {
    // The command name may contain spaces and parentheses: fields start after the last ')'.
    let fields: Vec<&str> = stat.get(stat.rfind(')')? + 2..)?.split(' ').collect();
    let state = fields.first()?.chars().next()?;
    let utime: u64 = fields.get(11)?.parse().ok()?;
    let stime: u64 = fields.get(12)?.parse().ok()?;
    Some((state, (utime + stime).saturating_mul(NS_PER_CLOCK_TICK)))
}

/// The first field of a `schedstat` file: time spent on a CPU, nanoseconds.
fn parse_schedstat_run_ns(text: &str) -> Option<u64> {
    text.split_whitespace().next()?.parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn progress_of_this_process_is_readable() {
        let sample = ProgressSample::read(std::process::id()).expect("own stat");
        assert!(!sample.stopped);
        // This thread is running while it reads.
        assert!(sample.busy);
        assert_eq!(ProgressSample::read(u32::MAX), None);
    }

    #[test]
    fn two_milliseconds_of_work_show_in_the_cpu_time() {
        let before = ProgressSample::read(std::process::id()).expect("own stat");
        let started = std::time::Instant::now();
        let mut spin = 0u64;
        while started.elapsed() < std::time::Duration::from_millis(2) {
            spin = std::hint::black_box(spin.wrapping_add(1));
        }
        // Going to sleep books the run time (a running thread's is booked at scheduler ticks).
        std::thread::sleep(std::time::Duration::from_millis(1));
        let after = ProgressSample::read(std::process::id()).expect("own stat");
        // Clock ticks (10 ms) would usually stand still over 2 ms; schedstat does not. (The
        // sum over live threads may also drop when another test's thread ends: a change too.)
        if std::path::Path::new("/proc/self/schedstat").exists() {
            assert_ne!(
                after.cpu_time_ns, before.cpu_time_ns,
                "{before:?} {after:?}"
            );
        }
    }

    #[test]
    fn stat_and_schedstat_lines_parse() {
        let stat = "42 (a (strange) name) S 1 42 42 0 -1 4194560 100 0 0 0 7 3 0 0 20 0 1 0";
        assert_eq!(parse_stat(stat), Some(('S', 10 * NS_PER_CLOCK_TICK)));
        assert_eq!(parse_stat("42 (cut"), None);
        assert_eq!(parse_schedstat_run_ns("48299 945552 2\n"), Some(48299));
        assert_eq!(parse_schedstat_run_ns(""), None);
    }
}
