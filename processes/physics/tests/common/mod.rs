//! Shared test fixtures.
#![allow(dead_code)]

use hopnav_physics::{
    DriveCommand, FrameInputs, FrameOutputs, HopRequest, PhysicsConfig, PhysicsSim,
};
use hopnav_world::config::ExplicitRockConfig;
use hopnav_world::{World, WorldConfig};

/// A flat world of `size_x × size_y` metres at 0.25 m, without craters or random rocks.
pub fn flat_world(size_x_m: f64, size_y_m: f64, rocks: &[ExplicitRockConfig]) -> World {
    let mut cfg = WorldConfig::default();
    cfg.terrain.size_x_m = size_x_m;
    cfg.terrain.size_y_m = size_y_m;
    cfg.terrain.relief_amplitude_m = 0.0;
    cfg.craters.count = 0;
    cfg.rocks.golombek_k = 0.0;
    cfg.rocks.explicit = rocks.to_vec();
    World::generate(&cfg).expect("valid world")
}

/// Default physics with the jumper at `jumper_xy` and the rover at `rover_xy`.
pub fn physics(jumper_xy: [f64; 2], rover_xy: [f64; 2]) -> PhysicsConfig {
    let mut cfg = PhysicsConfig::default();
    cfg.jumper.start_xy_m = jumper_xy;
    cfg.rover.start_xy_m = rover_xy;
    cfg
}

/// The hop scene: a flat 48 × 12 m world with the jumper at (−14, 2) and the rover at
/// (−14, −2.5), out of each other's way.
pub fn hop_scene() -> (World, PhysicsConfig) {
    (
        flat_world(48.0, 12.0, &[]),
        physics([-14.0, 2.0], [-14.0, -2.5]),
    )
}

/// Steps `frames` frames with the same inputs every frame; returns all outputs.
pub fn run(sim: &mut PhysicsSim, frames: usize, inputs: FrameInputs) -> Vec<FrameOutputs> {
    (0..frames).map(|_| sim.step_frame(&inputs)).collect()
}

/// The largest `value` over `outputs` (`f64::MIN` when there are none).
pub fn max_over(outputs: &[FrameOutputs], value: impl Fn(&FrameOutputs) -> f64) -> f64 {
    outputs.iter().map(value).fold(f64::MIN, f64::max)
}

/// Inputs that only drive the rover.
pub fn drive(waypoint_xy_m: [f64; 2], speed_mps: f64) -> FrameInputs {
    FrameInputs {
        drive: Some(DriveCommand {
            waypoint_xy_m,
            speed_mps,
            hold: false,
            reverse: false,
        }),
        hop_request: None,
    }
}

/// Yaw of a `[x, y, z, w]` quaternion, radians.
pub fn yaw_of(q: [f64; 4]) -> f64 {
    let [x, y, z, w] = q;
    (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z))
}

/// Inputs of frame `k` on the default world: the rover drives a square, the jumper is asked to
/// hop now and then.
pub fn square_drive_inputs(k: usize) -> FrameInputs {
    let corners = [[-6.0, -1.5], [-6.0, 4.0], [-12.0, 4.0], [-12.0, -1.5]];
    FrameInputs {
        drive: Some(DriveCommand {
            waypoint_xy_m: corners[(k / 50) % 4],
            speed_mps: 0.5,
            hold: false,
            reverse: false,
        }),
        hop_request: (k % 60 == 59).then_some(HopRequest {
            target_xy_m: [-2.0 - (k / 60) as f64 * 3.0, 6.0],
        }),
    }
}
