//! The physics simulation: rapier world, jumper, rover and sensors, stepped one frame at a time.
//!
//! ```
//! use hopnav_physics::{FrameInputs, PhysicsConfig, PhysicsSim};
//! use hopnav_world::{World, WorldConfig};
//!
//! let mut wc = WorldConfig::default();
//! wc.terrain.size_x_m = 40.0;
//! wc.terrain.size_y_m = 16.0;
//! wc.rocks.golombek_k = 0.0;
//! let world = World::generate(&wc).unwrap();
//! let mut sim = PhysicsSim::new(&world, &PhysicsConfig::default(), 42).unwrap();
//! let out = sim.step_frame(&FrameInputs::default());
//! assert_eq!(out.frame_index, 0);
//! assert_eq!(out.jumper_status.hop_count, 1); // Table 1 hop launched at frame 0
//! ```
//!
//! # Determinism
//! Single-threaded rapier (no `parallel` feature), fixed substeps, no wall clock, and seeded
//! noise: the same world, config, seed and inputs give bitwise-identical outputs.

mod resume;

pub use resume::{ResumeError, SimSnapshot};

use hopnav_world::World;
use hopnav_world::terrain::Heightfield;
use rapier3d::parry::shape::Cuboid;
use rapier3d::prelude::{PhysicsWorld, QueryFilter};

use crate::colliders::{BLOCKING_ROCK_GROUP, CLIMBABLE_ROCK_GROUP, WorldColliders, query_groups};
use crate::config::PhysicsConfig;
use crate::error::PhysicsError;
use crate::frame::{BodyState, DriveCommand, FrameInputs, FrameOutputs, HopState};
use crate::jumper::Jumper;
use crate::math::{DVec3, Vec3};
use crate::rover::{Rover, StartError};
use crate::sensors::{Altimeter, Imu, ImuAccumulator};

/// The whole physics simulation.
pub struct PhysicsSim {
    cfg: PhysicsConfig,
    pw: PhysicsWorld,
    terrain: Heightfield,
    world_colliders: WorldColliders,
    jumper: Jumper,
    rover: Rover,
    altimeter: Altimeter,
    imu: Imu,
    imu_acc: ImuAccumulator,
    frame_index: u64,
    sim_time_s: f64,
    rejected_inputs: u32,
    last: FrameOutputs,
}

impl PhysicsSim {
    /// Builds the rapier world from `world`, places the jumper and rover at their start poses.
    ///
    /// Fails on an invalid config, a start outside the terrain, a start inside a rock, or
    /// overlapping starts.
    pub fn new(world: &World, config: &PhysicsConfig, seed: u64) -> Result<Self, PhysicsError> {
        config.validate()?;
        let terrain = world.terrain().clone();
        check_inside(
            &terrain,
            "physics.jumper.start_xy_m",
            config.jumper.start_xy_m,
            config.jumper.half_extent_m * 2.0,
        )?;
        check_inside(
            &terrain,
            "physics.rover.start_xy_m",
            config.rover.start_xy_m,
            0.0,
        )?;
        let min_gap = config.jumper.half_extent_m * std::f64::consts::SQRT_2
            + 0.5 * config.rover.wheelbase_m.hypot(config.rover.track_m)
            + config.rover.wheel_radius_m;
        let [jx, jy] = config.jumper.start_xy_m;
        let [rx, ry] = config.rover.start_xy_m;
        if (jx - rx).hypot(jy - ry) < min_gap {
            return Err(PhysicsError::StartsOverlap {
                distance_m: (jx - rx).hypot(jy - ry),
                min_distance_m: min_gap,
            });
        }

        let mut pw = PhysicsWorld::new();
        pw.gravity = Vec3::new(0.0, 0.0, -(config.gravity_mps2 as f32));
        pw.integration_parameters.dt = config.substep_s() as f32;
        pw.integration_parameters.num_solver_iterations = config.solver_iterations as usize;
        let world_colliders = WorldColliders::insert(
            &mut pw,
            world,
            config.terrain_friction,
            config.rock_friction,
            config.rover.max_climbable_height_m,
        );
        // Build the broad phase so the start poses can be checked with scene queries.
        pw.detect_collisions(&(), &());
        check_jumper_start(&pw, world, &world_colliders, config)?;
        let rover = Rover::new(&mut pw, &config.rover, &terrain).map_err(|e| {
            let [x_m, y_m] = config.rover.start_xy_m;
            match e {
                StartError::InsideRock {
                    collider,
                    footprint_pose,
                    footprint,
                } => {
                    let index = world_colliders.rock_at(&pw, collider, &footprint_pose, &footprint);
                    rock_error(world, "physics.rover.start_xy_m", [x_m, y_m], index)
                }
                StartError::OutsideTerrain | StartError::TooSteep => {
                    outside_error(&terrain, "physics.rover.start_xy_m", [x_m, y_m], 0.0)
                }
            }
        })?;
        let jumper = Jumper::new(&mut pw, &config.jumper, &terrain);
        let mut sim = Self {
            cfg: config.clone(),
            pw,
            terrain,
            world_colliders,
            jumper,
            rover,
            altimeter: Altimeter::new(&config.altimeter, seed),
            imu: Imu::new(&config.imu, seed),
            imu_acc: ImuAccumulator::default(),
            frame_index: 0,
            sim_time_s: 0.0,
            rejected_inputs: 0,
            last: FrameOutputs::default(),
        };
        sim.last.jumper = sim.jumper.body_state(&sim.pw);
        sim.last.rover = sim.rover.body_state();
        Ok(sim)
    }

    /// Simulates one frame (`substeps` fixed physics steps) and returns its outputs.
    pub fn step_frame(&mut self, inputs: &FrameInputs) -> FrameOutputs {
        self.apply_inputs(inputs);
        let dt = self.cfg.substep_s();
        let g = self.cfg.gravity_mps2;
        self.jumper
            .begin_frame(&mut self.pw, &self.cfg.jumper, &self.terrain, g);
        for _ in 0..self.cfg.substeps {
            self.rover
                .pre_substep(&mut self.pw, &self.cfg.rover, &self.terrain, dt);
            self.pw.step();
            self.jumper.after_substep(&self.pw, &self.cfg.jumper, dt);
            self.imu_acc.add(
                self.rover.rotation(),
                self.rover.acceleration_world_mps2(),
                self.rover.angular_velocity_world_radps(),
                g,
            );
        }
        self.jumper
            .end_frame(&self.pw, &self.cfg.jumper, self.cfg.frame_period_s);
        self.sim_time_s = (self.frame_index + 1) as f64 * self.cfg.frame_period_s;

        let jumper = self.jumper.body_state(&self.pw);
        let rover = self.rover.body_state();
        let (force, rate) = self.imu_acc.take_mean();
        let out = FrameOutputs {
            frame_index: self.frame_index,
            sim_time_s: self.sim_time_s,
            jumper,
            rover,
            altimeter: self.altimeter.sample(jumper.position_m[2]),
            imu: self
                .imu
                .sample(force, rate, self.rover.rotation(), self.cfg.frame_period_s),
            jumper_status: self.jumper.status(),
            rover_status: self.rover.status(),
            rejected_inputs: self.rejected_inputs,
        };
        self.frame_index += 1;
        self.last = out;
        out
    }

    fn apply_inputs(&mut self, inputs: &FrameInputs) {
        if let Some(cmd) = inputs.drive {
            let finite =
                cmd.waypoint_xy_m.iter().all(|v| v.is_finite()) && cmd.speed_mps.is_finite();
            if finite {
                self.rover.set_command(DriveCommand {
                    speed_mps: cmd.speed_mps.clamp(0.0, self.cfg.rover.max_speed_mps),
                    ..cmd
                });
            } else {
                self.rejected_inputs += 1;
            }
        }
        if let Some(req) = inputs.hop_request {
            if req.target_xy_m.iter().all(|v| v.is_finite()) {
                self.jumper.request_hop(req.target_xy_m);
            } else {
                self.rejected_inputs += 1;
            }
        }
    }

    /// The configuration in use.
    pub fn config(&self) -> &PhysicsConfig {
        &self.cfg
    }

    /// Outputs of the last frame (the start state before the first frame).
    pub fn last_outputs(&self) -> &FrameOutputs {
        &self.last
    }

    /// Frames simulated so far.
    pub fn frame_count(&self) -> u64 {
        self.frame_index
    }

    /// Simulated time, seconds.
    pub fn sim_time_s(&self) -> f64 {
        self.sim_time_s
    }

    /// Jumper ground truth now.
    pub fn jumper_state(&self) -> BodyState {
        self.jumper.body_state(&self.pw)
    }

    /// Rover ground truth now.
    pub fn rover_state(&self) -> BodyState {
        self.rover.body_state()
    }

    /// Jumper hop phase.
    pub fn hop_state(&self) -> HopState {
        self.jumper.state()
    }

    /// Hops launched so far.
    pub fn hop_count(&self) -> u32 {
        self.jumper.hop_count()
    }

    /// Rover collisions with non-climbable rocks so far.
    pub fn rover_collisions(&self) -> u32 {
        self.rover.collision_count()
    }

    /// Queues a hop toward `target_xy_m` (same as a [`FrameInputs::hop_request`]).
    pub fn request_hop(&mut self, target_xy_m: [f64; 2]) {
        self.apply_inputs(&FrameInputs {
            drive: None,
            hop_request: Some(crate::frame::HopRequest { target_xy_m }),
        });
    }

    /// Replaces the rover's drive command (same as a [`FrameInputs::drive`]).
    pub fn set_drive(&mut self, cmd: DriveCommand) {
        self.apply_inputs(&FrameInputs {
            drive: Some(cmd),
            hop_request: None,
        });
    }

    /// The static world colliders (terrain and rocks).
    pub fn world_colliders(&self) -> &WorldColliders {
        &self.world_colliders
    }

    /// The rapier world, read-only (for debugging and visualisation).
    pub fn physics_world(&self) -> &PhysicsWorld {
        &self.pw
    }
}

fn check_inside(
    terrain: &Heightfield,
    key: &str,
    xy: [f64; 2],
    margin_m: f64,
) -> Result<(), PhysicsError> {
    let [ox, oy] = terrain.origin_m();
    let [ex, ey] = terrain.extent_m();
    let ok = xy[0] >= ox + margin_m
        && xy[0] <= ox + ex - margin_m
        && xy[1] >= oy + margin_m
        && xy[1] <= oy + ey - margin_m;
    if ok {
        Ok(())
    } else {
        Err(outside_error(terrain, key, xy, margin_m))
    }
}

fn outside_error(terrain: &Heightfield, key: &str, xy: [f64; 2], margin_m: f64) -> PhysicsError {
    let [ox, oy] = terrain.origin_m();
    let [ex, ey] = terrain.extent_m();
    PhysicsError::StartOutsideTerrain {
        key: key.to_string(),
        x_m: xy[0],
        y_m: xy[1],
        min_x_m: ox + margin_m,
        max_x_m: ox + ex - margin_m,
        min_y_m: oy + margin_m,
        max_y_m: oy + ey - margin_m,
    }
}

fn rock_error(world: &World, key: &str, xy: [f64; 2], rock_index: Option<usize>) -> PhysicsError {
    let rock_index = rock_index.unwrap_or(usize::MAX);
    let (rx, ry, rh) = world
        .rocks()
        .get(rock_index)
        .map_or((f64::NAN, f64::NAN, f64::NAN), |r| {
            (r.center_m[0], r.center_m[1], r.height_m)
        });
    PhysicsError::StartInsideRock {
        key: key.to_string(),
        x_m: xy[0],
        y_m: xy[1],
        rock_index,
        rock_x_m: rx,
        rock_y_m: ry,
        rock_height_m: rh,
    }
}

/// The jumper's upright start cube (enlarged by 1 cm) must not overlap any rock.
fn check_jumper_start(
    pw: &PhysicsWorld,
    world: &World,
    cols: &WorldColliders,
    cfg: &PhysicsConfig,
) -> Result<(), PhysicsError> {
    let [x, y] = cfg.jumper.start_xy_m;
    let h = cfg.jumper.half_extent_m + 0.01;
    let z = world.terrain().height_at(x, y) + h;
    let cube = Cuboid::new(Vec3::splat(h as f32));
    let pose = rapier3d::math::Pose::from_translation(crate::math::to_f32(DVec3::new(x, y, z)));
    let rocks = pw.query_pipeline_with_filter(
        QueryFilter::only_fixed().groups(query_groups(BLOCKING_ROCK_GROUP | CLIMBABLE_ROCK_GROUP)),
    );
    match rocks.intersect_shape(pose, &cube).next() {
        Some((handle, _)) => {
            let index = cols.rock_at(pw, handle, &pose, &cube);
            Err(rock_error(
                world,
                "physics.jumper.start_xy_m",
                [x, y],
                index,
            ))
        }
        None => Ok(()),
    }
}
