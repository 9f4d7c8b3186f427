//! The jumper's state at the end of a frame, and putting a fresh jumper into it: how a
//! restarted physics continues a hop instead of starting the mission over.

use rapier3d::prelude::PhysicsWorld;

use super::{Jumper, LaunchOrder};
use crate::config::JumperConfig;
use crate::frame::{BodyState, HopRecord, HopState};
use crate::math::{DQuat, DVec3, to_f32};

/// The hop cycle beyond the body's pose and velocities.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JumperSnapshot {
    /// Current phase.
    pub state: HopState,
    /// Hops launched so far.
    pub hop_count: u32,
    /// The hop in progress, or the last one.
    pub hop: Option<HopRecord>,
    /// Target of a request waiting for the jumper to settle.
    pub pending_target_xy_m: Option<[f64; 2]>,
    /// Whether the body has left the ground in the current hop.
    pub airborne: bool,
    /// Consecutive slow frames since landing.
    pub settle_frames: u32,
    /// Time since the first ground contact of the current hop, seconds.
    pub since_landing_s: f64,
    /// Heading of the last launch (or the start yaw), radians.
    pub yaw_rad: f64,
}

impl Jumper {
    /// The hop cycle now. A launch order that is not a hop request (the initial hop before
    /// the first frame) is not part of it: a resumed jumper never relaunches its first hop.
    pub fn snapshot(&self) -> JumperSnapshot {
        JumperSnapshot {
            state: self.state,
            hop_count: self.hop_count,
            hop: self.hop,
            pending_target_xy_m: match self.pending {
                Some(LaunchOrder::Target(target)) => Some(target),
                _ => None,
            },
            airborne: self.airborne,
            settle_frames: self.settle_frames,
            since_landing_s: self.since_landing_s,
            yaw_rad: self.yaw_rad,
        }
    }

    /// Puts the body at `body` (pose, world-frame velocities, contact) and the hop cycle at
    /// `snapshot`, in flight or at rest. Any launch order of its own (the initial hop) is
    /// dropped.
    pub fn restore(
        &mut self,
        pw: &mut PhysicsWorld,
        cfg: &JumperConfig,
        body: &BodyState,
        snapshot: &JumperSnapshot,
    ) {
        self.state = snapshot.state;
        self.hop_count = snapshot.hop_count;
        self.hop = snapshot.hop;
        self.pending = snapshot.pending_target_xy_m.map(LaunchOrder::Target);
        self.airborne = snapshot.airborne;
        self.in_contact = body.in_contact;
        self.settle_frames = snapshot.settle_frames;
        self.since_landing_s = snapshot.since_landing_s;
        self.yaw_rad = snapshot.yaw_rad;
        let Some(rb) = pw.bodies.get_mut(self.body) else {
            return;
        };
        let [x, y, z, w] = body.orientation_xyzw;
        let mut rotation = DQuat::from_xyzw(x, y, z, w);
        // The state came from rapier's f32 pose: keep its bits unless it is off unit length.
        if (rotation.length_squared() - 1.0).abs() > 1e-6 {
            rotation = rotation.normalize();
        }
        rb.set_position(
            rapier3d::math::Pose::from_parts(
                to_f32(DVec3::from_array(body.position_m)),
                rotation.as_quat(),
            ),
            true,
        );
        rb.set_linvel(to_f32(DVec3::from_array(body.linear_velocity_mps)), true);
        rb.set_angvel(to_f32(DVec3::from_array(body.angular_velocity_radps)), true);
        rb.reset_forces(true);
        rb.reset_torques(true);
        // Damping as the hop cycle left it: none in flight (and before the first hop); the
        // landing cage's after touching down, until the next launch.
        let caged = self.state != HopState::InFlight && self.hop_count > 0;
        let (linear, angular) = if caged {
            (
                cfg.landing_linear_damping_per_s,
                cfg.landing_angular_damping_per_s,
            )
        } else {
            (0.0, 0.0)
        };
        rb.set_linear_damping(linear as f32);
        rb.set_angular_damping(angular as f32);
    }
}
