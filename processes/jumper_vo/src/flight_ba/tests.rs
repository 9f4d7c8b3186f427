//! The adjustment on synthetic hops: ground points seen from a known ballistic flight.

use super::*;
use crate::frames::body_from_camera;
use crate::rng::NoiseRng;
use nalgebra::{Point3, Vector2};

const SIGMA: f64 = 0.5 / 400.0;

fn model() -> FlightModel {
    FlightModel {
        launch_position_m: Vector3::new(0.0, 0.0, 0.5),
        launch_rotation: UnitQuaternion::from_axis_angle(&Vector3::y_axis(), -0.3),
        gravity_mps2: 3.711,
        body_from_camera: body_from_camera(0.5, &Vector3::new(-0.1, 0.0, 0.0)),
    }
}

fn truth() -> FlightParams {
    FlightParams {
        velocity_mps: Vector3::new(5.0, 0.3, 8.66),
        rate_radps: Vector3::new(0.0, 0.1, 0.0),
        attitude_correction_rad: Vector3::zeros(),
    }
}

fn settings() -> BaSettings {
    BaSettings {
        sighting_sigma: SIGMA,
        robust_scale_sigmas: 3.0,
        altimeter_sigma_m: 1.0,
        max_iterations: 15,
        min_points: 20,
        min_ray_angle_rad: 0.5f64.to_radians(),
    }
}

fn prior(mean: FlightParams) -> FlightPrior {
    FlightPrior {
        mean,
        velocity_sigma_mps: 1.0,
        rate_sigma_radps: 0.05,
        attitude_sigma_rad: 0.01,
    }
}

/// Sightings of a grid of ground points from keyframes every 0.3 s of the true flight, with
/// pixel noise; `outliers` of them moved far off.
fn hop_sightings(seed: u64, outliers: usize) -> (HopWindow, Vec<Vector3<f64>>) {
    let model = model();
    let truth = truth();
    let mut rng = NoiseRng::new(seed);
    let points: Vec<Vector3<f64>> = (0..900)
        .map(|k| {
            let (i, j) = ((k % 30) as f64, (k / 30) as f64);
            Vector3::new(-25.0 + 1.7 * i, -25.0 + 1.7 * j, 0.2 * rng.gaussian())
        })
        .collect();
    let mut window = HopWindow::new(12);
    let mut moved = 0;
    for step in 1..=12 {
        let tau = 0.3 * f64::from(step);
        let camera_from_world = model.camera_from_world(&truth, tau);
        let mut seen = Vec::new();
        for (id, p) in points.iter().enumerate() {
            let pc = camera_from_world * Point3::from(*p);
            if pc.z < 1.0 {
                continue;
            }
            let x = Vector2::new(pc.x / pc.z, pc.y / pc.z);
            if x.x.abs() > 0.5 || x.y.abs() > 0.4 {
                continue;
            }
            let mut noisy = x + Vector2::new(rng.gaussian(), rng.gaussian()) * SIGMA;
            if moved < outliers && id % 7 == 0 {
                noisy += Vector2::new(0.05, -0.03);
                moved += 1;
            }
            seen.push((id as u32, noisy));
        }
        window.add_keyframe(tau, seen);
        let altitude = model.position_m(&truth, tau).z + rng.gaussian();
        window.add_altitude(tau, altitude);
    }
    (window, points)
}

fn position_error_m(params: &FlightParams) -> f64 {
    let model = model();
    (1..=12)
        .map(|k| {
            let tau = 0.3 * f64::from(k);
            (model.position_m(params, tau) - model.position_m(&truth(), tau)).norm()
        })
        .fold(0.0, f64::max)
}

/// Adjusts `window` from `start`, the prior centred on `start`.
fn adjust_from(window: &HopWindow, start: &FlightParams) -> BaOutcome {
    adjust(
        &model(),
        &prior(*start),
        &settings(),
        start,
        window.sightings(),
        window.altitudes(),
    )
    .expect("adjusts")
}

#[test]
fn a_wrong_launch_velocity_and_spin_are_pulled_to_the_truth() {
    let (window, _) = hop_sightings(3, 0);
    let mut start = truth();
    start.velocity_mps += Vector3::new(0.4, -0.3, 0.2);
    start.rate_radps += Vector3::new(0.01, -0.02, 0.005);
    let outcome = adjust_from(&window, &start);
    assert!(outcome.cost_after < outcome.cost_before);
    assert!(outcome.median_error_sigmas_after < 1.5, "{outcome:?}");
    let before = position_error_m(&start);
    let after = position_error_m(&outcome.params);
    assert!(before > 1.0, "{before}");
    assert!(after < 0.1 * before, "{before} m -> {after} m");
}

#[test]
fn the_truth_stays_put_and_outliers_do_not_drag_it() {
    let (window, _) = hop_sightings(5, 60);
    let outcome = adjust_from(&window, &truth());
    assert!(position_error_m(&outcome.params) < 0.05, "{outcome:?}");
    let rate_error = (outcome.params.rate_radps - truth().rate_radps).norm();
    assert!(rate_error < 0.002, "{rate_error}");
}

#[test]
fn degenerate_input_gives_an_error_never_a_panic_or_nan() {
    let start = truth();
    let none = adjust(&model(), &prior(start), &settings(), &start, &[], &[]);
    assert!(matches!(none, Err(BaError::TooFewPoints { found: 0, .. })));
    // The same image twice: no parallax, no point.
    let mut window = HopWindow::new(4);
    let same: Vec<(u32, Vector2<f64>)> = (0..100)
        .map(|i| (i, Vector2::new(0.001 * f64::from(i), 0.0)))
        .collect();
    window.add_keyframe(0.1, same.clone());
    window.add_keyframe(0.1 + 1e-9, same);
    let still = adjust(
        &model(),
        &prior(start),
        &settings(),
        &start,
        window.sightings(),
        &[],
    );
    assert!(still.is_err(), "{still:?}");
    let mut bad = start;
    bad.velocity_mps.x = f64::NAN;
    let nan = adjust(&model(), &prior(start), &settings(), &bad, &[], &[]);
    assert!(matches!(nan, Err(BaError::BadInput(_))));
    let mut zero_sigma = settings();
    zero_sigma.sighting_sigma = 0.0;
    assert!(adjust(&model(), &prior(start), &zero_sigma, &start, &[], &[]).is_err());
}
