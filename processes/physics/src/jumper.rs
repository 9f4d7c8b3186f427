//! The jumping robot: a dynamic rapier cube, launched ballistically and left to land.
//!
//! # Hop cycle
//! - **Settled**: at rest. When a launch order is pending (the initial hop, or a
//!   [`HopRequest`](crate::HopRequest)), the robot "sets itself to the launch angle" as in the
//!   paper: its pose is set to `Rz(heading) · Ry(−angle)` (nose up along the launch direction,
//!   which also models self-righting), resting with its lowest corner on the support it stood
//!   on, and the launch velocity and the body-frame angular velocity are applied.
//! - **InFlight**: from launch to the **first ground contact**: the first substep, after the
//!   body has been airborne, in which the solver applied a contact impulse to the jumper (this
//!   also catches speculative contacts resolved within one substep at 10 m/s) or a contact
//!   point with the terrain, a rock or the rover is closer than `contact_distance_m`. The
//!   landing position is the body centre after that substep; the apex is the highest centre z
//!   minus the launch centre z. On flat ground this reproduces the drag-free analytic hop
//!   (Table 1: 23.34 m, 10.10 m) to ≈ 0.1 %, the semi-implicit Euler integration error at
//!   10 ms substeps.
//! - **Landing**: bouncing/sliding until the speed stays below `settle_speed_mps` and the
//!   angular speed below `settle_angular_speed_radps` for `settle_frames` consecutive frames
//!   (or `settle_timeout_s` after landing), then Settled.
//!
//! Requests arriving during a hop are kept (the latest wins) and flown once settled. Targets
//! outside the terrain are pulled 1 m inside it (and the hop is reported as clamped).
//!
//! The body is a cube (with equal half extents its lowest point at 60° and at the ≈ 33° it has
//! pitched to on landing is the same within 2 mm, so launch and landing heights agree) with
//! soft CCD; there is no drag (the Martian atmosphere is thin).

mod snapshot;

pub use snapshot::JumperSnapshot;

use hopnav_world::terrain::Heightfield;
use rapier3d::prelude::{
    ColliderBuilder, ColliderHandle, PhysicsWorld, RigidBodyBuilder, RigidBodyHandle,
};

use crate::colliders::{JUMPER_GROUP, member_of};
use crate::config::JumperConfig;
use crate::frame::{BodyState, HopRecord, HopState, JumperStatus};
use crate::hop_planner::{HopLimits, plan_hop};
use crate::math::{
    DQuat, DVec3, quat_from_yaw_pitch_roll, quat_to_xyzw, to_f32, to_f64, vec_to_array,
};

/// Gap left between the body and its support when it is posed for launch, metres.
const LAUNCH_GAP_M: f64 = 0.002;
/// Soft-CCD prediction distance of the jumper, metres: contacts are predicted this far ahead,
/// which covers the 0.1–0.12 m a 10–12 m/s body moves per 10 ms substep (full CCD costs a
/// heightfield shape cast per substep and is not needed).
const SOFT_CCD_M: f64 = 0.3;
/// Hop targets are kept this far inside the terrain border, metres.
const TARGET_MARGIN_M: f64 = 1.0;

/// A launch waiting for the jumper to settle.
#[derive(Debug, Clone, Copy, PartialEq)]
enum LaunchOrder {
    /// Fly these parameters (the initial hop).
    Direct {
        heading_rad: f64,
        speed_mps: f64,
        angle_rad: f64,
    },
    /// Plan toward this target.
    Target([f64; 2]),
}

/// The jumper's rapier body and hop state machine.
#[derive(Debug, Clone)]
pub struct Jumper {
    body: RigidBodyHandle,
    collider: ColliderHandle,
    half_extent_m: f64,
    state: HopState,
    hop_count: u32,
    pending: Option<LaunchOrder>,
    hop: Option<HopRecord>,
    airborne: bool,
    in_contact: bool,
    settle_frames: u32,
    since_landing_s: f64,
    yaw_rad: f64,
}

impl Jumper {
    /// Inserts the jumper upright at `start_xy_m`, resting on the terrain.
    pub fn new(pw: &mut PhysicsWorld, cfg: &JumperConfig, terrain: &Heightfield) -> Self {
        let h = cfg.half_extent_m;
        let [x, y] = cfg.start_xy_m;
        let ground = max_ground_under(terrain, x, y, h * std::f64::consts::SQRT_2);
        let rotation = quat_from_yaw_pitch_roll(cfg.start_yaw_rad, 0.0, 0.0);
        let position = DVec3::new(x, y, ground + h + LAUNCH_GAP_M);
        let body = pw.insert_body(
            RigidBodyBuilder::dynamic()
                .translation(to_f32(position))
                .rotation(to_f32(rotation.to_scaled_axis()))
                .soft_ccd_prediction(SOFT_CCD_M as f32),
        );
        let collider = pw.insert_collider(
            ColliderBuilder::cuboid(h as f32, h as f32, h as f32)
                .mass(cfg.mass_kg as f32)
                .friction(cfg.friction as f32)
                .restitution(cfg.restitution as f32)
                .collision_groups(member_of(JUMPER_GROUP)),
            Some(body),
        );
        let pending = cfg.initial_hop.then_some(LaunchOrder::Direct {
            heading_rad: cfg.start_yaw_rad,
            speed_mps: cfg.launch_speed_mps,
            angle_rad: cfg.launch_angle_rad,
        });
        Self {
            body,
            collider,
            half_extent_m: h,
            state: HopState::Settled,
            hop_count: 0,
            pending,
            hop: None,
            airborne: false,
            in_contact: true,
            settle_frames: 0,
            since_landing_s: 0.0,
            yaw_rad: cfg.start_yaw_rad,
        }
    }

    /// Rapier body handle.
    pub fn body(&self) -> RigidBodyHandle {
        self.body
    }

    /// Rapier collider handle.
    pub fn collider(&self) -> ColliderHandle {
        self.collider
    }

    /// Current phase.
    pub fn state(&self) -> HopState {
        self.state
    }

    /// Hops launched so far.
    pub fn hop_count(&self) -> u32 {
        self.hop_count
    }

    /// The hop in progress, or the last one.
    pub fn current_hop(&self) -> Option<HopRecord> {
        self.hop
    }

    /// Queues a hop toward `target_xy_m` (replacing any queued request).
    pub fn request_hop(&mut self, target_xy_m: [f64; 2]) {
        self.pending = Some(LaunchOrder::Target(target_xy_m));
    }

    /// Status for the frame outputs.
    pub fn status(&self) -> JumperStatus {
        JumperStatus {
            state: self.state,
            hop_count: self.hop_count,
            current_hop: self.hop,
            pending_target_xy_m: match self.pending {
                Some(LaunchOrder::Target(t)) => Some(t),
                _ => None,
            },
        }
    }

    /// Launches a pending order if the jumper is settled. Call once at the start of a frame.
    pub fn begin_frame(
        &mut self,
        pw: &mut PhysicsWorld,
        cfg: &JumperConfig,
        terrain: &Heightfield,
        gravity_mps2: f64,
    ) {
        if self.state == HopState::Landing
            && let Some(rb) = pw.bodies.get_mut(self.body)
        {
            // The landing cage soaks up the impact: the body stops near where it came down.
            rb.set_linear_damping(cfg.landing_linear_damping_per_s as f32);
            rb.set_angular_damping(cfg.landing_angular_damping_per_s as f32);
        }
        if self.state != HopState::Settled {
            return;
        }
        let Some(order) = self.pending.take() else {
            return;
        };
        let Some(rb) = pw.bodies.get(self.body) else {
            return;
        };
        let pose = rb.position();
        let centre = to_f64(pose.translation);
        let rotation = pose.rotation.as_dquat();
        let support_z = centre.z - self.lowest_offset_m(rotation);
        let (heading, speed, angle, clamped, target) = self.resolve_order(
            order,
            cfg,
            terrain,
            [centre.x, centre.y, support_z],
            gravity_mps2,
        );
        // Set to the launch attitude: nose up by the launch angle along the heading.
        let launch_rot = quat_from_yaw_pitch_roll(heading, -angle, 0.0);
        let launch_pos = DVec3::new(
            centre.x,
            centre.y,
            support_z + self.lowest_offset_m(launch_rot) + LAUNCH_GAP_M,
        );
        let (sa, ca) = angle.sin_cos();
        let (sh, ch) = heading.sin_cos();
        let linvel = DVec3::new(speed * ca * ch, speed * ca * sh, speed * sa);
        let angvel = launch_rot * DVec3::from_array(cfg.launch_angular_velocity_body_radps);
        let Some(rb) = pw.bodies.get_mut(self.body) else {
            return;
        };
        rb.set_position(
            rapier3d::math::Pose::from_parts(to_f32(launch_pos), launch_rot.as_quat()),
            true,
        );
        rb.set_linvel(to_f32(linvel), true);
        rb.set_angvel(to_f32(angvel), true);
        rb.set_linear_damping(0.0);
        rb.set_angular_damping(0.0);
        rb.reset_forces(true);
        rb.reset_torques(true);
        self.hop_count += 1;
        self.yaw_rad = heading;
        self.state = HopState::InFlight;
        self.airborne = false;
        self.settle_frames = 0;
        self.since_landing_s = 0.0;
        self.hop = Some(HopRecord {
            index: self.hop_count,
            target_xy_m: target,
            launch_speed_mps: speed,
            launch_angle_rad: angle,
            heading_rad: heading,
            clamped,
            launch_position_m: vec_to_array(launch_pos),
            landing_position_m: None,
            apex_height_m: 0.0,
            flight_time_s: 0.0,
        });
    }

    /// Heading, speed and angle of a launch order, whether they were clamped (speed, angle or
    /// a target off the terrain) and the requested target, from the support point
    /// `support_m` under the body.
    fn resolve_order(
        &self,
        order: LaunchOrder,
        cfg: &JumperConfig,
        terrain: &Heightfield,
        support_m: [f64; 3],
        gravity_mps2: f64,
    ) -> (f64, f64, f64, bool, Option<[f64; 2]>) {
        match order {
            LaunchOrder::Direct {
                heading_rad,
                speed_mps,
                angle_rad,
            } => (heading_rad, speed_mps, angle_rad, false, None),
            LaunchOrder::Target(requested) => {
                let t = clamp_to_terrain(terrain, requested);
                let limits = HopLimits {
                    min_speed_mps: cfg.min_launch_speed_mps,
                    max_speed_mps: cfg.max_launch_speed_mps,
                    min_angle_rad: cfg.min_launch_angle_rad,
                    max_angle_rad: cfg.max_launch_angle_rad,
                };
                let plan = plan_hop(
                    support_m,
                    [t[0], t[1], terrain.height_at(t[0], t[1])],
                    cfg.launch_angle_rad,
                    self.yaw_rad,
                    &limits,
                    gravity_mps2,
                );
                (
                    plan.heading_rad,
                    plan.launch_speed_mps,
                    plan.launch_angle_rad,
                    plan.clamped || t != requested,
                    Some(requested),
                )
            }
        }
    }

    /// Updates contact, apex and landing after one physics substep of `dt_s`.
    pub fn after_substep(&mut self, pw: &PhysicsWorld, cfg: &JumperConfig, dt_s: f64) {
        let contact_m = cfg.contact_distance_m as f32;
        // A pair touches when the solver pushed on it this substep (this also catches
        // speculative contacts resolved within the step) or a contact point is within reach.
        self.in_contact = pw
            .narrow_phase
            .contact_pairs_with(self.collider)
            .any(|pair| {
                pair.total_impulse() != rapier3d::math::Vector::ZERO
                    || pair
                        .manifolds()
                        .iter()
                        .any(|m| m.points.iter().any(|p| p.dist <= contact_m))
            });
        if self.state != HopState::InFlight {
            return;
        }
        let Some(rb) = pw.bodies.get(self.body) else {
            return;
        };
        let centre = to_f64(rb.translation());
        let Some(hop) = self.hop.as_mut() else {
            return;
        };
        hop.flight_time_s += dt_s;
        hop.apex_height_m = hop.apex_height_m.max(centre.z - hop.launch_position_m[2]);
        if !self.in_contact {
            self.airborne = true;
        } else if self.airborne {
            hop.landing_position_m = Some(vec_to_array(centre));
            self.state = HopState::Landing;
        }
    }

    /// Advances the settle detector at the end of a frame of `frame_s`.
    pub fn end_frame(&mut self, pw: &PhysicsWorld, cfg: &JumperConfig, frame_s: f64) {
        if self.state != HopState::Landing {
            return;
        }
        self.since_landing_s += frame_s;
        let Some(rb) = pw.bodies.get(self.body) else {
            return;
        };
        let slow = f64::from(rb.linvel().length()) < cfg.settle_speed_mps
            && f64::from(rb.angvel().length()) < cfg.settle_angular_speed_radps;
        self.settle_frames = if slow { self.settle_frames + 1 } else { 0 };
        if self.settle_frames >= cfg.settle_frames || self.since_landing_s >= cfg.settle_timeout_s {
            self.state = HopState::Settled;
        }
    }

    /// Ground-truth state (world-frame velocities).
    pub fn body_state(&self, pw: &PhysicsWorld) -> BodyState {
        let Some(rb) = pw.bodies.get(self.body) else {
            return BodyState::default();
        };
        let pose = rb.position();
        BodyState {
            position_m: vec_to_array(to_f64(pose.translation)),
            orientation_xyzw: quat_to_xyzw(pose.rotation.as_dquat()),
            linear_velocity_mps: vec_to_array(to_f64(rb.linvel())),
            angular_velocity_radps: vec_to_array(to_f64(rb.angvel())),
            in_contact: self.in_contact,
        }
    }

    /// Depth of the lowest cube corner below the centre for `world_from_body` rotation `q`.
    fn lowest_offset_m(&self, q: DQuat) -> f64 {
        let h = self.half_extent_m;
        let m = rapier3d::glamx::DMat3::from_quat(q);
        // z of a corner = Σ ±h·R[2][k]; the lowest is −h·Σ|R[2][k]|.
        h * (m.x_axis.z.abs() + m.y_axis.z.abs() + m.z_axis.z.abs())
    }
}

/// `xy` moved inside the terrain by at least [`TARGET_MARGIN_M`] (less on tiny maps).
fn clamp_to_terrain(terrain: &Heightfield, xy: [f64; 2]) -> [f64; 2] {
    let [ox, oy] = terrain.origin_m();
    let [ex, ey] = terrain.extent_m();
    let mx = TARGET_MARGIN_M.min(ex / 2.0);
    let my = TARGET_MARGIN_M.min(ey / 2.0);
    [
        xy[0].clamp(ox + mx, ox + ex - mx),
        xy[1].clamp(oy + my, oy + ey - my),
    ]
}

/// Highest terrain point within `radius_m` of (x, y) (centre plus 8 points on the circle).
fn max_ground_under(terrain: &Heightfield, x: f64, y: f64, radius_m: f64) -> f64 {
    let mut z = terrain.height_at(x, y);
    for k in 0..8 {
        let a = f64::from(k) * std::f64::consts::FRAC_PI_4;
        z = z.max(terrain.height_at(x + radius_m * a.cos(), y + radius_m * a.sin()));
    }
    z
}
