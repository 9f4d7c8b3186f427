//! The scouting suite's terrains (`config/scenarios/scout_*.toml`): each validates, is the
//! same world for the same seed, and holds the landform it promises.

use hopnav_world::landforms::{scarp::place_scarp, scenario_frame};
use hopnav_world::rocks::RockSource;
use hopnav_world::{World, WorldConfig};

mod common;

/// The `[world]` table of `config/scenarios/NAME.toml`, with `seed`, validated.
fn scenario(name: &str, seed: u64) -> WorldConfig {
    let mut config = common::scenario_world(name);
    config.seed = seed;
    config.validate().unwrap_or_else(|e| panic!("{name}: {e}"));
    config
}

/// The steepest ground slope met along the straight line from `from_m` to `to_m`.
fn steepest_between(world: &World, from_m: [f64; 2], to_m: [f64; 2]) -> f64 {
    let length_m = (to_m[0] - from_m[0]).hypot(to_m[1] - from_m[1]);
    let steps = (length_m / 0.125).ceil() as usize;
    (0..steps)
        .map(|step| {
            let at = |k: usize| {
                let t = k as f64 / steps as f64;
                let (x, y) = (
                    from_m[0] + t * (to_m[0] - from_m[0]),
                    from_m[1] + t * (to_m[1] - from_m[1]),
                );
                world.ground_height_at(x, y)
            };
            (at(step + 1) - at(step)).abs() / (length_m / steps as f64)
        })
        .fold(0.0, f64::max)
}

fn too_steep() -> f64 {
    30_f64.to_radians().tan()
}

#[test]
fn every_suite_terrain_is_the_same_world_for_the_same_seed() {
    for name in [
        "scout_cul_de_sacs",
        "scout_scarp",
        "scout_craters",
        "scout_corridors",
    ] {
        let a = World::generate(&scenario(name, 4)).expect("world");
        let b = World::generate(&scenario(name, 4)).expect("world");
        assert_eq!(a.terrain().heights_m(), b.terrain().heights_m(), "{name}");
        assert_eq!(a.rocks(), b.rocks(), "{name}");
        let other = World::generate(&scenario(name, 5)).expect("world");
        assert_ne!(a.rocks(), other.rocks(), "{name}: the seed changes nothing");
    }
}

#[test]
fn the_cul_de_sac_terrain_holds_three_walls_of_boulders_too_tall_to_climb() {
    let world = World::generate(&scenario("scout_cul_de_sacs", 2)).expect("world");
    for index in 0..3 {
        let wall: Vec<_> = world
            .rocks()
            .iter()
            .filter(|rock| rock.source == RockSource::CulDeSac(index))
            .collect();
        assert!(
            wall.len() > 30,
            "cul-de-sac {index}: {} boulders",
            wall.len()
        );
        assert!(wall.iter().all(|rock| rock.height_m > 0.4));
    }
}

#[test]
fn the_scarp_shuts_the_line_and_its_ramps_are_drivable() {
    for seed in 1..=3 {
        let mut config = scenario("scout_scarp", seed);
        // Craters could fall on a ramp; the scarp is what is judged here.
        config.craters.count = 0;
        let world = World::generate(&config).expect("world");
        let frame = scenario_frame(&config.scenario).expect("A and B");
        let scarp = place_scarp(seed, &config.landforms.scarp, &frame).expect("a scarp");
        let line_m = |side_m: f64| {
            let half_m = 0.5 * config.landforms.scarp.ramp_length_m + 3.0;
            (
                frame.world_m(scarp.along_m - half_m - 2.0, side_m),
                frame.world_m(scarp.along_m + half_m + 2.0, side_m),
            )
        };
        let (from, to) = line_m(0.0);
        assert!(
            steepest_between(&world, from, to) > too_steep(),
            "seed {seed}: the line is open"
        );
        for &side_m in &scarp.ramp_sides_m {
            let (from, to) = line_m(side_m);
            let slope = steepest_between(&world, from, to);
            assert!(
                slope < too_steep(),
                "seed {seed}: the ramp at {side_m} m rises {slope}"
            );
        }
    }
}

#[test]
fn the_crater_field_holds_rims_too_steep_to_drive() {
    let world = World::generate(&scenario("scout_craters", 3)).expect("world");
    assert_eq!(world.craters().len(), 20);
    let steep_walled = world
        .craters()
        .iter()
        .filter(|crater| {
            let [x, y] = [crater.center_m[0], crater.center_m[1]];
            steepest_between(&world, [x, y], [x + crater.diameter_m, y]) > too_steep()
        })
        .count();
    assert!(
        steep_walled >= 15,
        "{steep_walled} of 20 craters have walls too steep"
    );
}

#[test]
fn the_corridor_field_is_a_dense_band_of_boulders() {
    let config = scenario("scout_corridors", 6);
    let world = World::generate(&config).expect("world");
    let band = world
        .rocks()
        .iter()
        .filter(|rock| rock.source == RockSource::CorridorField)
        .count();
    // 20 m deep across a 64 m wide terrain at 1 m spacing, less the corridors.
    assert!((1000..1400).contains(&band), "{band} boulders in the band");
}
