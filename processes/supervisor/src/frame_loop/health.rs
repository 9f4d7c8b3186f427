//! The frame loop's view of its children's health: heartbeats, exits, the hang watchdog and
//! due restarts.

use super::*;

impl FrameLoop {
    pub(super) fn receive_heartbeats(&mut self, heartbeats: &Subscriber<Heartbeat>) {
        heartbeats.clear_events();
        while let Ok(Some(heartbeat)) = heartbeats.receive() {
            self.on_heartbeat(&heartbeat);
        }
    }

    pub(super) fn on_heartbeat(&mut self, heartbeat: &Heartbeat) {
        let slot_index = heartbeat.slot as usize;
        let Some(slot) = self.stats.slots.get_mut(slot_index) else {
            return;
        };
        let from_current = heartbeat.incarnation == slot.incarnation
            && slot
                .child
                .as_ref()
                .is_some_and(|child| child.pid() == heartbeat.pid);
        if !from_current {
            return; // a late heartbeat of a previous incarnation
        }
        slot.last_heartbeat = Instant::now();
        slot.record_rejected(heartbeat.rejected_samples);
        let restarted = slot.incarnation > 0
            && matches!(slot.phase, Phase::Starting { .. })
            && heartbeat.state() == Some(ProcessState::Ready);
        self.faults.on_alive(slot_index, Instant::now(), restarted);
        let Some(slot) = self.stats.slots.get_mut(slot_index) else {
            return;
        };
        match heartbeat.state() {
            Some(ProcessState::Ready) if matches!(slot.phase, Phase::Starting { .. }) => {
                slot.phase = Phase::Running;
                if restarted {
                    // Before its first release: hand the restarted process its last state.
                    for relays in self.relays.iter_mut().filter(|r| r.slot == slot_index) {
                        relays.relays.iter_mut().for_each(|relay| relay.hand_over());
                    }
                }
                let Some(slot) = self.stats.slots.get_mut(slot_index) else {
                    return;
                };
                let startup_s = heartbeat.processing_time_ns as f64 * 1e-9;
                slot.last_startup_s = Some(startup_s);
                let since_start = self.started.elapsed().as_secs_f64();
                if let Some(exit) = slot.exits.last_mut()
                    && exit.recovered_after_s.is_none()
                {
                    exit.recovered_after_s = Some((since_start - exit.at_s).max(0.0));
                    exit.startup_s = Some(startup_s);
                }
                let (releases, outcomes) = self.scheduler.set_live(slot_index, true);
                self.record_outcomes(&outcomes);
                self.release(&releases);
                if restarted {
                    // The promoted standby is in service: prepare the next one.
                    self.spawn_standby(slot_index);
                }
            }
            Some(ProcessState::Completed) => {
                if let Some(frame_index) = heartbeat.completed_frame() {
                    slot.record_cycle(heartbeat.processing_time_ns);
                    let (releases, outcomes) = self.scheduler.on_completed(
                        slot_index,
                        frame_index,
                        heartbeat.stamp.publish_stamp_ns,
                    );
                    self.record_outcomes(&outcomes);
                    self.release(&releases);
                }
            }
            _ => {}
        }
    }

    pub(super) fn reap_children(&mut self) {
        for slot in &mut self.stats.slots {
            // A standby that ended on its own (its `prepare` failed?) is not replaced: the
            // slot's restarts are cold from then on.
            if let Some(exit) = slot.standby.as_mut().and_then(ChildProcess::try_reap) {
                slot.standby = None;
                slot.standby_failed = true;
                eprintln!(
                    "\nthe standby of {} {exit}; its restarts will be cold",
                    slot.name
                );
            }
        }
        for slot_index in 0..self.stats.slots.len() {
            let slot = &mut self.stats.slots[slot_index];
            let Some(exit) = slot.child.as_mut().and_then(ChildProcess::try_reap) else {
                continue;
            };
            slot.child = None;
            let reason = match slot.killed_for_hang.take() {
                Some(why) => format!("hung ({why}), killed"),
                None => exit.to_string(),
            };
            self.faults.on_exit(slot_index, Instant::now(), &reason);
            let slot = &mut self.stats.slots[slot_index];
            slot.exits.push(ExitRecord {
                frame_index: self.next_frame.saturating_sub(1),
                at_s: self.started.elapsed().as_secs_f64(),
                reason: reason.clone(),
                recovered_after_s: None,
                restart: None,
                startup_s: None,
            });
            let name = slot.name.clone();
            let decision = slot.restarts.on_exit(&exit, Instant::now());
            let (releases, outcomes) = self.scheduler.set_live(slot_index, false);
            self.record_outcomes(&outcomes);
            self.release(&releases);
            // The dead node's ports count against the topics' limits until removed: one dead
            // and one new port fit every topic, so the restart need not wait for the clean-up.
            self.janitor.sweep();
            let slot = &mut self.stats.slots[slot_index];
            match decision {
                RestartDecision::RestartAfter(delay) => {
                    eprintln!("\n{name} {reason}; restarting in {} ms", delay.as_millis());
                    slot.phase = Phase::WaitingToRestart {
                        at: Instant::now() + delay,
                    };
                }
                RestartDecision::LeaveStopped => {
                    slot.phase = Phase::Stopped;
                    if self.config.run.lockstep {
                        self.stop = Some(LoopEnd::Stopped(format!(
                            "{name} {reason} and its restart policy is {:?}; lockstep cannot continue without it",
                            slot.config.restart
                        )));
                    } else {
                        eprintln!("\n{name} {reason}; left stopped by its restart policy");
                    }
                }
                RestartDecision::IntensityExceeded {
                    restarts_in_window,
                    window,
                } => {
                    slot.phase = Phase::Stopped;
                    self.stop = Some(LoopEnd::Stopped(format!(
                        "{name} {reason}: {restarts_in_window} restarts within {:.1} s exceed restart.max_restarts = {}",
                        window.as_secs_f64(),
                        self.config.restart.max_restarts
                    )));
                }
            }
        }
    }

    /// Kills processes that stopped heartbeating: after `watchdog.stall_timeout_frames` if
    /// they make no progress (stopped, or asleep without using CPU since the silence began),
    /// after `watchdog.heartbeat_timeout_frames` whatever they do, and after
    /// `run.startup_timeout_s` if they never got ready.
    pub(super) fn watchdog(&mut self, heartbeats: &Subscriber<Heartbeat>) {
        // Judge on fresh news: whatever the loop did since it last read heartbeats (reaping,
        // cleaning up a dead node) must not count as the children's silence.
        self.receive_heartbeats(heartbeats);
        let judged_at = Instant::now();
        let hung = self.hung_processes();
        if hung.is_empty() {
            return;
        }
        // A last look, without reading /proc again: a process that was asleep when judged and
        // has heartbeated since was only slow to be scheduled (or the supervisor was).
        self.receive_heartbeats(heartbeats);
        for (slot_index, why) in hung {
            let slot = &mut self.stats.slots[slot_index];
            if slot.last_heartbeat >= judged_at {
                continue;
            }
            if let Some(child) = slot.child.as_mut() {
                slot.hangs_detected += 1;
                slot.killed_for_hang = Some(why);
                child.kill();
            }
        }
    }

    /// The processes the watchdog finds hung now, with the reason.
    pub(super) fn hung_processes(&mut self) -> Vec<(usize, String)> {
        let mut hung = Vec::new();
        let period = self.period;
        let limits = SilenceLimits {
            period,
            stall: period.mul_f64(self.config.watchdog.stall_timeout_frames),
            hard_frames: self.config.watchdog.heartbeat_timeout_frames,
        };
        let startup_limit = Duration::from_secs_f64(self.config.run.startup_timeout_s);
        let now = Instant::now();
        for (slot_index, slot) in self.stats.slots.iter_mut().enumerate() {
            if slot.killed_for_hang.is_some() {
                continue; // killed already, waiting to be reaped
            }
            let Some(pid) = slot.child.as_ref().map(ChildProcess::pid) else {
                continue;
            };
            let silence = now.duration_since(slot.last_heartbeat);
            let why = match slot.phase {
                Phase::Starting { .. } if silence > startup_limit => Some(format!(
                    "not ready after {:.1} s (run.startup_timeout_s)",
                    silence.as_secs_f64()
                )),
                Phase::Running if silence > period => {
                    let progress = ProgressSample::read(pid);
                    let (baseline_cpu_time_ns, seen_at) = *slot
                        .silence_cpu_time_ns
                        .get_or_insert((progress.map_or(0, |sample| sample.cpu_time_ns), now));
                    let silence = Silence {
                        silent_for: silence,
                        watched_for: now.duration_since(seen_at),
                        baseline_cpu_time_ns,
                    };
                    hang_verdict(&limits, &silence, progress)
                }
                _ => {
                    slot.silence_cpu_time_ns = None;
                    None
                }
            };
            if let Some(why) = why {
                hung.push((slot_index, why));
            }
        }
        hung
    }

    pub(super) fn restart_due(&mut self) {
        let now = Instant::now();
        for slot_index in 0..self.stats.slots.len() {
            let slot = &mut self.stats.slots[slot_index];
            if let Phase::WaitingToRestart { at } = slot.phase
                && now >= at
            {
                slot.incarnation += 1;
                match self.restart(slot_index) {
                    Ok(how) => {
                        if let Some(exit) = self.stats.slots[slot_index].exits.last_mut() {
                            exit.restart = Some(how.to_owned());
                        }
                    }
                    Err(error) => self.stop = Some(LoopEnd::Stopped(error.to_string())),
                }
            }
        }
    }
}
