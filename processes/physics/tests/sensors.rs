//! Altimeter noise statistics and IMU readings at rest.

mod common;

use common::{flat_world, hop_scene, max_over, physics, run};
use hopnav_physics::config::AltimeterConfig;
use hopnav_physics::sensors::Altimeter;
use hopnav_physics::{FrameInputs, PhysicsSim};

/// The rover at (−10, 3) and the jumper at (0, −2) on flat ground, no hop at the start.
fn rover_beside_a_resting_jumper() -> PhysicsSim {
    let world = flat_world(32.0, 12.0, &[]);
    let mut cfg = physics([-10.0, 3.0], [0.0, -2.0]);
    cfg.jumper.initial_hop = false;
    PhysicsSim::new(&world, &cfg, 4).unwrap()
}

#[test]
fn altimeter_noise_matches_sigma() {
    let cfg = AltimeterConfig::default();
    let mut alt = Altimeter::new(&cfg, 9);
    let n = 20_000;
    let (mut sum, mut sum2) = (0.0, 0.0);
    for _ in 0..n {
        let s = alt.sample(5.0);
        let e = s.altitude_m - s.true_altitude_m;
        // Pressure and altitude agree through the barometric law.
        let h = -cfg.scale_height_m * (s.pressure_pa / cfg.surface_pressure_pa).ln();
        assert!((h - s.altitude_m).abs() < 1e-6);
        sum += e;
        sum2 += e * e;
    }
    let mean = sum / n as f64;
    let std = (sum2 / n as f64 - mean * mean).sqrt();
    assert!(mean.abs() < 0.03, "mean {mean}");
    assert!((std - cfg.sigma_m).abs() < 0.03, "std {std}");
    // Surface pressure ≈ 610 Pa; 1 m ≈ 0.055 Pa.
    assert!((alt.pressure_at_pa(0.0) - 610.0).abs() < 1e-9);
}

#[test]
fn altimeter_in_the_sim_tracks_the_jumper() {
    let (world, cfg) = hop_scene();
    let mut sim = PhysicsSim::new(&world, &cfg, 4).unwrap();
    let outs = run(&mut sim, 150, FrameInputs::default());
    let errs: Vec<f64> = outs
        .iter()
        .map(|o| o.altimeter.altitude_m - o.jumper.position_m[2])
        .collect();
    let std = (errs.iter().map(|e| e * e).sum::<f64>() / errs.len() as f64).sqrt();
    assert!((0.8..1.2).contains(&std), "std {std}");
    let apex = max_over(&outs, |o| o.altimeter.true_altitude_m);
    assert!(apex > 10.0);
}

#[test]
fn imu_at_rest_reads_plus_g_up() {
    let mut sim = rover_beside_a_resting_jumper();
    let n = 200;
    let mut f = [0.0; 3];
    let mut w = [0.0; 3];
    for _ in 0..n {
        let o = sim.step_frame(&FrameInputs::default());
        for k in 0..3 {
            f[k] += o.imu.specific_force_body_mps2[k] / n as f64;
            w[k] += o.imu.angular_velocity_body_radps[k] / n as f64;
        }
    }
    eprintln!("mean specific force {f:?}, mean rate {w:?}");
    assert!((f[2] - 3.711).abs() < 0.03, "{f:?}");
    assert!(f[0].abs() < 0.03 && f[1].abs() < 0.03, "{f:?}");
    assert!(w.iter().all(|v| v.abs() < 0.003), "{w:?}");
}

#[test]
fn imu_sees_the_turn() {
    let mut sim = rover_beside_a_resting_jumper();
    let inputs = common::drive([0.0, 5.0], 0.5);
    let outs: Vec<_> = (0..40).map(|_| sim.step_frame(&inputs)).collect();
    let max_rate = max_over(&outs, |o| o.imu.angular_velocity_body_radps[2]);
    let truth = max_over(&outs, |o| o.rover.angular_velocity_radps[2]);
    assert!(
        (max_rate - truth).abs() < 0.02 && truth > 0.5,
        "imu {max_rate} truth {truth}"
    );
    // Reported attitude stays close to the truth (noise and drift are small).
    let o = outs.last().unwrap();
    let yaw_imu = common::yaw_of(o.imu.orientation_xyzw);
    let yaw_true = common::yaw_of(o.rover.orientation_xyzw);
    assert!((yaw_imu - yaw_true).abs() < 0.02);
}
