//! `hopnav top`'s bookkeeping: one row per process of a running launch, built from the
//! heartbeats it publishes and from what the kernel says of its OS process. Plain data, so it
//! is testable without a launch.

use std::collections::{BTreeMap, VecDeque};

use hopnav_ipc::messages::{Heartbeat, ProcessState};

use crate::text_table::align_columns;

/// What the kernel says of one OS process at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProcSample {
    /// CPU time the process has used so far (all its threads, exited ones too), nanoseconds.
    pub cpu_ns: Option<u64>,
    /// Resident memory, bytes.
    pub resident_bytes: Option<u64>,
}

/// One process of the launch as `top` knows it.
#[derive(Debug, Clone)]
struct ProcessRow {
    name: String,
    /// The name came from the process itself (else it is the slot's, and is asked again).
    identified: bool,
    pid: u32,
    incarnation: u32,
    state: u32,
    budget_ns: Option<u64>,
    last_heartbeat_ns: u64,
    /// `(arrival, processing time)` of the frames completed within the window.
    frames: VecDeque<(u64, u64)>,
    frames_seen: u64,
    over_budget: u64,
    /// The last kernel sample and when it was taken, for the CPU share between two.
    last_proc: Option<(u64, ProcSample)>,
    cpu_percent: Option<f64>,
    resident_bytes: Option<u64>,
}

/// Every process heard from, by slot.
#[derive(Debug, Clone)]
pub struct ProcessTable {
    window_ns: u64,
    silent_after_ns: u64,
    rows: BTreeMap<u32, ProcessRow>,
}

/// Who a heartbeat's sender is: its name and frame budget, looked up by pid.
pub trait Identify {
    /// Name and frame budget (nanoseconds) of OS process `pid`, if known.
    fn identify(&mut self, pid: u32) -> (Option<String>, Option<u64>);
}

impl ProcessTable {
    /// An empty table whose frame-time percentiles cover the last `window_ns`; a process
    /// without a heartbeat for `silent_after_ns` shows as silent, and its pid (which the
    /// system may give to another process) is no longer read.
    pub fn new(window_ns: u64, silent_after_ns: u64) -> Self {
        Self {
            window_ns,
            silent_after_ns,
            rows: BTreeMap::new(),
        }
    }

    /// A heartbeat arrived at `now_ns`. A new pid in a slot (a restart) starts its row anew
    /// but for the counts of budget misses, which belong to the slot.
    pub fn on_heartbeat(&mut self, heartbeat: &Heartbeat, now_ns: u64, who: &mut dyn Identify) {
        let row = self
            .rows
            .entry(heartbeat.slot)
            .or_insert_with(|| ProcessRow {
                name: String::new(),
                identified: false,
                pid: 0,
                incarnation: 0,
                state: heartbeat.state,
                budget_ns: None,
                last_heartbeat_ns: now_ns,
                frames: VecDeque::new(),
                frames_seen: 0,
                over_budget: 0,
                last_proc: None,
                cpu_percent: None,
                resident_bytes: None,
            });
        if row.pid != heartbeat.pid {
            row.pid = heartbeat.pid;
            row.identified = false;
            row.frames.clear();
            row.last_proc = None;
            row.cpu_percent = None;
        }
        if !row.identified {
            let (name, budget_ns) = who.identify(heartbeat.pid);
            row.identified = name.is_some();
            row.name = name.unwrap_or_else(|| format!("slot {}", heartbeat.slot));
            row.budget_ns = budget_ns;
        }
        row.incarnation = heartbeat.incarnation;
        row.state = heartbeat.state;
        row.last_heartbeat_ns = now_ns;
        if ProcessState::from_code(heartbeat.state) == Some(ProcessState::Completed) {
            row.frames.push_back((now_ns, heartbeat.processing_time_ns));
            row.frames_seen += 1;
            if row
                .budget_ns
                .is_some_and(|budget_ns| heartbeat.processing_time_ns > budget_ns)
            {
                row.over_budget += 1;
            }
        }
    }

    /// Takes a kernel sample of every process at `now_ns` (`sample` reads one pid) and
    /// forgets frames older than the window.
    pub fn refresh(&mut self, now_ns: u64, sample: &mut dyn FnMut(u32) -> ProcSample) {
        let oldest_kept_ns = now_ns.saturating_sub(self.window_ns);
        for row in self.rows.values_mut() {
            while row
                .frames
                .front()
                .is_some_and(|&(arrival_ns, _)| arrival_ns < oldest_kept_ns)
            {
                row.frames.pop_front();
            }
            if now_ns.saturating_sub(row.last_heartbeat_ns) > self.silent_after_ns {
                (row.last_proc, row.cpu_percent, row.resident_bytes) = (None, None, None);
                continue;
            }
            let current = sample(row.pid);
            row.resident_bytes = current.resident_bytes;
            row.cpu_percent = match (row.last_proc, current.cpu_ns) {
                (
                    Some((
                        then_ns,
                        ProcSample {
                            cpu_ns: Some(before),
                            ..
                        },
                    )),
                    Some(after),
                ) if now_ns > then_ns => {
                    Some(100.0 * after.saturating_sub(before) as f64 / (now_ns - then_ns) as f64)
                }
                _ => None,
            };
            row.last_proc = Some((now_ns, current));
        }
    }

    /// The table as printed: one line per process, columns aligned.
    pub fn render(&self, now_ns: u64) -> String {
        let mut lines = vec![
            [
                "PROCESS", "PID", "STATE", "CPU%", "RSS", "P50 MS", "P99 MS", "BUDGET", "OVER",
                "RESTARTS",
            ]
            .map(str::to_owned),
        ];
        for row in self.rows.values() {
            let mut times_ns: Vec<u64> = row.frames.iter().map(|&(_, time_ns)| time_ns).collect();
            times_ns.sort_unstable();
            let ms = |value: Option<u64>| {
                value.map_or("-".to_owned(), |ns| format!("{:.2}", ns as f64 * 1e-6))
            };
            let state = if now_ns.saturating_sub(row.last_heartbeat_ns) > self.silent_after_ns {
                "silent".to_owned()
            } else {
                state_name(row.state)
            };
            lines.push([
                row.name.clone(),
                row.pid.to_string(),
                state,
                row.cpu_percent
                    .map_or("-".to_owned(), |p| format!("{p:.1}")),
                row.resident_bytes
                    .map_or("-".to_owned(), |b| hopnav_ipc::live::human_bytes(b as f64)),
                ms(percentile(&times_ns, 0.5)),
                ms(percentile(&times_ns, 0.99)),
                ms(row.budget_ns),
                format!("{}/{}", row.over_budget, row.frames_seen),
                row.incarnation.to_string(),
            ]);
        }
        align_columns(&lines, |column| column == 1 || column > 2)
    }
}

/// The `q`-quantile of ascending `sorted` (nearest rank), `None` when empty.
fn percentile(sorted: &[u64], q: f64) -> Option<u64> {
    let last = sorted.len().checked_sub(1)?;
    let rank = ((q * sorted.len() as f64).ceil() as usize).clamp(1, last + 1) - 1;
    sorted.get(rank).copied()
}

fn state_name(code: u32) -> String {
    match ProcessState::from_code(code) {
        Some(ProcessState::Ready) => "ready",
        Some(ProcessState::Completed) => "running",
        Some(ProcessState::Idle) => "idle",
        Some(ProcessState::Stopping) => "stopping",
        None => "?",
    }
    .to_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    const MS: u64 = 1_000_000;

    struct Known;

    impl Identify for Known {
        fn identify(&mut self, pid: u32) -> (Option<String>, Option<u64>) {
            match pid {
                10 | 11 => (Some("mapper".to_owned()), Some(15 * MS)),
                _ => (None, None),
            }
        }
    }

    fn completed(slot: u32, pid: u32, incarnation: u32, time_ns: u64) -> Heartbeat {
        Heartbeat {
            slot,
            pid,
            incarnation,
            processing_time_ns: time_ns,
            state: ProcessState::Completed.code(),
            ..Heartbeat::default()
        }
    }

    fn row<'a>(table: &'a str, name: &str) -> Vec<&'a str> {
        table
            .lines()
            .find(|line| line.starts_with(name))
            .unwrap_or_else(|| panic!("no {name} in\n{table}"))
            .split_whitespace()
            .collect()
    }

    #[test]
    fn frame_times_give_percentiles_and_budget_misses() {
        let mut table = ProcessTable::new(10_000 * MS, 1_000 * MS);
        for i in 0..100 {
            let time_ns = if i == 7 { 20 * MS } else { (1 + i % 5) * MS };
            table.on_heartbeat(&completed(3, 10, 0, time_ns), i * 100 * MS, &mut Known);
        }
        let text = table.render(9_900 * MS);
        let mapper = row(&text, "mapper");
        assert_eq!(mapper[1..3], ["10", "running"], "{text}");
        assert_eq!(
            mapper[5..],
            ["3.00", "5.00", "15.00", "1/100", "0"],
            "{text}"
        );
    }

    #[test]
    fn a_restart_starts_the_row_anew_but_keeps_the_slots_misses() {
        let mut table = ProcessTable::new(10_000 * MS, 1_000 * MS);
        table.on_heartbeat(&completed(3, 10, 0, 30 * MS), 0, &mut Known);
        table.on_heartbeat(&completed(3, 11, 1, 2 * MS), 100 * MS, &mut Known);
        let text = table.render(200 * MS);
        let mapper = row(&text, "mapper");
        assert_eq!(mapper[1], "11");
        assert_eq!(mapper[5..], ["2.00", "2.00", "15.00", "1/2", "1"], "{text}");
    }

    #[test]
    fn cpu_share_comes_from_two_kernel_samples_and_silence_is_shown() {
        let mut table = ProcessTable::new(10_000 * MS, 1_000 * MS);
        let mut cpu_ns = 0;
        let mut sample = |_pid| {
            cpu_ns += 250 * MS;
            ProcSample {
                cpu_ns: Some(cpu_ns),
                resident_bytes: Some(3 * 1024 * 1024),
            }
        };
        table.on_heartbeat(&completed(0, 99, 0, MS), 0, &mut Known);
        table.refresh(500 * MS, &mut sample);
        table.on_heartbeat(&completed(0, 99, 0, MS), 1_000 * MS, &mut Known);
        table.refresh(1_500 * MS, &mut sample);
        let text = table.render(1_500 * MS);
        let unknown = row(&text, "slot 0");
        assert_eq!(unknown[2..6], ["99", "running", "25.0", "3.00"], "{text}");
        assert_eq!(unknown[9], "-", "no budget known: {text}");
        // Silent: its pid is no longer read (the system may have given it to another).
        table.refresh(3_000 * MS, &mut sample);
        let text = table.render(3_000 * MS);
        assert_eq!(row(&text, "slot 0")[3..5], ["silent", "-"], "{text}");
    }

    #[test]
    fn a_process_not_yet_identified_is_asked_again() {
        struct LateName(u32);
        impl Identify for LateName {
            fn identify(&mut self, _pid: u32) -> (Option<String>, Option<u64>) {
                self.0 += 1;
                match self.0 {
                    1 => (None, None),
                    _ => (Some("camera".to_owned()), Some(30 * MS)),
                }
            }
        }
        let mut table = ProcessTable::new(10_000 * MS, 1_000 * MS);
        let mut who = LateName(0);
        table.on_heartbeat(&completed(1, 7, 0, 40 * MS), 0, &mut who);
        assert!(table.render(0).contains("slot 1"));
        table.on_heartbeat(&completed(1, 7, 0, 40 * MS), 100 * MS, &mut who);
        let text = table.render(100 * MS);
        assert_eq!(row(&text, "camera")[7..9], ["30.00", "1/2"], "{text}");
        table.on_heartbeat(&completed(1, 7, 0, MS), 200 * MS, &mut who);
        assert_eq!(who.0, 2, "asked once more, then no longer");
    }

    #[test]
    fn old_frames_leave_the_window() {
        let mut table = ProcessTable::new(1_000 * MS, 1_000 * MS);
        table.on_heartbeat(&completed(3, 10, 0, 9 * MS), 0, &mut Known);
        table.on_heartbeat(&completed(3, 10, 0, MS), 5_000 * MS, &mut Known);
        table.refresh(5_000 * MS, &mut |_| ProcSample {
            cpu_ns: None,
            resident_bytes: None,
        });
        let text = table.render(5_000 * MS);
        let mapper = row(&text, "mapper");
        assert_eq!(mapper[5..7], ["1.00", "1.00"]);
        assert_eq!(percentile(&[], 0.5), None);
    }
}
