//! Executes the supervisor's share of injected faults (kills and stalls at a frame) and keeps
//! the record of each fault: when it fired, when the supervisor detected it, when the process
//! was back. Drops, corruption and delays run inside the target (see `hopnav_ipc::fault`).

use std::time::Instant;

use hopnav_config::fault::{FaultKind, FaultSpec};
use serde::Serialize;

/// What became of one fault.
#[derive(Debug, Clone, Serialize)]
pub struct FaultRecord {
    /// The specification.
    pub fault: String,
    /// Target process.
    pub process: String,
    /// Frame at which it fired (kills and stalls).
    pub injected_frame: Option<u64>,
    /// Seconds after the launch started at which it fired.
    pub injected_at_s: Option<f64>,
    /// Seconds from firing to the supervisor noticing (exit reaped or hang detected).
    pub detected_after_s: Option<f64>,
    /// Seconds from firing to the process working again (ready after a restart, or its
    /// first heartbeat after a stall).
    pub recovered_after_s: Option<f64>,
    /// Frame during which the process was working again (for kills and stalls): frames from
    /// `injected_frame` to here are the fault's downtime in simulated time.
    pub recovered_frame: Option<u64>,
    /// What happened, in words.
    pub effect: String,
}

/// What the frame loop must do now.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FaultAction {
    /// SIGKILL the slot's process.
    Kill(usize),
    /// SIGSTOP it.
    Stop(usize),
    /// SIGCONT it.
    Continue(usize),
}

#[derive(Debug)]
struct Scheduled {
    slot: usize,
    frame: u64,
    kind: FaultKind,
    record: usize,
}

#[derive(Debug)]
struct Stall {
    slot: usize,
    resume_at: Instant,
    record: usize,
}

/// The faults of one launch.
#[derive(Debug, Default)]
pub struct FaultInjector {
    scheduled: Vec<Scheduled>,
    stalls: Vec<Stall>,
    /// Fired faults waiting for detection or recovery: (slot, record, fired at).
    open: Vec<(usize, usize, Instant)>,
    records: Vec<FaultRecord>,
    /// The frame the launch is in (the last `on_frame_start`).
    frame_index: u64,
}

impl FaultInjector {
    /// Plans `specs`; `slot_of` maps a process name to its slot (None = not in the graph).
    pub fn new(
        specs: &[FaultSpec],
        frame_rate_hz: f64,
        slot_of: impl Fn(&str) -> Option<usize>,
    ) -> Result<Self, String> {
        let mut injector = Self::default();
        for spec in specs {
            let slot = slot_of(&spec.process).ok_or_else(|| {
                format!(
                    "fault {:?} targets {:?}, which is not an enabled process of this launch",
                    spec.text, spec.process
                )
            })?;
            let record = injector.records.len();
            let in_process = matches!(
                spec.kind,
                FaultKind::Drop { .. } | FaultKind::Corrupt { .. } | FaultKind::Delay { .. }
            );
            injector.records.push(FaultRecord {
                fault: spec.text.clone(),
                process: spec.process.clone(),
                injected_frame: None,
                injected_at_s: None,
                detected_after_s: None,
                recovered_after_s: None,
                recovered_frame: None,
                effect: match spec.kind {
                    FaultKind::Drop { percent } => format!(
                        "the publisher dropped ~{percent}% of its samples all launch; consumers bridge the gaps"
                    ),
                    FaultKind::Corrupt { percent } => format!(
                        "~{percent}% of the samples went out with garbled headers all launch; see the consumers' rejected counts"
                    ),
                    FaultKind::Delay { delay_ms } => format!(
                        "every step started {delay_ms} ms late all launch; see its cycle times and budget misses"
                    ),
                    FaultKind::Kill | FaultKind::Stall { .. } => {
                        "not fired (the launch ended first)".into()
                    }
                },
            });
            if let (Some(at), false) = (spec.at, in_process) {
                injector.scheduled.push(Scheduled {
                    slot,
                    frame: at.frame(frame_rate_hz),
                    kind: spec.kind,
                    record,
                });
            }
        }
        Ok(injector)
    }

    /// Actions due when frame `frame_index` starts.
    pub fn on_frame_start(
        &mut self,
        frame_index: u64,
        now: Instant,
        since_start_s: f64,
        actions: &mut Vec<FaultAction>,
    ) {
        self.frame_index = frame_index;
        let mut index = 0;
        while index < self.scheduled.len() {
            if self.scheduled[index].frame > frame_index {
                index += 1;
                continue;
            }
            let due = self.scheduled.swap_remove(index);
            let record = &mut self.records[due.record];
            record.injected_frame = Some(frame_index);
            record.injected_at_s = Some(since_start_s);
            match due.kind {
                FaultKind::Kill => {
                    record.effect = "SIGKILL sent".into();
                    actions.push(FaultAction::Kill(due.slot));
                }
                FaultKind::Stall { duration_ms } => {
                    record.effect = format!("SIGSTOP for {duration_ms} ms");
                    actions.push(FaultAction::Stop(due.slot));
                    self.stalls.push(Stall {
                        slot: due.slot,
                        resume_at: now + std::time::Duration::from_millis(duration_ms),
                        record: due.record,
                    });
                }
                _ => {}
            }
            self.open.push((due.slot, due.record, now));
        }
    }

    /// Stalls whose time is up.
    pub fn due_resumes(&mut self, now: Instant, actions: &mut Vec<FaultAction>) {
        self.stalls.retain(|stall| {
            if now >= stall.resume_at {
                actions.push(FaultAction::Continue(stall.slot));
                false
            } else {
                true
            }
        });
    }

    /// The process in `slot` exited (or was killed as hung) at `now`.
    pub fn on_exit(&mut self, slot: usize, now: Instant, reason: &str) {
        for (open_slot, record, fired) in &self.open {
            let entry = &mut self.records[*record];
            if *open_slot == slot && entry.detected_after_s.is_none() {
                entry.detected_after_s = Some(now.duration_since(*fired).as_secs_f64());
                entry.effect = format!("{}; detected: {reason}", entry.effect);
            }
        }
        // A stalled process that was killed needs no SIGCONT.
        self.stalls.retain(|stall| stall.slot != slot);
    }

    /// The process in `slot` reported ready after a restart, or heartbeated after a stall.
    pub fn on_alive(&mut self, slot: usize, now: Instant, restarted: bool) {
        let stalls = &self.stalls;
        let frame_index = self.frame_index;
        self.open.retain(|(open_slot, record, fired)| {
            if *open_slot != slot || stalls.iter().any(|stall| stall.record == *record) {
                return true;
            }
            let entry = &mut self.records[*record];
            // A kill is only recovered by a restart; a stall by any sign of life.
            let is_kill = entry.fault.starts_with("kill:");
            if is_kill && !restarted {
                return true;
            }
            entry.recovered_after_s = Some(now.duration_since(*fired).as_secs_f64());
            entry.recovered_frame = Some(frame_index);
            entry.effect = format!(
                "{}; recovered: {}",
                entry.effect,
                if restarted {
                    "restarted and ready"
                } else {
                    "resumed heartbeats"
                }
            );
            false
        });
    }

    /// True while some stall still has to be resumed.
    pub fn has_pending_resume(&self) -> bool {
        !self.stalls.is_empty()
    }

    /// The records, for the report.
    pub fn into_records(self) -> Vec<FaultRecord> {
        self.records
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn specs(texts: &[&str]) -> Vec<FaultSpec> {
        texts.iter().map(|text| text.parse().unwrap()).collect()
    }

    #[test]
    fn a_kill_fires_at_its_frame_and_records_detection_and_recovery() {
        let slot_of = |name: &str| (name == "camera").then_some(1);
        let mut injector = FaultInjector::new(&specs(&["kill:camera@2s"]), 10.0, slot_of).unwrap();
        let start = Instant::now();
        let mut actions = Vec::new();
        injector.on_frame_start(19, start, 1.9, &mut actions);
        assert!(actions.is_empty());
        injector.on_frame_start(20, start, 2.0, &mut actions);
        assert_eq!(actions, vec![FaultAction::Kill(1)]);
        injector.on_alive(1, start, false); // a late heartbeat is not a recovery
        injector.on_exit(
            1,
            start + std::time::Duration::from_millis(5),
            "killed by signal 9",
        );
        injector.on_frame_start(22, start, 2.2, &mut actions);
        injector.on_alive(1, start + std::time::Duration::from_millis(300), true);
        let records = injector.into_records();
        assert_eq!(records[0].injected_frame, Some(20));
        assert_eq!(records[0].recovered_frame, Some(22));
        assert!((records[0].detected_after_s.unwrap() - 0.005).abs() < 1e-6);
        assert!((records[0].recovered_after_s.unwrap() - 0.3).abs() < 1e-6);
    }

    #[test]
    fn a_stall_resumes_after_its_duration() {
        let mut injector =
            FaultInjector::new(&specs(&["stall:mapper@f3+500ms"]), 10.0, |_| Some(0)).unwrap();
        let start = Instant::now();
        let mut actions = Vec::new();
        injector.on_frame_start(3, start, 0.3, &mut actions);
        assert_eq!(actions, vec![FaultAction::Stop(0)]);
        actions.clear();
        injector.due_resumes(start + std::time::Duration::from_millis(499), &mut actions);
        assert!(actions.is_empty());
        injector.due_resumes(start + std::time::Duration::from_millis(500), &mut actions);
        assert_eq!(actions, vec![FaultAction::Continue(0)]);
        injector.on_alive(0, start + std::time::Duration::from_millis(520), false);
        assert!(injector.into_records()[0].recovered_after_s.is_some());
    }

    #[test]
    fn unknown_targets_are_refused() {
        let error = FaultInjector::new(&specs(&["kill:mapper@1s"]), 10.0, |_| None).unwrap_err();
        assert!(error.contains("not an enabled process"), "{error}");
    }
}
