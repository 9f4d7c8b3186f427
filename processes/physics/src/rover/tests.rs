//! Tests of the `rover` module.

use super::*;

#[test]
fn ball_wheel_rests_on_slopes() {
    let r = 0.15;
    for slope_deg in [0.0f64, 5.0, 10.0, 20.0, 30.0] {
        for dir_deg in [0.0f64, 10.0, 22.5, 45.0, 200.0] {
            let (g, d) = (slope_deg.to_radians().tan(), dir_deg.to_radians());
            let (sd, cd) = d.sin_cos();
            let plane = |x: f64, y: f64| 0.3 + g * (x * cd + y * sd);
            let gradient = |_: f64, _: f64| [g * cd, g * sd];
            let exact = plane(0.1, -0.2) + r / slope_deg.to_radians().cos();
            let z = wheel_on_terrain_z(plane, gradient, 0.1, -0.2, r);
            assert!(
                (z - exact).abs() < 1e-9,
                "{slope_deg}° {dir_deg}°: {z} vs {exact}"
            );
        }
    }
}

#[test]
fn wheels_fold_to_the_front_half_plane() {
    let pi = std::f64::consts::PI;
    assert!((fold_to_half_plane(0.75 * pi) + 0.25 * pi).abs() < 1e-12);
    assert!((fold_to_half_plane(-0.75 * pi) - 0.25 * pi).abs() < 1e-12);
    assert_eq!(fold_to_half_plane(0.3), 0.3);
}
