//! Own-harness benchmark of the physics step: wall time per 100 ms frame (all substeps,
//! controller, queries and sensors) on a generated world, with the jumper hopping back and
//! forth and the rover driving a square.
//!
//! ```
//! use hopnav_physics::bench::{PhysicsBenchConfig, run_physics_bench};
//! let mut cfg = PhysicsBenchConfig::default();
//! cfg.frames = 5;
//! cfg.warmup_frames = 0;
//! cfg.world.terrain.size_x_m = 40.0;
//! cfg.world.terrain.size_y_m = 16.0;
//! let report = run_physics_bench(&cfg).unwrap();
//! assert_eq!(report.frames, 5);
//! ```

use std::fmt;
use std::time::Instant;

use hopnav_world::{World, WorldConfig};

use crate::config::PhysicsConfig;
use crate::error::BenchError;
use crate::frame::{DriveCommand, FrameInputs, FrameOutputs, HopRequest, HopState};
use crate::sim::PhysicsSim;

/// What to benchmark.
#[derive(Debug, Clone, PartialEq)]
pub struct PhysicsBenchConfig {
    /// Timed frames.
    pub frames: u32,
    /// Untimed frames first.
    pub warmup_frames: u32,
    /// Noise seed.
    pub seed: u64,
    /// The world (default: 64 m × 64 m at 0.25 m with Golombek rocks, k = 0.07).
    pub world: WorldConfig,
    /// The physics.
    pub physics: PhysicsConfig,
}

impl Default for PhysicsBenchConfig {
    fn default() -> Self {
        Self {
            frames: 2000,
            warmup_frames: 20,
            seed: 1,
            world: WorldConfig::default(),
            physics: PhysicsConfig::default(),
        }
    }
}

/// Timing percentiles, microseconds.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Percentiles {
    /// Median.
    pub p50_us: f64,
    /// 99th percentile.
    pub p99_us: f64,
    /// Maximum.
    pub max_us: f64,
    /// Mean.
    pub mean_us: f64,
}

impl Percentiles {
    /// Percentiles of `samples_us` (sorted in place).
    pub fn of(samples_us: &mut [f64]) -> Self {
        if samples_us.is_empty() {
            return Self::default();
        }
        samples_us.sort_by(f64::total_cmp);
        let at = |q: f64| samples_us[((samples_us.len() - 1) as f64 * q).round() as usize];
        Self {
            p50_us: at(0.5),
            p99_us: at(0.99),
            max_us: at(1.0),
            mean_us: samples_us.iter().sum::<f64>() / samples_us.len() as f64,
        }
    }
}

/// Results of one benchmark run.
#[derive(Debug, Clone, PartialEq)]
pub struct PhysicsBenchReport {
    /// Timed frames.
    pub frames: u32,
    /// Substeps per frame.
    pub substeps: u32,
    /// Frame period, seconds.
    pub frame_period_s: f64,
    /// Heightfield nodes (nx, ny).
    pub grid_nodes: [usize; 2],
    /// Rock colliders.
    pub rocks: usize,
    /// Rocks taller than the rover can climb.
    pub blocking_rocks: usize,
    /// World generation time, milliseconds.
    pub world_ms: f64,
    /// `PhysicsSim::new` time (colliders, hulls), milliseconds.
    pub setup_ms: f64,
    /// Wall time per frame (all substeps).
    pub frame: Percentiles,
    /// Mean wall time per substep, microseconds.
    pub substep_mean_us: f64,
    /// Hops launched during the run.
    pub hops: u32,
    /// Horizontal distance the rover drove, metres.
    pub rover_path_m: f64,
    /// Rover rock collisions.
    pub rover_collisions: u32,
}

impl fmt::Display for PhysicsBenchReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let budget_us = self.frame_period_s * 1e6;
        writeln!(
            f,
            "physics bench: {} frames x {} substeps, {}x{} heightfield, {} rocks ({} block the rover)",
            self.frames,
            self.substeps,
            self.grid_nodes[0],
            self.grid_nodes[1],
            self.rocks,
            self.blocking_rocks
        )?;
        writeln!(
            f,
            "  setup: world {:.1} ms, physics {:.1} ms",
            self.world_ms, self.setup_ms
        )?;
        writeln!(
            f,
            "  per frame: p50 {:.1} us  p99 {:.1} us  max {:.1} us  mean {:.1} us  (p99 = {:.3} % of the {:.0} ms budget)",
            self.frame.p50_us,
            self.frame.p99_us,
            self.frame.max_us,
            self.frame.mean_us,
            100.0 * self.frame.p99_us / budget_us,
            self.frame_period_s * 1e3
        )?;
        writeln!(f, "  per substep: mean {:.1} us", self.substep_mean_us)?;
        write!(
            f,
            "  activity: {} hops, rover drove {:.1} m, {} rock collisions",
            self.hops, self.rover_path_m, self.rover_collisions
        )
    }
}

/// What the benchmark asks of the robots: the jumper hops between two points 20 m apart
/// whenever settled; the rover drives a 6 m square around its start, skipping a corner after
/// 50 frames blocked.
struct BenchDriver {
    hop_targets: [[f64; 2]; 2],
    next_hop: usize,
    corners: [[f64; 2]; 4],
    corner: usize,
    blocked_frames: u32,
}

impl BenchDriver {
    fn new(physics: &PhysicsConfig) -> Self {
        let [jx, jy] = physics.jumper.start_xy_m;
        let [rx, ry] = physics.rover.start_xy_m;
        Self {
            hop_targets: [[jx + 20.0, jy], [jx, jy]],
            next_hop: 0,
            corners: [
                [rx + 6.0, ry],
                [rx + 6.0, ry - 6.0],
                [rx, ry - 6.0],
                [rx, ry],
            ],
            corner: 0,
            blocked_frames: 0,
        }
    }

    /// The next frame's inputs, after the frame that produced `last`.
    fn inputs(&mut self, last: &FrameOutputs) -> FrameInputs {
        let st = last.rover_status;
        if st.mode == crate::frame::RoverMode::Arrived || self.blocked_frames >= 50 {
            self.corner = (self.corner + 1) % self.corners.len();
            self.blocked_frames = 0;
        }
        self.blocked_frames = if st.blocked.is_some() {
            self.blocked_frames + 1
        } else {
            0
        };
        let hop_request = (last.jumper_status.state == HopState::Settled
            && last.jumper_status.pending_target_xy_m.is_none())
        .then(|| {
            self.next_hop = (self.next_hop + 1) % self.hop_targets.len();
            HopRequest {
                target_xy_m: self.hop_targets[self.next_hop],
            }
        });
        FrameInputs {
            drive: Some(DriveCommand {
                waypoint_xy_m: self.corners[self.corner],
                speed_mps: 0.5,
                hold: false,
                reverse: false,
            }),
            hop_request,
        }
    }
}

/// Runs the benchmark: the jumper hops between two points 20 m apart whenever settled; the rover
/// drives a 6 m square around its start, skipping a corner after 5 s blocked.
pub fn run_physics_bench(cfg: &PhysicsBenchConfig) -> Result<PhysicsBenchReport, BenchError> {
    let t0 = Instant::now();
    let world = World::generate(&cfg.world)?;
    let world_ms = t0.elapsed().as_secs_f64() * 1e3;
    let t1 = Instant::now();
    let mut sim = PhysicsSim::new(&world, &cfg.physics, cfg.seed)?;
    let setup_ms = t1.elapsed().as_secs_f64() * 1e3;

    let mut driver = BenchDriver::new(&cfg.physics);
    let [rx, ry] = cfg.physics.rover.start_xy_m;
    let mut samples_us = Vec::with_capacity(cfg.frames as usize);
    let mut path_m = 0.0;
    let mut last_xy = [rx, ry];
    let total = cfg.warmup_frames + cfg.frames;
    for k in 0..total {
        let inputs = driver.inputs(sim.last_outputs());
        let t = Instant::now();
        let out = sim.step_frame(&inputs);
        let us = t.elapsed().as_secs_f64() * 1e6;
        if k >= cfg.warmup_frames {
            samples_us.push(us);
        }
        let [x, y, _] = out.rover.position_m;
        path_m += (x - last_xy[0]).hypot(y - last_xy[1]);
        last_xy = [x, y];
    }
    let frame = Percentiles::of(&mut samples_us);
    let substeps = cfg.physics.substeps;
    let cols = sim.world_colliders();
    Ok(PhysicsBenchReport {
        frames: cfg.frames,
        substeps,
        frame_period_s: cfg.physics.frame_period_s,
        grid_nodes: [world.terrain().nx(), world.terrain().ny()],
        rocks: cols.rock_count(),
        blocking_rocks: cols.blocking_count(),
        world_ms,
        setup_ms,
        frame,
        substep_mean_us: frame.mean_us / f64::from(substeps.max(1)),
        hops: sim.hop_count(),
        rover_path_m: path_m,
        rover_collisions: sim.rover_collisions(),
    })
}
