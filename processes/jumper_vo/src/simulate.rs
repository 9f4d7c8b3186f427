//! Offline hop simulation: renders the analytic Table-1 hop with the world rasterizer and samples
//! a noisy altimeter, so tests and `hopnav eval vo` can run the pipeline without IPC or physics.
//!
//! The camera follows `world_from_body(t) · body_from_camera`; frame `k` is taken at
//! `t = k / fps` after launch; the altimeter reads the body altitude plus `N(0, σ²)`.
//! Frames listed in `blackout_frames` are rendered black (sensor dropout, for robustness tests).
//!
//! ```no_run
//! use hopnav_jumper_vo::simulate::{SimConfig, simulate_hop};
//! let hop = simulate_hop(&SimConfig::default()).unwrap();
//! assert_eq!(hop.images.len(), 47);
//! ```

use crate::config::JumperVoConfig;
use crate::frames::body_from_camera;
use crate::rng::NoiseRng;
use crate::trajectory::HopTrajectory;
use hopnav_world::camera::CameraConfig;
use hopnav_world::raster::{RenderConfig, RenderScene, Renderer};
use hopnav_world::{World, WorldConfig};
use nalgebra::{Isometry3, Point3, Vector3};

pub use hopnav_world::SimError;

/// What to simulate.
#[derive(Debug, Clone, PartialEq)]
pub struct SimConfig {
    /// Terrain, rocks and texture.
    pub world: WorldConfig,
    /// Hop parameters; `launch_position_m.z` is replaced by ground height + `start_height_m`.
    pub hop: HopTrajectory,
    /// Height of the body origin above the terrain at launch, metres.
    pub start_height_m: f64,
    /// Camera pitch below body −x, radians.
    pub mount_pitch_down_rad: f64,
    /// Camera centre in the body frame, metres.
    pub camera_offset_body_m: Vector3<f64>,
    /// Camera intrinsics and near plane.
    pub camera: CameraConfig,
    /// Renderer options (pixel noise, sky value).
    pub render: RenderConfig,
    /// Frame rate, frames per second.
    pub fps: f64,
    /// Frames to render; `None`: every frame up to touchdown.
    pub num_frames: Option<usize>,
    /// Altimeter noise σ, metres.
    pub altimeter_sigma_m: f64,
    /// Seed of the altimeter noise (and of the pixel noise).
    pub seed: u64,
    /// Frames rendered black.
    pub blackout_frames: Vec<usize>,
}

impl Default for SimConfig {
    fn default() -> Self {
        let mut world = WorldConfig::default();
        world.terrain.size_x_m = 80.0;
        world.terrain.size_y_m = 64.0;
        let mut hop = HopTrajectory::table1();
        hop.launch_position_m = Point3::new(-10.0, 0.0, 0.0);
        Self {
            world,
            hop,
            start_height_m: 0.3,
            mount_pitch_down_rad: 30f64.to_radians(),
            camera_offset_body_m: Vector3::new(-0.1, 0.0, 0.0),
            camera: CameraConfig::default(),
            render: RenderConfig::default(),
            fps: 10.0,
            num_frames: None,
            altimeter_sigma_m: 1.0,
            seed: 1,
            blackout_frames: Vec::new(),
        }
    }
}

/// A rendered hop: images, truth and sensor samples, one entry per frame.
#[derive(Debug, Clone)]
pub struct SimulatedHop {
    /// Image width, pixels.
    pub width_px: usize,
    /// Image height, pixels.
    pub height_px: usize,
    /// Intrinsics in the vision library's type.
    pub camera: hopnav_vision::camera::PinholeCamera,
    /// The hop actually flown (launch altitude on the terrain).
    pub hop: HopTrajectory,
    /// Mount used to render.
    pub body_from_camera: Isometry3<f64>,
    /// Frame times since launch, seconds.
    pub t_s: Vec<f64>,
    /// Packed 8-bit grayscale frames.
    pub images: Vec<Vec<u8>>,
    /// Truth `world_from_body` per frame.
    pub truth_world_from_body: Vec<Isometry3<f64>>,
    /// Noisy altimeter per frame, metres.
    pub altimeter_m: Vec<f64>,
}

impl SimulatedHop {
    /// `config` with the robot model of this simulation: its launch spin (the analytic hop
    /// pitches about body y at `pitch_rate_radps`, nose-up positive) and no landing slide
    /// (the analytic hop stops dead at touchdown). The VO's settings are kept.
    pub fn robot_config(&self, config: &JumperVoConfig) -> JumperVoConfig {
        JumperVoConfig {
            launch_angular_velocity_body_radps: [0.0, -self.hop.pitch_rate_radps, 0.0],
            landing_slide_decay_per_s: 0.0,
            ..config.clone()
        }
    }
}

/// Renders the hop of `cfg`.
pub fn simulate_hop(cfg: &SimConfig) -> Result<SimulatedHop, SimError> {
    if !(cfg.fps.is_finite() && cfg.fps > 0.0 && cfg.fps <= 1000.0) {
        return Err(SimError::BadParameter {
            key: "fps",
            message: format!("must be in (0, 1000], got {}", cfg.fps),
        });
    }
    if !(cfg.altimeter_sigma_m.is_finite() && cfg.altimeter_sigma_m >= 0.0) {
        return Err(SimError::BadParameter {
            key: "altimeter_sigma_m",
            message: format!("must be finite and >= 0, got {}", cfg.altimeter_sigma_m),
        });
    }
    let world = World::generate(&cfg.world)?;
    let mut hop = cfg.hop;
    let ground_m = world.ground_height_at(hop.launch_position_m.x, hop.launch_position_m.y);
    hop.launch_position_m.z = ground_m + cfg.start_height_m;
    let body_from_camera = body_from_camera(cfg.mount_pitch_down_rad, &cfg.camera_offset_body_m);
    let mut render_cfg = cfg.render.clone();
    render_cfg.noise_seed = cfg.render.noise_seed ^ cfg.seed;
    let mut renderer = Renderer::new(&cfg.camera, &render_cfg)?;
    let scene = RenderScene::new(&world)?;
    renderer.prepare(&scene);
    let wc = renderer.camera();
    let camera = hopnav_vision::camera::PinholeCamera::new(
        wc.width_px,
        wc.height_px,
        wc.fx_px,
        wc.fy_px,
        wc.cx_px,
        wc.cy_px,
    )
    // The renderer validated this camera; only a field of view too small to give a finite
    // focal length gets here.
    .map_err(|error| SimError::BadParameter {
        key: "camera",
        message: error.to_string(),
    })?;
    let (w, h) = (wc.width_px as usize, wc.height_px as usize);
    let num_frames = cfg
        .num_frames
        .unwrap_or_else(|| (hop.flight_time_s() * cfg.fps).floor() as usize + 1);
    let mut rng = NoiseRng::new(cfg.seed);
    let mut out = SimulatedHop {
        width_px: w,
        height_px: h,
        camera,
        hop,
        body_from_camera,
        t_s: Vec::with_capacity(num_frames),
        images: Vec::with_capacity(num_frames),
        truth_world_from_body: Vec::with_capacity(num_frames),
        altimeter_m: Vec::with_capacity(num_frames),
    };
    for k in 0..num_frames {
        let t = k as f64 / cfg.fps;
        let world_from_body = hop.world_from_body(t);
        let mut image = vec![0u8; w * h];
        if !cfg.blackout_frames.contains(&k) {
            renderer.render(
                &scene,
                &(world_from_body * body_from_camera),
                k as u64,
                &mut image,
                w,
            )?;
        }
        out.t_s.push(t);
        out.images.push(image);
        out.truth_world_from_body.push(world_from_body);
        out.altimeter_m
            .push(world_from_body.translation.z + cfg.altimeter_sigma_m * rng.gaussian());
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_hop_renders_textured_ground() {
        let mut cfg = SimConfig::default();
        cfg.world.terrain.size_x_m = 48.0;
        cfg.world.terrain.size_y_m = 32.0;
        cfg.num_frames = Some(3);
        cfg.blackout_frames = vec![2];
        let hop = simulate_hop(&cfg).unwrap();
        assert_eq!(hop.images.len(), 3);
        let img = &hop.images[1];
        let mean = img.iter().map(|&v| f64::from(v)).sum::<f64>() / img.len() as f64;
        let var = img
            .iter()
            .map(|&v| (f64::from(v) - mean).powi(2))
            .sum::<f64>()
            / img.len() as f64;
        assert!(var > 20.0, "texture variance {var}");
        assert!(hop.images[2].iter().all(|&v| v == 0));
        // Launch is above the ground.
        assert!(hop.truth_world_from_body[0].translation.z > 0.0 || cfg.start_height_m > 0.0);
    }
}
