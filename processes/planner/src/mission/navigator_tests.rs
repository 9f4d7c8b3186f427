//! Tests of the navigator: driving a point rover over revealed grids.

use super::*;
use crate::mission::SCOUT_BATCH_QUIET_S;

fn at(xy_m: [f64; 2]) -> RoverPose {
    RoverPose { xy_m, yaw_rad: 0.0 }
}

/// Drives a point rover along the decisions; cells within `reveal_m` are revealed from
/// `truth` each frame. Returns the last decision and the frames used.
fn drive(
    navigator: &mut Navigator,
    truth: &Grid,
    start_m: [f64; 2],
    reveal_m: f64,
    max_frames: usize,
) -> (Decision, usize) {
    drive_among_hidden(navigator, truth, &[], start_m, reveal_m, max_frames)
}

/// [`drive`] with `hidden` cells that stop the rover but that no sensor ever reveals.
fn drive_among_hidden(
    navigator: &mut Navigator,
    truth: &Grid,
    hidden: &[Cell],
    start_m: [f64; 2],
    reveal_m: f64,
    max_frames: usize,
) -> (Decision, usize) {
    let geometry = *navigator.geometry();
    let mut rover = at(start_m);
    let step_m: f64 = 0.05;
    for frame in 0..max_frames {
        let rover_m = rover.xy_m;
        let mut changes = Vec::new();
        for index in 0..truth.cell_count() {
            let cell = truth.cell_at(index).unwrap();
            let centre_m = geometry.center_of(cell);
            if distance_m(centre_m, rover_m) <= reveal_m
                && navigator.grid().state(cell) == Some(CellState::Unknown)
            {
                changes.push(CellChange::new(cell, truth.state(cell).unwrap(), 0));
            }
        }
        navigator.queue_changes(changes);
        let decision = navigator.step(rover, None, frame as f64 * 0.1).unwrap();
        if decision.hold {
            return (decision, frame);
        }
        let [dx, dy] = [
            decision.waypoint_m[0] - rover_m[0],
            decision.waypoint_m[1] - rover_m[1],
        ];
        let length = dx.hypot(dy).max(1e-9);
        let advance = step_m.min(length);
        let next_m = [
            rover_m[0] + dx / length * advance,
            rover_m[1] + dy / length * advance,
        ];
        let blocked = geometry
            .cell_of(next_m)
            .is_some_and(|cell| hidden.contains(&cell));
        if !blocked {
            // A reversing rover keeps its heading; otherwise it faces where it goes.
            let yaw_rad = if decision.reverse {
                rover.yaw_rad
            } else {
                dy.atan2(dx)
            };
            rover = RoverPose {
                xy_m: next_m,
                yaw_rad,
            };
        }
    }
    panic!(
        "no terminal decision in {max_frames} frames: rover {rover:?}, {:?}",
        navigator.counters()
    );
}

fn walled_world() -> (MapGeometry, Grid) {
    let geometry = MapGeometry::new(0.0, 0.0, 0.5, 60, 40).unwrap();
    let mut truth = Grid::new(60, 40, CellState::Free).unwrap();
    // A wall one cell thick across x = 15 m, open above y = 17 m.
    for y in 0..34 {
        truth
            .apply(&CellChange::new(Cell::new(30, y), CellState::Obstacle, 0))
            .unwrap();
    }
    (geometry, truth)
}

#[test]
fn reaches_the_goal_around_a_thin_wall_it_discovers() {
    let (geometry, truth) = walled_world();
    let mut config = NavigatorConfig::default();
    config.scout.enabled = false;
    let mut navigator = Navigator::new(geometry, [2.0, 5.0], [28.0, 5.0], config).unwrap();
    let (decision, _) = drive(&mut navigator, &truth, [2.0, 5.0], 4.0, 2000);
    assert_eq!(decision.status, MissionStatus::GoalReached);
    assert!(navigator.counters().replans >= 1);
    assert!(navigator.counters().total_expansions > 0);
}

#[test]
fn an_unreachable_goal_is_a_clear_status_not_a_hang() {
    let (geometry, mut truth) = walled_world();
    for y in 34..40 {
        truth
            .apply(&CellChange::new(Cell::new(30, y), CellState::Obstacle, 0))
            .unwrap();
    }
    let mut config = NavigatorConfig::default();
    config.scout.enabled = false;
    let mut navigator = Navigator::new(geometry, [2.0, 5.0], [28.0, 5.0], config).unwrap();
    let (decision, _) = drive(&mut navigator, &truth, [2.0, 5.0], 40.0, 2000);
    assert_eq!(decision.status, MissionStatus::Unreachable);
    assert_eq!(decision.speed_mps, 0.0);
}

#[test]
fn doubtful_obstacles_that_alone_cut_off_the_goal_are_driven_through_at_a_cost() {
    let (geometry, truth) = walled_world();
    let mut config = NavigatorConfig::default();
    config.scout.enabled = false;
    let mut navigator = Navigator::new(geometry, [2.0, 5.0], [28.0, 5.0], config).unwrap();
    // The rover's rocks close the wall below y = 17 m; the jumper's, above it.
    let confirmed = (0..truth.cell_count()).map(|index| {
        let cell = truth.cell_at(index).unwrap();
        MapChange::from(CellChange::new(cell, truth.state(cell).unwrap(), 0))
    });
    navigator.queue_changes(confirmed);
    let doubtful = (34..40).map(|y| MapChange {
        change: CellChange::new(Cell::new(30, y), CellState::Obstacle, 0),
        doubtful: true,
        scouted: false,
        rock: true,
    });
    navigator.queue_changes(doubtful);
    let decision = navigator.step(at([2.0, 5.0]), None, 0.0).unwrap();
    assert_eq!(decision.status, MissionStatus::Driving);
    assert!(navigator.counters().doubts_relaxed);
    assert!(
        navigator
            .path()
            .iter()
            .any(|cell| cell.x == 30 && cell.y >= 34)
    );
    // The rover's stereo confirms one of them: the path avoids it from then on.
    let confirmed_rock = navigator
        .path()
        .iter()
        .copied()
        .find(|cell| cell.x == 30)
        .unwrap();
    navigator.queue_changes([CellChange::new(confirmed_rock, CellState::Obstacle, 0)]);
    navigator.step(at([2.0, 5.0]), None, 0.1).unwrap();
    assert!(!navigator.path().contains(&confirmed_rock));
    let (decision, _) = drive(&mut navigator, &truth, [2.0, 5.0], 0.0, 4000);
    assert_eq!(decision.status, MissionStatus::GoalReached);
}

#[test]
fn a_rover_tilted_beyond_the_safe_limit_backs_off_and_marks_the_cell_ahead() {
    let geometry = MapGeometry::new(0.0, 0.0, 0.5, 40, 20).unwrap();
    let mut config = NavigatorConfig::default();
    config.scout.enabled = false;
    let limit_rad = config.max_safe_tilt_rad;
    let mut navigator = Navigator::new(geometry, [2.0, 5.0], [18.0, 5.0], config).unwrap();
    navigator.set_rover_tilt(0.5 * limit_rad);
    let first = navigator.step(at([2.0, 5.0]), None, 0.0).unwrap();
    assert!(!first.reverse);
    navigator.set_rover_tilt(1.1 * limit_rad);
    let tilted = navigator.step(at([2.5, 5.0]), None, 0.1).unwrap();
    assert!(tilted.reverse, "{tilted:?}");
    assert!(tilted.waypoint_m[0] < 2.5);
    let counters = navigator.counters();
    assert_eq!((counters.tilt_stops, counters.blocked_marks), (1, 1));
    let ahead = geometry.cell_of([2.5 + 0.8, 5.0]).unwrap();
    assert_eq!(navigator.grid().state(ahead), Some(CellState::Obstacle));
    // Backed off onto level ground, it plans around the marked cell.
    navigator.set_rover_tilt(f64::NAN);
    navigator.set_rover_tilt(0.0);
    let level = navigator.step(at([1.5, 5.0]), None, 1.0).unwrap();
    assert!(!level.reverse && !navigator.path().contains(&ahead));
}

#[test]
fn a_rover_starting_on_a_steep_slope_stops_only_if_it_gets_steeper() {
    let geometry = MapGeometry::new(0.0, 0.0, 0.5, 40, 20).unwrap();
    let mut config = NavigatorConfig::default();
    config.scout.enabled = false;
    let steep_rad = config.max_safe_tilt_rad + 0.05;
    let mut navigator = Navigator::new(geometry, [2.0, 5.0], [18.0, 5.0], config).unwrap();
    navigator.set_rover_tilt(steep_rad);
    assert!(!navigator.step(at([2.0, 5.0]), None, 0.0).unwrap().reverse);
    navigator.set_rover_tilt(steep_rad + 0.01);
    assert!(!navigator.step(at([2.1, 5.0]), None, 0.1).unwrap().reverse);
    navigator.set_rover_tilt(steep_rad + 0.1);
    assert!(navigator.step(at([2.2, 5.0]), None, 0.2).unwrap().reverse);
    assert_eq!(navigator.counters().tilt_stops, 1);
}

#[test]
fn a_rover_stuck_on_an_unmapped_rock_backs_off_marks_it_and_goes_around() {
    let geometry = MapGeometry::new(0.0, 0.0, 0.5, 40, 20).unwrap();
    // A rock no camera sees, straight on the line from start to goal.
    let rock = geometry.cell_of([10.0, 5.0]).unwrap();
    let mut config = NavigatorConfig::default();
    config.scout.enabled = false;
    let mut navigator = Navigator::new(geometry, [2.0, 5.0], [18.0, 5.0], config).unwrap();
    let mut reversed = false;
    let mut rover = at([2.0, 5.0]);
    for frame in 0..3000 {
        let decision = navigator.step(rover, None, frame as f64 * 0.1).unwrap();
        reversed |= decision.reverse;
        if decision.hold {
            assert_eq!(decision.status, MissionStatus::GoalReached);
            break;
        }
        let [dx, dy] = [
            decision.waypoint_m[0] - rover.xy_m[0],
            decision.waypoint_m[1] - rover.xy_m[1],
        ];
        let length = dx.hypot(dy).max(1e-9);
        let advance = 0.05_f64.min(length);
        let next_m = [
            rover.xy_m[0] + dx / length * advance,
            rover.xy_m[1] + dy / length * advance,
        ];
        // The chassis front (0.5 m ahead) may not enter the rock's cell.
        let yaw_rad = if decision.reverse {
            rover.yaw_rad
        } else {
            dy.atan2(dx)
        };
        let front_m = RoverPose {
            xy_m: next_m,
            yaw_rad,
        }
        .ahead_m(0.5);
        if geometry.cell_of(front_m) != Some(rock) {
            rover = RoverPose {
                xy_m: next_m,
                yaw_rad,
            };
        }
    }
    assert!(distance_m(rover.xy_m, [18.0, 5.0]) < 1.0, "{rover:?}");
    assert!(reversed, "it backed off");
    assert!(navigator.counters().blocked_marks >= 1);
    assert_eq!(navigator.grid().state(rock), Some(CellState::Obstacle));
    // The ring around the bumped cell is marked too: the next path keeps the body clear.
    for side in [Cell::new(rock.x, rock.y - 1), Cell::new(rock.x, rock.y + 1)] {
        assert_eq!(navigator.grid().state(side), Some(CellState::Obstacle));
    }
}

#[test]
fn bump_marks_that_alone_cut_off_the_goal_are_forgotten() {
    let (geometry, mut truth) = walled_world();
    // Close the wall but for one gap at y = 10 m.
    for y in 34..40 {
        truth
            .apply(&CellChange::new(Cell::new(30, y), CellState::Obstacle, 0))
            .unwrap();
    }
    let gap = Cell::new(30, 20);
    truth
        .apply(&CellChange::new(gap, CellState::Free, 0))
        .unwrap();
    let mut config = NavigatorConfig::default();
    config.scout.enabled = false;
    let mut navigator = Navigator::new(geometry, [13.0, 10.25], [28.0, 10.25], config).unwrap();
    // The rover sits still facing the gap for a while (a wheel slipping, say): a stall.
    let stuck = RoverPose {
        xy_m: [14.4, 10.25],
        yaw_rad: 0.0,
    };
    let changes: Vec<CellChange> = (0..truth.cell_count())
        .filter_map(|index| truth.cell_at(index))
        .map(|cell| CellChange::new(cell, truth.state(cell).unwrap(), 0))
        .collect();
    navigator.queue_changes(changes);
    for frame in 0..40 {
        navigator.step(stuck, None, frame as f64 * 0.1).unwrap();
    }
    assert_eq!(navigator.counters().blocked_marks, 1);
    assert_eq!(navigator.grid().state(gap), Some(CellState::Obstacle));
    // Backed off, it finds the gap closed by its own mark: it forgets the mark and goes on.
    let (decision, _) = drive(&mut navigator, &truth, [13.6, 10.25], 40.0, 3000);
    assert_eq!(decision.status, MissionStatus::GoalReached);
    assert_eq!(navigator.counters().bump_marks_forgotten, 1);
}

#[test]
fn an_obstacle_reported_on_the_goal_does_not_make_it_unreachable() {
    let geometry = MapGeometry::new(0.0, 0.0, 0.5, 20, 20).unwrap();
    let mut navigator =
        Navigator::new(geometry, [1.0, 5.0], [8.0, 5.0], NavigatorConfig::default()).unwrap();
    let goal = geometry.cell_of([8.0, 5.0]).unwrap();
    navigator.queue_changes([CellChange::new(goal, CellState::Obstacle, 0)]);
    let decision = navigator.step(at([1.0, 5.0]), None, 0.0).unwrap();
    assert_eq!(decision.status, MissionStatus::Driving);
    assert_eq!(navigator.grid().state(goal), Some(CellState::Free));
}

#[test]
fn start_at_the_goal_holds_at_once() {
    let geometry = MapGeometry::new(0.0, 0.0, 0.5, 20, 20).unwrap();
    let mut navigator =
        Navigator::new(geometry, [5.0, 5.0], [5.2, 5.0], NavigatorConfig::default()).unwrap();
    let decision = navigator.step(at([5.0, 5.0]), None, 0.0).unwrap();
    assert_eq!(decision.status, MissionStatus::GoalReached);
    assert!(decision.hold);
}

#[test]
fn asks_the_jumper_to_scout_beyond_sensing_range_once_per_interval() {
    let geometry = MapGeometry::new(0.0, 0.0, 0.5, 100, 20).unwrap();
    let mut navigator = Navigator::new(
        geometry,
        [1.0, 5.0],
        [48.0, 5.0],
        NavigatorConfig::default(),
    )
    .unwrap();
    // The rover turns a little between calls: it is not stuck.
    let turned = |yaw_rad| RoverPose {
        xy_m: [1.0, 5.0],
        yaw_rad,
    };
    // Nothing before the first interval: the jumper's own first hop is in the air.
    assert!(
        navigator
            .step(turned(0.0), None, 1.0)
            .unwrap()
            .scout
            .is_none()
    );
    let decision = navigator.step(turned(0.5), None, 10.0).unwrap();
    let scout = decision.scout.expect("a hop request");
    assert!((scout.target_m[0] - 20.75).abs() < 0.5, "{scout:?}");
    assert!(
        navigator
            .step(turned(0.0), None, 12.0)
            .unwrap()
            .scout
            .is_none()
    );
    assert_eq!(navigator.counters().scout_requests, 1);
}

#[test]
fn outside_positions_are_errors_not_panics() {
    let geometry = MapGeometry::new(0.0, 0.0, 0.5, 20, 20).unwrap();
    assert!(
        Navigator::new(
            geometry,
            [-5.0, 5.0],
            [5.0, 5.0],
            NavigatorConfig::default()
        )
        .is_err()
    );
    let mut navigator =
        Navigator::new(geometry, [1.0, 1.0], [8.0, 8.0], NavigatorConfig::default()).unwrap();
    assert!(navigator.step(at([f64::NAN, 1.0]), None, 0.0).is_err());
    assert_eq!(
        navigator.queue_changes([CellChange::new(Cell::new(99, 0), CellState::Obstacle, 0)]),
        1
    );
}

/// A rock cell as the mapper reports one only the jumper saw.
fn jumper_only_rock(cell: Cell) -> MapChange {
    MapChange {
        change: CellChange::new(cell, CellState::Obstacle, 0),
        doubtful: true,
        scouted: true,
        rock: true,
    }
}

/// Whether the navigator's path stays out of column `x`, rows `rows`.
fn path_avoids_column(navigator: &Navigator, x: u32, rows: std::ops::Range<u32>) -> bool {
    navigator
        .path()
        .iter()
        .all(|cell| !(cell.x == x && rows.contains(&cell.y)))
}

/// A navigator without scouting that planned once, at t = 0, from the rover at (2, 5) m
/// across an all-unknown map.
fn planned_on_an_unknown_map() -> (Navigator, RoverPose) {
    let (geometry, _) = walled_world();
    let mut config = NavigatorConfig::default();
    config.scout.enabled = false;
    let mut navigator = Navigator::new(geometry, [2.0, 5.0], [28.0, 5.0], config).unwrap();
    let rover = at([2.0, 5.0]);
    navigator.step(rover, None, 0.0).unwrap();
    (navigator, rover)
}

#[test]
fn a_hops_jumper_cells_change_the_route_once_when_its_clouds_stop_coming() {
    let (mut navigator, rover) = planned_on_an_unknown_map();
    let straight_cost = navigator.counters().path_cost;
    // A rock across the straight line, seen by the jumper in three keyframe clouds 0.3 s apart.
    let scouted = |y: u32| jumper_only_rock(Cell::new(30, y));
    for (frame, rows) in [(1, 8..10), (4, 10..12), (7, 6..8)] {
        navigator.queue_changes(rows.map(scouted));
        let decision = navigator.step(rover, None, f64::from(frame) * 0.1).unwrap();
        assert!(
            !decision.replanned,
            "frame {frame}: taken before the hop's clouds ended"
        );
    }
    assert_eq!(navigator.counters().path_cost, straight_cost);
    // Quiet for SCOUT_BATCH_QUIET_S: the whole batch is taken, one replan.
    let decision = navigator
        .step(rover, None, 0.75 + SCOUT_BATCH_QUIET_S)
        .unwrap();
    assert!(decision.replanned);
    assert_eq!(navigator.counters().replans, 1);
    assert!(navigator.counters().path_cost > straight_cost);
    assert!(path_avoids_column(&navigator, 30, 6..12));
}

#[test]
fn a_held_jumper_rock_just_ahead_on_the_path_is_taken_at_once() {
    let (mut navigator, rover) = planned_on_an_unknown_map();
    // 2 m ahead of the rover, across its straight route: waiting for the hop's clouds to stop
    // would let it drive into the rock.
    navigator.queue_changes((8..12).map(|y| jumper_only_rock(Cell::new(8, y))));
    let decision = navigator.step(rover, None, 0.1).unwrap();
    assert!(decision.replanned, "held while the rover drives into it");
    assert!(path_avoids_column(&navigator, 8, 8..12));
}

#[test]
fn the_rovers_word_on_a_cell_supersedes_a_held_jumper_one() {
    let (mut navigator, rover) = planned_on_an_unknown_map();
    let cell = Cell::new(30, 10);
    navigator.queue_changes([jumper_only_rock(cell)]);
    // The rover's stereo sees the same cell before the batch is taken: only near a rock.
    navigator.queue_changes([CellChange::new(cell, CellState::Free, 300)]);
    navigator.step(rover, None, 5.0).unwrap();
    assert_eq!(navigator.grid().state(cell), Some(CellState::Free));
    assert_eq!(navigator.grid().extra_cost(cell), Some(300));
}

#[test]
fn a_costlier_cell_on_the_route_is_a_replan_and_a_rock_across_it_a_route_change() {
    let (mut navigator, rover) = planned_on_an_unknown_map();
    // Dearer, but not by as much as stepping around it: the same route at a higher price.
    navigator.queue_changes([CellChange::new(Cell::new(20, 10), CellState::Free, 300)]);
    assert!(navigator.step(rover, None, 0.1).unwrap().replanned);
    assert_eq!(navigator.counters().replans, 1);
    assert_eq!(navigator.counters().route_changes, 0);
    // A rock the rover's stereo saw across the route: it goes another way.
    navigator
        .queue_changes((6..15).map(|y| CellChange::new(Cell::new(30, y), CellState::Obstacle, 0)));
    assert!(navigator.step(rover, None, 0.2).unwrap().replanned);
    assert_eq!(navigator.counters().replans, 2);
    assert_eq!(navigator.counters().route_changes, 1);
}

#[test]
fn a_route_found_after_an_unreachable_spell_counts_as_a_route_change() {
    let (mut navigator, rover) = planned_on_an_unknown_map();
    let wall = |ys: std::ops::Range<u32>, state| {
        ys.map(move |y| CellChange::new(Cell::new(30, y), state, 0))
    };
    navigator.queue_changes(wall(0..40, CellState::Obstacle));
    let decision = navigator.step(rover, None, 0.1).unwrap();
    assert_eq!(decision.status, MissionStatus::Unreachable);
    assert!(navigator.path().is_empty());
    // A gap opens at the far end: the rover goes the long way round, not straight on.
    navigator.queue_changes(wall(36..40, CellState::Free));
    let decision = navigator.step(rover, None, 0.2).unwrap();
    assert_eq!(decision.status, MissionStatus::Driving);
    assert_eq!(navigator.counters().route_changes, 1);
}

/// A 20 m × 10 m unknown map, the rover at (2, 5) bound for (18, 5), with a corridor at
/// y = 8 m reported free from x = 2 m to 18 m (ground the jumper flew over).
fn navigator_with_a_free_corridor(unknown_extra_cost: u32) -> Navigator {
    let geometry = MapGeometry::new(0.0, 0.0, 0.5, 40, 20).unwrap();
    let mut config = NavigatorConfig::default();
    config.scout.enabled = false;
    config.unknown_extra_cost = unknown_extra_cost;
    let mut navigator = Navigator::new(geometry, [2.0, 5.0], [18.0, 5.0], config).unwrap();
    navigator.queue_changes((4..37).map(|x| CellChange::new(Cell::new(x, 16), CellState::Free, 0)));
    navigator
}

#[test]
fn an_unknown_premium_routes_the_rover_along_ground_seen_free() {
    let on_corridor =
        |navigator: &Navigator| navigator.path().iter().filter(|cell| cell.y == 16).count();
    let mut optimist = navigator_with_a_free_corridor(0);
    optimist.step(at([2.0, 5.0]), None, 0.0).unwrap();
    assert_eq!(on_corridor(&optimist), 0, "{:?}", optimist.path());
    // Through the corridor: 6 m of unknown ground plus 16 m seen free, against 16 m of
    // unknown ground at 1.5x.
    let mut cautious = navigator_with_a_free_corridor(500);
    cautious.step(at([2.0, 5.0]), None, 0.0).unwrap();
    assert!(on_corridor(&cautious) >= 20, "{:?}", cautious.path());
}

#[test]
fn ground_found_free_where_the_path_expected_it_is_no_replan() {
    let geometry = MapGeometry::new(0.0, 0.0, 0.5, 40, 20).unwrap();
    let truth = Grid::new(40, 20, CellState::Free).unwrap();
    let mut config = NavigatorConfig::default();
    config.scout.enabled = false;
    config.unknown_extra_cost = 500;
    let mut navigator = Navigator::new(geometry, [2.0, 5.0], [18.0, 5.0], config).unwrap();
    let (decision, _) = drive(&mut navigator, &truth, [2.0, 5.0], 3.0, 2000);
    assert_eq!(decision.status, MissionStatus::GoalReached);
    assert_eq!(navigator.counters().replans, 0);
}

#[test]
fn the_footprint_sweep_takes_a_nearer_waypoint_when_the_body_would_brush_a_rock() {
    // 0.25 m cells; a rock cell 0.45 m beside the straight line ahead (the centre clears it,
    // the 0.8 m wide body does not). The rock's lethal margin is not on the map (as when the
    // mapper left it out): only the sweep can see the body's problem.
    let geometry = MapGeometry::new(0.0, 0.0, 0.25, 40, 40).unwrap();
    let rock = geometry.cell_of([2.0, 5.45]).unwrap();
    let waypoint = |footprint_check: bool| {
        let config = NavigatorConfig {
            footprint_check,
            lookahead_m: 3.0,
            ..NavigatorConfig::default()
        };
        let mut navigator = Navigator::new(geometry, [0.6, 5.0], [9.0, 5.0], config).unwrap();
        let mut changes: Vec<MapChange> = (0..40)
            .flat_map(|y| (0..40).map(move |x| Cell::new(x, y)))
            .map(|cell| CellChange::new(cell, CellState::Free, 0).into())
            .collect();
        changes.push(MapChange {
            change: CellChange::new(rock, CellState::Obstacle, 0),
            doubtful: false,
            scouted: false,
            rock: true,
        });
        navigator.queue_changes(changes);
        navigator
            .step(at([0.6, 5.0]), None, 0.0)
            .unwrap()
            .waypoint_m
    };
    let without = waypoint(false);
    let with = waypoint(true);
    assert!(
        without[0] > 2.5,
        "no sweep: the look-ahead point {without:?}"
    );
    assert!(with[0] < without[0], "the sweep kept {with:?}");
}
