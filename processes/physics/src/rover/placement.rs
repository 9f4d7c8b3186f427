//! Where the chassis rests: the wheels' heights on the terrain and the climbable rocks, the
//! pitch and roll they give, and whether the footprint then meets a rock, a too steep slope
//! or the terrain's edge.

use hopnav_world::terrain::Heightfield;
use rapier3d::math::Pose;
use rapier3d::parry::query::ShapeCastOptions;
use rapier3d::parry::shape::{Ball, Cuboid};
use rapier3d::prelude::{ColliderHandle, PhysicsWorld, QueryFilter, QueryPipeline};

use super::rock_separation::separates_from_rock;
use crate::colliders::{BLOCKING_ROCK_GROUP, CLIMBABLE_ROCK_GROUP, query_groups};
use crate::config::RoverConfig;
use crate::frame::BlockReason;
use crate::math::{DQuat, DVec3, Vec3, quat_from_yaw_pitch_roll, to_f32};

/// How far below the contact plane the blocking footprint box reaches, metres.
const FOOTPRINT_BELOW_M: f64 = 0.05;
/// Height above the local terrain from which wheel balls are swept down, beyond the
/// climbable height and the wheel radius, metres.
const SWEEP_MARGIN_M: f64 = 1.0;

/// A candidate chassis pose resting on its wheels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Placement {
    pub(super) position: DVec3,
    pub(super) rotation: DQuat,
    /// Larger of |pitch| and |roll|, radians.
    pub(super) tilt_rad: f64,
}

/// Why a placement failed; `Rock` carries the collider that blocked and the footprint pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Blocked {
    Rock(ColliderHandle, Pose),
    Slope,
    Boundary,
}

impl Blocked {
    pub(super) fn reason(self) -> BlockReason {
        match self {
            Self::Rock(..) => BlockReason::Rock,
            Self::Slope => BlockReason::Slope,
            Self::Boundary => BlockReason::Boundary,
        }
    }
}

/// Geometry derived from the config once.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Geometry {
    pub(super) wheels_body_m: [[f64; 2]; 4],
    pub(super) wheel: Ball,
    pub(super) wheel_radius_m: f64,
    pub(super) footprint: Cuboid,
    /// Body-frame z of the footprint box centre.
    pub(super) footprint_z_m: f64,
    /// Body-frame height of the chassis centre above the contact plane.
    pub(super) centre_above_contact_m: f64,
    pub(super) sweep_height_m: f64,
    /// Allowed wheel-centre x and y ranges (terrain minus one wheel radius).
    pub(super) x_range_m: [f64; 2],
    pub(super) y_range_m: [f64; 2],
}

impl Geometry {
    pub(super) fn new(cfg: &RoverConfig, terrain: &Heightfield) -> Self {
        let r = cfg.wheel_radius_m;
        let [chx, chy, chz] = cfg.chassis_half_extents_m;
        let hx = chx.max(cfg.wheelbase_m / 2.0 + r);
        let hy = chy.max(cfg.track_m / 2.0 + cfg.wheel_width_m / 2.0);
        let centre_above_contact_m = cfg.ground_clearance_m + chz;
        let top = chz;
        let bottom = -centre_above_contact_m - FOOTPRINT_BELOW_M;
        let [ox, oy] = terrain.origin_m();
        let [ex, ey] = terrain.extent_m();
        Self {
            wheels_body_m: cfg.wheel_positions_body_m(),
            wheel: Ball::new(r as f32),
            wheel_radius_m: r,
            footprint: Cuboid::new(Vec3::new(
                hx as f32,
                hy as f32,
                ((top - bottom) / 2.0) as f32,
            )),
            footprint_z_m: (top + bottom) / 2.0,
            centre_above_contact_m,
            sweep_height_m: cfg.max_climbable_height_m + r + SWEEP_MARGIN_M,
            x_range_m: [ox + r, ox + ex - r],
            y_range_m: [oy + r, oy + ey - r],
        }
    }

    /// Pose of the footprint box for a body at `position` with `rotation`.
    pub(super) fn footprint_pose(&self, position: DVec3, rotation: DQuat) -> Pose {
        Pose::from_parts(
            to_f32(position + rotation * DVec3::new(0.0, 0.0, self.footprint_z_m)),
            rotation.as_quat(),
        )
    }
}

/// Centre height of a ball wheel of radius `r` resting on the terrain at (x, y): the highest
/// of `h(p) + √(r² − |p − c|²)` over sample points `p` under the ball: the centre, the
/// contact point a plane with the local gradient would have (exact on planes), and three
/// rings of 8 samples (0.25 r, 0.5 r, 0.9 r) for bumps. Sweeping a ball against the rapier
/// heightfield gives nearly the same answer but costs ≈ 15 µs per wheel.
pub(super) fn wheel_on_terrain_z(
    height_at: impl Fn(f64, f64) -> f64,
    gradient_at: impl Fn(f64, f64) -> [f64; 2],
    x: f64,
    y: f64,
    r: f64,
) -> f64 {
    let sample = |dx: f64, dy: f64| {
        let d2 = dx * dx + dy * dy;
        height_at(x + dx, y + dy) + (r * r - d2).max(0.0).sqrt()
    };
    let mut z = sample(0.0, 0.0);
    let [gx, gy] = gradient_at(x, y);
    let g = gx.hypot(gy);
    if g > 1e-12 && g.is_finite() {
        // On a plane of slope α the ball touches uphill at horizontal offset r·sin α.
        let offset = r * g / (1.0 + g * g).sqrt();
        z = z.max(sample(offset * gx / g, offset * gy / g));
    }
    for ring in [0.25, 0.5, 0.9] {
        for k in 0..8 {
            let (sa, ca) = (f64::from(k) * std::f64::consts::FRAC_PI_4).sin_cos();
            z = z.max(sample(ring * r * ca, ring * r * sa));
        }
    }
    z
}

/// Rests the chassis on its wheels at (xy, yaw), or says why it cannot be there. A pose
/// tilted beyond `max_tilt_rad` is refused unless it is less tilted than `current_tilt_rad`:
/// a rover that ended up at the limit may always move back toward level ground (otherwise a
/// turn that brought its roll to exactly the limit would lock it in place for good).
pub(super) fn place(
    pw: &PhysicsWorld,
    geo: &Geometry,
    cfg: &RoverConfig,
    terrain: &Heightfield,
    (xy, yaw): ([f64; 2], f64),
    current_tilt_rad: f64,
    current_footprint: Option<(&Pose, f32)>,
) -> Result<Placement, Blocked> {
    let climbable = pw.query_pipeline_with_filter(
        QueryFilter::only_fixed().groups(query_groups(CLIMBABLE_ROCK_GROUP)),
    );
    let wheel_z = wheel_heights(geo, terrain, &climbable, (xy, yaw))?;
    // FL, FR, RL, RR.
    let front = 0.5 * (wheel_z[0] + wheel_z[1]);
    let rear = 0.5 * (wheel_z[2] + wheel_z[3]);
    let left = 0.5 * (wheel_z[0] + wheel_z[2]);
    let right = 0.5 * (wheel_z[1] + wheel_z[3]);
    let pitch = -(front - rear).atan2(cfg.wheelbase_m);
    let roll = (left - right).atan2(cfg.track_m);
    let tilt_rad = pitch.abs().max(roll.abs());
    if tilt_rad > cfg.max_tilt_rad && tilt_rad >= current_tilt_rad {
        return Err(Blocked::Slope);
    }
    let rotation = quat_from_yaw_pitch_roll(yaw, pitch, roll);
    let contact_centre = DVec3::new(
        xy[0],
        xy[1],
        0.25 * wheel_z.iter().sum::<f64>() - geo.wheel_radius_m,
    );
    let position = contact_centre + rotation * DVec3::new(0.0, 0.0, geo.centre_above_contact_m);
    let footprint_pose = geo.footprint_pose(position, rotation);
    let blocking = pw.query_pipeline_with_filter(
        QueryFilter::only_fixed().groups(query_groups(BLOCKING_ROCK_GROUP)),
    );
    if let Some((h, _)) = blocking
        .intersect_shape(footprint_pose, &geo.footprint)
        .next()
        && !current_footprint.is_some_and(|(current, min_reduction_m)| {
            separates_from_rock(
                pw,
                h,
                &geo.footprint,
                (current, &footprint_pose),
                min_reduction_m,
            )
        })
    {
        return Err(Blocked::Rock(h, footprint_pose));
    }
    Ok(Placement {
        position,
        rotation,
        tilt_rad,
    })
}

/// Centre heights of the four wheels (FL, FR, RL, RR) of a chassis at `xy` heading `yaw`: each resting on the terrain or on a climbable rock beneath it,
/// whichever is higher; `Boundary` when a wheel leaves the terrain.
fn wheel_heights(
    geo: &Geometry,
    terrain: &Heightfield,
    climbable: &QueryPipeline<'_>,
    (xy, yaw): ([f64; 2], f64),
) -> Result<[f64; 4], Blocked> {
    let (s, c) = yaw.sin_cos();
    let r = geo.wheel_radius_m;
    let mut wheel_z = [0.0f64; 4];
    for (z, p) in wheel_z.iter_mut().zip(geo.wheels_body_m) {
        let wx = xy[0] + c * p[0] - s * p[1];
        let wy = xy[1] + s * p[0] + c * p[1];
        let inside = (geo.x_range_m[0]..=geo.x_range_m[1]).contains(&wx)
            && (geo.y_range_m[0]..=geo.y_range_m[1]).contains(&wy);
        if !inside {
            return Err(Blocked::Boundary);
        }
        let ground_z = terrain.height_at(wx, wy);
        *z = wheel_on_terrain_z(
            |x, y| terrain.height_at(x, y),
            |x, y| terrain.gradient_at(x, y),
            wx,
            wy,
            r,
        );
        // Climbable rocks: sweep the wheel ball down from above the tallest of them.
        let start = DVec3::new(wx, wy, ground_z + geo.sweep_height_m);
        let max_toi = geo.sweep_height_m + SWEEP_MARGIN_M;
        let hit = climbable.cast_shape(
            &Pose::from_translation(to_f32(start)),
            Vec3::new(0.0, 0.0, -1.0),
            &geo.wheel,
            ShapeCastOptions::with_max_time_of_impact(max_toi as f32),
        );
        if let Some((_, hit)) = hit {
            *z = z.max(start.z - f64::from(hit.time_of_impact));
        }
    }
    Ok(wheel_z)
}
