//! The rover: a rigid chassis on four independently driven and steered wheels.
//!
//! # Model (and why)
//! The chassis is a rapier **kinematic position-based** body moved by four-wheel-independent-
//! steering (4WIS) kinematics; wheel contact comes from scene queries, not from joint motors.
//! A jointed multibody with steered, motor-driven wheels on a heightfield needs solver tuning
//! to avoid jitter, wheel slip and sinking at 10 substeps per frame, and its climbing ability
//! would only indirectly depend on a "max climbable height". The kinematic model is robust,
//! bitwise deterministic, cheap, makes the climbable height an exact configured number, and
//! still pushes the (dynamic) jumper around if they meet.
//!
//! Per substep:
//! 1. **Controller**: for a drive command `(waypoint, speed, hold)` it turns on the spot when
//!    the heading error exceeds `turn_in_place_enter_rad` (until below `…_exit_rad`), else
//!    drives with a proportional heading correction, slowing to stop at the waypoint. A
//!    `reverse` command backs up rear first toward a waypoint behind (how a rover gets away
//!    from a rock it ran into: turning on the spot there would sweep a corner into the rock).
//! 2. **Steering**: each wheel's target angle follows from the commanded body twist
//!    (`v_wheel = v·x̂ + ω ẑ × p_wheel`; a wheel may roll backwards to stay within ±90°), slewed
//!    at `max_steer_rate_radps`. The chassis only moves while all wheels are within
//!    `steer_tolerance_rad` of their targets, so switching between driving and turning on the
//!    spot stops the rover, re-steers the wheels, then moves.
//! 3. **Twist** is rate-limited (`max_accel_mps2`, `max_yaw_accel_radps2`) and integrated.
//! 4. **Wheel contact**: each wheel is a ball of the wheel radius at its horizontal position
//!    (yaw-only footprint). Its centre height is the higher of (a) the ball resting on the
//!    terrain (bilinear height samples under it, exact on planes), and (b) the ball swept down against
//!    the **climbable** rocks; so a wheel rolls smoothly up and over small rocks.
//!    Pitch and roll come from the front/rear and left/right wheel heights; the chassis centre
//!    sits `ground_clearance_m + half height` above the contact plane along body z.
//! 5. **Blocking**: the move is refused when the footprint box (wheels and chassis, from just
//!    below the contact plane to the chassis top) intersects a rock taller than
//!    `max_climbable_height_m` (a collision, counted once per contact episode), when pitch or
//!    roll would exceed `max_tilt_rad`, or when a wheel would leave the terrain. A refused move
//!    stops the rover dead.
//!
//! Velocities (for ground truth and the IMU) are finite differences of the committed poses.

mod placement;
mod rock_separation;
mod snapshot;

use placement::{Blocked, Geometry, place};

pub use snapshot::{RestoreError, RoverSnapshot};

use hopnav_world::terrain::Heightfield;
use rapier3d::math::Pose;
use rapier3d::parry::shape::Cuboid;
use rapier3d::prelude::{
    ColliderBuilder, ColliderHandle, PhysicsWorld, RigidBodyBuilder, RigidBodyHandle,
};

use crate::colliders::{ROVER_GROUP, member_of};
use crate::config::RoverConfig;
use crate::frame::{BlockReason, BodyState, DriveCommand, RoverMode, RoverStatus};
use crate::math::{
    DQuat, DVec3, angular_velocity_world, quat_to_xyzw, to_f32, vec_to_array, wrap_angle,
};

/// A move out of a rock must reduce the footprint's penetration by at least this, metres.
const SEPARATION_EPSILON_M: f32 = 1e-4;

/// A rock contact episode ends once the rover is this far from where it was blocked, metres …
const CONTACT_RELEASE_M: f64 = 0.05;
/// … or has turned this much, radians.
const CONTACT_RELEASE_RAD: f64 = 0.05;

/// The rover: kinematic chassis, 4WIS controller and wheel-contact model.
#[derive(Debug, Clone)]
pub struct Rover {
    body: RigidBodyHandle,
    geo: Geometry,
    xy_m: [f64; 2],
    yaw_rad: f64,
    position: DVec3,
    rotation: DQuat,
    /// Larger of |pitch| and |roll| of the current pose, radians.
    tilt_rad: f64,
    linvel: DVec3,
    angvel: DVec3,
    accel: DVec3,
    v_mps: f64,
    w_radps: f64,
    steer_rad: [f64; 4],
    wheel_speed_mps: [f64; 4],
    command: Option<DriveCommand>,
    arrived: bool,
    turning: bool,
    mode: RoverMode,
    blocked: Option<BlockReason>,
    collisions: u32,
    /// Pose `(x, y, yaw)` at which the current rock contact episode began.
    rock_contact: Option<[f64; 3]>,
    distance_m: f64,
}

/// A rover start pose that cannot be used.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StartError {
    /// A wheel would be off the terrain.
    OutsideTerrain,
    /// The footprint box (at this pose) overlaps this blocking rock collider.
    InsideRock {
        /// The rock compound collider.
        collider: ColliderHandle,
        /// Pose of the footprint box.
        footprint_pose: Pose,
        /// The footprint box.
        footprint: Cuboid,
    },
    /// The start tilt exceeds the limit.
    TooSteep,
}

impl Rover {
    /// Places the rover at its start pose and inserts its kinematic body.
    ///
    /// The broad phase of `pw` must already contain the world colliders
    /// (call `pw.detect_collisions` after inserting them).
    pub fn new(
        pw: &mut PhysicsWorld,
        cfg: &RoverConfig,
        terrain: &Heightfield,
    ) -> Result<Self, StartError> {
        let geo = Geometry::new(cfg, terrain);
        let xy = cfg.start_xy_m;
        let placement = place(pw, &geo, cfg, terrain, (xy, cfg.start_yaw_rad), 0.0, None).map_err(
            |b| match b {
                Blocked::Rock(collider, footprint_pose) => StartError::InsideRock {
                    collider,
                    footprint_pose,
                    footprint: geo.footprint,
                },
                Blocked::Slope => StartError::TooSteep,
                Blocked::Boundary => StartError::OutsideTerrain,
            },
        )?;
        let [chx, chy, chz] = cfg.chassis_half_extents_m;
        let body = pw.insert_body(
            RigidBodyBuilder::kinematic_position_based()
                .translation(to_f32(placement.position))
                .rotation(to_f32(placement.rotation.to_scaled_axis())),
        );
        let _collider = pw.insert_collider(
            ColliderBuilder::cuboid(chx as f32, chy as f32, chz as f32)
                .collision_groups(member_of(ROVER_GROUP)),
            Some(body),
        );
        Ok(Self {
            body,
            geo,
            xy_m: xy,
            yaw_rad: cfg.start_yaw_rad,
            position: placement.position,
            rotation: placement.rotation,
            tilt_rad: placement.tilt_rad,
            linvel: DVec3::ZERO,
            angvel: DVec3::ZERO,
            accel: DVec3::ZERO,
            v_mps: 0.0,
            w_radps: 0.0,
            steer_rad: [0.0; 4],
            wheel_speed_mps: [0.0; 4],
            command: None,
            arrived: false,
            turning: false,
            mode: RoverMode::Idle,
            blocked: None,
            collisions: 0,
            rock_contact: None,
            distance_m: 0.0,
        })
    }

    /// Rapier body handle.
    pub fn body(&self) -> RigidBodyHandle {
        self.body
    }

    /// Replaces the drive command (a new waypoint clears the "arrived" latch).
    pub fn set_command(&mut self, cmd: DriveCommand) {
        if self
            .command
            .is_none_or(|c| c.waypoint_xy_m != cmd.waypoint_xy_m)
        {
            self.arrived = false;
        }
        self.command = Some(cmd);
    }

    /// Collisions with non-climbable rocks so far.
    pub fn collision_count(&self) -> u32 {
        self.collisions
    }

    /// `world_from_body` rotation of the chassis.
    pub fn rotation(&self) -> DQuat {
        self.rotation
    }

    /// World-frame acceleration over the last substep, m/s².
    pub fn acceleration_world_mps2(&self) -> DVec3 {
        self.accel
    }

    /// World-frame angular velocity over the last substep, rad/s.
    pub fn angular_velocity_world_radps(&self) -> DVec3 {
        self.angvel
    }

    /// Runs the controller and moves the chassis for one substep of `dt_s`; call before the
    /// rapier step (it sets the kinematic target).
    pub fn pre_substep(
        &mut self,
        pw: &mut PhysicsWorld,
        cfg: &RoverConfig,
        terrain: &Heightfield,
        dt_s: f64,
    ) {
        let (v_des, w_des) = self.controller(cfg);
        let aligned = self.steer_wheels(cfg, v_des, w_des, dt_s);
        let (v_tgt, w_tgt) = if aligned { (v_des, w_des) } else { (0.0, 0.0) };
        self.v_mps = approach(self.v_mps, v_tgt, cfg.max_accel_mps2 * dt_s);
        self.w_radps = approach(self.w_radps, w_tgt, cfg.max_yaw_accel_radps2 * dt_s);
        let (p0, q0, v0) = (self.position, self.rotation, self.linvel);
        if self.v_mps != 0.0 || self.w_radps != 0.0 {
            let yaw = self.yaw_rad + self.w_radps * dt_s;
            let mid = self.yaw_rad + 0.5 * self.w_radps * dt_s;
            let xy = [
                self.xy_m[0] + self.v_mps * mid.cos() * dt_s,
                self.xy_m[1] + self.v_mps * mid.sin() * dt_s,
            ];
            let current_footprint = self.footprint_pose();
            match place(
                pw,
                &self.geo,
                cfg,
                terrain,
                (xy, yaw),
                self.tilt_rad,
                Some((&current_footprint, SEPARATION_EPSILON_M)),
            ) {
                Ok(p) => {
                    self.tilt_rad = p.tilt_rad;
                    self.xy_m = xy;
                    self.yaw_rad = wrap_angle(yaw);
                    self.position = p.position;
                    self.rotation = p.rotation;
                    self.update_rock_contact();
                }
                Err(b) => {
                    if b.reason() == BlockReason::Rock && self.rock_contact.is_none() {
                        self.collisions += 1;
                        self.rock_contact = Some([self.xy_m[0], self.xy_m[1], self.yaw_rad]);
                    }
                    // The chassis stays put, but the drive keeps its ramped rates, as motors
                    // keep pushing: zeroing them made every move from a standstill start at
                    // one substep of acceleration, and a turn that would swing a corner out of
                    // a rock then moved it by less than SEPARATION_EPSILON_M, was refused,
                    // and restarted from zero for good (compare seeds 3 and 13 wedged).
                    self.blocked = Some(b.reason());
                }
            }
        }
        self.update_wheel_speeds();
        self.linvel = (self.position - p0) / dt_s;
        self.angvel = angular_velocity_world(q0, self.rotation, dt_s);
        self.accel = (self.linvel - v0) / dt_s;
        // Touch the body only when it moved: a modified body costs rapier extra work.
        let moved = self.position != p0 || self.rotation != q0;
        if moved && let Some(rb) = pw.bodies.get_mut(self.body) {
            rb.set_next_kinematic_position(Pose::from_parts(
                to_f32(self.position),
                self.rotation.as_quat(),
            ));
        }
    }

    /// After a successful move: ends the rock contact episode once the rover has moved or
    /// turned away from where it began (creeping along the rock keeps it, and its report).
    fn footprint_pose(&self) -> Pose {
        self.geo.footprint_pose(self.position, self.rotation)
    }

    fn update_rock_contact(&mut self) {
        match self.rock_contact {
            Some([x, y, yaw])
                if (self.xy_m[0] - x).hypot(self.xy_m[1] - y) < CONTACT_RELEASE_M
                    && wrap_angle(self.yaw_rad - yaw).abs() < CONTACT_RELEASE_RAD =>
            {
                self.blocked = Some(BlockReason::Rock);
            }
            _ => {
                self.rock_contact = None;
                self.blocked = None;
            }
        }
    }

    /// Desired (forward speed, yaw rate) and mode from the drive command.
    fn controller(&mut self, cfg: &RoverConfig) -> (f64, f64) {
        let Some(cmd) = self.command else {
            self.mode = RoverMode::Idle;
            self.distance_m = 0.0;
            return (0.0, 0.0);
        };
        let dx = cmd.waypoint_xy_m[0] - self.xy_m[0];
        let dy = cmd.waypoint_xy_m[1] - self.xy_m[1];
        let d = dx.hypot(dy);
        self.distance_m = d;
        if cmd.hold {
            self.mode = RoverMode::Holding;
            return (0.0, 0.0);
        }
        if self.arrived || d <= cfg.arrive_tolerance_m {
            self.arrived = true;
            self.turning = false;
            self.mode = RoverMode::Arrived;
            return (0.0, 0.0);
        }
        let v_stop = (2.0 * cfg.max_accel_mps2 * d).sqrt();
        if cmd.reverse {
            // Rear first: steer the rear toward the waypoint, never turn on the spot.
            self.turning = false;
            self.mode = RoverMode::Reversing;
            let err = wrap_angle(dy.atan2(dx) - self.yaw_rad - std::f64::consts::PI);
            let w = (cfg.heading_gain_per_s * err)
                .clamp(-cfg.max_yaw_rate_radps, cfg.max_yaw_rate_radps);
            let v = cmd.speed_mps.min(cfg.max_speed_mps).min(v_stop).max(0.0);
            return (-v, w);
        }
        let err = wrap_angle(dy.atan2(dx) - self.yaw_rad);
        if self.turning {
            // A turn on the spot that a rock refuses is not insisted on once the heading is
            // within the error that would start one: the rover drives on, steering, instead
            // (insisting froze a rover whose turn swung a corner into a rock for 80 s).
            let refused = self.blocked == Some(BlockReason::Rock);
            self.turning = err.abs() >= cfg.turn_in_place_exit_rad
                && !(refused && err.abs() <= cfg.turn_in_place_enter_rad);
        } else {
            self.turning = err.abs() > cfg.turn_in_place_enter_rad;
        }
        let w =
            (cfg.heading_gain_per_s * err).clamp(-cfg.max_yaw_rate_radps, cfg.max_yaw_rate_radps);
        if self.turning {
            self.mode = RoverMode::Turning;
            return (0.0, w);
        }
        self.mode = RoverMode::Driving;
        let v = cmd.speed_mps.min(cfg.max_speed_mps).min(v_stop).max(0.0);
        (v, w)
    }

    /// Slews the wheel steering toward the twist (v, w); true when all are within tolerance.
    fn steer_wheels(&mut self, cfg: &RoverConfig, v: f64, w: f64, dt_s: f64) -> bool {
        let max_step = cfg.max_steer_rate_radps * dt_s;
        let mut aligned = true;
        for (steer, p) in self.steer_rad.iter_mut().zip(self.geo.wheels_body_m) {
            let (vx, vy) = (v - w * p[1], w * p[0]);
            if vx.hypot(vy) < 1e-9 {
                continue;
            }
            let target = fold_to_half_plane(vy.atan2(vx));
            *steer += (target - *steer).clamp(-max_step, max_step);
            aligned &= (target - *steer).abs() <= cfg.steer_tolerance_rad;
        }
        aligned
    }

    fn update_wheel_speeds(&mut self) {
        let (v, w) = (self.v_mps, self.w_radps);
        for ((speed, steer), p) in self
            .wheel_speed_mps
            .iter_mut()
            .zip(self.steer_rad)
            .zip(self.geo.wheels_body_m)
        {
            let (vx, vy) = (v - w * p[1], w * p[0]);
            let (s, c) = steer.sin_cos();
            *speed = vx * c + vy * s;
        }
    }

    /// Ground-truth state (world-frame velocities; the wheels always touch the ground).
    pub fn body_state(&self) -> BodyState {
        BodyState {
            position_m: vec_to_array(self.position),
            orientation_xyzw: quat_to_xyzw(self.rotation),
            linear_velocity_mps: vec_to_array(self.linvel),
            angular_velocity_radps: vec_to_array(self.angvel),
            in_contact: true,
        }
    }

    /// Controller status.
    pub fn status(&self) -> RoverStatus {
        RoverStatus {
            mode: self.mode,
            blocked: self.blocked,
            collision_count: self.collisions,
            steer_angles_rad: self.steer_rad,
            wheel_speeds_mps: self.wheel_speed_mps,
            forward_speed_mps: self.v_mps,
            yaw_rate_radps: self.w_radps,
            distance_to_waypoint_m: self.distance_m,
        }
    }
}

/// Moves `value` toward `target` by at most `max_step`.
fn approach(value: f64, target: f64, max_step: f64) -> f64 {
    value + (target - value).clamp(-max_step, max_step)
}

/// Maps a wheel heading to `(−π/2, π/2]` (the wheel rolls backwards for the other half).
fn fold_to_half_plane(a: f64) -> f64 {
    let half = std::f64::consts::FRAC_PI_2;
    if a > half {
        a - std::f64::consts::PI
    } else if a <= -half {
        a + std::f64::consts::PI
    } else {
        a
    }
}

#[cfg(test)]
use placement::wheel_on_terrain_z;

#[cfg(test)]
mod tests;
