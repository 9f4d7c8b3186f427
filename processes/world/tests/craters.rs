//! Fresh craters: depth ≈ 0.2 × diameter, raised rim.

mod common;

use common::sized_world;
use hopnav_world::{World, WorldConfig};

/// A rock-free world of `size_m` on a `spacing_m` grid with `count` craters of diameters in
/// `diameter_m` (min, max).
fn cratered(size_m: [f64; 2], spacing_m: f64, count: u32, diameter_m: [f64; 2]) -> WorldConfig {
    let mut cfg = sized_world(size_m[0], size_m[1], 0.0);
    cfg.terrain.spacing_m = spacing_m;
    cfg.craters.count = count;
    cfg.craters.diameter_min_m = diameter_m[0];
    cfg.craters.diameter_max_m = diameter_m[1];
    cfg
}

#[test]
fn crater_depth_is_a_fifth_of_the_diameter() {
    let mut cfg = cratered([20.0, 20.0], 0.05, 1, [6.0, 6.0]);
    cfg.terrain.relief_amplitude_m = 0.0;
    cfg.texture.texel_m = 0.05;
    let w = World::generate(&cfg).unwrap();
    let c = w.craters()[0];
    assert!((c.diameter_m - 6.0).abs() < 1e-9);
    let (lo, hi) = w.terrain().height_range_m();
    let depth = hi - lo; // rim crest to floor on otherwise flat ground
    assert!(
        (depth / c.diameter_m - 0.2).abs() < 0.2 * 0.03,
        "depth {depth}"
    );
    assert!(hi > 0.2 && (hi - 0.04 * 6.0).abs() < 0.01, "rim {hi}");
    let floor = w.ground_height_at(c.center_m[0], c.center_m[1]);
    assert!((floor - lo).abs() < 1e-3);
    // Far from the crater the ground is untouched.
    let far = w.ground_height_at(
        c.center_m[0] + 9.5_f64.copysign(-c.center_m[0]),
        c.center_m[1],
    );
    assert!(far.abs() < 1e-9);
}

#[test]
fn crater_rims_keep_clear_of_start_and_goal() {
    let mut cfg = cratered([30.0, 12.0], 0.1, 60, [3.0, 8.0]);
    cfg.scenario.start_m = Some([-10.0, 0.0]);
    cfg.scenario.goal_m = Some([10.0, 0.0]);
    cfg.scenario.clear_radius_m = 2.0;
    let mut placed = 0;
    for seed in 0..10 {
        cfg.seed = seed;
        let world = World::generate(&cfg).unwrap();
        placed += world.craters().len();
        for crater in world.craters() {
            for point in [[-10.0, 0.0], [10.0, 0.0]] {
                let (dx, dy) = (crater.center_m[0] - point[0], crater.center_m[1] - point[1]);
                let gap_m = dx.hypot(dy) - crater.diameter_m / 2.0;
                assert!(gap_m > 2.0, "seed {seed}: rim {gap_m} m from {point:?}");
            }
        }
    }
    // Most craters find a clear spot: the rule moves them, it does not empty the map.
    assert!(placed > 10 * 60 * 3 / 4, "only {placed} craters placed");
}
