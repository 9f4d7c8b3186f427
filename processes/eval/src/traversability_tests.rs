//! Tests of the traversability judge (`traversability.rs`).
use super::*;

fn rock(x: f64, y: f64, radius_m: f64, height_m: f64) -> RockEllipse {
    RockEllipse::round([x, y], radius_m, height_m)
}

#[test]
fn the_gap_to_an_elongated_rock_follows_its_yawed_ellipse() {
    let rock = RockEllipse {
        center_m: [1.0, 1.0],
        semi_axes_m: [0.6, 0.2],
        yaw_rad: std::f64::consts::FRAC_PI_2,
        height_m: 0.4,
    };
    // Yawed a quarter turn: the long axis runs along world y.
    assert!((rock.gap_m([1.0, 2.0]) - 0.4).abs() < 1e-9);
    assert!((rock.gap_m([2.0, 1.0]) - 0.8).abs() < 1e-9);
    assert!(rock.gap_m([1.0, 1.1]) < 0.0);
}

fn grid(lethal: impl Fn([f64; 2]) -> bool) -> Vec<MapCell> {
    (-20..20)
        .flat_map(|y| (-20..20).map(move |x| (x, y)))
        .map(|(x, y)| {
            let centre_m = [0.125 + 0.25 * f64::from(x), 0.125 + 0.25 * f64::from(y)];
            MapCell {
                centre_m,
                lethal: lethal(centre_m),
                uncertain: false,
                costly: false,
                unobserved: false,
            }
        })
        .collect()
}

/// `blocked_area` over a 0.25 m grid near a one-point track, for a rover that climbs
/// 0.2 m with a 0.4 m inscribed radius.
fn judged_near_track(cells: &[MapCell], rocks: &[RockEllipse], track: [f64; 2]) -> BlockedArea {
    blocked_area(
        cells,
        rocks,
        &Reach::NearTrack(&[track]),
        0.25,
        0.2,
        0.4,
        |_| false,
    )
}

#[test]
fn the_gap_to_an_outline_is_its_distance_to_the_nearest_edge_negative_inside() {
    let square = RockOutline {
        outline_m: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
        center_m: [0.5, 0.5],
        height_m: 0.4,
    };
    assert!((square.gap_m([0.5, 0.5]) + 0.5).abs() < 1e-12);
    assert!((square.gap_m([0.9, 0.5]) + 0.1).abs() < 1e-12);
    assert!((square.gap_m([1.3, 0.5]) - 0.3).abs() < 1e-12);
    assert!((square.gap_m([2.0, 2.0]) - 2f64.sqrt()).abs() < 1e-12);
    let degenerate = RockOutline {
        outline_m: vec![[0.0, 0.0]],
        ..square
    };
    assert_eq!(degenerate.gap_m([0.0, 0.0]), f64::INFINITY);
}

#[test]
fn a_map_that_blocks_twice_the_ground_has_a_ratio_near_two_and_no_misses() {
    let rocks = [rock(0.0, 0.0, 0.3, 0.5)];
    let cells = grid(|c| c[0].hypot(c[1]) < 0.7 * std::f64::consts::SQRT_2);
    let result = judged_near_track(&cells, &rocks, [0.0, 0.0]);
    let ratio = result.blocked_area_ratio.unwrap();
    assert!((1.7..2.3).contains(&ratio), "{ratio}");
    assert_eq!(result.missed_lethal_cells, 0);
    assert!(result.false_lethal_cells > 0);
}

#[test]
fn a_climbable_rock_is_not_lethal_and_a_missed_rock_is_counted() {
    let rocks = [rock(0.0, 0.0, 0.3, 0.15), rock(2.0, 0.0, 0.3, 0.5)];
    let result = judged_near_track(&grid(|_| false), &rocks, [0.0, 0.0]);
    assert!(result.true_lethal_cells > 0, "the tall rock only");
    assert_eq!(result.missed_lethal_cells, result.true_lethal_cells);
    assert_eq!(result.missed_lethal_percent(), Some(100.0));
    assert_eq!(result.blocked_area_ratio, Some(0.0));
}

#[test]
fn a_rock_held_uncertain_is_counted_apart_from_the_missed_ones() {
    // The right half of a tall rock's lethal disc is mapped maybe too tall, the left half
    // traversable.
    let rocks = [rock(0.0, 0.0, 0.3, 0.5)];
    let mut cells = grid(|_| false);
    for cell in &mut cells {
        cell.uncertain = cell.centre_m[0] > 0.0 && cell.centre_m[0].hypot(cell.centre_m[1]) < 1.0;
        cell.costly = cell.uncertain;
    }
    let result = judged_near_track(&cells, &rocks, [0.0, 0.0]);
    assert!(result.uncertain_lethal_cells > 0);
    assert_eq!(
        result.missed_lethal_cells + result.uncertain_lethal_cells,
        result.true_lethal_cells
    );
    assert_eq!(
        result.missed_lethal_cells, result.uncertain_lethal_cells,
        "the disc is symmetric"
    );
    assert_eq!(result.open_lethal_percent(), Some(100.0));
    assert_eq!(result.missed_lethal_percent(), Some(50.0));
    assert_eq!(
        result.blocked_area_ratio,
        Some(0.0),
        "uncertain is not lethal"
    );
}

#[test]
fn a_lethal_disc_drawn_too_small_is_missed_at_its_rim_and_an_unseen_rock_as_unseen() {
    // The rock at the origin is mapped lethal out to 0.3 m of its centre, 0.4 m short of
    // its truly lethal disc (0.3 + 0.4 m): its misses lie in the outer cell's width or
    // deeper. The near-limit rock at x = 3 has no mapped cell over it.
    let rocks = [rock(0.0, 0.0, 0.3, 0.5), rock(3.0, 0.0, 0.3, 0.22)];
    let mut cells = grid(|c| c[0].hypot(c[1]) < 0.3);
    cells.retain(|cell| (cell.centre_m[0] - 3.0).hypot(cell.centre_m[1]) > 0.45);
    // No feature landed beyond x = 2.2 (around the far rock).
    for cell in &mut cells {
        cell.unobserved = cell.centre_m[0] > 2.2;
    }
    let result = judged_near_track(&cells, &rocks, [0.0, 0.0]);
    let causes = result.missed_by_cause;
    assert!(causes.rim_of_lethal_rock > 0 && causes.inside_of_lethal_rock > 0);
    assert!(causes.rock_not_seen > 0);
    assert_eq!(
        causes.rim_of_lethal_rock + causes.inside_of_lethal_rock + causes.rock_not_seen,
        result.missed_lethal_cells
    );
    assert_eq!(causes.missed(), result.missed_lethal_cells);
    assert_eq!(causes.near_limit_rock, causes.rock_not_seen);
    assert_eq!(causes.unobserved, causes.rock_not_seen);
}

#[test]
fn ground_too_steep_to_stand_on_is_truly_lethal_without_a_rock() {
    // A crater's wall along x > 1: a map that shuts it is right, one that leaves it open
    // misses it.
    let steep = |centre_m: [f64; 2]| centre_m[0] > 1.0;
    let judged = |cells: &[MapCell]| {
        blocked_area(
            cells,
            &[] as &[RockEllipse],
            &Reach::NearTrack(&[[0.0, 0.0]]),
            0.25,
            0.2,
            0.4,
            steep,
        )
    };
    let shut = judged(&grid(|c| c[0] > 1.0));
    assert!(shut.true_lethal_cells > 0);
    assert_eq!((shut.missed_lethal_cells, shut.false_lethal_cells), (0, 0));
    let open = judged(&grid(|_| false));
    assert_eq!(open.missed_lethal_cells, open.true_lethal_cells);
}

#[test]
fn cells_far_from_the_track_are_not_judged() {
    let rocks = [rock(0.0, 0.0, 0.3, 0.5)];
    let result = judged_near_track(&grid(|_| true), &rocks, [100.0, 100.0]);
    assert_eq!(result.judged_cells, 0);
    assert_eq!(result.blocked_area_ratio, None);
}

#[test]
fn each_rock_near_the_track_is_counted_by_what_the_map_made_of_it() {
    let rocks = [
        rock(0.0, 0.0, 0.3, 0.5),
        rock(2.0, 0.0, 0.3, 0.5),
        rock(-2.0, 0.0, 0.3, 0.5),
        rock(0.0, 30.0, 0.3, 0.5),
    ];
    let mut cells = grid(|c| c[0].hypot(c[1]) < 0.2);
    for cell in &mut cells {
        cell.costly = (cell.centre_m[0] - 2.0).hypot(cell.centre_m[1]) < 0.2;
    }
    cells.retain(|cell| cell.centre_m[0] < 3.0 || cell.centre_m[1].abs() > 1.0);
    cells.retain(|cell| (cell.centre_m[0] + 2.0).hypot(cell.centre_m[1]) > 0.6);
    let result = judged_near_track(&cells, &rocks, [0.0, 0.0]);
    // Lethal, only costly, not seen; the fourth is beyond 5 m of the track.
    assert_eq!(result.rocks_by_outcome, [1, 1, 0, 1]);
}

#[test]
fn only_cells_the_camera_looked_at_within_reach_are_judged() {
    // The camera at the origin looks along +x with a 60° field of view.
    let views = [CameraView {
        position_m: [0.0, 0.0],
        yaw_rad: 0.0,
    }];
    let reach = Reach::InView {
        views: &views,
        half_fov_rad: 30_f64.to_radians(),
    };
    assert!(reach.covers([3.0, 1.0]));
    assert!(!reach.covers([3.0, 2.5]), "outside the field of view");
    assert!(!reach.covers([-3.0, 0.0]), "behind the camera");
    assert!(!reach.covers([5.5, 0.0]), "beyond reach");
    let rocks = [rock(3.0, 0.0, 0.3, 0.5), rock(-3.0, 0.0, 0.3, 0.5)];
    let result = blocked_area(&grid(|_| false), &rocks, &reach, 0.25, 0.2, 0.4, |_| false);
    // Only the rock ahead counts, missed.
    assert_eq!(result.rocks_by_outcome, [0, 0, 1, 0]);
    assert!(result.true_lethal_cells > 0);
    assert_eq!(result.missed_lethal_cells, result.true_lethal_cells);
}
