//! The shape of the configuration. Unknown keys are errors, so a typo never goes unnoticed.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

/// The whole configuration of a launch.
///
/// The runtime's own tables are typed here. Every other top-level table (`[world]`,
/// `[physics]`, `[camera]`, …) belongs to one process library and is kept as TOML in
/// [`Self::sections`]; that library parses it with [`crate::parse_section`], and the launcher
/// validates every section at start and rejects tables nobody knows.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HopnavConfig {
    /// Frame clock and launch length.
    pub run: RunConfig,
    /// Hang detection.
    pub watchdog: WatchdogConfig,
    /// Restart intensity and backoff.
    pub restart: RestartConfig,
    /// The process graph: name → settings.
    pub processes: BTreeMap<String, ProcessConfig>,
    /// The latency probe graph.
    pub probe: ProbeConfig,
    /// The recorder (`--export-dataset`, `--record`).
    pub recorder: RecorderConfig,
    /// What the mission is: cooperative or rover-only, and when it ends.
    pub mission: MissionConfig,
    /// Faults to inject.
    #[serde(default)]
    pub faults: crate::fault::FaultsConfig,
    /// Process-specific tables, parsed by their own libraries.
    #[serde(flatten)]
    pub sections: toml::Table,
}

/// Frame clock and launch length.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunConfig {
    /// Frames per second of the real-time core.
    pub frame_rate_hz: f64,
    /// Frames per launch.
    pub frames: u64,
    /// Lockstep instead of wall-clock pacing.
    pub lockstep: bool,
    /// Time allowed for every process to report ready.
    pub startup_timeout_s: f64,
    /// Grace period for processes to exit after shutdown.
    pub shutdown_timeout_s: f64,
    /// Where run folders are created.
    pub out_dir: String,
}

impl RunConfig {
    /// The frame period in seconds.
    pub fn frame_period_s(&self) -> f64 {
        1.0 / self.frame_rate_hz
    }
}

/// Hang detection.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WatchdogConfig {
    /// Frame periods without a heartbeat before a process counts as hung, whatever it does
    /// (a step that runs away while using CPU).
    pub heartbeat_timeout_frames: u32,
    /// Frame periods without a heartbeat before a process that makes no progress (stopped,
    /// or asleep without using CPU) counts as hung. Processes heartbeat every period.
    pub stall_timeout_frames: f64,
}

/// Restart intensity and backoff, per process.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RestartConfig {
    /// Restarts allowed within `window_s`; one more stops the launch.
    pub max_restarts: u32,
    /// Sliding window for counting restarts.
    pub window_s: f64,
    /// First backoff delay.
    pub backoff_initial_ms: u64,
    /// Largest backoff delay.
    pub backoff_max_ms: u64,
    /// Keep a prepared standby of every restartable process, promoted on a restart.
    pub warm_standby: bool,
}

/// When a process that exited is started again.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RestartPolicy {
    /// Never restart; the launch continues without it (real time) or stops (lockstep).
    Never,
    /// Restart after a crash, a non-zero exit or a hang.
    OnFailure,
    /// Restart whenever it exits before shutdown, even cleanly.
    Always,
}

/// One process of the graph.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProcessConfig {
    /// Launch it.
    #[serde(default = "enabled_by_default")]
    pub enabled: bool,
    /// Position in the frame pipeline (0 runs first).
    pub stage: u32,
    /// Time one frame may take in this process.
    pub budget_ms: f64,
    /// Restart policy.
    pub restart: RestartPolicy,
}

fn enabled_by_default() -> bool {
    true
}

/// The latency probe graph.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProbeConfig {
    /// Width of the probe image, pixels.
    pub width_px: u32,
    /// Height of the probe image, pixels.
    pub height_px: u32,
}

/// The recorder: a dataset folder, an MCAP recording, or both.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RecorderConfig {
    /// Dataset folder (`--export-dataset`); empty for none.
    pub dir: String,
    /// MCAP file of every topic (`--record`); empty for none. One of `dir` and `mcap` is
    /// required when `processes.recorder.enabled`.
    pub mcap: String,
    /// Also write the images, clouds, robot frames, map snapshots and path into the MCAP file
    /// as Foxglove's well-known messages (so it opens in Foxglove); about doubles its size.
    pub foxglove: bool,
    /// Record the camera images (hopnav's image channels and their Foxglove RawImages) into
    /// the MCAP file. They are almost all of its size (250 KiB a frame, twice with Foxglove
    /// channels); `false` keeps the poses, clouds, map and path of a long mission small. The
    /// dataset folder (`dir`) keeps its images either way.
    pub images: bool,
    /// Address (IP:PORT) on which to serve the Foxglove channels live over the Foxglove
    /// WebSocket protocol (`--viewer`), for Foxglove to show a running launch; empty for none.
    /// Only this machine (`127.0.0.1:8765`) unless another address is given on purpose.
    pub viewer: String,
}

/// Who explores: both robots, or the rover alone (the baseline the paper compares against).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MissionMode {
    /// The rover asks the jumper to hop ahead and map what it cannot see.
    Cooperative,
    /// The jumper stays put; the rover maps with its own stereo camera only.
    RoverOnly,
}

impl MissionMode {
    /// The name used in config files and reports.
    pub fn name(self) -> &'static str {
        match self {
            MissionMode::Cooperative => "cooperative",
            MissionMode::RoverOnly => "rover-only",
        }
    }
}

/// The mission: from the world scenario's start A to its goal B.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MissionConfig {
    /// Cooperative or rover-only.
    pub mode: MissionMode,
    /// End the launch when the planner reports the goal reached (else run every frame).
    pub stop_on_goal: bool,
}
