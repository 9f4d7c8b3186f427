//! A faulted mission judged against the same launch without faults (`hopnav chaos`): did the
//! rover still reach B, and what did the faults cost in path and time.
//!
//! Time is counted in simulated frames. A fault that takes a process down costs the frames
//! from its injection to its recovery (`FaultRecord::recovered_frame`); the faulted mission
//! is allowed the unfaulted mission's frames plus that downtime, so "B not reached in time"
//! means work the recovery lost, not a short clock.

use hopnav_supervisor::fault_injector::FaultRecord;
use serde::Serialize;

/// The mission outcome of one launch, as the chaos table needs it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MissionOutcome {
    /// The planner reported B reached.
    pub goal_reached: bool,
    /// Simulated frames to B (or to the end of the launch).
    pub frames: u64,
    /// Distance the rover really drove, metres.
    pub executed_path_m: f64,
}

/// Verdict on a faulted mission.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// B reached within the unfaulted frames plus the faults' downtime.
    Reached,
    /// B reached, but later than that allowance.
    ReachedLate,
    /// B not reached.
    Lost,
    /// The unfaulted mission did not reach B itself: nothing to judge against.
    NoReference,
}

/// A faulted mission against its unfaulted reference.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FaultedMission {
    /// The faulted launch's own outcome.
    pub outcome: MissionOutcome,
    /// Frames the faults kept a process down (injection to recovery, summed over faults;
    /// a fault never recovered counts to the end of the launch).
    pub downtime_frames: u64,
    /// Frames the mission was allowed: the unfaulted frames plus the downtime.
    pub allowed_frames: Option<u64>,
    /// Executed path / the unfaulted run's − 1 (B reached in both).
    pub path_excess: Option<f64>,
    /// Frames to B / the unfaulted run's − 1 (B reached in both).
    pub time_excess: Option<f64>,
    /// The verdict.
    pub verdict: Verdict,
}

/// Frames the fired kills and stalls kept their process down; one never recovered counts
/// until `end_frame`.
pub fn downtime_frames(faults: &[FaultRecord], end_frame: u64) -> u64 {
    faults
        .iter()
        .filter_map(|fault| {
            let injected = fault.injected_frame?;
            let recovered = fault.recovered_frame.unwrap_or(end_frame);
            Some(recovered.saturating_sub(injected))
        })
        .sum()
}

/// Judges `outcome` (a launch with `faults`) against the unfaulted `reference`.
pub fn judge(
    reference: &MissionOutcome,
    outcome: MissionOutcome,
    faults: &[FaultRecord],
) -> FaultedMission {
    let downtime_frames = downtime_frames(faults, outcome.frames);
    if !reference.goal_reached {
        return FaultedMission {
            outcome,
            downtime_frames,
            allowed_frames: None,
            path_excess: None,
            time_excess: None,
            verdict: Verdict::NoReference,
        };
    }
    let allowed_frames = reference.frames + downtime_frames;
    let excess = |value: f64, base: f64| (base > 0.0).then(|| value / base - 1.0);
    let (path_excess, time_excess, verdict) = if outcome.goal_reached {
        let verdict = if outcome.frames <= allowed_frames {
            Verdict::Reached
        } else {
            Verdict::ReachedLate
        };
        (
            excess(outcome.executed_path_m, reference.executed_path_m),
            excess(outcome.frames as f64, reference.frames as f64),
            verdict,
        )
    } else {
        (None, None, Verdict::Lost)
    };
    FaultedMission {
        outcome,
        downtime_frames,
        allowed_frames: Some(allowed_frames),
        path_excess,
        time_excess,
        verdict,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fault(injected: Option<u64>, recovered: Option<u64>) -> FaultRecord {
        FaultRecord {
            fault: "kill:planner@f10".into(),
            process: "planner".into(),
            injected_frame: injected,
            injected_at_s: None,
            detected_after_s: None,
            recovered_after_s: None,
            recovered_frame: recovered,
            effect: String::new(),
        }
    }

    fn outcome(goal_reached: bool, frames: u64, executed_path_m: f64) -> MissionOutcome {
        MissionOutcome {
            goal_reached,
            frames,
            executed_path_m,
        }
    }

    #[test]
    fn downtime_counts_fired_faults_to_recovery_or_to_the_end() {
        let faults = [
            fault(Some(10), Some(12)),
            fault(None, None),         // never fired (the launch ended first)
            fault(Some(100), None),    // never recovered
            fault(Some(50), Some(50)), // recovered within its frame
        ];
        assert_eq!(downtime_frames(&faults, 130), 2 + 30);
    }

    #[test]
    fn a_mission_is_allowed_the_unfaulted_frames_plus_the_downtime() {
        let reference = outcome(true, 900, 40.0);
        let faults = [fault(Some(100), Some(140))];
        let on_time = judge(&reference, outcome(true, 940, 41.0), &faults);
        assert_eq!(on_time.verdict, Verdict::Reached);
        assert_eq!(on_time.allowed_frames, Some(940));
        assert!((on_time.path_excess.unwrap() - 0.025).abs() < 1e-12);
        let late = judge(&reference, outcome(true, 941, 41.0), &faults);
        assert_eq!(late.verdict, Verdict::ReachedLate);
        let lost = judge(&reference, outcome(false, 1200, 30.0), &faults);
        assert_eq!(lost.verdict, Verdict::Lost);
        assert_eq!(lost.path_excess, None);
    }

    #[test]
    fn without_an_unfaulted_success_nothing_is_judged() {
        let reference = outcome(false, 200, 10.0);
        let judged = judge(&reference, outcome(true, 150, 9.0), &[]);
        assert_eq!(judged.verdict, Verdict::NoReference);
        assert_eq!(judged.allowed_frames, None);
    }
}
