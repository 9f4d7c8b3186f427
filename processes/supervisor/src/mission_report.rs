//! The mission section of the run report.

use std::io::Write;

use serde::{Deserialize, Serialize};

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
    /// Straight-line distance from A to B, metres.
    pub straight_line_m: Option<f64>,
    /// True distance from the rover to B at the end, metres.
    pub final_distance_to_goal_m: Option<f64>,
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
    /// Cells the mapper published.
    pub mapped_cells: usize,
    /// Of them, obstacles.
    pub obstacle_cells: usize,
    /// Of them, inflated.
    pub inflated_cells: usize,
    /// Length of the path the planner would have driven knowing every rock from the start,
    /// metres (evaluation only: the most any scouting could shorten the drive to).
    #[serde(default)]
    pub full_knowledge_path_m: Option<f64>,
    /// Length of the path the planner would have driven knowing from the start the map the
    /// robots built by the end (unknown cells free, as planned; the rover's bump marks left
    /// out), metres. Above `full_knowledge_path_m` by what the map's errors cost (false or
    /// misplaced obstacles, missed rocks); below `executed_path_m` by what learning the map on
    /// the way cost, the part a scout that arrives earlier can win back.
    #[serde(default)]
    pub built_map_path_m: Option<f64>,
    /// Obstacle cells against the world's rocks (evaluation only).
    pub map_accuracy: Option<crate::map_accuracy::MapAccuracy>,
    /// Each robot's VO against the truth of the same frames (evaluation only).
    pub vo: Vec<crate::vo_accuracy::VoAccuracy>,
}

impl MissionReport {
    /// Prints the mission lines of the summary.
    pub fn print(&self, out: &mut impl Write) -> std::io::Result<()> {
        let distance = |value: Option<f64>| value.map_or("-".to_owned(), |m| format!("{m:.1} m"));
        writeln!(
            out,
            "mission ({}): {} after {:.1} s — rover drove {:.1} m (A–B {}), {} to go; {} replans ({} moved the route), {} expansions, {} jump requests, {} hops, {} collisions; map {} cells ({} obstacle, {} inflated)",
            self.mode,
            if self.goal_reached {
                "goal reached".to_owned()
            } else {
                format!("goal NOT reached ({})", self.final_state)
            },
            self.mission_time_s,
            self.executed_path_m,
            distance(self.straight_line_m),
            distance(self.final_distance_to_goal_m),
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
        if let Some(accuracy) = &self.map_accuracy {
            writeln!(
                out,
                "map vs truth: {} obstacle cells on rocks, {} false (rover {}, jumper {} of which {} beside a rock, both {}); rocks the rover cannot climb near its track: {} of {} mapped",
                accuracy.true_obstacle_cells,
                accuracy.false_obstacle_cells(),
                accuracy.false_by_rover,
                accuracy.false_by_jumper,
                accuracy.false_by_jumper_misplaced,
                accuracy.false_by_both,
                accuracy.blocking_rocks_found,
                accuracy.blocking_rocks_near_track
            )?;
        }
        if let Some(best_m) = self.full_knowledge_path_m {
            // The comparison means something only for a drive that got to B.
            let comparison = if self.goal_reached {
                format!(
                    "; the rover drove {:+.1} % more",
                    100.0 * (self.executed_path_m / best_m.max(1e-9) - 1.0)
                )
            } else {
                String::new()
            };
            writeln!(
                out,
                "full-knowledge path (every rock known from the start): {best_m:.1} m{comparison}"
            )?;
        }
        if let Some(built_m) = self.built_map_path_m {
            writeln!(
                out,
                "built-map path (the final map known from the start): {built_m:.1} m; what was learnt on the way cost {:+.1} m",
                self.executed_path_m - built_m
            )?;
        }
        for vo in &self.vo {
            writeln!(
                out,
                "{} VO vs truth over {} poses: ATE Sim(3) {:.3} m, SE(3) {:.3} m, final error {:.3} m after {:.1} m travelled ({:.2} %)",
                vo.robot,
                vo.poses,
                vo.ate_sim3_m,
                vo.ate_se3_m,
                vo.final_error_m,
                vo.travelled_m,
                vo.drift_percent
            )?;
        }
        Ok(())
    }
}
