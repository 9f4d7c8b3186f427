//! The mission section of the run report.

use std::io::Write;

use serde::{Deserialize, Serialize};

use crate::rover_motion::MotionTimes;

/// How the mission went (ground truth for distances; the planner's own counters).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MissionReport {
    /// `cooperative` or `rover-only`.
    pub mode: String,
    /// The planner reported the goal reached.
    pub goal_reached: bool,
    /// The planner's last state (Waiting, Driving, GoalReached, Unreachable).
    pub final_state: String,
    /// Simulated time to the goal, or to the end of the launch, seconds.
    pub mission_time_s: f64,
    /// Distance the rover really drove, metres.
    pub executed_path_m: f64,
    /// Replans forced by map changes on the path being followed.
    pub replans: u64,
    /// Of them, replans after which the rover's route moved (more than a cell off the old
    /// one), not only its cost.
    #[serde(default)]
    pub route_changes: u64,
    /// D* Lite node expansions over the mission.
    pub node_expansions: u64,
    /// Hops the rover asked the jumper for.
    pub jump_requests: u32,
    /// Times the jumper really took off (its first hop included).
    pub jumper_hops: u32,
    /// Rover collisions with rocks it cannot climb.
    pub collisions: u32,
    /// How the rover's mission time split between driving, reversing, turning on the spot
    /// and standing still (from the truth's velocities; `None` in reports written before).
    #[serde(default)]
    pub rover_motion_times: Option<MotionTimes>,
    /// Cells the mapper published.
    pub mapped_cells: usize,
    /// Of them, obstacles.
    pub obstacle_cells: usize,
    /// Of them, inflated.
    pub inflated_cells: usize,
    /// What the evaluator added (`hopnav-eval`: straight line and distance left to B,
    /// full-knowledge and built-map paths, map accuracy, VO accuracy). The runtime neither
    /// computes nor reads these; they sit beside the fields above in `report.json`.
    #[serde(flatten)]
    pub evaluation: serde_json::Map<String, serde_json::Value>,
}

impl MissionReport {
    /// Prints the mission lines of the summary.
    pub fn print(&self, out: &mut impl Write) -> std::io::Result<()> {
        writeln!(
            out,
            "mission ({}): {} after {:.1} s — rover drove {:.1} m; {} replans ({} moved the route), {} expansions, {} jump requests, {} hops, {} collisions; map {} cells ({} obstacle, {} inflated)",
            self.mode,
            if self.goal_reached {
                "goal reached".to_owned()
            } else {
                format!("goal NOT reached ({})", self.final_state)
            },
            self.mission_time_s,
            self.executed_path_m,
            self.replans,
            self.route_changes,
            self.node_expansions,
            self.jump_requests,
            self.jumper_hops,
            self.collisions,
            self.mapped_cells,
            self.obstacle_cells,
            self.inflated_cells
        )?;
        if let Some(times) = &self.rover_motion_times {
            writeln!(
                out,
                "rover's time: driving {:.1} s, reversing {:.1} s, turning on the spot {:.1} s, standing still {:.1} s",
                times.driving_s, times.reversing_s, times.turning_s, times.still_s
            )?;
        }
        Ok(())
    }
}
