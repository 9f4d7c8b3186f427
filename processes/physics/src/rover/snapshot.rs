//! The rover's state at the end of a frame, and putting a fresh rover into it: how a
//! restarted physics continues the drive instead of starting the mission over.

use hopnav_world::terrain::Heightfield;
use rapier3d::math::Pose;
use rapier3d::prelude::PhysicsWorld;

use super::{Blocked, Rover, place};
use crate::config::RoverConfig;
use crate::frame::{BlockReason, BodyState, DriveCommand};
use crate::math::{DQuat, DVec3, to_f32, wrap_angle};

/// The controller and wheel state beyond the chassis velocities.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RoverSnapshot {
    /// Wheel-contact centre (x, y), world metres.
    pub xy_m: [f64; 2],
    /// Heading, radians.
    pub yaw_rad: f64,
    /// Current forward speed, m/s.
    pub forward_speed_mps: f64,
    /// Current yaw rate, rad/s.
    pub yaw_rate_radps: f64,
    /// Steering angle of each wheel (FL, FR, RL, RR), radians.
    pub steer_angles_rad: [f64; 4],
    /// The drive command in force.
    pub command: Option<DriveCommand>,
    /// Whether the rover arrived at the command's waypoint.
    pub arrived: bool,
    /// Whether it is turning on the spot.
    pub turning: bool,
    /// Why the last move was refused, while blocked.
    pub blocked: Option<BlockReason>,
    /// Collisions with rocks it cannot climb so far.
    pub collisions: u32,
    /// Pose (x, y, yaw) at which the current rock contact episode began.
    pub rock_contact: Option<[f64; 3]>,
}

/// Why a rover could not be put back where a snapshot says it was.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum RestoreError {
    /// The chassis cannot rest there: a wheel off the terrain or a rock it cannot climb in
    /// the footprint (a snapshot of another world).
    #[error("the rover cannot stand at ({x_m:.2}, {y_m:.2}): {reason:?}")]
    CannotStand {
        /// Contact centre x, metres.
        x_m: f64,
        /// Contact centre y, metres.
        y_m: f64,
        /// What is in the way.
        reason: BlockReason,
    },
    /// Resting the chassis at (x, y, yaw) puts its origin this far from the snapshot's body
    /// pose (a snapshot of another world or configuration).
    #[error(
        "the rover resting at the snapshot's (x, y, yaw) is {offset_m:.3} m from its body pose"
    )]
    PoseMismatch {
        /// Distance between the two origins, metres.
        offset_m: f64,
    },
}

/// Largest distance between the re-placed chassis origin and the snapshot's body pose; the
/// placement is deterministic, so on the same world the two agree to rounding.
const POSE_TOLERANCE_M: f64 = 0.01;

/// A restored rover may overlap a rock this much deeper than where it stood (f32 round
/// trips), metres.
const RESTORE_DEPTH_TOLERANCE_M: f32 = 1e-3;

impl Rover {
    /// The controller now.
    pub fn snapshot(&self) -> RoverSnapshot {
        RoverSnapshot {
            xy_m: self.xy_m,
            yaw_rad: self.yaw_rad,
            forward_speed_mps: self.v_mps,
            yaw_rate_radps: self.w_radps,
            steer_angles_rad: self.steer_rad,
            command: self.command,
            arrived: self.arrived,
            turning: self.turning,
            blocked: self.blocked,
            collisions: self.collisions,
            rock_contact: self.rock_contact,
        }
    }

    /// Rests the chassis at the snapshot's (x, y, yaw) (height, pitch and roll follow from
    /// the terrain, as for every move) with `body`'s velocities, and takes over its
    /// controller. Checks that the placement reproduces `body`'s position; on an error the
    /// rover is left as it was.
    pub fn restore(
        &mut self,
        pw: &mut PhysicsWorld,
        cfg: &RoverConfig,
        terrain: &Heightfield,
        body: &BodyState,
        snapshot: &RoverSnapshot,
    ) -> Result<(), RestoreError> {
        let [x_m, y_m] = snapshot.xy_m;
        // The rover stood there, whatever its tilt: a slope limit does not apply, and a rock
        // it overlapped (moving out of it) may overlap it as deep again.
        let stood = self.geo.footprint_pose(
            DVec3::from_array(body.position_m),
            DQuat::from_array(body.orientation_xyzw),
        );
        let placement = place(
            pw,
            &self.geo,
            cfg,
            terrain,
            (snapshot.xy_m, snapshot.yaw_rad),
            f64::INFINITY,
            Some((&stood, -RESTORE_DEPTH_TOLERANCE_M)),
        )
        .map_err(|blocked| RestoreError::CannotStand {
            x_m,
            y_m,
            reason: match blocked {
                Blocked::Rock(..) => BlockReason::Rock,
                Blocked::Slope => BlockReason::Slope,
                Blocked::Boundary => BlockReason::Boundary,
            },
        })?;
        let offset_m = placement
            .position
            .distance(DVec3::from_array(body.position_m));
        // NaN (a non-finite pose) fails too.
        if offset_m.is_nan() || offset_m > POSE_TOLERANCE_M {
            return Err(RestoreError::PoseMismatch { offset_m });
        }
        self.xy_m = snapshot.xy_m;
        self.yaw_rad = wrap_angle(snapshot.yaw_rad);
        self.position = placement.position;
        self.rotation = placement.rotation;
        self.tilt_rad = placement.tilt_rad;
        self.linvel = DVec3::from_array(body.linear_velocity_mps);
        self.angvel = DVec3::from_array(body.angular_velocity_radps);
        self.accel = DVec3::ZERO;
        self.v_mps = snapshot.forward_speed_mps;
        self.w_radps = snapshot.yaw_rate_radps;
        self.steer_rad = snapshot.steer_angles_rad;
        self.command = snapshot.command;
        self.arrived = snapshot.arrived;
        self.turning = snapshot.turning;
        self.blocked = snapshot.blocked;
        self.collisions = snapshot.collisions;
        self.rock_contact = snapshot.rock_contact;
        self.update_wheel_speeds();
        if let Some(rb) = pw.bodies.get_mut(self.body) {
            let pose = Pose::from_parts(to_f32(self.position), self.rotation.as_quat());
            rb.set_position(pose, true);
            rb.set_next_kinematic_position(pose);
        }
        Ok(())
    }
}
