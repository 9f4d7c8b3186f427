//! The `traversability` model in the whole map: clouds in, classes out.

use hopnav_ipc::messages::{CellClass, FeaturePoint, Robot};

use crate::config::{MapperConfig, ObstacleModel};
use crate::geometry::GridGeometry;
use crate::map::FeatureMap;

/// The cells' own beliefs only (no rock fitted as a dome; `dome_map` fits them).
fn config() -> MapperConfig {
    MapperConfig {
        obstacle_model: ObstacleModel::Traversability,
        cell_size_m: 0.25,
        dome_base_per_height: 0.0,
        ..MapperConfig::default()
    }
}

fn map() -> FeatureMap {
    let config = config();
    FeatureMap::sixteen_m_square(&config)
}

fn point(x: f32, y: f32, z: f32, height_m: f32, sigma_m: f32) -> FeaturePoint {
    FeaturePoint {
        position_m: [x, y, z],
        height_above_ground_m: height_m,
        depth_sigma_m: sigma_m,
        ..FeaturePoint::default()
    }
}

/// A rover stereo cloud of flat ground on a 5 cm lattice over `[x0, x1] × [y0, y1]`, with
/// round rocks `(centre, radius, height)` standing on it (a dome of that height).
fn rover_cloud(
    x_range: (f32, f32),
    y_range: (f32, f32),
    rocks: &[([f32; 2], f32, f32)],
) -> Vec<FeaturePoint> {
    let mut cloud = Vec::new();
    let steps = |(lo, hi): (f32, f32)| ((hi - lo) / 0.05).round() as i32;
    for i in 0..=steps(x_range) {
        for j in 0..=steps(y_range) {
            let (x, y) = (x_range.0 + 0.05 * i as f32, y_range.0 + 0.05 * j as f32);
            let mut height_m = 0.0f32;
            for &([cx, cy], radius_m, rock_height_m) in rocks {
                let r = (x - cx).hypot(y - cy);
                if r < radius_m {
                    height_m = height_m.max(rock_height_m * (1.0 - (r / radius_m).powi(2)).sqrt());
                }
            }
            cloud.push(point(x, y, height_m, height_m, 0.02));
        }
    }
    cloud
}

fn class_at(map: &FeatureMap, x_m: f64, y_m: f64) -> CellClass {
    let (x, y) = map.geometry().cell_of(x_m, y_m).expect("inside");
    map.cell_state(x, y).expect("cell").class
}

fn geometry_of(map: &FeatureMap) -> GridGeometry {
    *map.geometry()
}

#[test]
fn a_climbable_rock_on_a_slope_stays_traversable() {
    // 10° slope along x; a 0.18 m rock at (1, 1). Heights unknown (a monocular cloud): the
    // map judges them against the ground plane it fits to the neighbourhood.
    let mut map = map();
    let slope = 10f32.to_radians().tan();
    let mut cloud = Vec::new();
    for i in 0..60 {
        for j in 0..60 {
            let (x, y) = (-0.5 + 0.05 * i as f32, -0.5 + 0.05 * j as f32);
            let r = (x - 1.0).hypot(y - 1.0);
            let rock_m = if r < 0.3 {
                0.18 * (1.0 - (r / 0.3).powi(2)).sqrt()
            } else {
                0.0
            };
            cloud.push(point(x, y, slope * x + rock_m, f32::NAN, 0.01));
        }
    }
    for _ in 0..4 {
        map.insert_cloud(Robot::Jumper, &cloud);
        map.update();
    }
    assert_eq!(class_at(&map, 1.0, 1.0), CellClass::Free);
    // With measured heights (the rover's stereo), the same.
    let mut measured = self::map();
    for _ in 0..4 {
        measured.insert_cloud(
            Robot::Rover,
            &rover_cloud((0.0, 2.0), (0.0, 2.0), &[([1.0, 1.0], 0.3, 0.18)]),
        );
        measured.update();
    }
    assert_eq!(class_at(&measured, 1.0, 1.0), CellClass::Free);
    // Fitted as a dome (flatter than the Golombek shape the fit expects), the same.
    let mut fitted = dome_map();
    for _ in 0..4 {
        fitted.insert_cloud_seen_from(
            Robot::Rover,
            Some([-1.0, 1.0, 1.0]),
            &rover_cloud((0.0, 2.0), (0.0, 2.0), &[([1.0, 1.0], 0.3, 0.18)]),
        );
        fitted.update();
    }
    assert!(
        !blocks(&fitted, 1.0, 1.0),
        "{:?}",
        class_at(&fitted, 1.0, 1.0)
    );
}

#[test]
fn an_unclimbable_rock_becomes_a_lethal_disc_of_about_the_inscribed_radius() {
    let mut map = map();
    let rock = ([1.0, 1.0], 0.25, 0.25);
    for _ in 0..3 {
        map.insert_cloud(
            Robot::Rover,
            &rover_cloud((-1.5, 3.5), (-1.5, 3.5), &[rock]),
        );
        map.update();
    }
    assert_eq!(class_at(&map, 1.0, 1.0), CellClass::Obstacle);
    let inscribed_m = config().rover_body.inscribed_radius_m();
    // Centres within the inscribed radius of the rock's edge are lethal…
    for angle in [0.0f64, 1.0, 2.0, 3.0, 4.0, 5.0] {
        let r_m = 0.25 + 0.6 * inscribed_m;
        let class = class_at(&map, 1.0 + r_m * angle.cos(), 1.0 + r_m * angle.sin());
        assert!(
            matches!(class, CellClass::Lethal | CellClass::Obstacle),
            "{class:?} at {angle} rad"
        );
    }
    // … and ground a body length away is not.
    for angle in [0.0f64, 1.5, 3.0, 4.5] {
        let r_m = 0.25 + inscribed_m + 0.6;
        let class = class_at(&map, 1.0 + r_m * angle.cos(), 1.0 + r_m * angle.sin());
        assert!(
            matches!(class, CellClass::Free | CellClass::Inflated),
            "{class:?} at {angle} rad"
        );
    }
    // The lethal area is a disc around the rock, not a block of the old 3×3 cells.
    let cell_m2 = 0.0625;
    let lethal_m2 = (0..geometry_of(&map).height_cells)
        .flat_map(|y| (0..geometry_of(&map).width_cells).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            matches!(
                map.cell_state(x, y).map(|c| c.class),
                Some(CellClass::Lethal | CellClass::Obstacle)
            )
        })
        .count() as f64
        * cell_m2;
    let true_m2 = std::f64::consts::PI * (0.25 + inscribed_m).powi(2);
    assert!(
        lethal_m2 < 1.8 * true_m2,
        "lethal {lethal_m2:.2} m² for a true {true_m2:.2} m²"
    );
}

#[test]
fn a_false_wall_from_one_misplaced_jumper_cloud_is_cleared_by_rover_stereo() {
    let mut map = map();
    // Two jumper clouds (a bad keyframe and its neighbour) draw a 0.6 m wall across x = 2.
    let wall: Vec<FeaturePoint> = (0..40)
        .map(|i| point(2.0, -1.0 + 0.05 * i as f32, 0.6, 0.6, 0.02))
        .collect();
    map.insert_cloud(Robot::Jumper, &wall);
    map.insert_cloud(Robot::Jumper, &wall);
    map.update();
    assert_eq!(class_at(&map, 2.0, 0.0), CellClass::Obstacle);
    // The rover, 1 m up at x = 0, sees the bare ground behind it, cloud after cloud.
    let ground = rover_cloud((2.4, 3.5), (-1.5, 1.5), &[]);
    for _ in 0..6 {
        map.insert_cloud_seen_from(Robot::Rover, Some([0.0, 0.0, 1.0]), &ground);
        map.update();
    }
    let class = class_at(&map, 2.0, 0.0);
    assert!(
        !matches!(class, CellClass::Obstacle | CellClass::Lethal),
        "the wall stayed: {class:?}"
    );
    assert!(map.beliefs().expect("traversability").rays_counted() > 0);
}

#[test]
fn a_single_bad_cloud_never_makes_a_lethal_cell() {
    let mut map = map();
    let spike: Vec<FeaturePoint> = (0..30).map(|_| point(0.6, 0.6, 1.0, 1.0, 0.02)).collect();
    map.insert_cloud(Robot::Jumper, &spike);
    map.update();
    assert_ne!(class_at(&map, 0.6, 0.6), CellClass::Obstacle);
}

#[test]
fn bad_points_are_refused_and_counted_never_a_panic() {
    let mut map = map();
    let cloud = [
        point(f32::NAN, 0.0, 0.0, 0.0, 0.02),
        point(0.0, f32::INFINITY, 0.0, 0.0, 0.02),
        point(0.0, 0.0, 0.0, f32::INFINITY, 0.02),
        point(0.0, 0.0, 0.3, 0.3, 0.0),
        point(0.0, 0.0, 0.3, 0.3, -0.1),
        point(500.0, 0.0, 0.0, 0.0, 0.02),
        point(0.0, 0.0, 0.0, 0.0, 0.02),
    ];
    let accepted = map.insert_cloud_seen_from(Robot::Rover, Some([f64::NAN, 0.0, 1.0]), &cloud);
    map.update();
    let counters = map.counters();
    assert_eq!(accepted, 1);
    assert_eq!(counters.non_finite, 3);
    assert_eq!(counters.bad_sigma, 2);
    assert_eq!(counters.outside_grid, 1);
}

#[test]
fn two_unclimbable_rocks_1_1_m_apart_leave_a_corridor_for_the_rovers_centre() {
    // Rocks of 0.3 m radius, 0.3 m tall (as wide as twice their height, like the world's),
    // their edges 1.1 m apart across y = 0; the rover (0.8 m wide) fits with 0.15 m to spare
    // on each side.
    let mut map = map();
    let rocks = [([1.0, -0.85], 0.3, 0.3), ([1.0, 0.85], 0.3, 0.3)];
    for _ in 0..3 {
        map.insert_cloud(Robot::Rover, &rover_cloud((-1.0, 3.0), (-2.0, 2.0), &rocks));
        map.update();
    }
    assert_eq!(class_at(&map, 1.0, -0.85), CellClass::Obstacle);
    assert_eq!(class_at(&map, 1.0, 0.85), CellClass::Obstacle);
    // Some row of cells along y between the rocks is open to the centre all the way past them.
    let geometry = geometry_of(&map);
    let (x0, _) = geometry.cell_of(0.0, 0.0).expect("inside");
    let (x1, _) = geometry.cell_of(2.0, 0.0).expect("inside");
    let open_row = (-2..=2).any(|row| {
        let y_m = 0.125 + 0.25 * f64::from(row);
        (x0..=x1).all(|x| {
            let (_, y) = geometry.cell_of(0.0, y_m).expect("inside");
            !matches!(
                map.cell_state(x, y).map(|cell| cell.class),
                Some(CellClass::Obstacle | CellClass::Lethal)
            )
        })
    });
    assert!(open_row, "the gap closed on the map");
}

#[test]
fn the_width_prior_puts_a_half_seen_rocks_back_behind_its_face_not_in_front() {
    // A 0.3 m tall rock of 0.3 m radius at (2, 0); the rover, 1 m up at the origin, sees
    // only its near half.
    let lethal_at = |prior: f64, x_m: f64| {
        let config = MapperConfig {
            rock_width_prior: prior,
            ..config()
        };
        let mut map = FeatureMap::sixteen_m_square(&config);
        let near_half = rover_cloud((0.5, 2.0), (-1.0, 1.0), &[([2.0, 0.0], 0.3, 0.3)]);
        for _ in 0..3 {
            map.insert_cloud_seen_from(Robot::Rover, Some([0.0, 0.0, 1.0]), &near_half);
            map.update();
        }
        matches!(
            class_at(&map, x_m, 0.1),
            CellClass::Lethal | CellClass::Obstacle
        )
    };
    // 0.3 m behind the rock's back edge (x = 2.3): lethal only with the prior.
    assert!(!lethal_at(0.0, 2.6));
    assert!(lethal_at(1.0, 2.6));
    // In front, 0.55 m from the seen face (x = 1.7): the prior does not push the margin
    // towards the rover.
    assert!(!lethal_at(1.0, 1.15));
}

fn dome_map() -> FeatureMap {
    let config = MapperConfig {
        dome_base_per_height: 1.0,
        ..config()
    };
    FeatureMap::sixteen_m_square(&config)
}

fn blocks(map: &FeatureMap, x_m: f64, y_m: f64) -> bool {
    matches!(
        class_at(map, x_m, y_m),
        CellClass::Lethal | CellClass::Obstacle
    )
}

#[test]
fn a_fitted_dome_covers_the_back_of_a_half_seen_rock() {
    // A 0.3 m tall rock of 0.3 m radius at (2, 0); the rover, 1 m up at the origin, sees
    // only its near half.
    let near_half = rover_cloud((0.5, 2.0), (-1.0, 1.0), &[([2.0, 0.0], 0.3, 0.3)]);
    let (mut plain, mut fitted) = (map(), dome_map());
    for map in [&mut plain, &mut fitted] {
        for _ in 0..3 {
            map.insert_cloud_seen_from(Robot::Rover, Some([0.0, 0.0, 1.0]), &near_half);
            map.update();
        }
    }
    // The unseen back half of the rock is the rock's only with the fit, and so is the
    // ground within the inscribed radius of its back edge (x = 2.3).
    assert_eq!(class_at(&fitted, 2.2, 0.1), CellClass::Obstacle);
    assert!(blocks(&fitted, 2.55, 0.1));
    assert!(!blocks(&plain, 2.55, 0.1));
    // Beyond the back edge by the inscribed radius and more, the ground stays open; in
    // front, the margin is not pushed towards the rover.
    assert!(!blocks(&fitted, 2.9, 0.1));
    assert!(!blocks(&fitted, 1.15, 0.1));
    let dome = fitted.domes().expect("fit on");
    let geometry = geometry_of(&fitted);
    let (x, y) = geometry.cell_of(1.9, 0.1).expect("inside");
    let mut rocks = Vec::new();
    dome.near(&geometry, geometry.index(x, y), 0.0, |rock, _| {
        rocks.push(*rock)
    });
    let rock = rocks.first().expect("a dome over the rock");
    assert!((rock.height_m - 0.3).abs() < 0.05, "{rock:?}");
    assert!((rock.centre_m[0] - 2.0).abs() < 0.1, "{rock:?}");
}

/// A rover stereo cloud of ground rising `slope` per metre along x, over `[x0, x1] ×
/// [y0, y1]` on a 5 cm lattice, with a round rock of `radius_m` at `centre` resting as the
/// world rests its rocks: on the lowest ground under its footprint, its top `height_m`
/// above that. Heights are measured above the sloped ground under each point.
fn rock_resting_on_a_slope(
    slope: f32,
    centre: [f32; 2],
    radius_m: f32,
    height_m: f32,
) -> Vec<FeaturePoint> {
    let base_z_m = slope * (centre[0] - radius_m);
    let mut cloud = Vec::new();
    for i in 0..=50 {
        for j in 0..=50 {
            let (x, y) = (
                centre[0] - 1.25 + 0.05 * i as f32,
                centre[1] - 1.25 + 0.05 * j as f32,
            );
            let ground_m = slope * x;
            let r = (x - centre[0]).hypot(y - centre[1]);
            let rock_m = if r < radius_m {
                base_z_m + height_m * (1.0 - (r / radius_m).powi(2)).sqrt()
            } else {
                f32::NEG_INFINITY
            };
            let z = ground_m.max(rock_m);
            cloud.push(point(x, y, z, z - ground_m, 0.02));
        }
    }
    cloud
}

#[test]
fn a_rock_on_a_slope_is_judged_by_the_step_from_its_downhill_foot() {
    // On a 10° slope a rock resting on its lowest foot stands lower above the ground at its
    // middle than the step it makes from below: a 0.23 m rock shows about 0.18 m there, which
    // the physics still blocks, and a 0.17 m one shows about 0.12 m, which it lets the rover
    // climb.
    let slope = 10f32.to_radians().tan();
    let judged = |height_m: f32| {
        let mut map = dome_map();
        for _ in 0..3 {
            map.insert_cloud_seen_from(
                Robot::Rover,
                Some([-1.0, 1.0, 1.0]),
                &rock_resting_on_a_slope(slope, [1.0, 1.0], 0.3, height_m),
            );
            map.update();
        }
        blocks(&map, 1.0, 1.0)
    };
    assert!(judged(0.23), "a rock too tall from below was left open");
    assert!(!judged(0.17), "a climbable rock on a slope was shut");
}

#[test]
fn the_fit_keeps_the_corridor_and_lets_rover_stereo_clear_a_false_wall() {
    let mut map = dome_map();
    let rocks = [([1.0, -0.85], 0.3, 0.3), ([1.0, 0.85], 0.3, 0.3)];
    for _ in 0..3 {
        map.insert_cloud_seen_from(
            Robot::Rover,
            Some([-2.0, 0.0, 1.0]),
            &rover_cloud((-1.0, 3.0), (-2.0, 2.0), &rocks),
        );
        map.update();
    }
    assert!(blocks(&map, 1.0, -0.85) && blocks(&map, 1.0, 0.85));
    assert!(
        !blocks(&map, 1.0, 0.125) || !blocks(&map, 1.0, -0.125),
        "the gap closed"
    );
    // A misplaced jumper cloud's compact blob of 0.5 m points fits a dome at (5, 5) …
    let blob: Vec<FeaturePoint> = (0..25)
        .map(|i| {
            let (dx, dy) = (0.05 * (i % 5) as f32, 0.05 * (i / 5) as f32);
            point(5.0 + dx, 5.0 + dy, 0.5, 0.5 - dx, 0.02)
        })
        .collect();
    map.insert_cloud(Robot::Jumper, &blob);
    map.insert_cloud(Robot::Jumper, &blob);
    map.update();
    assert!(blocks(&map, 5.1, 5.1));
    // … which the rover's rays to the bare ground behind it refute.
    let ground = rover_cloud((5.6, 6.5), (4.0, 6.0), &[]);
    for _ in 0..6 {
        map.insert_cloud_seen_from(Robot::Rover, Some([3.0, 5.1, 1.0]), &ground);
        while {
            map.update();
            map.pending_cells() > 0
        } {}
    }
    assert!(!blocks(&map, 5.1, 5.1), "the blob stayed");
}

#[test]
fn a_snapshot_keeps_the_fitted_rocks() {
    let mut map = dome_map();
    let near_half = rover_cloud((0.5, 2.0), (-1.0, 1.0), &[([2.0, 0.0], 0.3, 0.3)]);
    for _ in 0..3 {
        map.insert_cloud_seen_from(Robot::Rover, Some([0.0, 0.0, 1.0]), &near_half);
        map.update();
    }
    let mut bytes = Vec::new();
    crate::snapshot::encode(&map, &mut bytes).expect("encode");
    let mut restored = dome_map();
    crate::snapshot::restore(&mut restored, &bytes).expect("restore");
    while {
        restored.update();
        restored.pending_cells() > 0
    } {}
    assert_eq!(class_at(&restored, 2.2, 0.1), CellClass::Obstacle);
}

#[test]
fn ground_seen_under_a_claimed_dome_refutes_it() {
    // The near face of a 0.33 m dome at (2.3, 0) as the rover would see it (points 0.2–0.3 m
    // from the centre), but the ground around that centre, where the dome's top would
    // stand, was seen bare: the points belong to something else, not to such a rock.
    let arc: Vec<FeaturePoint> = (0..12)
        .map(|i| {
            let angle = std::f32::consts::PI + (i % 4) as f32 * 0.3 - 0.45;
            let d = [0.3f32, 0.25, 0.2][i / 4];
            let (x, y) = (2.3 + d * angle.cos(), d * angle.sin());
            let height_m = (0.33f32 * 0.33 - d * d).sqrt();
            point(x, y, height_m, height_m, 0.02)
        })
        .collect();
    let ground = rover_cloud((2.2, 3.0), (-0.6, 0.6), &[]);
    let run = |with_ground: bool| {
        let mut map = dome_map();
        for _ in 0..3 {
            map.insert_cloud_seen_from(Robot::Rover, Some([0.0, 0.0, 1.0]), &arc);
            if with_ground {
                map.insert_cloud_seen_from(Robot::Rover, Some([0.0, 0.0, 1.0]), &ground);
            }
            while {
                map.update();
                map.pending_cells() > 0
            } {}
        }
        // The cell under the dome's top (the arc's own cells inflate in both cases).
        class_at(&map, 2.3, 0.1) == CellClass::Obstacle
    };
    assert!(run(false), "the arc alone fits a tall dome");
    assert!(!run(true), "the bare ground did not refute it");
}

#[test]
fn the_noisy_points_of_a_low_rock_fit_no_tall_dome() {
    // A 0.12 m rock of 0.25 m radius at (2, 0), its points ± 4 cm off (a deterministic
    // pattern), the bare ground seen around it: its tallest points read 0.16 m, which the
    // fit could take for the flank of a dome twice as tall set behind them.
    let mut map = dome_map();
    let mut cloud = rover_cloud((0.5, 3.0), (-1.0, 1.0), &[([2.0, 0.0], 0.25, 0.12)]);
    for (i, p) in cloud.iter_mut().enumerate() {
        if p.height_above_ground_m > 0.0 {
            let noise_m = [0.04, -0.02, 0.03, -0.04, 0.0][i % 5];
            p.height_above_ground_m += noise_m;
            p.position_m[2] += noise_m;
        }
    }
    for _ in 0..3 {
        map.insert_cloud_seen_from(Robot::Rover, Some([0.0, 0.0, 1.0]), &cloud);
        while {
            map.update();
            map.pending_cells() > 0
        } {}
    }
    for x_m in [1.8, 2.0, 2.2, 2.4] {
        assert!(!blocks(&map, x_m, 0.1), "blocked at x = {x_m}");
    }
}

#[test]
fn the_ground_around_a_maybe_too_tall_rock_costs_as_much_as_the_rock() {
    // A rock just under the climb limit (0.19 m, 0.25 m radius) at (2, 0), seen whole: too
    // tall only maybe (within two sigmas of the fit), so costly but open. Wherever the rover's centre would put its body on the
    // rock whatever the heading (within the inscribed radius of its edge), the cost must be
    // that of driving onto the rock, or the planner skirts it through its inscribed ring.
    let uncertain_cost = config().uncertain_cost;
    let mut map = dome_map();
    let cloud = rover_cloud((0.5, 3.5), (-1.5, 1.5), &[([2.0, 0.0], 0.25, 0.19)]);
    for _ in 0..3 {
        map.insert_cloud_seen_from(Robot::Rover, Some([0.0, 0.0, 1.0]), &cloud);
        while {
            map.update();
            map.pending_cells() > 0
        } {}
    }
    let state_at = |x_m: f64, y_m: f64| {
        let (x, y) = map.geometry().cell_of(x_m, y_m).expect("inside");
        map.cell_state(x, y).expect("cell")
    };
    assert!(!blocks(&map, 2.0, 0.1), "a rock under the limit was shut");
    // On the rock, and 0.2 m and 0.3 m beyond its edge (the inscribed radius is 0.4 m): the
    // map says "maybe too tall" there, not "traversable".
    for (x_m, y_m) in [(2.0, 0.1), (2.0, 0.45), (2.0, -0.55), (2.45, 0.1)] {
        let state = state_at(x_m, y_m);
        assert!(
            state.extra_cost >= uncertain_cost && state.class == CellClass::Uncertain,
            "({x_m}, {y_m}): {state:?}"
        );
    }
    // Beyond the circumscribed radius only a fraction of it, and traversable.
    let beyond = state_at(2.0, 1.25);
    assert!(beyond.extra_cost < uncertain_cost / 2);
    assert!(matches!(
        beyond.class,
        CellClass::Inflated | CellClass::Free
    ));
}

/// A rover stereo cloud of bare ground `z = profile(x)` on a 5 cm lattice over `[x0, x1] ×
/// [y0, y1]` (heights above the local ground are 0: the stereo's local ground follows it).
fn ground_cloud(
    x_range: (f32, f32),
    y_range: (f32, f32),
    profile: impl Fn(f32) -> f32,
) -> Vec<FeaturePoint> {
    let steps = |(lo, hi): (f32, f32)| ((hi - lo) / 0.05).round() as i32;
    let mut cloud = Vec::new();
    for i in 0..=steps(x_range) {
        for j in 0..=steps(y_range) {
            let (x, y) = (x_range.0 + 0.05 * i as f32, y_range.0 + 0.05 * j as f32);
            cloud.push(point(x, y, profile(x), 0.0, 0.02));
        }
    }
    cloud
}

#[test]
fn a_crater_wall_too_steep_to_drive_is_lethal_and_a_gentle_ramp_is_not() {
    // Flat up to x = 2, then rising at `rise` per metre.
    let judged = |rise: f32| {
        let mut map = map();
        let cloud = ground_cloud((0.0, 5.0), (-1.0, 1.0), |x| rise * (x - 2.0).max(0.0));
        for _ in 0..2 {
            map.insert_cloud_seen_from(Robot::Rover, Some([-1.0, 0.0, 1.0]), &cloud);
            while {
                map.update();
                map.pending_cells() > 0
            } {}
        }
        (class_at(&map, 3.5, 0.1), class_at(&map, 0.5, 0.1))
    };
    // 39°, a fresh crater's rim: beyond the 30° the rover accepts.
    assert_eq!(judged(0.8), (CellClass::Lethal, CellClass::Free));
    // 15°: driven up without a cost.
    assert_eq!(judged(0.27), (CellClass::Free, CellClass::Free));
}
