//! The run report: `report.json` for tools, a table for people.

use std::io::Write;
use std::path::Path;

use hopnav_ipc::latency::LatencySummary;
use serde::Serialize;

/// One process in the report.
#[derive(Debug, Clone, Serialize)]
pub struct ProcessReport {
    /// Process name.
    pub name: String,
    /// Pipeline stage.
    pub stage: u32,
    /// Budget per frame, ms.
    pub budget_ms: f64,
    /// Time spent in `step` per frame.
    pub cycle_time: LatencySummary,
    /// Frames over budget.
    pub budget_misses: u64,
    /// Frames completed (all incarnations).
    pub frames_completed: u64,
    /// Restarts.
    pub restarts: u32,
    /// Exits observed before shutdown, with their reason.
    pub exits: Vec<ExitRecord>,
    /// Times the watchdog found it silent and killed it.
    pub hangs_detected: u32,
    /// Samples it rejected (last value it reported).
    pub rejected_samples: u64,
}

/// An unplanned exit of a process.
#[derive(Debug, Clone, Serialize)]
pub struct ExitRecord {
    /// Frame the supervisor had started when the exit was seen.
    pub frame_index: u64,
    /// Seconds since launch start.
    pub at_s: f64,
    /// How it ended.
    pub reason: String,
    /// Seconds from the exit to the restarted process reporting ready, if it came back.
    pub recovered_after_s: Option<f64>,
    /// How it came back: `standby` (a prepared standby was promoted) or `cold` (a new
    /// process started from scratch).
    pub restart: Option<String>,
    /// The start-up time the restarted process itself reported (from exec, or from its
    /// promotion, to ready), s.
    pub startup_s: Option<f64>,
}

/// The whole run.
#[derive(Debug, Clone, Serialize)]
pub struct RunReport {
    /// Run id (also the folder name and the iceoryx2 namespace).
    pub run_id: String,
    /// `lockstep` or `real-time`.
    pub mode: String,
    /// How the launch ended: `completed`, `interrupted` or `stopped: <reason>`.
    pub outcome: String,
    /// Frames asked for.
    pub frames_requested: u64,
    /// Frames every stage finished.
    pub frames_completed: u64,
    /// Frames finished with a process down or skipping it.
    pub frames_degraded: u64,
    /// Frames given up on (real time only).
    pub frames_abandoned: u64,
    /// Nominal frame period, ms.
    pub frame_period_ms: f64,
    /// Wall-clock duration of the frame loop, s.
    pub wall_time_s: f64,
    /// Tick of frame k to the last stage finishing frame k.
    pub end_to_end_latency: LatencySummary,
    /// Frames whose end-to-end latency exceeded the frame period.
    pub end_to_end_misses: u64,
    /// Per process.
    pub processes: Vec<ProcessReport>,
    /// Stale resources of dead earlier launches removed at start.
    pub stale_runs_cleaned: Vec<String>,
    /// Files of this launch's namespace left after shutdown (0 unless something leaked).
    pub leftover_files: usize,
    /// Injected faults and what became of them.
    pub faults: Vec<crate::fault_injector::FaultRecord>,
    /// The mission outcome (absent when the graph has no planner).
    pub mission: Option<crate::mission_report::MissionReport>,
    /// The Fig.-6 map of the mission, if one was drawn.
    pub mission_figure: Option<String>,
    /// The evaluator's summary lines (its figures are in `mission`).
    #[serde(skip)]
    pub evaluation_summary: Vec<String>,
    /// The configuration used.
    pub config: serde_json::Value,
}

impl RunReport {
    /// Writes `report.json` into `run_dir`.
    pub fn write_json(&self, run_dir: &Path) -> std::io::Result<()> {
        let text = serde_json::to_string_pretty(self).map_err(std::io::Error::other)?;
        std::fs::write(run_dir.join("report.json"), text)
    }

    /// Prints the human summary.
    pub fn print_summary(&self, out: &mut impl Write) -> std::io::Result<()> {
        writeln!(
            out,
            "\nrun {}: {} ({} mode) — {}/{} frames in {:.1} s, {} degraded, {} abandoned",
            self.run_id,
            self.outcome,
            self.mode,
            self.frames_completed,
            self.frames_requested,
            self.wall_time_s,
            self.frames_degraded,
            self.frames_abandoned
        )?;
        writeln!(
            out,
            "end-to-end latency: p50 {:.3} ms, p99 {:.3} ms, max {:.3} ms; {} misses of the {:.0} ms frame",
            self.end_to_end_latency.p50_ms,
            self.end_to_end_latency.p99_ms,
            self.end_to_end_latency.max_ms,
            self.end_to_end_misses,
            self.frame_period_ms
        )?;
        writeln!(
            out,
            "{:<14} {:>5} {:>9} {:>9} {:>9} {:>9} {:>7} {:>8} {:>6} {:>8}",
            "process",
            "stage",
            "budget",
            "p50 ms",
            "p99 ms",
            "max ms",
            "misses",
            "restarts",
            "hangs",
            "rejected"
        )?;
        for process in &self.processes {
            writeln!(
                out,
                "{:<14} {:>5} {:>9.1} {:>9.3} {:>9.3} {:>9.3} {:>7} {:>8} {:>6} {:>8}",
                process.name,
                process.stage,
                process.budget_ms,
                process.cycle_time.p50_ms,
                process.cycle_time.p99_ms,
                process.cycle_time.max_ms,
                process.budget_misses,
                process.restarts,
                process.hangs_detected,
                process.rejected_samples
            )?;
        }
        for fault in &self.faults {
            let seconds =
                |value: Option<f64>| value.map_or("-".to_owned(), |s| format!("{:.0} ms", s * 1e3));
            writeln!(
                out,
                "fault {:<28} frame {:>5}  detected after {:>8}  recovered after {:>8}  {}",
                fault.fault,
                fault
                    .injected_frame
                    .map_or("-".to_owned(), |frame| frame.to_string()),
                seconds(fault.detected_after_s),
                seconds(fault.recovered_after_s),
                fault.effect
            )?;
        }
        if let Some(mission) = &self.mission {
            mission.print(out)?;
        }
        for line in &self.evaluation_summary {
            writeln!(out, "{line}")?;
        }
        if let Some(figure) = &self.mission_figure {
            writeln!(out, "map figure: {figure}")?;
        }
        Ok(())
    }
}
