//! The frame loop's children: spawning, warm standbys, restarts and shutdown.

use super::*;

impl FrameLoop {
    /// The in-process faults of `slot_index`'s current incarnation, `HOPNAV_FAULTS` format.
    pub(super) fn faults_env(&self, slot_index: usize) -> Option<String> {
        let slot = &self.stats.slots[slot_index];
        let own: Vec<_> = self
            .fault_specs
            .iter()
            .filter(|spec| spec.process == slot.name)
            .cloned()
            .collect();
        hopnav_ipc::fault::encode_env(self.config.faults.seed, slot.incarnation, &own)
    }

    pub(super) fn child_spec(&self, slot_index: usize, standby: bool) -> ChildSpec<'_> {
        let slot = &self.stats.slots[slot_index];
        ChildSpec {
            faults_env: if standby {
                None
            } else {
                self.faults_env(slot_index)
            },
            executable: &self.executable,
            name: &slot.name,
            run_id: self.namespace.run_id(),
            slot: slot_index,
            incarnation: slot.incarnation,
            config_path: &self.config_path,
            heartbeat_period_ms: (self.period.as_millis() as u64).max(1),
            standby,
        }
    }

    /// Starts the current incarnation of `slot_index` from scratch.
    pub(super) fn spawn(&mut self, slot_index: usize) -> Result<(), LaunchError> {
        let child = ChildProcess::spawn(&self.child_spec(slot_index, false)).map_err(|source| {
            LaunchError::Spawn {
                name: self.stats.slots[slot_index].name.clone(),
                source,
            }
        })?;
        self.stats.slots[slot_index].child = Some(child);
        self.begin_starting(slot_index);
        Ok(())
    }

    pub(super) fn begin_starting(&mut self, slot_index: usize) {
        let slot = &mut self.stats.slots[slot_index];
        slot.begin_incarnation();
        slot.phase = Phase::Starting {
            since: Instant::now(),
        };
        slot.last_heartbeat = Instant::now();
        slot.silence_cpu_time_ns = None;
    }

    /// Starts a warm standby for `slot_index` if it may have one and has none.
    pub(super) fn spawn_standby(&mut self, slot_index: usize) {
        let slot = &self.stats.slots[slot_index];
        let wanted = self.config.restart.warm_standby
            && slot.config.restart != hopnav_config::RestartPolicy::Never
            && slot.standby.is_none()
            && !slot.standby_failed
            && self.stop.is_none();
        if !wanted {
            return;
        }
        match ChildProcess::spawn(&self.child_spec(slot_index, true)) {
            Ok(child) => self.stats.slots[slot_index].standby = Some(child),
            Err(error) => self.give_up_standby(
                slot_index,
                "start a standby",
                &error,
                "its restarts will be cold",
            ),
        }
    }

    /// Marks `slot_index` as one that gets no more standbys (its restarts are cold) and says
    /// why: `cannot {what} of NAME: {error}; {consequence}`.
    fn give_up_standby(
        &mut self,
        slot_index: usize,
        what: &str,
        error: &dyn std::fmt::Display,
        consequence: &str,
    ) {
        let slot = &mut self.stats.slots[slot_index];
        slot.standby_failed = true;
        eprintln!("\ncannot {what} of {}: {error}; {consequence}", slot.name);
    }

    /// Restarts `slot_index` (its incarnation already counted up): promotes its standby if
    /// it has one, else starts it cold. Returns how.
    pub(super) fn restart(&mut self, slot_index: usize) -> Result<&'static str, LaunchError> {
        if let Some(mut standby) = self.stats.slots[slot_index].standby.take() {
            let how = if standby.is_prepared() {
                "standby"
            } else {
                "standby (still preparing)"
            };
            let promotion = Promotion {
                incarnation: self.stats.slots[slot_index].incarnation,
                faults: self.faults_env(slot_index),
            };
            match standby.promote(&promotion) {
                Ok(()) => {
                    self.stats.slots[slot_index].child = Some(standby);
                    self.begin_starting(slot_index);
                    return Ok(how);
                }
                Err(error) => {
                    self.give_up_standby(
                        slot_index,
                        "promote the standby",
                        &error,
                        "starting it cold",
                    );
                    standby.kill_and_reap();
                }
            }
        }
        self.spawn(slot_index).map(|()| "cold")
    }

    /// Spawns every process and waits until all report ready.
    pub fn start_all(
        &mut self,
        heartbeats: &Subscriber<Heartbeat>,
        waitset: &WaitSet<IpcService>,
    ) -> Result<(), LaunchError> {
        for slot_index in 0..self.stats.slots.len() {
            self.spawn(slot_index)?;
        }
        let timeout = Duration::from_secs_f64(self.config.run.startup_timeout_s);
        let deadline = Instant::now() + timeout;
        loop {
            self.receive_heartbeats(heartbeats);
            for slot in &mut self.stats.slots {
                if let Some(exit) = slot.child.as_mut().and_then(ChildProcess::try_reap) {
                    slot.child = None;
                    return Err(LaunchError::DiedAtStartup {
                        name: slot.name.clone(),
                        reason: exit.to_string(),
                    });
                }
            }
            let waiting: Vec<&str> = self
                .stats
                .slots
                .iter()
                .filter(|slot| matches!(slot.phase, Phase::Starting { .. }))
                .map(|slot| slot.name.as_str())
                .collect();
            if waiting.is_empty() {
                break;
            }
            if Instant::now() >= deadline {
                return Err(LaunchError::StartupTimeout {
                    names: waiting.join(", "),
                    timeout_s: self.config.run.startup_timeout_s,
                });
            }
            match waitset
                .wait_and_process_once_with_timeout(|_| CallbackProgression::Continue, HOUSEKEEPING)
            {
                Ok(WaitSetRunResult::TerminationRequest) => return Err(LaunchError::Interrupted),
                // A signal that only cut the wait short; termination shows up on the next wait.
                Ok(WaitSetRunResult::Interrupt) => continue,
                Ok(_) => {}
                Err(error) => return Err(LaunchError::Wait(format!("{error:?}"))),
            }
        }
        // The graph is up: now prepare the standbys (at idle priority) for quick restarts.
        for slot_index in 0..self.stats.slots.len() {
            self.spawn_standby(slot_index);
        }
        if self.config.run.lockstep {
            // Lockstep is about reproducible runs, not wall time: let the standbys finish
            // preparing first, so a restart at any frame is as quick as at any other.
            self.wait_for_standbys(heartbeats, waitset, Instant::now() + timeout)?;
        }
        self.started = Instant::now();
        Ok(())
    }

    /// Waits until every standby has prepared (or died, or the start-up deadline passed).
    pub(super) fn wait_for_standbys(
        &mut self,
        heartbeats: &Subscriber<Heartbeat>,
        waitset: &WaitSet<IpcService>,
        deadline: Instant,
    ) -> Result<(), LaunchError> {
        loop {
            self.receive_heartbeats(heartbeats);
            let mut waiting = Vec::new();
            for slot in &mut self.stats.slots {
                let Some(standby) = slot.standby.as_mut() else {
                    continue;
                };
                if let Some(exit) = standby.try_reap() {
                    slot.standby = None;
                    slot.standby_failed = true;
                    eprintln!(
                        "the standby of {} {exit}; its restarts will be cold",
                        slot.name
                    );
                } else if !standby.is_prepared() {
                    waiting.push(slot.name.clone());
                }
            }
            if waiting.is_empty() {
                return Ok(());
            }
            if Instant::now() >= deadline {
                eprintln!(
                    "standbys still preparing after run.startup_timeout_s: {}",
                    waiting.join(", ")
                );
                return Ok(());
            }
            match waitset
                .wait_and_process_once_with_timeout(|_| CallbackProgression::Continue, HOUSEKEEPING)
            {
                Ok(WaitSetRunResult::TerminationRequest) => return Err(LaunchError::Interrupted),
                Ok(_) => {}
                Err(error) => return Err(LaunchError::Wait(format!("{error:?}"))),
            }
        }
    }

    /// Asks every process to stop, waits for the grace period, then kills what is left.
    pub fn shutdown(&mut self) {
        self.status.finish();
        // Standbys end cleanly when their stdin closes (once prepared); the rest are killed.
        let mut standbys: Vec<ChildProcess> = self
            .stats
            .slots
            .iter_mut()
            .filter_map(|slot| slot.standby.take())
            .collect();
        standbys.iter_mut().for_each(ChildProcess::retire);
        let deadline = Instant::now() + Duration::from_millis(500);
        while !standbys.is_empty() && Instant::now() < deadline {
            standbys.retain_mut(|standby| standby.try_reap().is_none());
            std::thread::sleep(Duration::from_millis(2));
        }
        standbys.into_iter().for_each(ChildProcess::kill_and_reap);
        for (slot_index, publisher) in self.step_publishers.iter_mut().enumerate() {
            if self.stats.slots[slot_index].child.is_some() {
                let _ = publisher.send_with(|tick| {
                    tick.command = FrameCommand::Shutdown.code();
                    tick.mode = ClockMode::Lockstep.code();
                });
            }
        }
        let grace = Duration::from_secs_f64(self.config.run.shutdown_timeout_s);
        if !self.wait_for_exits(grace) {
            for slot in &mut self.stats.slots {
                if let Some(child) = slot.child.as_ref() {
                    eprintln!(
                        "{} did not stop within {:.1} s; sending SIGTERM",
                        slot.name,
                        grace.as_secs_f64()
                    );
                    child.terminate();
                }
            }
            if !self.wait_for_exits(Duration::from_secs(1)) {
                for slot in &mut self.stats.slots {
                    if let Some(child) = slot.child.as_mut() {
                        eprintln!("{} ignored SIGTERM; killing it", slot.name);
                        child.kill();
                    }
                }
                self.wait_for_exits(Duration::from_secs(5));
            }
        }
        for slot in &mut self.stats.slots {
            if !matches!(slot.phase, Phase::Stopped) {
                slot.phase = Phase::Stopped;
            }
        }
    }

    pub(super) fn wait_for_exits(&mut self, limit: Duration) -> bool {
        let deadline = Instant::now() + limit;
        loop {
            for slot in &mut self.stats.slots {
                if slot
                    .child
                    .as_mut()
                    .and_then(ChildProcess::try_reap)
                    .is_some()
                {
                    slot.child = None;
                }
            }
            if self.stats.slots.iter().all(|slot| slot.child.is_none()) {
                return true;
            }
            if Instant::now() >= deadline {
                return false;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
    }
}
