//! planner → evaluation and visualisation: the current path, a `[PathPoint]` slice.

use iceoryx2::prelude::ZeroCopySend;

use super::{SampleStamp, coded_enum};

coded_enum! {
    /// Where the planner's mission stands.
    MissionState {
        /// No map geometry or rover pose yet.
        Waiting = 0,
        /// A path to the goal is known and the rover follows it.
        Driving = 1,
        /// The rover is within the goal tolerance and holds.
        GoalReached = 2,
        /// No path to the goal exists on the known map.
        Unreachable = 3,
    }
}

/// User header of a path sample.
#[repr(C)]
#[derive(Debug, Default, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::PathHeader")]
pub struct PathHeader {
    /// Frame identity and timing.
    pub stamp: SampleStamp,
    /// Planner cost of the path (1000 per straight cell).
    pub cost: u64,
    /// Replans so far.
    pub replan_count: u64,
    /// Replans so far after which the route moved, not only its cost.
    pub route_change_count: u64,
    /// Node expansions of the last replan.
    pub expansions: u64,
    /// Node expansions of all replans so far.
    pub total_expansions: u64,
    /// Points in the slice.
    pub point_count: u32,
    /// 1 if the goal is reachable on the known map.
    pub goal_reachable: u32,
    /// A [`MissionState`] code.
    pub state: u32,
    /// Jump requests sent to the jumper so far.
    pub jump_requests: u32,
}

/// One waypoint in the world frame.
#[repr(C)]
#[derive(Debug, Default, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::PathPoint")]
pub struct PathPoint {
    /// World x, metres.
    pub x_m: f64,
    /// World y, metres.
    pub y_m: f64,
}

const _: () = assert!(size_of::<PathHeader>() == 88);
const _: () = assert!(size_of::<PathPoint>() == 16);
