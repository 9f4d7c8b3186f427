//! Between the simulation and its messages: the ground truth consumers read, and the
//! [`msg::PhysicsState`] a restarted physics resumes from (see [`PhysicsSim::resume_from`]).
//!
//! [`PhysicsSim::resume_from`]: crate::PhysicsSim::resume_from

use hopnav_ipc::messages::{self as msg, BlockCode, HopPhase, Pose3};
use hopnav_ipc::validate::{Message, Rejection};

use crate::frame::{BlockReason, BodyState, DriveCommand, HopRecord, HopState};
use crate::jumper::JumperSnapshot;
use crate::noise::NoiseRng;
use crate::rover::RoverSnapshot;
use crate::sim::SimSnapshot;

/// A resume sample turned back into simulation state.
#[derive(Debug, Clone, PartialEq)]
pub struct Resume {
    /// The simulation's state.
    pub snapshot: SimSnapshot,
    /// Id of the last jump request the process took.
    pub last_jump_request: Option<u64>,
}

/// Why a resume sample cannot be used: it fails the message checks, or passes them but does
/// not describe a state this simulation can continue from.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ResumeSampleError {
    /// The sample fails the message checks (a subscriber already refuses it; this is for a
    /// sample that came another way).
    #[error("corrupt sample: {0}")]
    Invalid(#[from] Rejection),
    /// The stamp's sim time is not the frames simulated times this configuration's frame
    /// period (another frame rate, or a garbled sample).
    #[error("sim time {sim_time_ns} ns is not {frames_simulated} frames of {frame_period_s} s")]
    TimeMismatch {
        /// The stamp's sim time, nanoseconds.
        sim_time_ns: u64,
        /// Frames simulated, from the sample.
        frames_simulated: u64,
        /// This configuration's frame period, seconds.
        frame_period_s: f64,
    },
    /// A coded field holds a code this build does not know.
    #[error("unknown code {code} in {field}")]
    UnknownCode {
        /// Field name.
        field: &'static str,
        /// The code found.
        code: u32,
    },
    /// A noise generator's state is one no generator reaches (all-zero words).
    #[error("the {sensor} noise state is invalid")]
    BadNoise {
        /// Which sensor.
        sensor: &'static str,
    },
}

/// Largest difference between the stamp's sim time and frames × period, nanoseconds (the
/// stamp is rounded to whole nanoseconds).
const TIME_TOLERANCE_NS: f64 = 1_000.0;

/// One body's ground truth as published.
pub fn body_state(state: &BodyState, collisions: u32) -> msg::BodyState {
    msg::BodyState {
        world_from_body: Pose3 {
            position_m: state.position_m,
            orientation_xyzw: state.orientation_xyzw,
        },
        linear_velocity_mps: state.linear_velocity_mps,
        angular_velocity_radps: state.angular_velocity_radps,
        in_contact: u32::from(state.in_contact),
        collisions,
    }
}

fn from_body_state(state: &msg::BodyState) -> BodyState {
    BodyState {
        position_m: state.world_from_body.position_m,
        orientation_xyzw: state.world_from_body.orientation_xyzw,
        linear_velocity_mps: state.linear_velocity_mps,
        angular_velocity_radps: state.angular_velocity_radps,
        in_contact: state.in_contact != 0,
    }
}

/// The resume sample of `snapshot` (its stamp left default: the caller stamps it like the
/// body states of the same frame).
pub fn physics_state(snapshot: &SimSnapshot, last_jump_request: Option<u64>) -> msg::PhysicsState {
    let collisions = snapshot.rover_drive.collisions;
    msg::PhysicsState {
        stamp: msg::SampleStamp::default(),
        frames_simulated: snapshot.frames_simulated,
        last_jump_request_id: last_jump_request.unwrap_or(0),
        has_jump_request: u32::from(last_jump_request.is_some()),
        reserved: 0,
        jumper_body: body_state(&snapshot.jumper, 0),
        rover_body: body_state(&snapshot.rover, collisions),
        jumper: jumper_cycle(&snapshot.jumper_cycle),
        rover: rover_drive(&snapshot.rover_drive),
        altimeter_noise: noise_state(&snapshot.altimeter_noise),
        imu_noise: noise_state(&snapshot.imu_noise),
        imu_yaw_error_rad: snapshot.imu_yaw_error_rad,
    }
}

/// The simulation state in a resume sample, for a configuration of `frame_period_s`.
pub fn resume_state(
    state: &msg::PhysicsState,
    frame_period_s: f64,
) -> Result<Resume, ResumeSampleError> {
    state.validate()?;
    let expected_ns = state.frames_simulated as f64 * frame_period_s * 1e9;
    let offset_ns = (state.stamp.sim_time_ns as f64 - expected_ns).abs();
    if offset_ns.is_nan() || offset_ns > TIME_TOLERANCE_NS {
        return Err(ResumeSampleError::TimeMismatch {
            sim_time_ns: state.stamp.sim_time_ns,
            frames_simulated: state.frames_simulated,
            frame_period_s,
        });
    }
    let noise = |noise: &msg::NoiseState, sensor| {
        NoiseRng::from_state(noise.words, (noise.has_spare != 0).then_some(noise.spare))
            .ok_or(ResumeSampleError::BadNoise { sensor })
    };
    Ok(Resume {
        snapshot: SimSnapshot {
            frames_simulated: state.frames_simulated,
            jumper: from_body_state(&state.jumper_body),
            jumper_cycle: from_jumper_cycle(&state.jumper)?,
            rover: from_body_state(&state.rover_body),
            rover_drive: from_rover_drive(&state.rover)?,
            altimeter_noise: noise(&state.altimeter_noise, "altimeter")?,
            imu_noise: noise(&state.imu_noise, "IMU")?,
            imu_yaw_error_rad: state.imu_yaw_error_rad,
        },
        last_jump_request: (state.has_jump_request != 0).then_some(state.last_jump_request_id),
    })
}

fn noise_state(rng: &NoiseRng) -> msg::NoiseState {
    let (words, spare) = rng.state();
    msg::NoiseState {
        words,
        spare: spare.unwrap_or(0.0),
        has_spare: u32::from(spare.is_some()),
        reserved: 0,
    }
}

fn jumper_cycle(cycle: &JumperSnapshot) -> msg::JumperCycle {
    let hop = cycle.hop.unwrap_or_default();
    msg::JumperCycle {
        phase: match cycle.state {
            HopState::Settled => HopPhase::Settled,
            HopState::InFlight => HopPhase::InFlight,
            HopState::Landing => HopPhase::Landing,
        }
        .code(),
        hop_count: cycle.hop_count,
        airborne: u32::from(cycle.airborne),
        settle_frames: cycle.settle_frames,
        since_landing_s: cycle.since_landing_s,
        yaw_rad: cycle.yaw_rad,
        has_pending_target: u32::from(cycle.pending_target_xy_m.is_some()),
        hop_has_target: u32::from(hop.target_xy_m.is_some()),
        pending_target_m: cycle.pending_target_xy_m.unwrap_or_default(),
        hop_target_m: hop.target_xy_m.unwrap_or_default(),
        launch_speed_mps: hop.launch_speed_mps,
        launch_angle_rad: hop.launch_angle_rad,
        heading_rad: hop.heading_rad,
        launch_position_m: hop.launch_position_m,
        landing_position_m: hop.landing_position_m.unwrap_or_default(),
        has_landed: u32::from(hop.landing_position_m.is_some()),
        clamped: u32::from(hop.clamped),
        apex_height_m: hop.apex_height_m,
        flight_time_s: hop.flight_time_s,
    }
}

fn from_jumper_cycle(cycle: &msg::JumperCycle) -> Result<JumperSnapshot, ResumeSampleError> {
    let state = match HopPhase::from_code(cycle.phase) {
        Some(HopPhase::Settled) => HopState::Settled,
        Some(HopPhase::InFlight) => HopState::InFlight,
        Some(HopPhase::Landing) => HopState::Landing,
        None => {
            return Err(ResumeSampleError::UnknownCode {
                field: "jumper.phase",
                code: cycle.phase,
            });
        }
    };
    // Hop `hop_count` is the one described (none before the first launch).
    let hop = (cycle.hop_count > 0).then_some(HopRecord {
        index: cycle.hop_count,
        target_xy_m: (cycle.hop_has_target != 0).then_some(cycle.hop_target_m),
        launch_speed_mps: cycle.launch_speed_mps,
        launch_angle_rad: cycle.launch_angle_rad,
        heading_rad: cycle.heading_rad,
        clamped: cycle.clamped != 0,
        launch_position_m: cycle.launch_position_m,
        landing_position_m: (cycle.has_landed != 0).then_some(cycle.landing_position_m),
        apex_height_m: cycle.apex_height_m,
        flight_time_s: cycle.flight_time_s,
    });
    Ok(JumperSnapshot {
        state,
        hop_count: cycle.hop_count,
        hop,
        pending_target_xy_m: (cycle.has_pending_target != 0).then_some(cycle.pending_target_m),
        airborne: cycle.airborne != 0,
        settle_frames: cycle.settle_frames,
        since_landing_s: cycle.since_landing_s,
        yaw_rad: cycle.yaw_rad,
    })
}

fn rover_drive(drive: &RoverSnapshot) -> msg::RoverDrive {
    let command = drive.command.unwrap_or(DriveCommand {
        waypoint_xy_m: [0.0; 2],
        speed_mps: 0.0,
        hold: false,
        reverse: false,
    });
    msg::RoverDrive {
        xy_m: drive.xy_m,
        yaw_rad: drive.yaw_rad,
        forward_speed_mps: drive.forward_speed_mps,
        yaw_rate_radps: drive.yaw_rate_radps,
        steer_angles_rad: drive.steer_angles_rad,
        rock_contact: drive.rock_contact.unwrap_or_default(),
        command_waypoint_m: command.waypoint_xy_m,
        command_speed_mps: command.speed_mps,
        has_command: u32::from(drive.command.is_some()),
        command_hold: u32::from(command.hold),
        command_reverse: u32::from(command.reverse),
        arrived: u32::from(drive.arrived),
        turning: u32::from(drive.turning),
        in_rock_contact: u32::from(drive.rock_contact.is_some()),
        blocked: match drive.blocked {
            None => BlockCode::None,
            Some(BlockReason::Rock) => BlockCode::Rock,
            Some(BlockReason::Slope) => BlockCode::Slope,
            Some(BlockReason::Boundary) => BlockCode::Boundary,
        }
        .code(),
        collisions: drive.collisions,
    }
}

fn from_rover_drive(drive: &msg::RoverDrive) -> Result<RoverSnapshot, ResumeSampleError> {
    let blocked = match BlockCode::from_code(drive.blocked) {
        Some(BlockCode::None) => None,
        Some(BlockCode::Rock) => Some(BlockReason::Rock),
        Some(BlockCode::Slope) => Some(BlockReason::Slope),
        Some(BlockCode::Boundary) => Some(BlockReason::Boundary),
        None => {
            return Err(ResumeSampleError::UnknownCode {
                field: "rover.blocked",
                code: drive.blocked,
            });
        }
    };
    Ok(RoverSnapshot {
        xy_m: drive.xy_m,
        yaw_rad: drive.yaw_rad,
        forward_speed_mps: drive.forward_speed_mps,
        yaw_rate_radps: drive.yaw_rate_radps,
        steer_angles_rad: drive.steer_angles_rad,
        command: (drive.has_command != 0).then_some(DriveCommand {
            waypoint_xy_m: drive.command_waypoint_m,
            speed_mps: drive.command_speed_mps,
            hold: drive.command_hold != 0,
            reverse: drive.command_reverse != 0,
        }),
        arrived: drive.arrived != 0,
        turning: drive.turning != 0,
        blocked,
        collisions: drive.collisions,
        rock_contact: (drive.in_rock_contact != 0).then_some(drive.rock_contact),
    })
}
