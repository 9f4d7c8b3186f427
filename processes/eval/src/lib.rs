//! hopnav's evaluation: everything that compares a run with the truth. The runtime records
//! (the supervisor's [`hopnav_supervisor::MissionRecord`]); this crate regenerates the world
//! from the run's config and scores the record against it.
//!
//! - [`mission`]: a mission's scores (straight line, distance left, full-knowledge and
//!   built-map paths, map accuracy, VO accuracy) and their summary lines;
//! - [`full_knowledge`]: planning on a map known in full, with the planner's costs;
//! - [`map_accuracy`]: obstacle cells against rocks;
//! - [`vo_accuracy`]: VO estimates against the truth of the same frames;
//! - [`traversability`]: the ground the map blocks near the track against the rocks';
//! - [`contact_judge`]: each rock contact of the rover, the rock it met and the map's word
//!   on it then;
//! - [`line_of_sight`]: the map cells the rover's camera had in sight (for that judge);
//! - [`faulted_mission`]: a chaos launch's mission against the same launch without faults;
//! - [`jumper_vo`] and [`rover_vo`]: the offline VO evaluations (`hopnav eval vo`,
//!   `eval rover-vo`, `eval jumper-clouds`): each VO run over a rendered hop or traverse and
//!   scored against the truth it was rendered from; a recorded launch's jumper estimate too;
//! - [`figure`]: the mission's Fig.-6 map;
//! - [`evaluator`]: the [`hopnav_supervisor::MissionEvaluator`] `hopnav launch` passes in.
//!
//! Nothing here runs inside the process graph, and no robot ever reads it.
#![warn(missing_docs)]

pub mod blocked_area_judges;
pub mod contact_judge;
pub mod evaluator;
pub mod faulted_mission;
pub mod figure;
pub mod full_knowledge;
pub mod jumper_vo;
pub mod line_of_sight;
pub mod map_accuracy;
pub mod mission;
pub mod rover_vo;
pub mod traversability;
pub mod true_slope;
pub mod vo_accuracy;

pub use evaluator::TruthEvaluator;
pub use mission::{MissionEvaluation, MissionTruth};
