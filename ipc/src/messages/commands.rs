//! planner → physics: drive and jump commands; supervisor → all: control.

use iceoryx2::prelude::ZeroCopySend;

use super::{SampleStamp, Vec3, coded_enum};

/// Drive the rover toward a waypoint.
#[repr(C)]
#[derive(Debug, Default, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::DriveCommand")]
pub struct DriveCommand {
    /// Frame identity and timing.
    pub stamp: SampleStamp,
    /// Target waypoint x in the world frame, metres.
    pub waypoint_x_m: f64,
    /// Target waypoint y in the world frame, metres.
    pub waypoint_y_m: f64,
    /// Commanded ground speed, m/s (0 = stop).
    pub speed_mps: f64,
    /// 1 when the goal is reached and the rover must hold still.
    pub hold: u32,
    /// [`DriveDirection`] code: forward (turning on the spot as needed), or reverse (rear
    /// first, to back away from something the rover ran into).
    pub direction: u32,
}

coded_enum! {
    /// Which end of the rover leads.
    DriveDirection {
        /// Front first; the rover turns on the spot toward a waypoint behind it.
        Forward = 0,
        /// Rear first, toward a waypoint behind the rover (backing away from a rock).
        Reverse = 1,
    }
}

/// Ask the jumper to hop toward a region of interest.
#[repr(C)]
#[derive(Debug, Default, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::JumpRequest")]
pub struct JumpRequest {
    /// Frame identity and timing.
    pub stamp: SampleStamp,
    /// Where the jumper should land, world frame, metres.
    pub target_m: Vec3,
    /// Request counter of the planner.
    pub request_id: u64,
}

/// physics → jumper VO: the jumper launched a hop. Everything here is what the robot itself
/// commanded (its launch mechanism's attitude and velocity) and where it knows it stands: the
/// mission start for the first hop, its own estimate after that. Not ground truth.
#[repr(C)]
#[derive(Debug, Default, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::HopLaunch")]
pub struct HopLaunch {
    /// Frame identity and timing of the frame in which the launch happened.
    pub stamp: SampleStamp,
    /// `world_from_body` at the launch instant: commanded attitude at the launch point.
    pub world_from_body: super::Pose3,
    /// Commanded launch velocity in the world frame, m/s.
    pub velocity_mps: Vec3,
    /// Simulated time of the launch instant, nanoseconds since mission start.
    pub launch_time_ns: u64,
    /// 1-based hop number.
    pub hop_index: u32,
    /// 1 when the launch position is known: the mission's start point (first hop), or every
    /// hop's true launch point with the evaluation oracle `physics.jumper.oracle_launch_position`.
    pub position_known: u32,
}

coded_enum! {
    /// Launch-wide control requests.
    ControlKind {
        /// Stop the mission and exit cleanly.
        Shutdown = 1,
        /// The goal was reached.
        GoalReached = 2,
    }
}

/// A launch-wide control message.
#[repr(C)]
#[derive(Debug, Default, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::Control")]
pub struct Control {
    /// Frame identity and timing.
    pub stamp: SampleStamp,
    /// A [`ControlKind`] code.
    pub kind: u32,
    /// Slot of the sender in the process table.
    pub sender_slot: u32,
}

const _: () = assert!(size_of::<DriveCommand>() == 64);
const _: () = assert!(size_of::<JumpRequest>() == 64);
const _: () = assert!(size_of::<Control>() == 40);
const _: () = assert!(size_of::<HopLaunch>() == 128);
