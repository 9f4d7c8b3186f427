//! `hopnav top`: the processes of a running launch, live: CPU, memory, frame time p50/p99
//! against each one's budget, budget misses and restarts, refreshed every second.
//!
//! It listens to the heartbeats every process publishes (an extra subscriber that never
//! holds the launch back) and reads the rest from `/proc`.

use std::collections::HashMap;
use std::io::IsTerminal;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Args;
use hopnav_ipc::live::{TapSample, Watcher, fixed_message};
use hopnav_ipc::messages::Heartbeat;
use hopnav_ipc::topics;

use crate::top_table::{Identify, ProcSample, ProcessTable};
use crate::topic_window::{WindowArgs, continue_until, exit_code, watch_topic};

/// A process that sent no heartbeat for this long shows as silent (it heartbeats at least
/// every period while idle).
const SILENT_AFTER_NS: u64 = 2_000_000_000;

#[derive(Debug, Args)]
pub struct TopArgs {
    #[command(flatten)]
    window: WindowArgs,
    /// Print each refresh below the last instead of redrawing the screen (the default when
    /// the output is not a terminal).
    #[arg(long)]
    no_redraw: bool,
}

pub fn run(args: &TopArgs) -> ExitCode {
    let watched = watch_topic(
        &args.window,
        &topics::HEARTBEAT.name,
        |namespace, started_ns| Monitor {
            table: ProcessTable::new(args.window.window_ns(), SILENT_AFTER_NS),
            identities: ProcIdentities::default(),
            run_id: namespace.run_id().to_owned(),
            redraw: !args.no_redraw && std::io::stdout().is_terminal(),
            started_ns,
            stop_ns: args.window.stop_ns(started_ns),
        },
    );
    let watched = match watched {
        Ok(watched) => watched,
        Err(code) => return code,
    };
    if watched.rejected.total() > 0 {
        eprintln!("{} heartbeats rejected", watched.rejected.total());
    }
    exit_code(&watched.namespace, watched.end)
}

struct Monitor {
    table: ProcessTable,
    identities: ProcIdentities,
    run_id: String,
    redraw: bool,
    started_ns: u64,
    stop_ns: Option<u64>,
}

impl Watcher for Monitor {
    fn on_sample(&mut self, sample: &dyn TapSample, arrival_ns: u64) {
        if let Some(heartbeat) = fixed_message::<Heartbeat>(sample) {
            self.table
                .on_heartbeat(heartbeat, arrival_ns, &mut self.identities);
        }
    }

    fn on_tick(&mut self, now_ns: u64) -> ControlFlow<()> {
        self.table.refresh(now_ns, &mut read_proc);
        if self.redraw {
            // Clear the screen and home the cursor, as top does.
            print!("\x1b[2J\x1b[H");
        }
        let elapsed_s = now_ns.saturating_sub(self.started_ns) as f64 * 1e-9;
        println!(
            "launch {}: {elapsed_s:.0} s watched (CPU%: of one core over the last second; \
             OVER: frames over budget / frames seen; RESTARTS: starts of the slot before this one)",
            self.run_id
        );
        print!("{}", self.table.render(now_ns));
        if !self.redraw {
            println!();
        }
        continue_until(self.stop_ns, now_ns)
    }
}

/// Names and budgets from each process's command line (`hopnav run NAME … --config FILE`)
/// and the launch's resolved configuration file; each file is read once.
#[derive(Default)]
struct ProcIdentities {
    budgets_by_config: HashMap<PathBuf, Option<HashMap<String, f64>>>,
}

impl Identify for ProcIdentities {
    fn identify(&mut self, pid: u32) -> (Option<String>, Option<u64>) {
        let Ok(cmdline) = std::fs::read(format!("/proc/{pid}/cmdline")) else {
            return (None, None);
        };
        let args: Vec<String> = cmdline
            .split(|&byte| byte == 0)
            .map(|arg| String::from_utf8_lossy(arg).into_owned())
            .collect();
        let (name, config) = name_and_config(&args);
        let budget_ns = match (&name, config) {
            (Some(name), Some(config)) => self
                .budgets_by_config
                .entry(config.clone())
                .or_insert_with(|| budgets(&config))
                .as_ref()
                .and_then(|budgets| budgets.get(name))
                .map(|budget_ms| (budget_ms * 1e6) as u64),
            _ => None,
        };
        (name, budget_ns)
    }
}

/// The process name after `run` and the file after `--config` in a child's arguments.
fn name_and_config(args: &[String]) -> (Option<String>, Option<PathBuf>) {
    let after = |flag: &str| {
        args.iter()
            .position(|arg| arg == flag)
            .and_then(|at| args.get(at + 1))
    };
    (after("run").cloned(), after("--config").map(PathBuf::from))
}

/// Every process's frame budget in the configuration file at `path` (none if unreadable).
fn budgets(path: &Path) -> Option<HashMap<String, f64>> {
    let config = hopnav_config::load_file(path).ok()?;
    Some(
        config
            .processes
            .into_iter()
            .map(|(name, process)| (name, process.budget_ms))
            .collect(),
    )
}

/// CPU time of every thread of `pid`, living or exited (`/proc/PID/stat`), and its resident
/// memory (`/proc/PID/status`, VmRSS); what cannot be read stays unknown.
fn read_proc(pid: u32) -> ProcSample {
    let cpu_ns = std::fs::read_to_string(format!("/proc/{pid}/stat"))
        .ok()
        .and_then(|text| cpu_ns_of_stat(&text, clock_ticks_per_s()));
    let resident_bytes = std::fs::read_to_string(format!("/proc/{pid}/status"))
        .ok()
        .and_then(|text| vm_rss_bytes(&text));
    ProcSample {
        cpu_ns,
        resident_bytes,
    }
}

/// Clock ticks per second of `/proc/PID/stat`'s times (USER_HZ; 100 if unknown).
fn clock_ticks_per_s() -> u64 {
    // SAFETY: sysconf reads a constant of the system; it has no preconditions.
    let ticks = unsafe { libc::sysconf(libc::_SC_CLK_TCK) };
    u64::try_from(ticks)
        .ok()
        .filter(|&ticks| ticks > 0)
        .unwrap_or(100)
}

/// utime + stime (fields 14 and 15) of a `/proc/PID/stat` text, nanoseconds. The fields are
/// counted after the command name's closing parenthesis: the name may hold spaces.
fn cpu_ns_of_stat(stat: &str, ticks_per_s: u64) -> Option<u64> {
    let after_name = stat.get(stat.rfind(')')? + 1..)?;
    // Field 3 (the state) comes first, so field 14 is the twelfth.
    let mut fields = after_name.split_whitespace().skip(11);
    let user_ticks: u64 = fields.next()?.parse().ok()?;
    let system_ticks: u64 = fields.next()?.parse().ok()?;
    let ns_per_tick = 1_000_000_000 / ticks_per_s.max(1);
    Some(
        user_ticks
            .saturating_add(system_ticks)
            .saturating_mul(ns_per_tick),
    )
}

/// The `VmRSS:` line of a `/proc/PID/status` text, in bytes.
fn vm_rss_bytes(status: &str) -> Option<u64> {
    let line = status.lines().find(|line| line.starts_with("VmRSS:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_childs_name_and_config_come_from_its_arguments() {
        let args: Vec<String> = [
            "/x/hopnav",
            "run",
            "mapper",
            "--run-id",
            "r1",
            "--config",
            "/runs/r1/config.toml",
        ]
        .map(str::to_owned)
        .to_vec();
        let (name, config) = name_and_config(&args);
        assert_eq!(name.as_deref(), Some("mapper"));
        assert_eq!(config, Some(PathBuf::from("/runs/r1/config.toml")));
        assert_eq!(name_and_config(&["hopnav".to_owned()]), (None, None));
    }

    #[test]
    fn resident_memory_is_read_from_the_status_text() {
        let status = "Name:\thopnav\nVmPeak:\t  9000 kB\nVmRSS:\t    2048 kB\n";
        assert_eq!(vm_rss_bytes(status), Some(2 * 1024 * 1024));
        assert_eq!(vm_rss_bytes("Name:\tx\n"), None);
        assert_eq!(vm_rss_bytes("VmRSS:\tlots kB\n"), None);
    }

    #[test]
    fn cpu_time_sums_user_and_system_ticks_after_the_name() {
        let stat = "42 (a (b) c) S 1 42 42 0 -1 4194560 1 0 0 0 250 50 0 0 20 0 3 0";
        assert_eq!(cpu_ns_of_stat(stat, 100), Some(3_000_000_000));
        assert_eq!(cpu_ns_of_stat("42 (x) S 1 2", 100), None);
        assert_eq!(cpu_ns_of_stat("garbage", 100), None);
    }

    #[test]
    fn a_busy_thread_counts_in_this_process_and_an_absent_one_is_unknown() {
        use std::sync::atomic::{AtomicBool, Ordering};
        let me = read_proc(std::process::id());
        assert!(me.resident_bytes.is_some_and(|bytes| bytes > 0));
        let before = me.cpu_ns.expect("cpu time of this process");
        let stop = std::sync::Arc::new(AtomicBool::new(false));
        let busy = {
            let stop = stop.clone();
            std::thread::spawn(move || {
                let mut x = 0u64;
                while !stop.load(Ordering::Relaxed) {
                    x = std::hint::black_box(x.wrapping_add(1));
                }
            })
        };
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(20);
        let mut grew = false;
        while !grew && std::time::Instant::now() < deadline {
            std::thread::sleep(std::time::Duration::from_millis(50));
            grew = read_proc(std::process::id()).cpu_ns > Some(before);
        }
        stop.store(true, Ordering::Relaxed);
        busy.join().expect("busy thread");
        assert!(grew, "a spinning thread's time is not counted");
        let gone = read_proc(u32::MAX);
        assert_eq!((gone.cpu_ns, gone.resident_bytes), (None, None));
    }

    #[test]
    fn budgets_come_from_the_configuration_file_and_a_bad_one_gives_none() {
        let dir = std::env::temp_dir().join(format!("hopnav-top-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let good = dir.join("good.toml");
        std::fs::write(&good, "[processes.mapper]\nbudget_ms = 12.5\n").expect("write");
        let bad = dir.join("bad.toml");
        std::fs::write(&bad, "[processes.mapper\n").expect("write");
        assert_eq!(
            budgets(&good).and_then(|b| b.get("mapper").copied()),
            Some(12.5)
        );
        assert_eq!(budgets(&bad), None);
        assert_eq!(budgets(&dir.join("missing.toml")), None);
        std::fs::remove_dir_all(&dir).expect("cleanup");
    }
}
