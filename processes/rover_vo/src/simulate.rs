//! Offline rover traverse: a scripted path on the terrain, the body posed on the terrain (height
//! and normal), the stereo pair rendered with the world rasterizer, and a noisy IMU attitude —
//! no IPC and no physics, so tests and evaluations run anywhere.
//!
//! The rover drives straight between waypoints at `speed_mps` and turns on the spot at
//! `yaw_rate_radps` at each waypoint. Body: x forward along the heading projected on the
//! terrain's tangent plane, z along the terrain normal, origin `body_height_m` above the ground.
//! IMU attitude: truth · exp(N(0, σ²) per axis), then a yaw drift `yaw_drift_radps · t`.
//! Frames listed in `blackout_frames` are rendered black in both views (textureless).
//!
//! ```no_run
//! use hopnav_rover_vo::simulate::{TraverseConfig, simulate_traverse};
//! let sim = simulate_traverse(&TraverseConfig::default()).unwrap();
//! assert!(sim.distance_m() > 50.0);
//! ```

use crate::motion::Intrinsics;
use crate::pipeline::StereoRig;
use hopnav_robot::camera::{CameraMount, CameraRig};
use hopnav_vision::rng::XorShiftRng;
use hopnav_world::camera::{CameraConfig, PinholeCamera};
use hopnav_world::raster::{RenderConfig, RenderScene, Renderer};
use hopnav_world::{World, WorldConfig};
use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector3};

pub use hopnav_world::SimError;

/// What to simulate.
#[derive(Debug, Clone, PartialEq)]
pub struct TraverseConfig {
    /// Terrain, rocks and texture (default: `WorldConfig::default()`).
    pub world: WorldConfig,
    /// Path: the rover starts at the first waypoint facing the second.
    pub waypoints_xy_m: Vec<[f64; 2]>,
    /// Driving speed, m/s.
    pub speed_mps: f64,
    /// Turn-on-the-spot rate, rad/s.
    pub yaw_rate_radps: f64,
    /// Frame rate, frames per second.
    pub fps: f64,
    /// Body origin above the ground, metres.
    pub body_height_m: f64,
    /// Stereo intrinsics (both views).
    pub camera: CameraConfig,
    /// Stereo mount (midpoint of the pair) in the body frame.
    pub mount: CameraMount,
    /// Baseline, metres.
    pub baseline_m: f64,
    /// Renderer options.
    pub render: RenderConfig,
    /// IMU attitude noise σ per axis, radians.
    pub imu_noise_rad: f64,
    /// IMU yaw drift, rad/s.
    pub imu_yaw_drift_radps: f64,
    /// Noise seed.
    pub seed: u64,
    /// Frames rendered black.
    pub blackout_frames: Vec<usize>,
    /// Stop after this many frames (`None`: the whole path).
    pub max_frames: Option<usize>,
}

impl Default for TraverseConfig {
    fn default() -> Self {
        let rig = CameraRig::default();
        Self {
            world: WorldConfig::default(),
            // 40 m east, a 90° turn on the spot, 16 m north: 56 m.
            waypoints_xy_m: vec![[-22.0, -16.0], [18.0, -16.0], [18.0, 0.0]],
            speed_mps: 0.5,
            yaw_rate_radps: 0.5,
            fps: 10.0,
            body_height_m: 0.42,
            // The rover's stereo pair as the camera process renders it.
            camera: rig.rover,
            mount: rig.rover_mount,
            baseline_m: rig.rover_baseline_m,
            render: RenderConfig::default(),
            imu_noise_rad: 0.002,
            imu_yaw_drift_radps: 1e-4,
            seed: 1,
            blackout_frames: Vec::new(),
            max_frames: None,
        }
    }
}

/// A rendered traverse, one entry per frame.
#[derive(Debug, Clone)]
pub struct SimulatedTraverse {
    /// Stereo geometry (left camera mount, intrinsics, baseline).
    pub rig: StereoRig,
    /// Frame times, seconds.
    pub t_s: Vec<f64>,
    /// Left views, packed 8-bit.
    pub left: Vec<Vec<u8>>,
    /// Right views, packed 8-bit.
    pub right: Vec<Vec<u8>>,
    /// Truth `world_from_body`.
    pub truth_world_from_body: Vec<Isometry3<f64>>,
    /// Noisy IMU attitude.
    pub imu_attitude: Vec<UnitQuaternion<f64>>,
    /// Ground height under the start, metres (what the config would say).
    pub start_ground_z_m: f64,
    /// Smallest horizontal clearance between the body origin and a rock footprint, metres
    /// (the scripted path ignores rocks; rocks are lower than the camera, ≤ 0.6 m).
    pub min_rock_clearance_m: f64,
    /// The world rendered (for evaluating cloud heights).
    pub world: World,
}

impl SimulatedTraverse {
    /// Length of the truth path, metres.
    pub fn distance_m(&self) -> f64 {
        self.truth_world_from_body
            .windows(2)
            .map(|w| (w[1].translation.vector - w[0].translation.vector).norm())
            .sum()
    }
}

/// Body pose on the terrain at `(x, y)` with heading `yaw_rad`.
fn body_on_terrain(world: &World, x: f64, y: f64, yaw_rad: f64, height_m: f64) -> Isometry3<f64> {
    let n = Vector3::from(world.terrain().normal_at(x, y));
    let heading = Vector3::new(yaw_rad.cos(), yaw_rad.sin(), 0.0);
    let bx = (heading - n * heading.dot(&n)).normalize();
    let by = n.cross(&bx);
    let rot = Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[bx, by, n]));
    let z = world.ground_height_at(x, y) + height_m;
    Isometry3::from_parts(
        Translation3::new(x, y, z),
        UnitQuaternion::from_rotation_matrix(&rot),
    )
}

/// Planar path samples `(x, y, yaw)` at `1/fps` steps.
fn path_samples(cfg: &TraverseConfig) -> Vec<(f64, f64, f64)> {
    let step_m = cfg.speed_mps / cfg.fps;
    let turn_step = cfg.yaw_rate_radps / cfg.fps;
    let mut out = Vec::new();
    let wp = &cfg.waypoints_xy_m;
    let mut yaw = (wp[1][1] - wp[0][1]).atan2(wp[1][0] - wp[0][0]);
    for seg in wp.windows(2) {
        let (a, b) = (seg[0], seg[1]);
        let target = (b[1] - a[1]).atan2(b[0] - a[0]);
        // Turn on the spot.
        loop {
            let err = (target - yaw + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI)
                - std::f64::consts::PI;
            if err.abs() <= turn_step {
                yaw = target;
                break;
            }
            yaw += turn_step * err.signum();
            out.push((a[0], a[1], yaw));
        }
        let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
        let steps = (len / step_m).floor() as usize;
        for k in 0..steps {
            let s = k as f64 * step_m / len;
            out.push((a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]), yaw));
        }
    }
    if let Some(last) = wp.last() {
        out.push((last[0], last[1], yaw));
    }
    out
}

/// Renders the traverse of `cfg`.
pub fn simulate_traverse(cfg: &TraverseConfig) -> Result<SimulatedTraverse, SimError> {
    check_traverse(cfg)?;
    let world = World::generate(&cfg.world)?;
    let mut renderer = Renderer::new(&cfg.camera, &cfg.render)?;
    let scene = RenderScene::new(&world)?;
    renderer.prepare(&scene);
    let wc = *renderer.camera();
    let rig = rig_of(&wc, cfg);
    let (w, h) = (wc.width_px as usize, wc.height_px as usize);
    let mut samples = path_samples(cfg);
    if let Some(max) = cfg.max_frames {
        samples.truncate(max);
    }
    let n = samples.len();
    let mut rng = XorShiftRng::new(cfg.seed ^ 0x5EED);
    let start = cfg.waypoints_xy_m[0];
    let mut out = SimulatedTraverse {
        rig,
        t_s: Vec::with_capacity(n),
        left: Vec::with_capacity(n),
        right: Vec::with_capacity(n),
        truth_world_from_body: Vec::with_capacity(n),
        imu_attitude: Vec::with_capacity(n),
        start_ground_z_m: world.ground_height_at(start[0], start[1]),
        min_rock_clearance_m: f64::INFINITY,
        world: World::generate(&cfg.world)?,
    };
    for (k, &(x, y, yaw)) in samples.iter().enumerate() {
        let t = k as f64 / cfg.fps;
        let body = body_on_terrain(&world, x, y, yaw, cfg.body_height_m);
        out.min_rock_clearance_m = out.min_rock_clearance_m.min(rock_clearance_m(&world, x, y));
        let mut left = vec![0u8; w * h];
        let mut right = vec![0u8; w * h];
        if !cfg.blackout_frames.contains(&k) {
            renderer.render_stereo(
                &scene,
                &(body * rig.body_from_camera),
                cfg.baseline_m,
                k as u64,
                &mut left,
                &mut right,
                w,
            )?;
        }
        out.imu_attitude
            .push(imu_attitude(&mut rng, &body.rotation, t, cfg));
        out.t_s.push(t);
        out.left.push(left);
        out.right.push(right);
        out.truth_world_from_body.push(body);
    }
    Ok(out)
}

/// Refuses a traverse without a path or with a rate that is not positive.
fn check_traverse(cfg: &TraverseConfig) -> Result<(), SimError> {
    let bad = |key, message: String| Err(SimError::BadParameter { key, message });
    if cfg.waypoints_xy_m.len() < 2 {
        return bad("waypoints_xy_m", "needs at least two waypoints".into());
    }
    for (key, v) in [
        ("fps", cfg.fps),
        ("speed_mps", cfg.speed_mps),
        ("yaw_rate_radps", cfg.yaw_rate_radps),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return bad(key, format!("must be finite and > 0, got {v}"));
        }
    }
    Ok(())
}

/// The stereo rig of the rendering camera `wc` on the configured mount and baseline.
fn rig_of(wc: &PinholeCamera, cfg: &TraverseConfig) -> StereoRig {
    StereoRig {
        width_px: wc.width_px,
        height_px: wc.height_px,
        intrinsics: Intrinsics {
            fx_px: wc.fx_px,
            fy_px: wc.fy_px,
            cx_px: wc.cx_px,
            cy_px: wc.cy_px,
        },
        baseline_m: cfg.baseline_m,
        body_from_camera: cfg.mount.body_from_left_camera(cfg.baseline_m),
    }
}

/// Horizontal distance from `(x, y)` to the nearest rock's edge, metres.
fn rock_clearance_m(world: &World, x: f64, y: f64) -> f64 {
    let mut clearance_m = f64::INFINITY;
    for rock in world.rocks() {
        let d = ((rock.center_m[0] - x).powi(2) + (rock.center_m[1] - y).powi(2)).sqrt()
            - 0.5 * rock.diameter_m;
        clearance_m = clearance_m.min(d);
    }
    clearance_m
}

/// The IMU's attitude at `t`: the true one with white noise and a yaw drift.
fn imu_attitude(
    rng: &mut XorShiftRng,
    truth: &UnitQuaternion<f64>,
    t: f64,
    cfg: &TraverseConfig,
) -> UnitQuaternion<f64> {
    let noise = Vector3::new(rng.gaussian(), rng.gaussian(), rng.gaussian()) * cfg.imu_noise_rad;
    let drift = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), cfg.imu_yaw_drift_radps * t);
    drift * truth * UnitQuaternion::from_scaled_axis(noise)
}
