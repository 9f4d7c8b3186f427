//! What consumers check before they trust a sample, and how they count what they refuse.
//!
//! A sample from shared memory is input like any other: it may come from a crashed, restarted
//! or faulty producer. Consumers check headers (dims against slice length, finite numbers,
//! known codes) and sequence order, reject what fails, count it, and go on.

use crate::messages::{
    AltimeterSample, BodyStates, CellClass, CellUpdate, CloudHeader, Control, ControlKind,
    DriveCommand, DriveDirection, FeaturePoint, FrameTick, Heartbeat, HopLaunch, ImageHeader,
    ImuSample, JumpRequest, MapHeader, MissionState, PathHeader, PathPoint, PhysicsState,
    PixelFormat, PoseEstimate, ProcessState, Robot, SampleStamp,
};

/// Why a sample was rejected.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum Rejection {
    /// A number that must be finite is NaN or infinite.
    #[error("non-finite value in field {0}")]
    NonFinite(&'static str),
    /// An enumeration field holds a code this build does not know.
    #[error("unknown code {code} in field {field}")]
    UnknownCode {
        /// Field name.
        field: &'static str,
        /// The code found.
        code: u32,
    },
    /// The header's dimensions do not match the slice it came with.
    #[error("header announces {expected} elements but the slice holds {actual}")]
    LengthMismatch {
        /// Elements the header announces.
        expected: usize,
        /// Elements in the slice.
        actual: usize,
    },
    /// A dimension is zero or inconsistent (e.g. stride shorter than a row).
    #[error("bad dimensions: {0}")]
    BadDimensions(&'static str),
    /// Two fields contradict each other.
    #[error("inconsistent fields: {0}")]
    Inconsistent(&'static str),
    /// The sequence number did not increase for this publisher.
    #[error("sequence {received} does not follow {last} from the same publisher")]
    StaleSequence {
        /// Last accepted sequence.
        last: u64,
        /// Sequence received.
        received: u64,
    },
    /// An element of the slice failed its own check.
    #[error("element {index} invalid: {reason}")]
    BadElement {
        /// Index in the slice.
        index: usize,
        /// What was wrong.
        reason: &'static str,
    },
}

/// A message that leads with a [`SampleStamp`] and can check its own fields.
pub trait Message: Copy + Default + core::fmt::Debug + 'static {
    /// The sample's identity and timing.
    fn stamp(&self) -> &SampleStamp;
    /// Mutable access for the publisher, which fills sequence and publish stamp.
    fn stamp_mut(&mut self) -> &mut SampleStamp;
    /// Field checks beyond the stamp.
    fn validate(&self) -> Result<(), Rejection> {
        Ok(())
    }
}

/// A user header that announces the slice it travels with.
pub trait SliceHeader: Message {
    /// Element type of the slice.
    type Element: Copy + Default + core::fmt::Debug + 'static;
    /// Checks the header against the slice and, where cheap, each element.
    fn validate_slice(&self, elements: &[Self::Element]) -> Result<(), Rejection>;
}

fn finite(field: &'static str, values: &[f64]) -> Result<(), Rejection> {
    if values.iter().all(|value| value.is_finite()) {
        Ok(())
    } else {
        Err(Rejection::NonFinite(field))
    }
}

fn known<T>(field: &'static str, code: u32, parse: fn(u32) -> Option<T>) -> Result<(), Rejection> {
    parse(code)
        .map(|_| ())
        .ok_or(Rejection::UnknownCode { field, code })
}

fn length(expected: usize, actual: usize) -> Result<(), Rejection> {
    if expected == actual {
        Ok(())
    } else {
        Err(Rejection::LengthMismatch { expected, actual })
    }
}

macro_rules! stamped {
    ($type:ty, |$msg:ident| $check:block) => {
        impl Message for $type {
            fn stamp(&self) -> &SampleStamp {
                &self.stamp
            }
            fn stamp_mut(&mut self) -> &mut SampleStamp {
                &mut self.stamp
            }
            fn validate(&self) -> Result<(), Rejection> {
                let $msg = self;
                $check
            }
        }
    };
}

stamped!(FrameTick, |tick| {
    known(
        "command",
        tick.command,
        crate::messages::FrameCommand::from_code,
    )?;
    known("mode", tick.mode, crate::messages::ClockMode::from_code)
});
stamped!(Heartbeat, |heartbeat| {
    known("state", heartbeat.state, ProcessState::from_code)
});
stamped!(BodyStates, |states| {
    for body in [&states.jumper, &states.rover] {
        if !body.world_from_body.is_valid() {
            return Err(Rejection::NonFinite("world_from_body"));
        }
        finite("linear_velocity_mps", &body.linear_velocity_mps)?;
        finite("angular_velocity_radps", &body.angular_velocity_radps)?;
    }
    Ok(())
});
stamped!(AltimeterSample, |sample| {
    finite(
        "altimeter",
        &[
            sample.pressure_pa,
            sample.altitude_m,
            sample.altitude_sigma_m,
        ],
    )
});
stamped!(ImuSample, |sample| {
    finite("attitude_xyzw", &sample.attitude_xyzw)?;
    finite("angular_rate_radps", &sample.angular_rate_radps)?;
    finite("specific_force_mps2", &sample.specific_force_mps2)
});
stamped!(PoseEstimate, |pose| {
    if !pose.world_from_body.is_valid() {
        return Err(Rejection::NonFinite("world_from_body"));
    }
    finite(
        "confidence",
        &[pose.confidence, pose.scale, pose.position_sigma_m],
    )?;
    known("robot", pose.robot, Robot::from_code)
});
stamped!(DriveCommand, |command| {
    finite(
        "drive",
        &[
            command.waypoint_x_m,
            command.waypoint_y_m,
            command.speed_mps,
        ],
    )?;
    known("direction", command.direction, DriveDirection::from_code)
});
stamped!(JumpRequest, |request| {
    finite("target_m", &request.target_m)
});
stamped!(HopLaunch, |launch| {
    if !launch.world_from_body.is_valid() {
        return Err(Rejection::NonFinite("world_from_body"));
    }
    finite("velocity_mps", &launch.velocity_mps)
});
stamped!(PhysicsState, |state| {
    for body in [&state.jumper_body, &state.rover_body] {
        if !body.world_from_body.is_valid() {
            return Err(Rejection::NonFinite("world_from_body"));
        }
        finite("linear_velocity_mps", &body.linear_velocity_mps)?;
        finite("angular_velocity_radps", &body.angular_velocity_radps)?;
    }
    let jumper = &state.jumper;
    known(
        "jumper.phase",
        jumper.phase,
        crate::messages::HopPhase::from_code,
    )?;
    finite(
        "jumper",
        &[
            jumper.since_landing_s,
            jumper.yaw_rad,
            jumper.launch_speed_mps,
            jumper.launch_angle_rad,
            jumper.heading_rad,
            jumper.apex_height_m,
            jumper.flight_time_s,
        ],
    )?;
    finite("jumper.pending_target_m", &jumper.pending_target_m)?;
    finite("jumper.hop_target_m", &jumper.hop_target_m)?;
    finite("jumper.launch_position_m", &jumper.launch_position_m)?;
    finite("jumper.landing_position_m", &jumper.landing_position_m)?;
    let rover = &state.rover;
    known(
        "rover.blocked",
        rover.blocked,
        crate::messages::BlockCode::from_code,
    )?;
    finite(
        "rover",
        &[
            rover.yaw_rad,
            rover.forward_speed_mps,
            rover.yaw_rate_radps,
            rover.command_speed_mps,
        ],
    )?;
    finite("rover.xy_m", &rover.xy_m)?;
    finite("rover.steer_angles_rad", &rover.steer_angles_rad)?;
    finite("rover.rock_contact", &rover.rock_contact)?;
    finite("rover.command_waypoint_m", &rover.command_waypoint_m)?;
    finite(
        "noise",
        &[
            state.altimeter_noise.spare,
            state.imu_noise.spare,
            state.imu_yaw_error_rad,
        ],
    )?;
    let flags = [
        state.has_jump_request,
        state.altimeter_noise.has_spare,
        state.imu_noise.has_spare,
        jumper.airborne,
        jumper.has_pending_target,
        jumper.hop_has_target,
        jumper.has_landed,
        jumper.clamped,
        rover.has_command,
        rover.command_hold,
        rover.command_reverse,
        rover.arrived,
        rover.turning,
        rover.in_rock_contact,
    ];
    if flags.iter().any(|flag| *flag > 1) {
        return Err(Rejection::UnknownCode {
            field: "flag",
            code: flags.iter().copied().max().unwrap_or(0),
        });
    }
    Ok(())
});
stamped!(Control, |control| {
    known("kind", control.kind, ControlKind::from_code)
});
stamped!(ImageHeader, |header| {
    known("format", header.format, PixelFormat::from_code)?;
    let intrinsics = &header.intrinsics;
    finite(
        "intrinsics",
        &[
            intrinsics.fx_px,
            intrinsics.fy_px,
            intrinsics.cx_px,
            intrinsics.cy_px,
            header.baseline_m,
        ],
    )?;
    if !header.body_from_camera.is_valid() {
        return Err(Rejection::NonFinite("body_from_camera"));
    }
    if header.width_px == 0 || header.height_px == 0 {
        return Err(Rejection::BadDimensions("width or height is zero"));
    }
    if header.stride_bytes < header.width_px {
        return Err(Rejection::BadDimensions("stride shorter than a row"));
    }
    if !(1..=2).contains(&header.view_count) {
        return Err(Rejection::BadDimensions("view_count must be 1 or 2"));
    }
    Ok(())
});
stamped!(CloudHeader, |header| {
    if !header.world_from_camera.is_valid() {
        return Err(Rejection::NonFinite("world_from_camera"));
    }
    known("robot", header.robot, Robot::from_code)
});
stamped!(MapHeader, |header| {
    finite(
        "map geometry",
        &[header.origin_x_m, header.origin_y_m, header.cell_size_m],
    )?;
    if header.cell_size_m <= 0.0 || header.width_cells == 0 || header.height_cells == 0 {
        return Err(Rejection::BadDimensions(
            "empty grid or non-positive cell size",
        ));
    }
    Ok(())
});
stamped!(PathHeader, |header| {
    known("state", header.state, MissionState::from_code)?;
    if header.route_change_count > header.replan_count {
        return Err(Rejection::Inconsistent(
            "route_change_count exceeds replan_count (route changes are replans)",
        ));
    }
    Ok(())
});

impl SliceHeader for ImageHeader {
    type Element = u8;
    fn validate_slice(&self, pixels: &[u8]) -> Result<(), Rejection> {
        self.validate()?;
        length(self.expected_len_bytes(), pixels.len())
    }
}

impl SliceHeader for CloudHeader {
    type Element = FeaturePoint;
    fn validate_slice(&self, points: &[FeaturePoint]) -> Result<(), Rejection> {
        self.validate()?;
        length(self.point_count as usize, points.len())?;
        all_valid(
            points,
            "non-finite position or sigma",
            FeaturePoint::is_valid,
        )
    }
}

impl SliceHeader for MapHeader {
    type Element = CellUpdate;
    fn validate_slice(&self, cells: &[CellUpdate]) -> Result<(), Rejection> {
        self.validate()?;
        length(self.update_count as usize, cells.len())?;
        all_valid(cells, "cell outside the grid or unknown class", |cell| {
            cell.x < self.width_cells
                && cell.y < self.height_cells
                && CellClass::from_code(cell.class).is_some()
        })
    }
}

impl SliceHeader for PathHeader {
    type Element = PathPoint;
    fn validate_slice(&self, points: &[PathPoint]) -> Result<(), Rejection> {
        self.validate()?;
        length(self.point_count as usize, points.len())?;
        all_valid(points, "non-finite waypoint", |point| {
            point.x_m.is_finite() && point.y_m.is_finite()
        })
    }
}

/// Refuses the slice at its first element that is not `valid`, saying `reason`.
fn all_valid<T>(
    elements: &[T],
    reason: &'static str,
    valid: impl Fn(&T) -> bool,
) -> Result<(), Rejection> {
    match elements.iter().position(|element| !valid(element)) {
        Some(index) => Err(Rejection::BadElement { index, reason }),
        None => Ok(()),
    }
}

/// Remembers the last sequence of each publisher (bounded) and refuses repeats and regressions.
/// A restarted publisher is a new origin and starts afresh.
#[derive(Debug)]
pub struct SequenceGuard<Origin: PartialEq + Copy> {
    last_by_origin: Vec<(Origin, u64)>,
    capacity: usize,
}

impl<Origin: PartialEq + Copy> SequenceGuard<Origin> {
    /// A guard remembering at most `capacity` publishers (the least recent is forgotten).
    pub fn new(capacity: usize) -> Self {
        // Reserve for the usual few publishers only: an absurd capacity (a corrupt service
        // setting) must not become a huge allocation or a capacity-overflow panic.
        const PREALLOCATED: usize = 16;
        Self {
            last_by_origin: Vec::with_capacity(capacity.clamp(1, PREALLOCATED)),
            capacity: capacity.max(1),
        }
    }

    /// Accepts `sequence` from `origin` if it is newer than the last one seen from it.
    pub fn check(&mut self, origin: Origin, sequence: u64) -> Result<(), Rejection> {
        if let Some(index) = self.last_by_origin.iter().position(|(o, _)| *o == origin) {
            let (_, last) = self.last_by_origin.remove(index);
            if sequence <= last {
                self.last_by_origin.push((origin, last));
                return Err(Rejection::StaleSequence {
                    last,
                    received: sequence,
                });
            }
        } else if self.last_by_origin.len() == self.capacity {
            self.last_by_origin.remove(0);
        }
        self.last_by_origin.push((origin, sequence));
        Ok(())
    }
}

#[cfg(test)]
mod tests;
