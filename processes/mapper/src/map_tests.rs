//! Scenario tests of [`FeatureMap`]: rocks on sloped ground, diffs, bad input, bounded memory.

use super::*;
use hopnav_ipc::messages::FeaturePoint;

/// The first mapper's rule on 0.5 m cells (the `traversability` model has its own tests).
fn config() -> MapperConfig {
    MapperConfig {
        obstacle_model: crate::config::ObstacleModel::Features,
        cell_size_m: 0.5,
        ..MapperConfig::default()
    }
}

/// 16 m × 16 m, origin (−8, −8), 0.5 m cells.
fn new_map() -> FeatureMap {
    let config = config();
    FeatureMap::sixteen_m_square(&config)
}

/// Sloped ground (≈14° along x, ≈6° along y) with a little roughness.
fn ground_z(x: f32, y: f32) -> f32 {
    0.25 * x + 0.1 * y + 1.0
}

struct Noise(u64);

impl Noise {
    /// Uniform in [−amplitude, amplitude].
    fn next(&mut self, amplitude: f32) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        ((self.0 >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0) * amplitude
    }
}

/// A rock of `height_m` on `[3, 4) × [3, 4)` (2 × 2 cells) on sloped ground sampled every
/// 0.1 m over `[−4, 8) × [−4, 8)`. `measured` fills the true height above ground (a stereo
/// rover); otherwise it is NaN (a monocular jumper without a ground plane).
fn rock_on_slope(height_m: f32, measured: bool) -> Vec<FeaturePoint> {
    let mut noise = Noise(0x2545_f491_4f6c_dd1d);
    let mut points = Vec::new();
    for i in 0..120 {
        for j in 0..120 {
            let x = -4.0 + i as f32 * 0.1 + 0.05;
            let y = -4.0 + j as f32 * 0.1 + 0.05;
            let on_rock = (3.0..4.0).contains(&x) && (3.0..4.0).contains(&y);
            let above = if on_rock { height_m } else { 0.0 } + noise.next(0.02);
            points.push(FeaturePoint {
                position_m: [x, y, ground_z(x, y) + above],
                height_above_ground_m: if measured { above } else { f32::NAN },
                track_id: (i * 120 + j) as u32,
                depth_sigma_m: 0.05,
            });
        }
    }
    points
}

/// Inserts `cloud` as two keyframes that saw the same features (a rock needs two clouds).
fn seen_twice(map: &mut FeatureMap, robot: Robot, cloud: &[FeaturePoint]) {
    map.insert_cloud(robot, cloud);
    map.insert_cloud(robot, cloud);
}

fn class_at(map: &FeatureMap, x_m: f64, y_m: f64) -> CellClass {
    let (x, y) = map.geometry().cell_of(x_m, y_m).expect("inside");
    map.cell_state(x, y).expect("inside").class
}

fn assert_rock_with_ring(map: &FeatureMap) {
    for (x, y) in [(3.25, 3.25), (3.75, 3.25), (3.25, 3.75), (3.75, 3.75)] {
        assert_eq!(
            class_at(map, x, y),
            CellClass::Obstacle,
            "rock cell ({x}, {y})"
        );
    }
    // One and two cells (0.5 m, 1.0 m) from the rock: lethal (the rover's body would touch
    // it), then inflated, cost falling with distance. Rock cells are x, y ∈ {22, 23}.
    let near = map.cell_state(21, 22).expect("inside");
    let diagonal = map.cell_state(21, 21).expect("inside");
    let far = map.cell_state(20, 22).expect("inside");
    assert_eq!(
        (near.class, diagonal.class, far.class),
        (CellClass::Lethal, CellClass::Lethal, CellClass::Inflated)
    );
    assert!(near.extra_cost > far.extra_cost && far.extra_cost > 0);
    // Everything else on the slope: free.
    let mut obstacles = 0;
    for y in 8..32 {
        for x in 8..32 {
            let state = map.cell_state(x, y).expect("inside");
            let (cx, cy) = map.geometry().centre_m(x, y);
            let ring = (2.0..5.0).contains(&cx) && (2.0..5.0).contains(&cy);
            if !ring {
                assert_eq!(state.class, CellClass::Free, "slope cell ({x}, {y})");
            }
            obstacles += usize::from(state.class == CellClass::Obstacle);
        }
    }
    assert_eq!(obstacles, 4);
}

/// A 0.6 m rock on a slope, seen twice by `robot`, is an obstacle with its ring.
fn assert_rock_on_slope_seen_by(robot: Robot, measured_heights: bool) {
    let mut map = new_map();
    seen_twice(&mut map, robot, &rock_on_slope(0.6, measured_heights));
    map.update();
    assert_rock_with_ring(&map);
}

#[test]
fn rock_on_slope_without_measured_heights_is_an_obstacle_with_a_ring() {
    assert_rock_on_slope_seen_by(Robot::Jumper, false);
}

#[test]
fn rock_on_slope_with_measured_heights_is_an_obstacle_with_a_ring() {
    assert_rock_on_slope_seen_by(Robot::Rover, true);
}

#[test]
fn rock_streamed_in_small_clouds_gives_the_same_map() {
    let mut map = new_map();
    for chunk in rock_on_slope(0.6, false).chunks(97) {
        map.insert_cloud(Robot::Jumper, chunk);
        map.update();
    }
    assert_rock_with_ring(&map);
}

#[test]
fn a_per_frame_cell_limit_only_delays_the_same_map() {
    let config = MapperConfig {
        max_cells_per_frame: 50,
        ..config()
    };
    let mut map = FeatureMap::sixteen_m_square(&config);
    seen_twice(&mut map, Robot::Jumper, &rock_on_slope(0.6, false));
    let mut frames = 0;
    loop {
        map.update();
        frames += 1;
        if map.pending_cells() == 0 {
            break;
        }
        assert!(frames < 100);
    }
    assert!(frames > 10, "{frames}");
    assert_rock_with_ring(&map);
}

#[test]
fn low_rock_below_traversable_height_stays_free() {
    assert!(0.12 < config().traversable_height_m);
    for measured in [false, true] {
        let mut map = new_map();
        map.insert_cloud(Robot::Rover, &rock_on_slope(0.12, measured));
        map.update();
        for y in 8..32 {
            for x in 8..32 {
                let state = map.cell_state(x, y).expect("inside");
                assert_eq!(
                    state.class,
                    CellClass::Free,
                    "({x}, {y}) measured {measured}"
                );
                assert_eq!(state.extra_cost, 0);
            }
        }
    }
}

#[test]
fn steep_bare_slope_is_free_without_measured_heights() {
    // 30° along x plus a gentle bend: the lowest point of a neighbourhood is up to 2.3 m below
    // a cell, so a "lowest observation" ground without a plane would see obstacles everywhere.
    let mut map = new_map();
    let mut noise = Noise(99);
    let cloud: Vec<FeaturePoint> = (0..120 * 120)
        .map(|k| {
            let (x, y) = (-4.0 + (k % 120) as f32 * 0.1, -4.0 + (k / 120) as f32 * 0.1);
            let z = 0.577 * x + 0.02 * y * y + noise.next(0.02);
            FeaturePoint {
                position_m: [x, y, z],
                height_above_ground_m: f32::NAN,
                ..FeaturePoint::default()
            }
        })
        .collect();
    map.insert_cloud(Robot::Jumper, &cloud);
    map.update();
    for y in 8..32 {
        for x in 8..32 {
            assert_eq!(
                map.cell_state(x, y).expect("inside").class,
                CellClass::Free,
                "({x}, {y})"
            );
        }
    }
}

#[test]
fn single_outliers_do_not_make_obstacles() {
    let mut map = new_map();
    let mut cloud = rock_on_slope(0.0, false);
    // Two stray features 1.5 m above the ground in one cell: below the support of 3.
    for k in 0..2 {
        let (x, y) = (0.2 + 0.1 * k as f32, 0.2);
        cloud.push(FeaturePoint {
            position_m: [x, y, ground_z(x, y) + 1.5],
            height_above_ground_m: f32::NAN,
            ..FeaturePoint::default()
        });
    }
    map.insert_cloud(Robot::Jumper, &cloud);
    map.update();
    assert_eq!(class_at(&map, 0.25, 0.25), CellClass::Free);
}

#[test]
fn outliers_piling_up_over_a_long_mission_stay_free() {
    for measured in [false, true] {
        let mut map = new_map();
        let ground = rock_on_slope(0.0, measured);
        // Many keyframes see the same ground; every tenth adds one stray feature 1 m up in
        // the cell at (0.25, 0.25): after 100 keyframes that cell holds 10 high features.
        for keyframe in 0..100 {
            map.insert_cloud(Robot::Jumper, &ground[..ground.len() / 2]);
            if keyframe % 10 == 0 {
                let (x, y) = (0.2, 0.3);
                map.insert_cloud(
                    Robot::Jumper,
                    &[FeaturePoint {
                        position_m: [x, y, ground_z(x, y) + 1.0],
                        height_above_ground_m: if measured { 1.0 } else { f32::NAN },
                        ..FeaturePoint::default()
                    }],
                );
            }
            map.update();
        }
        assert_eq!(
            class_at(&map, 0.25, 0.25),
            CellClass::Free,
            "measured {measured}"
        );
        // A real rock keeps being an obstacle however often it is seen.
        for _ in 0..20 {
            map.insert_cloud(Robot::Jumper, &rock_on_slope(0.6, measured));
            map.update();
        }
        assert_rock_with_ring(&map);
    }
}

#[test]
fn observers_are_recorded_per_robot() {
    let mut map = new_map();
    let point = |x: f32| FeaturePoint {
        position_m: [x, 0.1, 0.0],
        height_above_ground_m: 0.0,
        ..FeaturePoint::default()
    };
    map.insert_cloud(Robot::Jumper, &[point(0.1), point(1.1)]);
    map.insert_cloud(Robot::Rover, &[point(0.2)]);
    map.update();
    let both = map.cell_state(16, 16).expect("inside");
    let jumper_only = map.cell_state(18, 16).expect("inside");
    assert_eq!(
        both.observed_by,
        (1 << Robot::Jumper.code()) | (1 << Robot::Rover.code())
    );
    assert_eq!(jumper_only.observed_by, 1 << Robot::Jumper.code());
    let stats = map.cell_stats(16, 16).expect("inside");
    assert_eq!(stats.count_by_robot[Robot::Rover.code() as usize], 1);
}

#[test]
fn only_changed_cells_are_published() {
    let mut map = new_map();
    let mut changes = Vec::new();
    map.insert_cloud(Robot::Rover, &rock_on_slope(0.0, true));
    map.update();
    let first = map.collect_changes(&mut changes);
    assert_eq!(first, 24 * 24, "every observed cell once");
    assert!(changes.iter().all(|c| c.class == CellClass::Free.code()));

    changes.clear();
    map.update();
    assert_eq!(map.collect_changes(&mut changes), 0, "nothing new");

    // More ground features in known cells: same class, same observers, nothing to send.
    map.insert_cloud(Robot::Rover, &rock_on_slope(0.0, true)[..500]);
    map.update();
    assert_eq!(map.collect_changes(&mut changes), 0);

    // A rock appears: its 4 cells and the inflation ring around them, nothing else.
    seen_twice(&mut map, Robot::Rover, &rock_on_slope(0.6, true));
    map.update();
    map.collect_changes(&mut changes);
    // Rock cells 22..=23; the 1 m ring reaches 2 cells straight, 1 diagonal: a 6 × 6 square
    // without its three-cell corners.
    assert_eq!(changes.len(), 6 * 6 - 4 * 3, "rock + ring");
    for change in &changes {
        assert!((20..=25).contains(&change.x) && (20..=25).contains(&change.y));
        let class = CellClass::from_code(change.class).expect("code");
        assert!(matches!(
            class,
            CellClass::Obstacle | CellClass::Lethal | CellClass::Inflated
        ));
    }

    // A second robot seeing a cell changes its observers: sent again.
    changes.clear();
    map.insert_cloud(
        Robot::Jumper,
        &[FeaturePoint {
            position_m: [-3.0, -3.0, ground_z(-3.0, -3.0)],
            height_above_ground_m: f32::NAN,
            ..FeaturePoint::default()
        }],
    );
    map.update();
    assert_eq!(map.collect_changes(&mut changes), 1);
    assert_eq!(changes[0].observed_by, 0b110);

    // A full republication sends every known cell.
    changes.clear();
    map.republish_all();
    let known = (0..32)
        .flat_map(|y| (0..32).map(move |x| (x, y)))
        .filter(|&(x, y)| map.cell_state(x, y).expect("inside").class != CellClass::Unknown)
        .count();
    assert_eq!(map.collect_changes(&mut changes), known);
}

#[test]
fn non_finite_and_outside_points_are_counted_and_dropped() {
    let mut map = new_map();
    let good = FeaturePoint {
        position_m: [0.1, 0.1, 0.0],
        height_above_ground_m: f32::NAN,
        ..FeaturePoint::default()
    };
    let mut nan_position = good;
    nan_position.position_m[0] = f32::NAN;
    let mut inf_position = good;
    inf_position.position_m[2] = f32::NEG_INFINITY;
    let mut inf_height = good;
    inf_height.height_above_ground_m = f32::INFINITY;
    let mut nan_sigma = good;
    nan_sigma.depth_sigma_m = f32::NAN;
    let mut outside = good;
    outside.position_m[0] = 8.0;
    let mut far_outside = good;
    far_outside.position_m[1] = -1e30;
    let mut implausible = good;
    implausible.height_above_ground_m = 40.0;
    let cloud = [
        good,
        nan_position,
        inf_position,
        inf_height,
        nan_sigma,
        outside,
        far_outside,
        implausible,
    ];
    assert_eq!(map.insert_cloud(Robot::Jumper, &cloud), 1);
    let counters = map.counters();
    assert_eq!(counters.accepted, 1);
    assert_eq!(counters.non_finite, 4);
    assert_eq!(counters.outside_grid, 2);
    assert_eq!(counters.implausible_height, 1);
    map.update();
    assert_eq!(class_at(&map, 0.1, 0.1), CellClass::Free);
}

#[test]
fn memory_stays_bounded_over_a_million_points() {
    let config = config();
    let mut map = FeatureMap::sixteen_m_square(&config);
    let bytes = map.memory_bytes();
    let capacities = (map.stats.capacity(), map.ground.samples.capacity());
    let mut noise = Noise(7);
    let mut cloud = vec![FeaturePoint::default(); 1000];
    for round in 0..1000 {
        for (k, point) in cloud.iter_mut().enumerate() {
            let (x, y) = (noise.next(9.0), noise.next(9.0)); // some fall outside
            point.position_m = [x, y, ground_z(x, y) + noise.next(0.05)];
            point.height_above_ground_m = if k % 2 == 0 { f32::NAN } else { 0.0 };
        }
        map.insert_cloud(Robot::Jumper, &cloud);
        if round % 250 == 249 {
            map.update();
        }
    }
    let counters = map.counters();
    assert_eq!(counters.accepted + counters.outside_grid, 1_000_000);
    assert!(counters.outside_grid > 0);
    assert_eq!(map.memory_bytes(), bytes);
    assert_eq!(
        (map.stats.capacity(), map.ground.samples.capacity()),
        capacities
    );
    assert!(bytes < 1024 * 1024, "{bytes} bytes for 1024 cells");
    let total: u64 = map.stats.iter().map(|s| u64::from(s.count)).sum();
    assert_eq!(total, counters.accepted);
}

#[test]
#[ignore = "timing, run with --release --ignored --nocapture"]
fn timing_of_a_dense_cloud() {
    let mut map = new_map();
    let cloud = rock_on_slope(0.6, false);
    let start = std::time::Instant::now();
    map.insert_cloud(Robot::Jumper, &cloud);
    let inserted = start.elapsed();
    map.update();
    let updated = start.elapsed();
    let mut changes = Vec::with_capacity(map.geometry().cell_count());
    map.collect_changes(&mut changes);
    eprintln!(
        "{} points, {} cells changed: insert {:?}, update {:?}, cell {} bytes, map {} bytes",
        cloud.len(),
        changes.len(),
        inserted,
        updated - inserted,
        size_of::<CellStats>(),
        map.memory_bytes()
    );
    let full = config().resolve_geometry((64.0, 64.0)).expect("valid");
    let full_map = FeatureMap::new(&config(), full);
    let mut bytes = Vec::new();
    let start = std::time::Instant::now();
    crate::snapshot::encode(&full_map, &mut bytes).expect("encode");
    eprintln!(
        "snapshot of {} cells: {} bytes in {:?}; map {} bytes",
        full.cell_count(),
        bytes.len(),
        start.elapsed(),
        full_map.memory_bytes()
    );
}

#[test]
fn one_cloud_alone_or_outvoted_makes_no_rock() {
    // A single keyframe that reads the rock high: not enough.
    let mut map = new_map();
    map.insert_cloud(Robot::Jumper, &rock_on_slope(0.6, true));
    map.update();
    assert_ne!(class_at(&map, 3.25, 3.25), CellClass::Obstacle);
    // Two distorted clouds read bare ground high, six good ones saw it as ground.
    let mut map = new_map();
    for _ in 0..6 {
        map.insert_cloud(Robot::Jumper, &rock_on_slope(0.0, true));
    }
    map.insert_cloud(Robot::Jumper, &rock_on_slope(0.6, true));
    map.insert_cloud(Robot::Jumper, &rock_on_slope(0.6, true));
    map.update();
    assert_ne!(class_at(&map, 3.25, 3.25), CellClass::Obstacle);
    // A third read of the rock tips the vote: 3 of 9 clouds.
    map.insert_cloud(Robot::Jumper, &rock_on_slope(0.6, true));
    map.update();
    assert_eq!(class_at(&map, 3.25, 3.25), CellClass::Obstacle);
}

#[test]
fn the_rovers_close_look_overrules_a_jumper_rock_and_confirms_a_real_one() {
    let jumper_rock = rock_on_slope(0.6, true);
    let bare_ground = rock_on_slope(0.0, true);
    // The jumper's clouds agree on a rock where the rover's stereo then sees bare ground (the
    // jumper's pose had drifted): the rover decides.
    let mut map = new_map();
    seen_twice(&mut map, Robot::Jumper, &jumper_rock);
    map.update();
    assert_eq!(class_at(&map, 3.25, 3.25), CellClass::Obstacle);
    map.insert_cloud(Robot::Rover, &bare_ground);
    map.update();
    assert_eq!(class_at(&map, 3.25, 3.25), CellClass::Free);
    // A rock both robots see stays.
    let mut map = new_map();
    seen_twice(&mut map, Robot::Jumper, &jumper_rock);
    map.insert_cloud(Robot::Rover, &rock_on_slope(0.6, true));
    map.update();
    assert_eq!(class_at(&map, 3.25, 3.25), CellClass::Obstacle);
    // A glance (a few rover features per cell) does not overrule the jumper…
    let glance: Vec<FeaturePoint> = bare_ground.iter().step_by(10).copied().collect();
    let mut map = new_map();
    seen_twice(&mut map, Robot::Jumper, &jumper_rock);
    map.insert_cloud(Robot::Rover, &glance);
    map.update();
    assert_eq!(class_at(&map, 3.25, 3.25), CellClass::Obstacle);
    // … and with the rule off (0) nothing does.
    let config = MapperConfig {
        rover_overrules_jumper_after: 0,
        ..config()
    };
    let mut map = FeatureMap::sixteen_m_square(&config);
    seen_twice(&mut map, Robot::Jumper, &jumper_rock);
    map.insert_cloud(Robot::Rover, &bare_ground);
    map.update();
    assert_eq!(class_at(&map, 3.25, 3.25), CellClass::Obstacle);
}

/// `count` features spread over the cell [3, 3.5) × [3, 3.5), the first `high` of them
/// `high_m` above the sloped ground, the rest on it; heights measured.
fn features_in_one_cell(count: usize, high: usize, high_m: f32) -> Vec<FeaturePoint> {
    (0..count)
        .map(|k| {
            let (x, y) = (
                3.02 + 0.07 * (k % 7) as f32,
                3.02 + 0.07 * (k / 7 % 7) as f32,
            );
            let above = if k < high { high_m } else { 0.0 };
            FeaturePoint {
                position_m: [x, y, ground_z(x, y) + above],
                height_above_ground_m: above,
                track_id: k as u32,
                depth_sigma_m: 0.05,
            }
        })
        .collect()
}

#[test]
fn the_jumpers_ground_view_does_not_dilute_a_small_rock_the_rover_sees() {
    // A 0.22 m rock (the rover climbs 0.2 m) fills part of a cell: 4 of the rover's 30
    // features there are on its top. The jumper, metres up, saw only ground there in ten
    // clouds: 100 features that must not outvote the rover's 4 high ones (4 of 130 is below
    // the 10 % fraction; 4 of the rover's 30 is not).
    let rover_view = features_in_one_cell(30, 4, 0.22);
    let jumper_view = features_in_one_cell(10, 0, 0.0);
    let mut map = new_map();
    map.insert_cloud(Robot::Rover, &rover_view);
    for _ in 0..10 {
        map.insert_cloud(Robot::Jumper, &jumper_view);
    }
    map.update();
    assert_eq!(class_at(&map, 3.25, 3.25), CellClass::Obstacle);
    // The rover's own evidence still has to pass the fraction: 3 stray high features among
    // 100 of its own stay free, with or without the jumper's view.
    let mut map = new_map();
    map.insert_cloud(Robot::Rover, &features_in_one_cell(100, 3, 0.22));
    map.update();
    assert_eq!(class_at(&map, 3.25, 3.25), CellClass::Free);
    for _ in 0..10 {
        map.insert_cloud(Robot::Jumper, &jumper_view);
    }
    map.update();
    assert_eq!(class_at(&map, 3.25, 3.25), CellClass::Free);
}
