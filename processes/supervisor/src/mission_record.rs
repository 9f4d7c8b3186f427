//! What the supervisor recorded of a mission, handed to a [`MissionEvaluator`] at the end.
//!
//! The runtime only records: the final map as the mapper published it, both robots' true
//! tracks and their VO estimates paired with the truth. Comparing that with the world (the
//! full-knowledge path, the map's accuracy, the VO's error, the figure) is evaluation, and
//! lives in the `hopnav-eval` crate, which the CLI passes in as the evaluator.

use std::path::Path;

use hopnav_config::{HopnavConfig, MissionMode};
use hopnav_ipc::messages::CellClass;
use serde_json::{Map, Value};

use crate::contact_log::RecordedContact;
use crate::mission_report::MissionReport;
use crate::vo_pairs::VoTrack;

/// One cell as the mapper last published it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RecordedCell {
    /// Column.
    pub x: u32,
    /// Row.
    pub y: u32,
    /// The mapper's class.
    pub class: CellClass,
    /// Bit per `Robot` code that observed it.
    pub observed_by: u32,
    /// The mapper's extra traversal cost (planner units).
    pub extra_cost: u32,
}

/// The mapper's final map: every cell it published, in row-major order.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordedMap {
    /// World position of cell (0, 0)'s corner, metres.
    pub origin_m: (f64, f64),
    /// Cell edge, metres.
    pub cell_size_m: f64,
    /// Cells sorted by (y, x).
    pub cells: Vec<RecordedCell>,
}

/// One robot's VO estimates paired with the truth of the same frames.
#[derive(Debug, Clone)]
pub struct RecordedVo {
    /// `jumper` or `rover`.
    pub robot: &'static str,
    /// The matched pairs.
    pub track: VoTrack,
}

/// Everything the supervisor recorded of one mission.
#[derive(Debug, Clone)]
pub struct MissionRecord {
    /// Cooperative or rover-only.
    pub mode: MissionMode,
    /// The final map (`None` when the mapper published nothing).
    pub map: Option<RecordedMap>,
    /// The rover's true track, a point every 5 cm, world metres.
    pub rover_track_m: Vec<(f64, f64)>,
    /// The jumper's true track, a point every 5 cm, world metres.
    pub jumper_track_m: Vec<(f64, f64)>,
    /// The rover's last true position, world metres.
    pub last_rover_m: Option<[f64; 2]>,
    /// The rover's rock contacts, oldest first.
    pub contacts: Vec<RecordedContact>,
    /// Both robots' VO pairs.
    pub vo: Vec<RecordedVo>,
}

/// What an evaluator found.
#[derive(Debug, Clone, Default)]
pub struct Evaluation {
    /// Fields merged into the report's `mission` section (the runtime does not read them).
    pub fields: Map<String, Value>,
    /// The mission figure it wrote, if any.
    pub figure_path: Option<String>,
    /// Lines for the launch summary.
    pub summary_lines: Vec<String>,
}

/// Scores a finished mission against the truth. The supervisor calls it once, after the
/// graph stopped and before `report.json` is written.
pub trait MissionEvaluator: Send + Sync {
    /// Compares `record` (whose runtime figures are `report`) with the world `config`
    /// describes; may write files (figures, trajectories) into `run_dir`. Problems are
    /// warnings, never a lost report.
    fn evaluate(
        &self,
        config: &HopnavConfig,
        report: &MissionReport,
        record: &MissionRecord,
        run_dir: &Path,
    ) -> Evaluation;
}

impl std::fmt::Debug for dyn MissionEvaluator {
    fn fmt(&self, formatter: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        formatter.write_str("MissionEvaluator")
    }
}
