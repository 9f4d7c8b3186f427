//! The harder cases of `eval vo` beside the Table 1 hop: a rock-deflected launch that tumbles,
//! and ten hops in a row where each starts from where the VO thinks the last one ended.

use hopnav_jumper_vo::config::JumperVoConfig;
use hopnav_jumper_vo::frames::rotation_from_euler;
use hopnav_jumper_vo::rng::NoiseRng;
use hopnav_jumper_vo::run::run_hop_from;
use hopnav_jumper_vo::simulate::{SimConfig, SimulatedHop, simulate_hop};
use hopnav_jumper_vo::trajectory::HopTrajectory;
use nalgebra::{Isometry3, Point3, Translation3, Vector3};

/// Spin of a tumbling launch, rad/s: drawn in this range, either sense.
pub const TUMBLE_RADPS: (f64, f64) = (10.0, 30.0);

/// One tumbling launch and how far from its landing the VO ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TumblingOutcome {
    /// The seed it was drawn from.
    pub seed: u64,
    /// True pitch rate, rad/s.
    pub spin_radps: f64,
    /// Launch heading off the commanded one, radians.
    pub heading_error_rad: f64,
    /// True launch speed over the commanded one.
    pub speed_ratio: f64,
    /// Distance between the VO's last pose and the true landing, metres.
    pub final_error_m: f64,
}

/// Ten (or `hops`) hops in a row over one terrain: the error after each.
#[derive(Debug, Clone, PartialEq)]
pub struct MultiHopOutcome {
    /// The seed.
    pub seed: u64,
    /// Distance between the VO's landing and the true one after each hop, metres.
    pub error_after_hop_m: Vec<f64>,
}

/// Renders `hop` over the terrain of `world_seed`, with the sensor noise of `noise_seed`.
fn simulate(world_seed: u64, noise_seed: u64, hop: HopTrajectory) -> Result<SimulatedHop, String> {
    let mut config = SimConfig {
        seed: noise_seed,
        hop,
        ..SimConfig::default()
    };
    config.world.seed = world_seed;
    simulate_hop(&config).map_err(|error| format!("simulating seed {world_seed}: {error}"))
}

fn final_error_m(hop: &SimulatedHop, last: Option<&Isometry3<f64>>) -> f64 {
    match (last, hop.truth_world_from_body.last()) {
        (Some(estimate), Some(truth)) => {
            (estimate.translation.vector - truth.translation.vector).norm()
        }
        _ => f64::NAN,
    }
}

/// A Table 1 launch a rock turned: the body spins at 10–30 rad/s (the camera sees sky and
/// blur most of the flight) and the velocity is off the commanded one in heading, elevation
/// and speed. The VO is told the commanded launch and the resting attitude, as in a mission.
pub fn tumbling_launch(seed: u64, config: &JumperVoConfig) -> Result<TumblingOutcome, String> {
    let nominal = SimConfig::default().hop;
    let mut rng = NoiseRng::new(seed ^ 0x7u64.rotate_left(40));
    let spin = TUMBLE_RADPS.0 + (TUMBLE_RADPS.1 - TUMBLE_RADPS.0) * rng.unit_open();
    let sense = if rng.unit_open() < 0.5 { -1.0 } else { 1.0 };
    let heading_error_rad = 0.3 * (2.0 * rng.unit_open() - 1.0);
    let speed_ratio = 0.8 + 0.3 * rng.unit_open();
    let flown = HopTrajectory {
        heading_rad: nominal.heading_rad + heading_error_rad,
        speed_mps: nominal.speed_mps * speed_ratio,
        elevation_rad: nominal.elevation_rad + 8f64.to_radians() * (2.0 * rng.unit_open() - 1.0),
        pitch_rate_radps: sense * spin,
        ..nominal
    };
    let hop = simulate(seed, seed, flown)?;
    // What the VO knows: the commanded hop (Table 1's spin) from the resting attitude.
    let believed = SimulatedHop {
        hop: nominal,
        ..hop.clone()
    };
    let vo_config = believed.robot_config(config);
    let launch_position = hop
        .truth_world_from_body
        .first()
        .map_or(Vector3::zeros(), |pose| pose.translation.vector);
    let resting = Isometry3::from_parts(
        Translation3::from(launch_position),
        rotation_from_euler(0.0, nominal.initial_pitch_rad, nominal.heading_rad),
    );
    let run = run_hop_from(&hop, &vo_config, resting).map_err(|error| error.to_string())?;
    Ok(TumblingOutcome {
        seed,
        spin_radps: sense * spin,
        heading_error_rad,
        speed_ratio,
        final_error_m: final_error_m(&hop, run.outputs.last().map(|o| &o.world_from_body)),
    })
}

/// Heading of hop `k` of a sequence: back and forth along x, drifting a few metres in y and
/// back every four hops, so ten hops stay on the 80 m × 64 m terrain.
fn sequence_heading_rad(k: usize) -> f64 {
    let back = if k % 2 == 1 {
        std::f64::consts::PI
    } else {
        0.0
    };
    let side = if k % 4 < 2 { 0.25 } else { -0.25 };
    back + side
}

/// `hops` Table 1 hops in a row: each launches where the last truly landed, and the VO starts
/// it from where it believed the last one ended (the resting attitude is known, as from the
/// IMU and sun sensor at rest), so errors add up hop by hop as in a mission.
pub fn hops_in_a_row(
    seed: u64,
    hops: usize,
    config: &JumperVoConfig,
) -> Result<MultiHopOutcome, String> {
    let mut launch_m = SimConfig::default().hop.launch_position_m;
    let mut believed_offset_m = Vector3::zeros();
    let mut error_after_hop_m = Vec::with_capacity(hops);
    for k in 0..hops {
        let flown = HopTrajectory {
            launch_position_m: launch_m,
            heading_rad: sequence_heading_rad(k),
            ..SimConfig::default().hop
        };
        let hop = simulate(seed, seed.wrapping_mul(1000).wrapping_add(k as u64), flown)?;
        let (Some(first), Some(last)) = (
            hop.truth_world_from_body.first(),
            hop.truth_world_from_body.last(),
        ) else {
            return Err(format!("seed {seed}: hop {k} rendered no frame"));
        };
        let believed_launch = Isometry3::from_parts(
            Translation3::from(first.translation.vector + believed_offset_m),
            first.rotation,
        );
        let run = run_hop_from(&hop, &hop.robot_config(config), believed_launch)
            .map_err(|error| error.to_string())?;
        let landed = run.outputs.last().map(|o| o.world_from_body);
        let error = final_error_m(&hop, landed.as_ref());
        error_after_hop_m.push(error);
        if let Some(landed) = landed {
            believed_offset_m = landed.translation.vector - last.translation.vector;
        }
        launch_m = Point3::new(last.translation.x, last.translation.y, 0.0);
    }
    Ok(MultiHopOutcome {
        seed,
        error_after_hop_m,
    })
}
