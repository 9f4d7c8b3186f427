//! The sampled rock population follows the Golombek model.

mod common;

use common::sized_world;
use hopnav_world::rocks::{Golombek, RockSource};
use hopnav_world::{World, WorldConfig};

fn world(k: f64, seed: u64) -> World {
    let mut cfg = WorldConfig {
        seed,
        ..WorldConfig::default()
    };
    cfg.terrain.relief_amplitude_m = 0.0; // faster in debug builds; irrelevant here
    cfg.craters.count = 0;
    cfg.rocks.golombek_k = k;
    World::generate(&cfg).unwrap()
}

#[test]
fn area_fraction_and_size_distribution_match_the_model() {
    for (k, seed) in [(0.07, 1), (0.16, 2)] {
        let w = world(k, seed);
        let g = Golombek::new(k);
        let [ex, ey] = w.terrain().extent_m();
        let area = ex * ey;
        let (dmin, dmax) = (0.1, 2.0);
        let expected = g.cumulative_area_fraction(dmin) - g.cumulative_area_fraction(dmax);
        let got = w.rock_area_fraction();
        assert!(
            (got - expected).abs() / expected < 0.02,
            "k={k}: area fraction {got} vs F(Dmin)-F(Dmax) = {expected}"
        );
        // The size distribution: area in rocks of D >= 0.3 m and >= 0.6 m.
        for d in [0.3, 0.6] {
            let want = g.cumulative_area_fraction(d) - g.cumulative_area_fraction(dmax);
            let have: f64 = w
                .rocks()
                .iter()
                .filter(|r| r.diameter_m >= d)
                .map(|r| r.footprint_area_m2())
                .sum::<f64>()
                / area;
            assert!(
                (have - want).abs() / want < 0.25,
                "k={k}: F({d}) sampled {have}, model {want}"
            );
        }
        assert!(w.rocks().iter().all(|r| r.source == RockSource::Golombek));
        assert!(
            w.rocks()
                .iter()
                .all(|r| (r.height_m / r.diameter_m - 0.5).abs() < 0.1)
        );
    }
}

#[test]
fn q_follows_golombek() {
    let g = Golombek::new(0.16);
    assert!((g.q() - (1.79 + 0.152 / 0.16)).abs() < 1e-12);
    assert!((g.cumulative_area_fraction(1.0) - 0.16 * (-g.q()).exp()).abs() < 1e-15);
}

#[test]
fn rocks_sit_on_the_ground_and_avoid_scenario_points() {
    let mut cfg = sized_world(24.0, 24.0, 0.16);
    cfg.scenario.start_m = Some([-5.0, 0.0]);
    cfg.scenario.goal_m = Some([5.0, 0.0]);
    cfg.scenario.clear_radius_m = 2.0;
    let w = World::generate(&cfg).unwrap();
    for r in w.rocks() {
        let ground = w.ground_height_at(r.center_m[0], r.center_m[1]);
        assert!(r.center_m[2] <= ground + 1e-9 && ground - r.center_m[2] < r.diameter_m);
        for p in [[-5.0, 0.0], [5.0, 0.0]] {
            let d = ((r.center_m[0] - p[0]).powi(2) + (r.center_m[1] - p[1]).powi(2)).sqrt();
            assert!(d > 2.0, "rock at {:?} inside a clear zone", r.center_m);
        }
    }
}
