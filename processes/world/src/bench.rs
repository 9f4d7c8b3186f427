//! Own-harness render benchmark: N frames of 320×320 from jumper-like poses.
//!
//! ```no_run
//! let report = hopnav_world::bench::render_bench(&hopnav_world::bench::RenderBenchOptions::default()).unwrap();
//! println!("{report}");
//! ```

use std::fmt;
use std::time::Instant;

use nalgebra::{Point3, Vector3};

use crate::camera::{CameraConfig, look_at};
use crate::error::{RenderError, WorldError};
use crate::raster::{RenderConfig, RenderScene, RenderStats, Renderer};
use crate::rng::Rng;
use crate::{World, WorldConfig};

/// Benchmark options.
#[derive(Debug, Clone)]
pub struct RenderBenchOptions {
    /// World to render (default: the default world, 64 m × 64 m).
    pub world: WorldConfig,
    /// Camera (default: 320×320, 45°).
    pub camera: CameraConfig,
    /// Renderer options.
    pub render: RenderConfig,
    /// Frames timed.
    pub frames: usize,
    /// Untimed frames first.
    pub warmup_frames: usize,
    /// Lowest and highest camera height above the ground, metres.
    pub height_range_m: (f64, f64),
    /// Lowest and highest downward pitch of the optical axis, radians.
    pub pitch_range_rad: (f64, f64),
    /// Seed of the pose sequence.
    pub seed: u64,
    /// Renders per pose; the fastest counts. 1 = plain per-frame timing. More than 1 filters
    /// out preemption on a loaded machine (it estimates the uncontended cost).
    pub repeats_per_pose: usize,
}

impl Default for RenderBenchOptions {
    fn default() -> Self {
        Self {
            world: WorldConfig::default(),
            camera: CameraConfig::default(),
            render: RenderConfig::default(),
            frames: 500,
            warmup_frames: 20,
            height_range_m: (0.5, 15.0),
            pitch_range_rad: (0.15, 1.3),
            seed: 42,
            repeats_per_pose: 1,
        }
    }
}

/// Benchmark failure.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// The world or scene could not be built.
    #[error(transparent)]
    World(#[from] WorldError),
    /// The renderer rejected its config or a frame.
    #[error(transparent)]
    Render(#[from] RenderError),
}

/// Timing results, milliseconds per frame.
#[derive(Debug, Clone)]
pub struct RenderBenchReport {
    /// Frames timed.
    pub frames: usize,
    /// Image size.
    pub width_px: u32,
    /// Image size.
    pub height_px: u32,
    /// World generation time, milliseconds.
    pub world_ms: f64,
    /// Scene (texture bake) time, milliseconds.
    pub scene_ms: f64,
    /// Median frame time.
    pub p50_ms: f64,
    /// 99th percentile frame time.
    pub p99_ms: f64,
    /// Slowest frame.
    pub max_ms: f64,
    /// Mean frame time.
    pub mean_ms: f64,
    /// Mean triangles submitted per frame.
    pub mean_triangles: f64,
    /// Rocks in the world.
    pub rocks: usize,
    /// Renders per pose (the fastest counted).
    pub repeats_per_pose: usize,
    /// What the slowest frame drew.
    pub slowest: RenderStats,
    /// Bytes of baked textures (all mip levels).
    pub texture_bytes: usize,
}

impl fmt::Display for RenderBenchReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let best = if self.repeats_per_pose > 1 {
            format!(" (best of {} per pose)", self.repeats_per_pose)
        } else {
            String::new()
        };
        write!(
            f,
            "render {}x{}: {} frames{best}, p50 {:.3} ms, p99 {:.3} ms, max {:.3} ms, mean {:.3} ms \
             ({:.0} triangles/frame, slowest frame {} chunks {} triangles {} rocks; \
             world {} rocks built in {:.0} ms, scene in {:.0} ms, textures {:.1} MB)",
            self.width_px,
            self.height_px,
            self.frames,
            self.p50_ms,
            self.p99_ms,
            self.max_ms,
            self.mean_ms,
            self.mean_triangles,
            self.slowest.chunks_drawn,
            self.slowest.triangles,
            self.slowest.rocks_drawn,
            self.rocks,
            self.world_ms,
            self.scene_ms,
            self.texture_bytes as f64 / 1e6
        )
    }
}

/// Renders `frames` images from random jumper-like poses (height above ground and downward
/// pitch drawn from the option ranges, random heading) on the calling thread.
pub fn render_bench(opts: &RenderBenchOptions) -> Result<RenderBenchReport, BenchError> {
    let t0 = Instant::now();
    let world = World::generate(&opts.world)?;
    let world_ms = t0.elapsed().as_secs_f64() * 1e3;
    let t1 = Instant::now();
    let scene = RenderScene::new(&world)?;
    let scene_ms = t1.elapsed().as_secs_f64() * 1e3;
    let mut renderer = Renderer::new(&opts.camera, &opts.render).map_err(RenderError::from)?;
    renderer.prepare(&scene);
    let (w, h) = (opts.camera.width_px, opts.camera.height_px);
    let stride = w as usize;
    let mut image = vec![0u8; stride * h as usize];
    let mut rng = Rng::new(opts.seed, 0xbe_4c);
    let [ex, ey] = world.terrain().extent_m();
    let mut times = Vec::with_capacity(opts.frames);
    let mut triangles = 0u64;
    let mut slowest = RenderStats::default();
    for i in 0..opts.warmup_frames + opts.frames {
        // Stay in the inner 80 % so most views look at terrain, like a hop over the map.
        let x = rng.uniform(-0.4 * ex, 0.4 * ex);
        let y = rng.uniform(-0.4 * ey, 0.4 * ey);
        let alt = rng.uniform(opts.height_range_m.0, opts.height_range_m.1);
        let pitch = rng.uniform(opts.pitch_range_rad.0, opts.pitch_range_rad.1);
        let yaw = rng.uniform(0.0, std::f64::consts::TAU);
        let eye = Point3::new(x, y, world.ground_height_at(x, y) + alt);
        let dir = Vector3::new(
            pitch.cos() * yaw.cos(),
            pitch.cos() * yaw.sin(),
            -pitch.sin(),
        );
        let pose = look_at(&eye, &(eye + dir), &Vector3::z());
        let mut dt = f64::INFINITY;
        let mut stats = Default::default();
        for _ in 0..opts.repeats_per_pose.max(1) {
            let t = Instant::now();
            stats = renderer.render(&scene, &pose, i as u64, &mut image, stride)?;
            dt = dt.min(t.elapsed().as_secs_f64() * 1e3);
        }
        if i >= opts.warmup_frames {
            if times.iter().all(|&t| t < dt) {
                slowest = stats;
            }
            times.push(dt);
            triangles += u64::from(stats.triangles);
        }
    }
    let n = times.len().max(1);
    let mean_ms = times.iter().sum::<f64>() / n as f64;
    times.sort_by(f64::total_cmp);
    let pct = |p: f64| -> f64 {
        if times.is_empty() {
            return 0.0;
        }
        let idx = ((p * (times.len() - 1) as f64).round() as usize).min(times.len() - 1);
        times[idx]
    };
    Ok(RenderBenchReport {
        frames: times.len(),
        width_px: w,
        height_px: h,
        world_ms,
        scene_ms,
        p50_ms: pct(0.5),
        p99_ms: pct(0.99),
        max_ms: times.last().copied().unwrap_or(0.0),
        mean_ms,
        mean_triangles: triangles as f64 / n as f64,
        rocks: world.rocks().len(),
        repeats_per_pose: opts.repeats_per_pose.max(1),
        slowest,
        texture_bytes: scene.texture_bytes(),
    })
}
